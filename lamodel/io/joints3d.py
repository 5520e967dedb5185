"""Joints the geometric tolerance misses, told in one warning line.

A joint (interface) exists where facets of two blocks are parallel, opposite and overlap
within the tolerance (:mod:`lamodel.geometry.interfaces3d`). Facets that would meet within
a looser tolerance (``NEAR_JOINT_FACTORS[-1]`` times it) but do not within it are
**near-joints**: gaps of a file written in single precision, or of a mesh modelled by hand.
A missing joint changes the structure (a block rests on fewer contacts, or on none), so the
reader says how many there are and the least looser tolerance that joins them (the whole
geometry read again at it: a tolerance it cannot be read with is never offered), and
leaves the choice to the user (``--tolerance``): the tolerance stays the one given, and
the result folder records it.

A COMPAS assembly may store its own interfaces (its graph's edges): the block pairs its
author found in contact. Then the check compares with those instead: the pairs stored but
not joined here, and how many of them a looser tolerance joins.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..errors import InputError
from ..geometry.interfaces3d import find_interfaces
from ..search.tuning import NEAR_JOINT_FACTORS


def joined_pairs(ids, interfaces) -> set:
    """The block pairs (sorted id tuples) that share at least one interface."""
    return {tuple(sorted((ids[f.a], ids[f.b]))) for f in interfaces}


def _pair(p) -> str:
    return f"blocks '{p[0]}' and '{p[1]}'"


@dataclass
class JointProbe:
    """The joints of one geometry as read (``polys``, ``interfaces`` at the absolute
    tolerance ``tol``, ``rel_tol`` of its size), and ``reread(t)``: its interfaces with the
    whole geometry read again at the absolute tolerance t (InputError if it cannot be)."""

    ids: list
    is_support: np.ndarray
    polys: list
    interfaces: list
    rel_tol: float
    tol: float
    reread: Callable

    def near(self, factor) -> set:
        """Pairs whose facets meet within ``factor`` times the tolerance but are not joined:
        the polyhedra as read, only the contact search looser (cheap: run on every read)."""
        joined = [(f.a, f.b) for f in self.interfaces]   # left out: only the others are searched
        try:
            loose = find_interfaces(self.polys, self.is_support, self.tol * factor, skip=joined)
        except InputError:
            return set()
        return joined_pairs(self.ids, loose) - joined_pairs(self.ids, self.interfaces)

    def least(self, wanted, factors) -> tuple:
        """(factor, the pairs of ``wanted`` joined): the least factor whose reading joins
        the most of them (``(None, set())``: none joins any)."""
        best = (None, set())
        for factor in factors:
            try:
                got = wanted & joined_pairs(self.ids, self.reread(self.tol * factor))
            except InputError:   # e.g. a block degenerates at that tolerance
                continue
            if len(got) > len(best[1]):
                best = (factor, got)
            if got == wanted:
                break
        return best


def missed_joints(where, probe: JointProbe, stored=None, factors=NEAR_JOINT_FACTORS) -> str | None:
    """The warning line about joints the tolerance misses (None when there are none);
    ``stored``: a COMPAS file's own interface pairs (sorted id tuples), None when it has none."""
    rel = probe.rel_tol
    ours = joined_pairs(probe.ids, probe.interfaces)
    if stored is None:
        wanted = probe.near(factors[-1])
        if not wanted:
            return None
        head = (f"{where}: {len(wanted)} pair{'s' if len(wanted) > 1 else ''} of blocks (first: "
                f"{_pair(min(wanted))}) have facets parallel, opposite and overlapping within tolerance "
                f"{rel * factors[-1]:g} but not within {rel:g}: not joined; ")
    else:
        support = {i for i, s in zip(probe.ids, probe.is_support) if s}
        stored = {p for p in stored if set(p) <= set(probe.ids)}   # edges of the file's blocks only
        wanted = {p for p in stored if p not in ours and not set(p) <= support}
        if not wanted:
            return None
        head = (f"{where}: {len(wanted)} of the {len(stored)} block pairs the file's own interfaces join have no "
                f"joint at tolerance {rel:g} (first: {_pair(min(wanted))}); ")
    factor, found = probe.least(wanted, factors)
    if not found:
        return head + f"no tolerance up to {rel * factors[-1]:g} reads them joined"
    return head + f"--tolerance {rel * factor:g} joins {'them' if found == wanted else f'{len(found)} of them'}"


def warn_missed_joints(where, probe: JointProbe, stored=None):
    """:func:`missed_joints` as a warning (the command line prints it on stderr)."""
    message = missed_joints(where, probe, stored)
    if message:
        warnings.warn(message, stacklevel=3)
