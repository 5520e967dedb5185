"""Shared fixtures: small structures built from polygons, and the repository paths."""
import os
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
INSTANCES = ROOT / "instances"


def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def stack_spec(n=2, width=1.0, height=1.0, mu=0.6, live=(1.0, 0.0)):
    """n equal blocks stacked on the ground: overturning of the whole stack about its
    toe needs alpha = (width/2) / (n height / 2) = width / (n height)."""
    blocks = [{"id": "ground", "vertices": rect(-2, -1, 2, 0), "support": True}]
    for i in range(n):
        blocks.append({"id": f"b{i + 1}", "vertices": rect(-width / 2, i * height, width / 2, (i + 1) * height)})
    return {"name": f"stack{n}", "mu": mu, "live_load": list(live), "blocks": blocks}


@pytest.fixture
def stack():
    from lamodel.io.jsonspec import structure_from_json
    return structure_from_json(stack_spec())


@pytest.fixture(scope="session")
def wall33():
    from lamodel.io.datfile import read_dat
    return read_dat(INSTANCES / "wall33.dat")


def run_script(script, *args, cwd=None, timeout=600):
    """Run one of scripts/ as a user would, with this interpreter."""
    import subprocess
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, str(ROOT / "scripts" / script), *map(str, args)], capture_output=True,
                          text=True, cwd=cwd or ROOT, env=env, timeout=timeout)


@pytest.fixture(scope="session")
def dask_cluster():
    """A real dask.distributed cluster on the loopback: a scheduler and 2 worker processes
    (one thread each) that import this checkout's lamodel. A task whose worker dies is
    rerun once elsewhere (allowed-failures 1), as lamodel's local pools do."""
    import dask
    from distributed import LocalCluster
    with dask.config.set({"distributed.scheduler.allowed-failures": 1}):
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=None, env={"PYTHONPATH": str(ROOT)})
    try:
        yield cluster
    finally:
        cluster.close()


def bound_parts(s):
    """(s, its lower-bound LPs, its exact data) with the opening motion in place."""
    if getattr(s, "dimension", 2) == 3:
        from lamodel.bound.space import BoundLPs3D as LPs, ExactData3D as Exact
    else:
        from lamodel.bound.exact import ExactData as Exact
        from lamodel.bound.lps import BoundLPs as LPs
    lps, ex = LPs(s), Exact(s)
    assert ex.use_opening_motion(lps.opening_motion())
    return s, lps, ex


def assert_same_structure(a, b, exact=True):
    """Two planar structures hold the same blocks, contacts and numbers (a round trip)."""
    assert a.blocks == b.blocks and a.supports == b.supports and a.contacts == b.contacts
    assert a.block_a == b.block_a and a.block_b == b.block_b
    for name in ("centroid", "dead", "live", "centre", "normal", "d", "mu"):
        same = np.array_equal if exact else np.allclose
        assert same(getattr(a, name), getattr(b, name)), name


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    if report.failed:
        item.lamodel_failed = True


@pytest.fixture(autouse=True)
def _no_process_outlives_a_failed_test(request):
    """The processes a test started (and theirs) are killed when it fails or times out (the
    per-test timeout of setup.cfg): a hung ``lamodel solve`` never outlives its test. Those
    of longer-lived fixtures (a Dask cluster) were there before the test and are spared."""
    import psutil
    me = psutil.Process()
    before = {p.pid for p in me.children(recursive=True)}
    yield
    if getattr(request.node, "lamodel_failed", False):
        left = [p for p in me.children(recursive=True) if p.pid not in before]
        for p in left:
            try:
                p.kill()
            except psutil.Error:
                pass
        psutil.wait_procs(left, timeout=5)


def descendants(pid) -> set:
    """Every process below ``pid`` (psutil when installed, else /proc)."""
    try:
        import psutil
        return {p.pid for p in psutil.Process(pid).children(recursive=True)}
    except ImportError:
        pass
    except Exception:  # the process is gone
        return set()
    found, todo = set(), [pid]
    while todo:
        p = todo.pop()
        try:
            kids = [int(k) for t in os.listdir(f"/proc/{p}/task")
                    for k in Path(f"/proc/{p}/task/{t}/children").read_text().split()]
        except OSError:
            continue
        found.update(kids)
        todo.extend(kids)
    return found
