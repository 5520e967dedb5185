"""The GA's evaluation of a genome, warm and pure (from a snapshot)."""
import pickle

import numpy as np

from lamodel.io import read
from lamodel.search.gap import GapSearch

from conftest import INSTANCES
from .helpers import collapse_violation, wall
from lamodel.search.gap.phases import associative
from lamodel.search.plan import first_certificate


def _after_first_certificate(name):
    e = GapSearch(read(INSTANCES / name))
    _, _, x0 = associative(e)
    e.fitness.associative(x0)
    e.alternation.alternate(x0)
    assert e.record.best is not None
    return e


def _evaluator(e):
    """An engine of its own on the same structure (as a GA worker has)."""
    return GapSearch(e.problem.user)


def test_evaluate_genome():
    s = wall(6)
    e = GapSearch(s)
    _, _, x0 = associative(e)
    e.fitness.associative(x0)
    first_certificate(e, x0)
    a0 = e.record.best.alpha
    f = e.fitness.evaluate(np.random.default_rng(0).normal(scale=0.3, size=s.n_contacts), chain_steps=3)
    assert np.isfinite(f) and f >= e.record.best.alpha - 1e-12   # fitness: a certified alpha
    assert e.record.best.alpha <= a0                               # the search keeps the least
    assert collapse_violation(s, e.record.best_user) <= 1e-7


def test_an_evaluation_does_not_depend_on_what_its_engine_did_before():
    e = _after_first_certificate("wall55.dat")
    snap = e.fitness.snapshot()
    rng = np.random.default_rng(3)
    genomes = [s * rng.standard_normal(e.problem.nc) for s in (0.1, 0.3, 1.0, 0.3, 1.0)]
    forward, backward = _evaluator(e), _evaluator(e)
    a = [forward.fitness.evaluate_pure(snap, g, 3, e.deadline) for g in genomes]
    b = [backward.fitness.evaluate_pure(snap, g, 3, e.deadline) for g in genomes[::-1]][::-1]
    for (alpha_a, states_a, lps_a, _), (alpha_b, states_b, lps_b, _) in zip(a, b):
        assert alpha_a == alpha_b and lps_a == lps_b
        assert [s.alpha for s in states_a] == [s.alpha for s in states_b]
        for sa, sb in zip(states_a, states_b):
            assert np.array_equal(sa.N, sb.N) and np.array_equal(sa.u, sb.u)
    # and the snapshot belongs to the search: evaluating leaves it untouched
    assert e.fitness.snapshot()["reference_N"].tobytes() == snap["reference_N"].tobytes()


def test_merged_states_are_recorded_as_if_found_here():
    e = _after_first_certificate("wall55.dat")
    before, lps = e.record.best.alpha, e.n_lps()
    seen = []
    e.record.on_state = seen.append
    alpha, states, n, learned = _evaluator(e).fitness.evaluate_pure(e.fitness.snapshot(), np.zeros(e.problem.nc), 3,
                                                                    e.deadline)
    e.fitness.merge(states, n, learned)
    assert e.n_lps() == lps + n and len(seen) == len(states)
    assert e.record.best.alpha <= min([before] + [s.alpha for s in states]) + 1e-15
    assert e.record.best_user is not None and max(e.record.best_user.residual.values()) <= 1e-7


def test_a_snapshot_pickles_and_an_evaluation_from_its_copy_is_the_same():
    """What a Dask task receives: the snapshot through pickle, bases as plain arrays."""
    e = _after_first_certificate("wall33.dat")
    snap = e.fitness.snapshot()
    copy = pickle.loads(pickle.dumps(snap))
    genome = 0.3 * np.random.default_rng(0).standard_normal(e.problem.nc)
    a = _evaluator(e).fitness.evaluate_pure(snap, genome, 3, e.deadline)
    b = _evaluator(e).fitness.evaluate_pure(copy, genome, 3, e.deadline)
    assert a[0] == b[0] and a[2] == b[2] and [s.alpha for s in a[1]] == [s.alpha for s in b[1]]
