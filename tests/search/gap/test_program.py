"""The formulation interface: both formulations implement it, and the search's steps run
on either without knowing which."""
import numpy as np
import pytest

from builders3d import box_on_ground
from lamodel.search.gap import FORMULATIONS, GapSearch, formulation_of
from lamodel.search.gap.problem import ScaledProblem
from lamodel.search.gap.problem3d import ConeProblem
from lamodel.search.gap.program import GapProgram
from lamodel.structure3d import Structure3D

from .helpers import wall
from lamodel.search.gap.phases import associative, stable
from lamodel.search.plan import first_certificate


@pytest.mark.parametrize("make", [lambda: wall(6), lambda: box_on_ground(1.0, 0.5, 2.0)])
def test_each_formulation_implements_the_interface(make):
    s = make()
    program = formulation_of(s)(s)
    assert isinstance(program, GapProgram)
    for name in [m for m in dir(GapProgram) if not m.startswith("_")]:
        assert hasattr(program, name), name


def test_the_formulation_follows_the_structure():
    assert formulation_of(wall(6)) is ScaledProblem
    assert formulation_of(box_on_ground(1.0, 1.0, 1.0)) is ConeProblem
    assert set(FORMULATIONS) >= {Structure3D}
    with pytest.raises(TypeError, match="no formulation"):
        formulation_of(object())


@pytest.mark.parametrize("make, alpha", [(lambda: wall(6), 0.6389818336884795),
                                         (lambda: box_on_ground(1.0, 0.5, 2.0, 0.6, (0.0, 1.0, 0.0)), 0.25)])
def test_the_same_steps_certify_in_the_plane_and_in_space(make, alpha):
    # associative bound, then the gap alternation, certification and descent of the first
    # certificate: the same objects on either formulation
    e = GapSearch(make())
    kind, a_assoc, x0 = associative(e)
    assert kind == "ok" and a_assoc >= alpha - 1e-9
    first_certificate(e, x0)
    assert e.record.best_user is not None
    assert e.record.best_user.alpha == pytest.approx(alpha, abs=1e-6)
    assert max(e.record.best_user.residual.values()) <= 1e-7
    assert stable(e)
    assert e.n_lps() > 0 and np.isfinite(e.record.alpha())
