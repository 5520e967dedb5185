#!/usr/bin/env python3
"""Write the .dat instance of a JSON geometry: python scripts/build_instance.py x.json -o x.dat

A thin shim over `lamodel build` (lamodel.cli); see `python scripts/build_instance.py --help`.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

if __name__ == "__main__":
    try:
        from lamodel.cli import command, exit_now
        status = command("build", prog="build_instance.py")
    except KeyboardInterrupt:  # Ctrl-C before lamodel's own handling is in place
        print("build_instance.py: interrupted", file=sys.stderr)
        sys.exit(130)
    exit_now(status)
