"""One validated options object and one clock."""
import math
import time

import pytest

from lamodel.errors import InputError
from lamodel.search.options import Deadline, SolveOptions


@pytest.mark.parametrize("field, value", [("starts", -1), ("workers", 0), ("pop_size", 1), ("generations", 0),
                                          ("time_limit", 0), ("time_limit", float("inf")), ("solver", "cplex"),
                                          ("xi_factor", -1.0), ("starts", 1.5)])
def test_options_reject_what_no_solve_can_use(field, value):
    with pytest.raises(InputError, match=field if field != "solver" else "solver 'cplex'"):
        SolveOptions(**{field: value})


def test_deadline():
    assert Deadline.after(None).left() == math.inf and not Deadline.after(None).expired()
    d = Deadline.after(0.05)
    assert 0 < d.left() <= 0.05 and not d.expired()
    time.sleep(0.06)
    assert d.expired() and d.left() < 0
    assert not d.extended(10).expired()
    assert Deadline.after(None).extended(5).at is None


def test_a_deadline_travels_as_the_seconds_left():
    """Pickled (to a worker process or a Dask worker on another machine) a deadline is its
    seconds left: the same end on the receiver's clock; a stop asked for arrives expired;
    none stays none."""
    import pickle
    d = pickle.loads(pickle.dumps(Deadline.after(30.0, stop=lambda: False)))
    assert d.stop is None and 29.0 < d.left() <= 30.0
    stopped = Deadline.after(None, stop=lambda: True)
    assert pickle.loads(pickle.dumps(stopped)).expired()
    assert pickle.loads(pickle.dumps(Deadline.after(None))).at is None
