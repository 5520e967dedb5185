"""Eq. (1)-(5) as matrices: the statics in friction-cone generator form and the
fictitious cohesive LP's columns write the same yield rows."""
import numpy as np

from lamodel.formulation.matrices import (cohesive_matrix, flow_matrix, generator_matrix, held_generators,
                                          yield_matrix)
from lamodel.formulation.scaling import scaled, scales
from lamodel.geometry import seed_wall
from lamodel.io.jsonspec import structure_from_json


def _wall33():
    return structure_from_json(seed_wall(6))


def test_generator_form_matches_yield_rows():
    """Held yield row <-> two lambdas at zero; every lambda >= 0 is admissible (eq. 4)."""
    s = _wall33()
    T = generator_matrix(s)
    S = -(yield_matrix(s) @ T).toarray()
    assert (S >= 0).all()
    assert ((S > 0).sum(axis=1) == 2).all()
    # the two generators of each row's slack are the ones holding it sets to zero
    assert np.array_equal(np.sort(np.nonzero(S)[1].reshape(-1, 2), axis=1), np.sort(held_generators(s.n_contacts),
                                                                                     axis=1))
    rng = np.random.default_rng(1)
    lam = rng.exponential(size=T.shape[1])
    assert (yield_matrix(s) @ (T @ lam) <= 1e-12).all()


def test_cohesive_columns_flow_one_row_each():
    """In the cohesive LP's columns (n1, n2, V) every flow row of the fictitious system has
    one coefficient: a bound on one column."""
    s = _wall33()
    Gc = (flow_matrix(s) @ cohesive_matrix(s)).tocsr()
    Gc.eliminate_zeros()
    assert np.all(np.diff(Gc.indptr) == 1)


def test_scaled_structure_has_unit_size_and_unit_mean_dead_load():
    s = _wall33()
    F, L = scales(s)
    t = scaled(s, F, L)
    assert abs(t.size() - 1.0) < 1e-12
    assert abs(np.hypot(t.dead[:, 0], t.dead[:, 1]).mean() - 1.0) < 1e-12
    assert np.array_equal(t.mu, s.mu)
