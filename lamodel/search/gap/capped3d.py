"""The search's programs in space for joints with strengths: crushing, tension, cohesion.

:class:`~.problem3d.ConeProblem` with the caps of :mod:`lamodel.formulation.space` (per
point ``N_c = -f_c A <= N <= N_t = min(f_t A, k / mu)`` and ``||T|| <= k - mu N``, k = c0 A). A point
has three rows: ``p`` its opening (``N = N_t``), ``np + p`` its sliding (on its cone, along
the slip) and ``2 np + p`` its crushing (``N = N_c``, the point closes); its opening or
crushing and its sliding may flow together (the domain's corners). The fictitious
cohesion is ``max(k - mu N, 0)`` (the search's ``-mu N`` plus k), the caps associative;
``alpha_K - alpha`` gains the caps' dissipation
(:func:`~lamodel.formulation.space.gap_constant`). The certificates are the exact LP of
:func:`lamodel.search.caps3d.statics_lp` and the held cone program (in the order of
size, as without strengths: CONE_LP_FIRST_POINTS), the state's
mechanism fitted to its statics (:func:`lamodel.search.caps3d.mechanism_lp`) where the
conic one fails the residual test; then the dry joints' candidates (exact motions,
polished, sliding directions aligned), which the residual test with the caps judges.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from .. import caps3d
from ..tuning import CAP_FAR, CONE_FLOW_TOLS, CONE_LP_FIRST_POINTS
from .problem3d import ConeProblem


class CappedConeProblem(ConeProblem):
    """The cone programs of a 3D structure whose joints have strengths (module doc)."""

    def slack(self, x):
        """Per point ``N_t - N`` (opening row), ``k - mu N - ||T||`` (sliding row) and
        ``N - N_c`` (crushing row; inf without a crushing cap), >= 0 in S."""
        N = x[:self.np]
        return np.concatenate([self.caps[1] - N, self.form.cone_slack(x[:3 * self.np]), N - self.caps[0]])

    def gap(self, x, xi, u=None):
        """alpha_K - alpha of the statics x for the mechanism (u, xi): eq. (5) with the caps."""
        return float(self.gap_weights(xi, u) @ x[:3 * self.np]) + self.form.gap_constant(self._moving_strains(xi, u))

    def flows(self, u, tol=CONE_FLOW_TOLS[0]):
        """xi (3 np) of the motion u: openings, slips and closings (crushing, where a point
        has a cap); motions below ``tol`` of the largest strain are none."""
        n = self.np
        q = self._strains(u)
        top = np.abs(q).max() if q.size else 0.0
        qn, slip = q[:n], np.hypot(q[n:2 * n], q[2 * n:])
        crushing = (qn < -tol * top) & np.isfinite(self.caps[0])
        return np.concatenate([np.where(qn > tol * top, qn, 0.0), np.where(slip > tol * top, slip, 0.0),
                               np.where(crushing, -qn, 0.0)])

    def pattern(self, u, flow):
        """The flow pattern and the sliding directions."""
        return super().pattern(u, flow) + b"caps"

    def certificates(self, u, xi, flow, cap):
        """Held statics for the mechanism u (module doc): at each threshold of
        CONE_FLOW_TOLS the points that open, slide and crush held, exact LP first."""
        n = self.np
        q = self.form.strains(u)
        top = np.abs(q).max()
        if not top > 0:
            return
        flow_open, flow_slip, flow_crush = self._split(flow)
        qn, slip = q[:n], np.hypot(q[n:2 * n], q[2 * n:])
        sdir = self._directions(u)
        tried = set()
        for tol in CONE_FLOW_TOLS:
            opening, crushing = flow_open & (qn > tol * top), flow_crush & (qn < -tol * top)
            sliding = flow_slip & (slip > tol * top)
            key = opening.tobytes() + sliding.tobytes() + crushing.tobytes()
            if key in tried or not (opening.any() or sliding.any() or crushing.any()):
                continue
            tried.add(key)
            held = np.concatenate([opening, sliding, crushing])
            for x in self._held_capped(opening, sliding, sdir, crushing):
                yield x, u, np.where(held, self.flows(u, 0.0), 0.0), held, "+certify-caps"
        # then the dry joints' candidates (exact motions, polished, aligned directions): they
        # know no caps, so the residual test with the caps keeps only those that hold them
        for x, v, _, held, tag in super().certificates(u, xi, flow[:2 * n], cap):
            held = np.concatenate([held, np.zeros(n, bool)])
            yield x, v, np.where(held, self.flows(v, 0.0), 0.0), held, tag

    def _held_capped(self, opening, sliding, sdir, crushing):
        """The held statics: the exact LP, the held cone program where it has none; beyond
        CONE_LP_FIRST_POINTS the cone program first and the LP only where its state fails
        (its cold LP grows fastest: 15 s against 0.2 s for the cone program at 2,288 points)."""
        def lp():
            self.deadline.check()
            self.n_lp += 1
            return caps3d.statics_lp(self.form, opening, sliding, sdir, crushing=crushing, deadline=self.deadline)

        def cone():
            res = self._ran(self.cone.statics(opening=opening, sliding=sliding, slide_dir=sdir, crushing=crushing,
                                              time_limit=self._left()), "held")
            return res.x if res.ok else None

        if self.np <= CONE_LP_FIRST_POINTS:
            x = lp()
            x = cone() if x is None else x
            if x is not None:
                yield x
            return
        for solve in (cone, lp):
            x = solve()
            if x is not None:
                yield x

    def crushing_message(self) -> str:
        """Why the structure cannot stand when its joints' caps are the reason: with dry,
        infinitely strong joints it stands (a cone program solved once, here); '' otherwise."""
        dry = replace(self.user, fc=None, ft=None, cohesion=None, area=None)
        status, x = ConeProblem(dry, self.deadline).statics()
        if status == "optimal" and x[-1] <= self.stable_alpha:
            return ("; with dry joints it stands: the joints crush under the dead load "
                    "(compressive strength fc too small for the forces their points carry)")
        return ""

    def glued_message(self) -> str:
        """Why no mechanism follows the load when the reason is joints that neither open nor
        slide (tensile and cohesion forces beyond CAP_FAR times the loads); '' otherwise."""
        _, tension, k = self.caps
        if np.isfinite(tension).all() and np.isfinite(k).all():
            return ""
        return (f" (its joints' tensile strength and cohesion, beyond {CAP_FAR:g} times the loads, glue them: "
                "a point of such strengths neither opens nor slides)")

    def _state(self, x, u, source):
        st = super()._state(x, u, source)
        st.crushable = np.isfinite(self.caps[0])
        return st
