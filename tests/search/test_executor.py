"""The executor: the same results in this process, in local processes and on a real Dask
cluster (a LocalCluster on 127.0.0.1); per-worker caching; retries when a worker dies."""
import os
import signal
import sys
import threading
import time
import uuid

import cloudpickle
import numpy as np
import pytest

from conftest import INSTANCES
from lamodel.search.executor import EVENT_TOPIC, Executor, run_tasks, task_seeds

# the Dask workers import lamodel from PYTHONPATH, not this test module: send it by value
cloudpickle.register_pickle_by_value(sys.modules[__name__])


# ---------------------------------------------------------------- task functions
def _draw(ctx, item, seed):
    return item, np.random.default_rng(seed).integers(0, 2**62, size=3).tolist()


def _built_here(shared):
    return os.getpid(), uuid.uuid4().hex  # a fresh token each time the context is built


def _report_context(ctx, item, seed):
    return ctx


def _die_once(folder, item, seed):
    """Item 2 kills its worker process the first time it runs (a crash, not an exception)."""
    marker = os.path.join(folder, f"died-{item}")
    if item == 2 and not os.path.exists(marker):
        open(marker, "w").close()
        os._exit(1)
    time.sleep(0.2)
    return item * 10


def _fail_on_one(ctx, item, seed):
    if item == 1:
        raise ValueError("item 1 is bad")
    return item


# ---------------------------------------------------------------- local
@pytest.mark.slow
def test_seeds_come_from_one_seed_sequence_whatever_the_workers():
    items = list(range(6))
    here = run_tasks(_draw, items, seed=7, workers=1)
    pool = run_tasks(_draw, items, seed=7, workers=2)
    assert [r.value for r in here] == [r.value for r in pool]
    assert all(r.ok and r.attempts == 1 for r in here + pool)
    # task i's seed is child i of SeedSequence(7): its draw, not a worker's
    expected = [np.random.default_rng(s).integers(0, 2**62, size=3).tolist() for s in task_seeds(7, 6)]
    assert [r.value[1] for r in pool] == expected
    assert len({tuple(v) for v in expected}) == 6
    assert run_tasks(_draw, items, seed=8, workers=1)[0].value != here[0].value


@pytest.mark.slow
def test_context_is_built_once_per_worker_process():
    results = run_tasks(_report_context, range(8), shared="a structure", prepare=_built_here, workers=2)
    tokens = {}
    for r in results:
        pid, token = r.value
        tokens.setdefault(pid, set()).add(token)
        assert r.worker == f"local pid {pid}"
    assert tokens and all(len(t) == 1 for t in tokens.values())
    assert os.getpid() not in tokens  # the work ran in the worker processes


@pytest.mark.slow
def test_a_local_worker_that_dies_is_recorded_and_its_task_retried(tmp_path):
    results = run_tasks(_die_once, range(5), shared=str(tmp_path), workers=2)
    assert [r.value for r in results] == [0, 10, 20, 30, 40]
    assert all(r.ok for r in results)
    assert results[2].attempts == 2 and "died" in results[2].lost[0]
    assert (tmp_path / "died-2").exists()


def test_a_task_failing_every_attempt_is_reported_and_the_rest_goes_on():
    results = run_tasks(_fail_on_one, range(3), workers=1, retries=1)
    assert [r.value for r in results] == [0, None, 2]
    assert results[1].error == "ValueError: item 1 is bad" and results[1].attempts == 2
    assert results[0].ok and results[0].attempts == 1


def test_workers_or_scheduler_not_both():
    from lamodel.errors import InputError
    with pytest.raises(InputError, match="not both"):
        Executor(workers=2, scheduler="tcp://127.0.0.1:1")
    with pytest.raises(InputError, match="expected an address tcp://HOST:PORT"):
        Executor(scheduler="127.0.0.1")


# ---------------------------------------------------------------- Dask
@pytest.mark.slow
def test_dask_gives_the_serial_alpha_on_wall33(dask_cluster):
    """wall33 (starts=0) solved as a task on the cluster: the alpha of the serial solve
    with the task's GA seed, to the last bit."""
    from lamodel.io import read
    from lamodel.parametric import study_from_dict, solve_variant
    from lamodel.search.driver import SolveOptions, solve
    structure = read(INSTANCES / "wall33.json")
    study = study_from_dict({"options": {"starts": 0}, "seed": 3}, structure)
    with Executor(scheduler=dask_cluster.scheduler_address) as ex:
        [res] = ex.map(solve_variant, study.variants(), shared=study, seed=study.seed)
    assert res.ok and res.attempts == 1 and res.worker in dask_cluster.scheduler_info["workers"]
    serial = solve(structure, SolveOptions(starts=0, seed=res.value["ga_seed"]))
    assert res.value["certified"] and serial.certified
    assert res.value["alpha"] == serial.best.alpha
    assert res.value["alpha"] == pytest.approx(0.638982, abs=1e-6)  # Table 1


@pytest.mark.slow
def test_dask_map_equals_local_map(dask_cluster):
    items = list(range(5))
    local = run_tasks(_draw, items, seed=11, workers=2)
    on_dask = run_tasks(_draw, items, seed=11, scheduler=dask_cluster.scheduler_address)
    assert [r.value for r in local] == [r.value for r in on_dask]
    assert {r.worker for r in on_dask} <= set(dask_cluster.scheduler_info["workers"])


def _kill_a_busy_worker(client, seen, killed):
    """Wait for a task started after the first ``seen`` events, then SIGKILL its worker."""
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        starts = [m for _, m in client.get_events(EVENT_TOPIC) if isinstance(m, dict)]
        if len(starts) > seen:
            victim = starts[-1]["worker"]
            time.sleep(0.1)  # mid-task: a wall33 solve takes a second or more
            pid = client.run(os.getpid, workers=[victim])[victim]
            os.kill(pid, signal.SIGKILL)
            killed.append(victim)
            return
        time.sleep(0.02)


@pytest.mark.slow
def test_a_worker_killed_mid_study_the_study_completes_with_the_retry_recorded(dask_cluster):
    from lamodel.io import read
    from lamodel.parametric import run_study, study_from_dict
    structure = read(INSTANCES / "wall33.json")
    study = study_from_dict({"options": {"starts": 0}, "seed": 5, "vary": {"mu": [0.4, 0.5, 0.65, 0.8, 0.9]}},
                            structure)
    with Executor(scheduler=dask_cluster.scheduler_address) as ex:
        ex.client.wait_for_workers(2)
        seen = len(ex.client.get_events(EVENT_TOPIC))  # earlier tests' tasks
        killed = []
        killer = threading.Thread(target=_kill_a_busy_worker, args=(ex.client, seen, killed), daemon=True)
        killer.start()
        df = run_study(study, executor=ex, progress=False)
        killer.join(timeout=60)
    assert killed, "no worker was killed"
    assert len(df) == 5 and df["certified"].all() and (df["error"] == "").all()
    retried = df[df["attempts"] == 2]
    assert len(retried) >= 1  # the task on the killed worker ran again, elsewhere
    assert (retried["worker"] != killed[0]).all()
    assert (df["attempts"] <= 2).all()
    # the science is that of a serial run
    serial = run_study(study, workers=1, progress=False)
    cols = ["mu", "alpha", "certified", "alpha_associative", "n_sliding", "n_hinging", "n_open", "ga_seed"]
    assert df[cols].equals(serial[cols])
