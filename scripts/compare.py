#!/usr/bin/env python
"""Compare two limit-analysis results: ``compare.py A B [--atol 1e-5]``.

A and B are result folders (summary.csv, blocks.csv, contacts.csv, runs.csv) or their
summary.csv. Exit status: 0 they agree within the tolerance, 1 they differ, 2 malformed or
missing input. The rules are documented in :mod:`lamodel.compare`.
"""
import sys

from lamodel.compare import main

if __name__ == "__main__":
    sys.exit(main())
