"""The fallback where the gap alternation stalls: the seed's chain from the stall."""
import numpy as np

from lamodel.geometry import seed_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.search.gap import GapSearch
from lamodel.search.gap.chains import FixedPoint
from lamodel.search.gap.dilatancy import Dilatancy

from .helpers import collapse_violation
from lamodel.search.gap.chains import FromZero
from lamodel.search.gap.phases import associative
from lamodel.search.plan import first_certificate


def _wall33(mu):
    return structure_from_json(seed_wall(6, mu=mu))


def test_the_alternation_stalls_on_a_mechanism_no_statics_holds_at_mu_09():
    """The cause, measured: on the seed's 33-block panel at mu = 0.9 the alternation stops
    with a positive gap (alpha_K - alpha) that rho does not shrink, the stalled mechanism's
    rows cannot all be held (its certification is infeasible), and the rows the stalled
    statics holds admit no mechanism."""
    e = GapSearch(_wall33(0.9))
    p = e.problem
    _, _, x0 = associative(e)
    best, x = e.alternation.alternate(x0)
    assert best is None and e.record.best is None
    _, _, _, u, xi = p.mechanism(-p.mu * p.N_of(x))
    gap = float(p.gap_weights(xi) @ x[:p.nl])
    assert gap > 1e-4
    assert e.certifier.certify(u, xi, "stall") is None
    tight = p.slack(x) <= 1e-9 * max(1.0, np.abs(x).max())
    assert p.mechanism(-p.mu * p.N_of(x), tight)[0] == "unbounded"


def test_the_first_certificate_falls_back_to_the_chains_and_certifies(monkeypatch):
    """Without the chains (from zero cohesion, and the fallback from the stall) and the
    dilatancy continuation, the first certificate (alternation and rescue) certifies
    nothing on that panel; with the fallback alone, the chain from the stall certifies a
    state that passes the independent check, below the associative bound."""
    s = _wall33(0.9)
    monkeypatch.setattr(FromZero, "run", lambda self, engine, start: None)
    monkeypatch.setattr(Dilatancy, "run", lambda self, engine, start: None)
    monkeypatch.setattr(FixedPoint, "run", lambda self, engine, start: None)
    e = GapSearch(s)
    _, a_assoc, x0 = associative(e)
    first_certificate(e, x0)
    assert e.record.best is None
    monkeypatch.undo()
    monkeypatch.setattr(FromZero, "run", lambda self, engine, start: None)
    monkeypatch.setattr(Dilatancy, "run", lambda self, engine, start: None)
    e = GapSearch(s)
    _, a_assoc, x0 = associative(e)
    first_certificate(e, x0)
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
        _, _, x0 = associative(e)
        p = e.problem
        n = p.n_lps()
        st = e.chains.chain(-p.mu * p.N_of(x0), 40, patience=patience)
        assert st is not None
        counts.append(p.n_lps() - n)
    assert counts[1] < counts[0]


def test_the_chain_from_zero_cohesion_reaches_the_least_known_state_of_the_panel():
    """On the 33-block panel at mu = 0.9 the chain from zero cohesion, which the first
    certificate runs where the alternation and the rescue stall, reaches 0.617364 (a
    twelve-block wedge), the multiplier the relaxed MPEC of Ferris & Tin-Loi certifies too
    (--method mpec): before the GA, so it does not depend on luck."""
    s = _wall33(0.9)
    e = GapSearch(s)
    _, _, x0 = associative(e)
    first_certificate(e, x0)
    st = e.record.best
    assert st is not None and st.alpha <= 0.617365 and st.source.startswith("zero-cohesion")
    assert FromZero().run(e, None).alpha <= 0.617365  # run once
