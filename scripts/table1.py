#!/usr/bin/env python3
"""The seed's Table 1 with lamodel's certified alpha: python scripts/table1.py [--out results/table1.csv]

A thin shim over `lamodel table1` (lamodel.cli); see `python scripts/table1.py --help`.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

if __name__ == "__main__":
    try:
        from lamodel.cli import command, exit_now
        status = command("table1", prog="table1.py")
    except KeyboardInterrupt:  # Ctrl-C before lamodel's own handling is in place
        print("table1.py: interrupted", file=sys.stderr)
        sys.exit(130)
    exit_now(status)
