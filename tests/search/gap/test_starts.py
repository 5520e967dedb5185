"""The starts of the gap alternation."""
import numpy as np

from lamodel.search.gap import GapSearch
from lamodel.search.tuning import RHO_CONTS

from .helpers import bond, collapse_violation


def test_continuation_starts_certify_and_give_the_lps_their_bases_back():
    """The continuation starts (rho raised from a low value) leave every LP with the basis
    it had (the GA after them starts where it would without them), and return certified
    states that pass the independent check, never above the associative bound."""
    s = bond(6, width=8)
    e = GapSearch(s)
    _, a_assoc, x0 = e.starts.associative()
    e.starts.first_certificate(x0)
    e.starts.stable()
    lps = e.problem.lps
    before = {name: lp.portable_basis() for name, lp in lps.items()}
    e.starts.continuations(x0)
    for name, lp in lps.items():
        after = lp.portable_basis()
        if before[name] is None:
            assert after is None
        else:
            assert all(np.array_equal(b, a) for b, a in zip(before[name], after))
    found = [e.starts.continuation(x0, rhos) for rhos in RHO_CONTS]
    assert any(st is not None for st in found)
    for st in found:
        if st is not None:
            assert st.alpha <= a_assoc + 1e-9
            assert collapse_violation(s, e.problem.to_user(st)) <= 1e-7


def test_near_active_rows_certify_a_stalled_statics():
    """From the last statics of an alternation, the mechanisms on its nearly active rows
    certify a state no lower than what the whole search can reach, and a valid one."""
    s = bond(4, width=6)
    e = GapSearch(s)
    _, a_assoc, x0 = e.starts.associative()
    _, x = e.alternation.alternate(x0)
    st = e.starts.certify_near(x, "near")
    assert st is not None and st.alpha <= a_assoc + 1e-9
    assert collapse_violation(s, e.problem.to_user(st)) <= 1e-7


def test_a_ladder_rho_by_rho_takes_the_steps_of_the_whole_ladder():
    """The continuation runs its penalty ladder one rho at a time (so that the work bound
    can end it between two): the same LPs and the same states as the whole ladder at once."""
    s = bond(6, width=8)
    runs = []
    for by_rho in (False, True):
        e = GapSearch(s)
        _, _, x0 = e.starts.associative()
        if by_rho:
            best, x = e.starts._ladder(x0, RHO_CONTS[0])
        else:
            best, x = e.alternation.alternate(x0, rhos=RHO_CONTS[0], source="continuation")
        runs.append((e.n_lps(), None if best is None else best.alpha, float(x[-1])))
    assert runs[0] == runs[1]


def test_the_continuations_stop_at_the_work_bound():
    """With the LP work already at the driver's bound the continuation starts (and the chain
    from zero cohesion) solve no LP; the work counted is that of the LPs solved."""
    e = GapSearch(bond(6, width=8))
    _, _, x0 = e.starts.associative()
    e.starts.first_certificate(x0)
    work = e.starts.work()
    assert work > 0 and work == sum(lp.work for lp in e.problem.lps.values())
    e.starts.work_bound = work
    lps = e.n_lps()
    e.starts.continuations(x0)
    assert e.n_lps() == lps
