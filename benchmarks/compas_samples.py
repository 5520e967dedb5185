"""COMPAS sample assemblies: blocks, supports, interfaces and area found by lamodel, beside
COMPAS's own interface count (when the file stores interfaces).

    PYTHONPATH=. python benchmarks/compas_samples.py FOLDER

Files without ``is_support`` flags get as supports the blocks whose lowest point is at the
assembly's lowest level (or, when that is every block, the lowest block). The tolerance is
the first of 1e-6, 1e-4 (relative to the size) that reads the file.
"""
import json
import sys
from pathlib import Path

import numpy as np

from lamodel.errors import InputError
from lamodel.io.assemblies import compas_spec, read_compas
from lamodel.output.tables3d import contacts_summary


def main(folder):
    print(f"{'sample':<20} {'blocks':>6} {'supports':>8} {'interfaces':>10} {'area':>9} {'COMPAS':>7} {'tol':>6}  note")
    for path in sorted(Path(folder).glob("*.json")):
        data = json.loads(path.read_text())
        nodes = data["data"]["graph"]["data"]
        theirs = sum(len(v.get("interfaces") or []) for e in nodes["edge"].values() for v in e.values())
        options = {}
        if not any(n.get("is_support") for n in nodes["node"].values()):
            spec = compas_spec(data)
            low = np.array([np.min(np.asarray(b["vertices"])[:, 2]) for b in spec["blocks"]])
            size = np.ptp(np.vstack([b["vertices"] for b in spec["blocks"]]), axis=0).max()
            below = low <= low.min() + 1e-3 * size
            if below.all():
                cz = [np.mean(np.asarray(b["vertices"])[:, 2]) for b in spec["blocks"]]
                below = np.arange(len(low)) == int(np.argmin(cz))
            options["supports"] = [b["id"] for b, s in zip(spec["blocks"], below) if s]
        note, row = "", None
        for tol in (1e-6, 1e-4):
            try:
                row = contacts_summary(read_compas(path, tolerance=tol, **options))
                break
            except InputError as exc:
                note = str(exc).split(": ", 1)[1][:70]
        if row is None:
            print(f"{path.stem:<20} {'-':>6} {'-':>8} {'-':>10} {'-':>9} {theirs or '-':>7} {'-':>6}  {note}")
            continue
        print(f"{path.stem:<20} {row['blocks']:>6} {row['supports']:>8} {row['interfaces']:>10} {row['area']:>9.4f} "
              f"{theirs or '-':>7} {tol:>6.0e}  {note if tol > 1e-6 else ''}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else ".")
