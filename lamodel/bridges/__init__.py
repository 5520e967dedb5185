"""Masonry arch bridges: a bridge described as an assessor would (span, rise, ring, fill,
abutments, an axle load), built into blocks with the fill's forces, and its adequacy factor
against the load's position (:mod:`.description`, :mod:`.ring`, :mod:`.deck`, :mod:`.fill`,
:mod:`.build`, :mod:`.picture`, :mod:`.adequacy`)."""
from .build import bridge_spec, case_name, case_positions, positions  # noqa: F401
from .description import Bridge, read_bridge  # noqa: F401
