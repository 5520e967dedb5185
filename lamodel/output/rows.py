"""One solve as one row of a study's table: the certified multiplier, the associative
bound and how the mechanism's contacts move."""
from __future__ import annotations

import numpy as np

from .modes import SLIDING, TURNING, modes_from_flow


def mode_counts(structure, xi) -> dict:
    """Contacts that slip (modes sliding, sliding+hinging, crushing+sliding), rotate
    (hinging, sliding+hinging, crushing, crushing+sliding) and open, in a mechanism's flow xi."""
    modes = modes_from_flow(structure, xi)
    return {"n_sliding": sum(m in SLIDING for m in modes),
            "n_hinging": sum(m in TURNING for m in modes),
            "n_open": sum(m == "open" for m in modes)}


def interface_counts(structure, point_modes) -> dict:
    """In space, the same counts by interface from its points' modes: an interface slips
    where a point slips, rotates (rocks about a line or a point, the plane's hinge) where
    some of its points open and others stay in touch or crush, opens where all open."""
    interface = np.asarray(structure.point_interface)
    modes = np.asarray(point_modes, dtype=object)
    opening = np.bincount(interface, modes == "opening", structure.n_interfaces)
    touching = np.bincount(interface, modes != "opening", structure.n_interfaces)
    slipping = np.bincount(interface, np.isin(modes, ("sliding", "crushing+sliding")), structure.n_interfaces)
    crushing = np.bincount(interface, np.isin(modes, ("crushing", "crushing+sliding")), structure.n_interfaces)
    return {"n_sliding": int((slipping > 0).sum()),
            "n_hinging": int((((opening > 0) & (touching > 0)) | (crushing > 0)).sum()),
            "n_open": int(((opening > 0) & (touching == 0)).sum())}


def outcome_row(outcome) -> dict:
    """The certified multiplier (NaN if none), the associative bound and the mechanism's
    mode counts of a :class:`lamodel.search.driver.Outcome`."""
    best = outcome.best
    row = {"alpha_c": best.alpha if best is not None else np.nan,
           "alpha_associative": outcome.alpha_associative,
           "certified": best is not None}
    if best is not None and getattr(outcome.structure, "dimension", 2) == 3:
        row.update(interface_counts(outcome.structure, best.modes))
    elif best is not None:
        row.update(mode_counts(outcome.structure, best.xi))
    else:
        row.update(n_sliding=0, n_hinging=0, n_open=0)
    row.update(seconds=outcome.wall_time_s, status=outcome.status)
    return row
