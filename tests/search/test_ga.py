"""The GA (pymoo) the search drives."""
import numpy as np

from lamodel.search.ga import genetic_search


def test_ga_is_deterministic_and_minimises():
    target = np.linspace(0.2, 1.8, 7)

    def sphere(g):
        return float(((g - target) ** 2).sum())

    a = genetic_search(sphere, 7, pop_size=20, generations=30, seed=5)
    b = genetic_search(sphere, 7, pop_size=20, generations=30, seed=5)
    c = genetic_search(sphere, 7, pop_size=20, generations=30, seed=6)
    assert np.array_equal(a[0], b[0]) and a[1] == b[1]
    assert not np.array_equal(a[0], c[0])
    assert a[1] < 0.05  # far below a random genome (~1.5 on average)
