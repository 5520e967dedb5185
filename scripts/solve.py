#!/usr/bin/env python3
"""Minimum collapse multiplier of a block assembly: python scripts/solve.py instances/wall33.dat

A thin shim over `lamodel solve` (lamodel.cli); see `python scripts/solve.py --help`.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

if __name__ == "__main__":
    try:
        from lamodel.cli import command, exit_now
        status = command("solve", prog="solve.py")
    except KeyboardInterrupt:  # Ctrl-C before lamodel's own handling is in place
        print("solve.py: interrupted", file=sys.stderr)
        sys.exit(130)
    exit_now(status)
