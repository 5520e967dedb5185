"""A bridge description turned into the block structure the solver reads: the JSON
geometry of :mod:`lamodel.io.jsonspec` (polygons a user can edit), with the fill's forces
as dead point loads, each load position as a load case of live point loads, and the
passive restraint as restraints. ``lamodel solve`` on it solves every position; the least
alpha (the adequacy factor) governs.
"""
from __future__ import annotations

import numpy as np

from ..search.tuning import BRIDGE_POSITIONS
from .description import Bridge, case_name, lateral_coefficient, passive_coefficient
from .fill import dead_loads, live_loads, restraints
from .deck import deck_blocks
from .ring import voussoir_id


def positions(bridge: Bridge) -> list:
    """The lead axle's positions: the file's, else evenly from springing to springing."""
    if bridge.positions is not None:
        return [float(x) for x in bridge.positions]
    return [float(f"{x:.12g}") for x in np.linspace(-bridge.span / 2, bridge.span / 2, BRIDGE_POSITIONS)]


def bridge_spec(bridge: Bridge, passive: bool = True) -> dict:
    """The JSON geometry of the bridge (module doc); ``passive=False`` leaves the passive
    restraint out."""
    loads = dead_loads(bridge)
    cases = {}
    for x in positions(bridge):
        live = live_loads(bridge, x, case_name(x))
        if live:   # a position whose axles all stand beyond the springings loads no block
            cases[x] = live
            loads += live
    crushing = f", fc {bridge.fc:g}" if bridge.fc is not None else ", no crushing"
    skew = f", skew {bridge.skew:g} deg (not modelled)" if bridge.skew else ""
    arches = (f"span {bridge.span:g}, rise {bridge.rise:g}" if not bridge.piers else
              "spans " + ", ".join(f"{s:g} (rise {r:g}, {shape}{_own_ring(ring)})" for s, r, shape, ring in bridge.spans)
              + " on piers "
              + ", ".join(f"{p.width:g} wide, {p.height:g} high ({p.kind})" for p in bridge.piers))
    text = (f"{bridge.description + ' ' if bridge.description else ''}Built from a bridge description: "
            f"{arches}, ring {bridge.thickness:g} ({bridge.rings} ring(s) of "
            f"{bridge.voussoirs} voussoirs{crushing}), width {bridge.width:g}{skew}, backing to {bridge.backing:g}; fill {bridge.fill_depth:g} over the crown, "
            f"unit weight {bridge.fill_weight:g}, phi {bridge.phi:g} deg, lateral {bridge.lateral} "
            f"(K = {lateral_coefficient(bridge):.4g}), passive {bridge.passive:g} K_p "
            f"(K_p = {passive_coefficient(bridge.phi):.4g}){'' if passive else ' left out'}, "
            f"{'Boussinesq dispersal' if bridge.dispersal == 'boussinesq' else f'spread {bridge.spread:g} deg'}; {len(bridge.axles)} axle(s) of {bridge.force:g}, patch {bridge.patch:g}.")
    if bridge.source:
        text += " Sources: " + "; ".join(f"{k}: {v}" for k, v in bridge.source.items()) + "."
    spec = {"name": bridge.name, "description": text, "mu": bridge.mu,
            "unit_weight": bridge.masonry_weight * bridge.width, "thickness": bridge.width}
    if bridge.units:
        spec["units"] = dict(bridge.units)
    spec["loads"] = loads
    if passive:
        spec["restraints"] = restraints(bridge)
    blocks = deck_blocks(bridge)
    spec["blocks"] = blocks["voussoirs"] + blocks["backing"] + blocks["foundations"]
    if bridge.cohesion or bridge.ft:
        spec["joints"] = ring_bond(bridge)
    return spec


def ring_bond(bridge: Bridge) -> list:
    """The mortar between the rings: ``joints`` entries (:mod:`lamodel.io.jsonspec`) giving
    every ring interface the ring's ``cohesion`` and ``ft``; the radial joints stay dry."""
    bond = {key: value for key, value in (("cohesion", bridge.cohesion), ("ft", bridge.ft)) if value}
    parts = [(f"s{k + 1}", bridge.part(k)) for k in range(len(bridge.spans))] if bridge.piers else [("", bridge)]
    return [{"between": [p + voussoir_id(part, k, i), p + voussoir_id(part, k + 1, i)], **bond}
            for p, part in parts for k in range(part.rings - 1) for i in range(part.voussoirs)]


def _own_ring(ring: tuple) -> str:
    """A span's own ring values in the built file's description ('' when it has none)."""
    return "".join(f", ring {key} {value:g}" for key, value in ring)


def case_positions(bridge: Bridge) -> dict:
    """Load case name -> lead axle position, for the positions that load the ring."""
    return {case_name(x): x for x in positions(bridge) if live_loads(bridge, x, case_name(x))}
