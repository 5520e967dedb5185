"""The adequacy factor of a bridge against the load's position: the certified collapse
multiplier of the axle group at each lead-axle position (each a load case of the built
structure), the least governing, with its mechanism in the terms of the arch-bridge tests
(how many hinges, how many of them crush, how many joints slide); as a table and a plot."""
from __future__ import annotations

from pathlib import Path

import pandas as pd

from ..io.jsonspec import structure_from_spec
from ..output.modes import SLIDING, TURNING, modes_from_flow
from ..search.options import SolveOptions
from ..studies import load_case_study
from .build import bridge_spec, case_positions
from .description import Bridge

#: Columns of :func:`adequacy_study`.
COLUMNS = ("position", "adequacy", "collapse_load", "certified", "status", "governing", "mechanism", "seconds")


def structure_of(bridge: Bridge, passive: bool = True):
    """The solver's Structure of a bridge (its load positions as load cases)."""
    return structure_from_spec(bridge_spec(bridge, passive), f"bridge '{bridge.name}'")


def adequacy_study(bridge: Bridge, options: SolveOptions | None = None, passive: bool = True,
                   progress=None) -> pd.DataFrame:
    """One row per position: the adequacy factor (alpha_c of the axle group), the collapse
    load per axle (alpha_c times the axle's force), whether certified; the least governs."""
    return adequacy_run(bridge, options, passive, progress)[0]


def adequacy_run(bridge: Bridge, options: SolveOptions | None = None, passive: bool = True, progress=None):
    """:func:`adequacy_study`'s table, and the outcomes by position (the solves' own)."""
    df, outcomes = load_case_study(structure_of(bridge, passive), options, progress)
    where = case_positions(bridge)
    out = pd.DataFrame({"position": df["case"].map(where), "adequacy": df["alpha_c"],
                        "collapse_load": df["alpha_c"] * bridge.force, "certified": df["certified"],
                        "status": df["status"], "governing": df["governing"],
                        "mechanism": [mechanism(outcomes.get(c)) for c in df["case"]], "seconds": df["seconds"]})
    return out[list(COLUMNS)], {where[c]: o for c, o in outcomes.items()}


def mechanism(outcome) -> str:
    """The collapse mechanism as the bridge tests report it: hinges (joints that turn),
    how many of them crush, joints that slide — the ring's, backing's and abutments'
    joints, not the fill's restraints; "-" without a certified mechanism."""
    if outcome is None or outcome.best is None:
        return "-"
    s = outcome.structure
    joints = modes_from_flow(s, outcome.best.xi)[:s.n_contacts - s.restraints]
    hinges = sum(m in TURNING for m in joints)
    crushing = sum("crushing" in m for m in joints)
    sliding = sum(m in SLIDING for m in joints)
    words = [f"{hinges} hinge{'s' if hinges != 1 else ''}"]
    if crushing and crushing == hinges:   # a finite fc: every hinge turns about a crushed zone
        words[0] += " (all crushing)"
    elif crushing:
        words.append(f"{crushing} crushing")
    if sliding:
        words.append(f"{sliding} sliding")
    return ", ".join(words)


def write_adequacy(bridge: Bridge, table: pd.DataFrame, folder, outcomes=None, passive: bool = True) -> list:
    """adequacy.csv and adequacy.png (the factor against the position) in ``folder``; with
    the ``outcomes`` by position (:func:`adequacy_run`), mechanism.png: the governing
    position's collapse mechanism drawn with the fill (:func:`.picture.plot_governing`)."""
    from ..io.files import write_csv
    from ..output.figures import save_open_figure
    folder = Path(folder)
    write_csv(table, folder / "adequacy.csv")  # atomically: a reader never sees half a table
    files = [str(folder / "adequacy.csv"), save_open_figure(adequacy_figure(bridge, table), folder / "adequacy.png")]
    governing = table.loc[table["governing"].astype(bool), "position"]
    outcome = None if outcomes is None or governing.empty else outcomes.get(governing.iloc[0])
    if outcome is not None and outcome.best is not None:
        from .picture import plot_governing
        files.append(plot_governing(bridge, outcome, folder / "mechanism.png", governing.iloc[0], passive))
    return files


def adequacy_figure(bridge: Bridge, table: pd.DataFrame):
    """A matplotlib figure: the adequacy factor against the lead axle's position, the
    governing one marked."""
    from ..output.figures import rolling_figure
    fig = rolling_figure(table.rename(columns={"adequacy": "alpha_c"}),
                         f"{bridge.name}: adequacy factor against the load position", bridge.units.get("length", ""))
    fig.axes[0].set_ylabel("adequacy factor (collapse multiplier)")
    return fig
