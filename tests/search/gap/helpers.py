"""Structures and an independent check shared by the tests of the search's pieces."""
import numpy as np

from lamodel.formulation.matrices import equilibrium_matrix, load_vectors
from lamodel.geometry import running_bond_wall, seed_wall
from lamodel.io.jsonspec import structure_from_json
from lamodel.structure import Structure


def collapse_violation(s: Structure, st) -> float:
    """Largest relative violation of the conditions of a collapse state, from scratch:
    equilibrium A s + f0 + alpha fbar = 0 (eq. 2), yield (eq. 4), compatibility of the
    cohesive flow rule, fbar^T u = 1, xi >= 0, flow only on rows at equality, and
    alpha = -u^T f0 - xi^T N_mu s_N (eq. 5)."""
    A = equilibrium_matrix(s).toarray()
    f0, fb = load_vectors(s)
    F = max(np.abs(f0).max(), np.abs(fb).max())
    N, V, M = st.N, st.V, st.M
    sf = np.concatenate([N, V, M])
    eq = np.abs(A @ sf + f0 + st.alpha * fb).max() / F
    slack = np.concatenate([-(s.mu * N + V), -(s.mu * N - V), -(s.d * N - M), -(s.d * N + M)])
    yld = max(-slack.min(), 0) / F
    xi = st.xi
    U = max(np.abs(st.u).max(), np.abs(xi).max())
    q = -A.T @ st.u  # opening, slip, rotation
    x1, x2, x3, x4 = np.split(xi, 4)
    qf = np.concatenate([s.d * (x3 + x4), x1 - x2, x4 - x3])
    comp = np.abs(q - qf).max() / U
    norm = abs(fb @ st.u - 1)
    neg = max(-xi.min(), 0) / U
    compl = np.abs(xi * slack).max() / (F * U)
    aK = -f0 @ st.u - np.sum(s.mu * N * (x1 + x2))
    vw = abs(aK - st.alpha) / max(1, abs(st.alpha))
    return max(eq, yld, comp, norm, neg, compl, vw)


def wall(courses):
    """The seed's wall of ``courses`` courses (6: wall33, 10: wall55)."""
    return structure_from_json(seed_wall(courses))


def bond(courses, width=25, mu=0.65):
    """A running-bond wall of ``courses`` courses of ``width`` blocks."""
    rows = [[0.5] + [1] * (width - 1) + [0.5] if r % 2 == 0 else [1] * width for r in range(courses)]
    return structure_from_json(running_bond_wall(rows, mu=mu, name=f"bond{courses}x{width}"))
