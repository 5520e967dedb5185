"""COMPAS sample assemblies: blocks, supports, interfaces and area found by lamodel at two
tolerances, and whether the structure then carries its dead load (a dead-load mechanism of
lamodel.search.unstable, or none); beside COMPAS's own interfaces (when the file stores
them: their number, and how many of those block pairs lamodel finds, and their total area).

    PYTHONPATH=. python benchmarks/compas_samples.py FOLDER

Files without ``is_support`` flags get as supports the blocks whose lowest point is at the
assembly's lowest level (or, when that is every block, the lowest block).
"""
import argparse
import json
from pathlib import Path

import warnings

import numpy as np

from lamodel.errors import InputError
from lamodel.io.assemblies import compas_spec, read_compas
from lamodel.output.tables3d import contacts_summary
from lamodel.search.tuning import SUPPORT_LEVEL
from lamodel.search.unstable import dead_load_mechanism3d

TOLERANCES = (1e-6, 1e-4)


def _their_area(nodes):
    """Total area of the interface polygons the file stores (Newell's formula)."""
    total = 0.0
    for e in nodes["edge"].values():
        for v in e.values():
            for it in v.get("interfaces") or []:
                p = np.asarray(it["data"]["points"], dtype=float)
                total += 0.5 * np.linalg.norm(np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0))
    return total


def _supports(data):
    spec = compas_spec(data)
    low = np.array([np.min(np.asarray(b["vertices"])[:, 2]) for b in spec["blocks"]])
    size = np.linalg.norm(np.ptp(np.vstack([b["vertices"] for b in spec["blocks"]]), axis=0))
    below = low <= low.min() + SUPPORT_LEVEL * size   # the level the "no block is a support" error counts
    if below.all():
        cz = [np.mean(np.asarray(b["vertices"])[:, 2]) for b in spec["blocks"]]
        below = np.arange(len(low)) == int(np.argmin(cz))
    return [b["id"] for b, s in zip(spec["blocks"], below) if s]


def main(folder):
    head = "".join(f" {'ifaces@' + format(t, '.0e'):>12} {'area':>8} {'matched':>7} {'stands':>6}" for t in TOLERANCES)
    print(f"{'sample':<15} {'blocks':>6} {'supports':>8}{head} {'COMPAS':>7} {'area':>8}  note")
    for path in sorted(Path(folder).glob("*.json")):
        data = json.loads(path.read_text())
        nodes = data["data"]["graph"]["data"]
        theirs = {tuple(sorted((a, b))) for a, e in nodes["edge"].items() for b, v in e.items() if v.get("interfaces")}
        options = {} if any(n.get("is_support") for n in nodes["node"].values()) else {"supports": _supports(data)}
        cells, sizes, note = "", None, ""
        for tol in TOLERANCES:
            try:
                with warnings.catch_warnings():   # the missed joints are the columns here
                    warnings.simplefilter("ignore")
                    s = read_compas(path, tolerance=tol, **options)
            except InputError as exc:
                cells += f" {'-':>12} {'-':>8} {'-':>7} {'-':>6}"
                note = note or str(exc).split(": ", 1)[1][:60]
                continue
            c = contacts_summary(s)
            sizes = sizes or (c["blocks"], c["supports"])
            ours = {tuple(sorted(p)) for p in zip(s.iface_a, s.iface_b)}
            matched = len(ours & theirs) if theirs else "-"
            stands = "yes" if dead_load_mechanism3d(s) is None else "no"
            cells += f" {c['interfaces']:>12} {c['area']:>8.4f} {matched:>7} {stands:>6}"
        blocks, supports = sizes or ("-", "-")
        area = f"{_their_area(nodes):.4f}" if theirs else "-"
        print(f"{path.stem:<15} {blocks:>6} {supports:>8}{cells} {len(theirs) or '-':>7} {area:>8}  {note}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folder", nargs="?", default=".", help="the folder of the COMPAS samples (default: here)")
    main(ap.parse_args().folder)
