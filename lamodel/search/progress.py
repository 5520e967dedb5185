"""The search's progress line: on stderr, on a terminal only.

``first certificate ██▍           20% of the work bound [02:05, associative bound 0.542451,
none certified yet]`` (a 1,020-block running-bond wall at mu = 0.9): the phase under way,
how much of the run's budget is spent, the associative bound (an upper bound on alpha_c,
known after the first LP) and the best certified alpha so far. The budget is the user's
time limit or, without one, the work bound that ends the phase under way
(:meth:`lamodel.search.budget.Budget.share`): counted LP work, so the share is
how far the default run is from its end, whatever the machine. The line is redrawn every
PROGRESS_REFRESH seconds by a thread of its own, also during a long LP.
"""
from __future__ import annotations

import threading
import time

from .tuning import PROGRESS_REFRESH


class Progress:
    """The progress line (see module doc). ``enabled`` False, or stderr not a terminal:
    nothing is drawn and no thread runs. ``time_limit``: the budget in seconds (None: the
    work bounds, through :meth:`follow`)."""

    def __init__(self, enabled: bool, time_limit: float | None = None):
        from tqdm import tqdm
        self.time_limit = time_limit
        of = "of the time limit" if time_limit is not None else "of the work bound"
        self.bar = tqdm(total=100, desc="associative LP", leave=False, disable=None if enabled else True,
                        bar_format="{desc} {bar:12} {percentage:3.0f}% " + of + " [{elapsed}{postfix}]")
        self.associative = self.alpha = None
        self._work_share = None  # () -> share of the work bound spent, or None
        self._t0 = time.monotonic()
        self._done = threading.Event()
        self._thread = None
        self._describe()
        if not self.bar.disable:
            self._thread = threading.Thread(target=self._redraw, name="lamodel-progress", daemon=True)
            self._thread.start()

    def follow(self, share):
        """``share()``: the share of the work bound spent so far (None: no bound yet)."""
        self._work_share = share

    def phase(self, name):
        self.bar.set_description_str(name, refresh=False)
        self._update()

    def bound(self, alpha_associative):
        """The associative multiplier, an upper bound on alpha_c."""
        self.associative = alpha_associative
        self._describe()

    def best(self, alpha):
        self.alpha = alpha
        self._describe()

    def _describe(self):
        words = []
        if self.associative is not None and self.associative < float("inf"):
            words.append(f"associative bound {self.associative:.6f}")
        words.append(f"best certified alpha {self.alpha:.6f}" if self.alpha is not None else "none certified yet")
        self.bar.set_postfix_str(", ".join(words), refresh=False)
        self._update()

    def _share(self):
        if self.time_limit is not None:
            return (time.monotonic() - self._t0) / self.time_limit if self.time_limit > 0 else 1.0
        return self._work_share() if self._work_share is not None else None

    def _update(self):
        if self.bar.disable:
            return
        share = self._share()
        if share is not None:
            self.bar.n = int(min(max(share, 0.0), 1.0) * 100 + 1e-9)  # 0.57 * 100 = 56.99...: 57
        self.bar.refresh()

    def _redraw(self):
        while not self._done.wait(PROGRESS_REFRESH):
            self._update()

    def close(self):
        self._done.set()
        if self._thread is not None:
            self._thread.join()
        self.bar.close()
