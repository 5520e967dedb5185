#!/usr/bin/env python3
"""Build a limit-analysis instance (.dat) from the JSON geometry of a block assembly.

    python scripts/build_instance.py instances/wall33.json -o instances/wall33.dat

Contacts, centroids and loads are derived from the polygons by lamodel.geometry; the
.dat file is written by lamodel.datfile. Bad input is reported as one line on stderr
(exit status 2).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("geometry", help="JSON geometry file (see lamodel.geometry)")
    parser.add_argument("-o", "--output", help="output .dat file (default: next to the JSON, with .dat)")
    parser.add_argument("--name", help="instance name (default: the JSON 'name' or the file stem)")
    args = parser.parse_args(argv)

    from lamodel.errors import InputError
    from lamodel.geometry import structure_from_json

    output = Path(args.output) if args.output else Path(args.geometry).with_suffix(".dat")
    try:
        structure = structure_from_json(args.geometry, name=args.name)
        from lamodel.datfile import write_dat  # lazily: the geometry checks need no .dat support
        write_dat(structure, output)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(f"{output}: {structure.n_blocks} blocks, {len(structure.supports)} supports, "
          f"{structure.n_contacts} contacts")
    return 0


if __name__ == "__main__":
    sys.exit(main())
