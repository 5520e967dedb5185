"""The values of a study spec (:mod:`lamodel.parametric`): numbers, lists and ranges, objects
with known keys, standard deviations; each refused in one line naming where it is."""
from __future__ import annotations

import json
import math

import numpy as np

from .errors import InputError

#: values of one range of a spec beyond which it is refused at once
MAX_RANGE = 10**6


def numbers(value, where) -> list[float]:
    """A number, a list of numbers, or a range {from, to, num | step} (both ends kept)."""
    if isinstance(value, dict):
        unknown = set(value) - {"from", "to", "num", "step"}
        if unknown or "from" not in value or "to" not in value or ("num" in value) == ("step" in value):
            raise InputError(f"{where}: expected a range {{\"from\": a, \"to\": b, \"num\": n}} or "
                             f"{{\"from\": a, \"to\": b, \"step\": h}}, got {json.dumps(value)}")
        a, b = number(value["from"], where), number(value["to"], where)
        if "num" in value:
            n = value["num"]
            if isinstance(n, bool) or not isinstance(n, int) or n < 1:
                raise InputError(f"{where}: num is {n!r}; expected a whole number >= 1")
            check_count(n, where)
            values = np.linspace(a, b, n) if n > 1 else np.array([a])
        else:
            h = number(value["step"], where)
            if h == 0 or (b - a) / h < 0:
                raise InputError(f"{where}: step {h:g} does not lead from {a:g} to {b:g}")
            n = math.floor((b - a) / h + 1e-9) + 1
            check_count(n, where)
            values = a + h * np.arange(n)
        return [round(float(v), 12) for v in values]  # 0.1 steps give 0.3, not 0.30000000000000004
    if isinstance(value, list):
        if not value:
            raise InputError(f"{where}: the list is empty; expected at least one value")
        return [number(v, where) for v in value]
    return [number(value, where)]


#: How a spec writes an infinite strength (JSON has no infinity; Python's reader also takes Infinity).
INFINITE = ("inf", "infinity")


def strengths(value, where) -> list[float]:
    """As :func:`numbers`, and a value (or a list's item) may be infinite: ``"inf"`` (the
    joint that never crushes, the dry joint's f_c)."""
    def one(v):
        if (isinstance(v, str) and v.strip().lower() in INFINITE) or (isinstance(v, float) and v == math.inf):
            return math.inf
        if isinstance(v, str):
            raise InputError(f"{where}: {json.dumps(v)} is not a number; expected a number or \"inf\"")
        return number(v, where)
    if isinstance(value, list) and value:
        return [one(v) for v in value]
    return [one(value)] if isinstance(value, (str, float)) else numbers(value, where)


def check_count(n, where):
    if n > MAX_RANGE:  # refused before any list is made (memory)
        raise InputError(f"{where}: the range has {n:.6g} values; expected at most {MAX_RANGE}")


def number(value, where) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{where}: {json.dumps(value)} is not a finite number")
    return float(value)


def check_keys(d, allowed, where):
    if not isinstance(d, dict):
        raise InputError(f"{where}: expected a JSON object, got {json.dumps(d)[:60]}")
    unknown = sorted(set(d) - set(allowed))
    if unknown:
        raise InputError(f"{where}: unknown key '{unknown[0]}'; expected {', '.join(allowed)}")


def sd_of(d, where) -> float:
    check_keys(d, ("sd", "per") if where.endswith("mu") else ("sd",), where)
    if "sd" not in d:
        raise InputError(f"{where}: 'sd' is missing; expected a standard deviation >= 0")
    sd = number(d["sd"], f"{where}.sd")
    if sd < 0:
        raise InputError(f"{where}.sd is {sd:g}; expected a standard deviation >= 0")
    return sd
