"""Descent from a certified state never raises alpha."""
from lamodel.search.gap import GapSearch

from .helpers import bond, collapse_violation
from lamodel.search.gap.phases import associative


def test_descent_never_raises_alpha_and_is_cached():
    s = bond(5, width=5, mu=0.9)
    e = GapSearch(s)
    _, _, x0 = associative(e)
    p = e.problem
    # from the first state the chain certifies, whatever it is
    st = None
    c = -p.mu * p.N_of(x0)
    for _ in range(6):
        status, _, xc, u, xi = p.mechanism(c)
        st = e.certifier.certify(u, xi, "t")
        if st is not None:
            break
        c = -p.mu * p.cohesive_N(xc)
    assert st is not None
    low = e.descent.descend(st)
    assert low.alpha <= st.alpha
    assert e.descent.descend(st) is low  # a descent depends on the certified state alone
    assert collapse_violation(s, p.to_user(low)) <= 1e-7
