"""Geometry of block assemblies: contacts found from polygons, and generators of walls
(running bond, with openings, of irregular stones), arches and portals (as JSON specs;
:func:`lamodel.io.jsonspec.structure_from_json` builds the Structure); in space, polyhedra,
their interfaces and generators of walls, façades, buildings, vaults, domes and towers (3D specs;
:func:`lamodel.io.json3d.structure3d_from_spec`)."""
from .contacts import find_contacts  # noqa: F401
from .generators import arch, portal, running_bond_wall, seed_instances, seed_wall, wall_with_openings  # noqa: F401
from .stones import stone_wall  # noqa: F401
from .generators3d import (barrel_vault, box_building, dome, extrude, extruded_seed_instances,  # noqa: F401
                           facade, tower, wall_panel)
