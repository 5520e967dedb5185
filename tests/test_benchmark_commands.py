"""Every benchmark script is a command the docs quote: ``--help`` says what it measures and
how to run it, and an unknown option is refused in one line (exit 2) before any
measurement starts (not taken for a case name, not a traceback)."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = [p for p in sorted((ROOT / "benchmarks").glob("*.py")) if "__main__" in p.read_text(encoding="utf-8")]


def _run(script, *args):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, str(script), *args], capture_output=True, text=True, timeout=120,
                          cwd=ROOT, env=env)


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_benchmark_scripts_answer_help_and_refuse_an_unknown_option(script):
    shown = _run(script, "--help")
    assert shown.returncode == 0 and shown.stdout.startswith("usage:"), shown.stdout + shown.stderr
    refused = _run(script, "--no-such-option")
    assert refused.returncode == 2, refused.stdout + refused.stderr
    last = refused.stderr.strip().splitlines()[-1]
    assert last.startswith(f"{script.name}: error:") and "Traceback" not in refused.stderr, refused.stderr
    assert not refused.stdout.strip(), f"{script.name} measured something before refusing: {refused.stdout[:200]}"
