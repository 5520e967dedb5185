"""The fallback where the gap alternation stalls: the seed's chain from the stall."""
import numpy as np

from lamodel.geometry import seed_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.gap import GapSearch, fallback as fallback_module

from .helpers import collapse_violation


def _wall33(mu):
    return structure_from_json(seed_wall(6, mu=mu))


def test_the_alternation_stalls_on_a_mechanism_no_statics_holds_at_mu_09():
    """The cause, measured: on the seed's 33-block panel at mu = 0.9 the alternation stops
    with a positive gap (alpha_K - alpha) that rho does not shrink, the stalled mechanism's
    rows cannot all be held (its certification is infeasible), and the rows the stalled
    statics holds admit no mechanism."""
    e = GapSearch(_wall33(0.9))
    p = e.problem
    _, _, x0 = e.starts.associative()
    best, x = e.alternation.alternate(x0)
    assert best is None and e.record.best is None
    _, _, _, u, xi = p.mechanism(-p.mu * p.N_of(x))
    gap = float(p.gap_weights(xi) @ x[:p.nl])
    assert gap > 1e-4
    assert e.certifier.certify(u, xi, "stall") is None
    tight = p.slack(x) <= 1e-9 * max(1.0, np.abs(x).max())
    assert p.mechanism(-p.mu * p.N_of(x), tight)[0] == "unbounded"


def test_the_first_certificate_falls_back_to_the_chain_and_certifies(monkeypatch):
    """Without the fallback the first certificate (alternation and rescue) certifies
    nothing on that panel; with it, the chain from the stall certifies a state that passes
    the independent check, below the associative bound."""
    s = _wall33(0.9)
    e = GapSearch(s)
    _, a_assoc, x0 = e.starts.associative()
    monkeypatch.setattr("lamodel.search.gap.starts.fallback", lambda *args, **kwargs: None)
    e.starts.first_certificate(x0)
    assert e.record.best is None
    monkeypatch.setattr("lamodel.search.gap.starts.fallback", fallback_module.fallback)
    e = GapSearch(s)
    _, a_assoc, x0 = e.starts.associative()
    e.starts.first_certificate(x0)
    st = e.record.best
    assert st is not None and st.source.startswith("fixed-point")
    assert st.alpha <= a_assoc + 1e-9
    assert collapse_violation(s, e.record.best_user) <= 1e-7


def test_the_chain_stops_after_its_patience():
    """Once it certified, the chain stops after ``patience`` steps without improvement:
    fewer mechanism LPs than the same chain without patience."""
    s = _wall33(0.9)
    counts = []
    for patience in (None, 2):
        e = GapSearch(s)
        _, _, x0 = e.starts.associative()
        p = e.problem
        n = p.n_lps()
        st = e.starts.chain(-p.mu * p.N_of(x0), 40, patience=patience)
        assert st is not None
        counts.append(p.n_lps() - n)
    assert counts[1] < counts[0]


def test_the_chain_from_zero_cohesion_reaches_the_least_known_state_of_the_panel():
    """On the 33-block panel at mu = 0.9 the chains from the stall and from the
    associative statics end at 0.685714 (a six-block wedge); the chain from zero cohesion
    reaches 0.617364 (a twelve-block wedge), the multiplier the relaxed MPEC of Ferris &
    Tin-Loi certifies too (--method mpec): before the GA, so it does not depend on luck."""
    s = _wall33(0.9)
    e = GapSearch(s)
    _, _, x0 = e.starts.associative()
    e.starts.first_certificate(x0)
    assert e.record.best.alpha > 0.68
    st = e.starts.from_zero()
    assert st is not None and st.alpha <= 0.617365 and st.source.startswith("zero-cohesion")
    assert e.record.best is st or e.record.best.alpha <= st.alpha
    assert collapse_violation(s, e.record.best_user) <= 1e-7
    lps = e.n_lps()
    assert e.starts.from_zero() is st and e.n_lps() == lps  # once


def test_the_chain_from_zero_cohesion_stops_at_the_work_limit():
    """With its work already spent (the driver's bound without a time limit) the chain
    from zero cohesion solves no LP."""
    e = GapSearch(_wall33(0.9))
    _, _, x0 = e.starts.associative()
    e.starts.first_certificate(x0)
    e.starts.work_limit = e.n_lps()
    lps = e.n_lps()
    assert e.starts.from_zero() is None and e.n_lps() == lps


def test_a_chain_whose_cohesions_come_back_goes_on_averaged(monkeypatch):
    """A chain that meets the cohesions of an earlier step again would go round the cycle
    until its step limit; from the first repeat it goes on averaged instead,
    c <- (1 - w) c + w c_new. No planar structure measured cycles (see
    :mod:`lamodel.search.gap.fallback`), so the cycle is forced here: the cohesive
    statics' normal forces alternate between those of two statics."""
    from lamodel.search.tuning import CHAIN_RELAXATION as w
    e = GapSearch(_wall33(0.9))
    p = e.problem
    _, _, x0 = e.starts.associative()
    _, x_stall = e.alternation.alternate(x0)
    forced = [p.N_of(x0), p.N_of(x_stall)]
    calls, seen = [], []

    def alternating(xc):
        calls.append(None)
        return forced[len(calls) % 2]
    mechanism = p.mechanism

    def recording(c, allowed=None):
        seen.append(np.array(c))
        return mechanism(c, allowed)
    monkeypatch.setattr(p, "cohesive_N", alternating)
    monkeypatch.setattr(p, "mechanism", recording)
    e.starts.chain(np.zeros(p.nc), 6)
    assert e.starts.cycles == 1
    # c0, the two cohesions of the cycle, then averages: never a third repeat
    c_cycle = -p.mu * forced[1]  # the cohesions the third step gave (the repeat)
    assert np.allclose(seen[3], (1 - w) * seen[2] + w * c_cycle)
    assert len(seen) >= 6 and not any(np.allclose(seen[k], seen[1]) for k in range(3, 6))
