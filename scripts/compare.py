#!/usr/bin/env python3
"""Compare two limit-analysis results: python scripts/compare.py A B [--atol 1e-5]

A thin shim over `lamodel compare` (lamodel.cli); see `python scripts/compare.py --help`.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

if __name__ == "__main__":
    try:
        from lamodel.cli import command, exit_now
        status = command("compare", prog="compare.py")
    except KeyboardInterrupt:  # Ctrl-C before lamodel's own handling is in place
        print("compare.py: interrupted", file=sys.stderr)
        sys.exit(130)
    exit_now(status)
