"""Geometry of block assemblies: contacts found from polygons, and generators of walls,
arches and portals (as JSON specs; :func:`lamodel.io.jsonspec.structure_from_json` builds
the Structure)."""
from .contacts import find_contacts  # noqa: F401
from .generators import arch, portal, running_bond_wall, seed_instances, seed_wall, wall_with_openings  # noqa: F401
