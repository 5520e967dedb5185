"""Reading a JSON structure file: what the planar format (:mod:`lamodel.io.jsonspec`) and
the spatial one (:mod:`lamodel.io.json3d`) share — the file, numbers, unknown fields, units,
and the head of each body (its id, ``support`` flag and friction). Each reader keeps only
what differs (the vertices, the loads). Errors are :class:`lamodel.errors.InputError`, one
line naming the file and the block or field.
"""
from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np

from ..errors import InputError
from .files import read_text

UNIT_FIELDS = ("length", "force")


def load_spec(source):
    """``(spec, where)``: a parsed dict as it is, or the JSON object of a file (named in
    ``where``; its ``name`` defaults to the file's stem)."""
    if isinstance(source, dict):
        return source, f"geometry '{source.get('name', '<dict>')}'"
    path = Path(source)
    where = str(path)
    text = read_text(path, "JSON geometry file")
    if not text.strip():
        raise InputError(f"{where}: the file is empty; expected a JSON object describing the blocks")
    twice = []

    def pairs(items):  # a key given twice in one object: JSON keeps the last, silently
        out = {}
        for key, value in items:
            if key in out:
                twice.append(key)
            out[key] = value
        return out
    try:
        spec = json.loads(text, object_pairs_hook=pairs)
    except json.JSONDecodeError as exc:
        raise InputError(f"{where}: malformed JSON at line {exc.lineno}, column {exc.colno} ({exc.msg}); "
                         "expected a JSON object describing the blocks") from None
    except RecursionError:
        raise InputError(f"{where}: JSON nested too deeply to read; expected a JSON object describing the "
                         "blocks") from None
    if not isinstance(spec, dict):
        kind = "null" if spec is None else type(spec).__name__
        raise InputError(f"{where}: the file holds a JSON {kind}; expected a JSON object with a 'blocks' list")
    for key in dict.fromkeys(twice):
        warnings.warn(f"{where}: '{key}' is given twice in one object; the last value is used", stacklevel=3)
    if "name" not in spec:
        spec = dict(spec, name=path.stem)
    return spec, where


def number(value, where, what, minimum=None):
    """A finite float from JSON, or an InputError saying what was expected."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{where}: {what} is {json.dumps(value)}; expected a finite number")
    if minimum is not None and value < minimum:
        raise InputError(f"{where}: {what} is {value}; expected a number >= {minimum}")
    return float(value)


def warn_unknown(where, keys, known, kind):
    """A warning (not an error) naming the fields a reader does not know."""
    unknown = sorted(set(keys) - set(known))
    if unknown:
        warnings.warn(f"{where}: unknown {kind} field(s) {', '.join(repr(k) for k in unknown)} ignored; "
                      f"known fields are {', '.join(known)}", stacklevel=4)


def json_object(value, where, what, known):
    """``value`` if it is a JSON object (its unknown fields warned about), else InputError."""
    if not isinstance(value, dict):
        raise InputError(f"{where}: {what} is {json.dumps(value)[:60]}; expected an object with fields {', '.join(known)}")
    warn_unknown(where, value.keys(), known, what)
    return value


def units(spec, where) -> dict:
    """The ``"units"`` field: ``{"length": "m", "force": "kN"}`` (either may be missing)."""
    if "units" not in spec:
        return {}
    given = json_object(spec["units"], where, "'units'", UNIT_FIELDS)
    for key, value in given.items():
        if key in UNIT_FIELDS and (not isinstance(value, str) or not value.strip()):
            raise InputError(f"{where}: units '{key}' is {json.dumps(value)}; expected a unit name such as "
                             + ("'m'" if key == "length" else "'kN'"))
    return {k: given[k].strip() for k in UNIT_FIELDS if k in given}


def body_head(body, pos, where, seen: dict, corners: str):
    """``(id, at)`` of ``blocks[pos]``: an object with a unique id without spaces and
    ``vertices`` (``corners`` says what they are, in the message when they are missing).
    ``seen`` (id -> position) is updated; ``at`` names the block in later messages."""
    if not isinstance(body, dict):
        raise InputError(f"{where}: blocks[{pos}] is {json.dumps(body)[:40]}; expected an object with 'id' and 'vertices'")
    if body.get("id") is None or isinstance(body["id"], (dict, list, bool)):
        raise InputError(f"{where}: blocks[{pos}] has no valid 'id'; expected a string or integer id")
    bid = str(body["id"])
    if not bid or any(c.isspace() for c in bid):  # ids are tokens of .dat files and CSV tables
        raise InputError(f"{where}: blocks[{pos}] has the id {json.dumps(body['id'])}; expected a non-empty id "
                         "without spaces")
    at = f"{where}: block '{bid}'"
    if bid in seen:
        raise InputError(f"{at} is declared twice (blocks[{seen[bid]}] and blocks[{pos}]); expected unique ids")
    seen[bid] = pos
    if "vertices" not in body:
        raise InputError(f"{at} has no 'vertices'; expected {corners}")
    return bid, at


def body_support_mu(body, at, mu_all):
    """``(support, mu)`` of a body: its ``support`` flag and its own ``mu`` or the file's."""
    support = body.get("support", False)
    if not isinstance(support, bool):
        raise InputError(f"{at}: 'support' is {json.dumps(support)}; expected true or false")
    if "mu" in body:
        return support, number(body["mu"], at, "'mu'", 0.0)
    if mu_all is None:
        raise InputError(f"{at} has no friction coefficient; expected a top-level 'mu' or a 'mu' on every block")
    return support, mu_all


def blocks_of(spec, where) -> list:
    """The ``"blocks"`` list, never empty."""
    bodies = spec.get("blocks")
    if bodies is None and ("span" in spec or "spans" in spec) and "ring" in spec:  # a bridge (lamodel.bridges)
        raise InputError(f"{where}: a bridge description, not blocks; expected `lamodel bridge {where} OUT.json` "
                         "first, then `lamodel solve OUT.json`")
    if not isinstance(bodies, list) or not bodies:
        raise InputError(f"{where}: 'blocks' is missing or empty; expected a list of blocks with 'id' and 'vertices'")
    return bodies


def check_supports(where, is_support):
    """At least one support and one movable block (``is_support``: a flag per body)."""
    if not is_support.any():
        raise InputError(f"{where}: no block is a support; expected at least one body with \"support\": true")
    if is_support.all():
        raise InputError(f"{where}: every body is a support; expected at least one movable block")


def writes_live(spec, also=()) -> bool:
    """Whether the file writes live loads of its own (live point loads, or any of the
    fields ``also``): then alpha multiplies only those, unless it gives a ``live_load``."""
    loads = spec.get("loads")
    point = isinstance(loads, list) and any(isinstance(x, dict) and x.get("kind", "live") == "live" for x in loads)
    return point or any(key in spec for key in also)


def validated(structure, where):
    """``structure.validate()``, its message naming the file (``where``), not the structure."""
    try:
        return structure.validate()
    except InputError as exc:  # "structure 'x': ..." -> "<file>: ..."
        raise InputError(f"{where}: {str(exc).split(': ', 1)[1]}") from None



#: The joints' strengths a JSON object may give (the structure, a body, a joint), each a
#: stress in the file's force per length squared but the thickness (a length): see
#: :mod:`lamodel.formulation.joints`.
STRENGTH_FIELDS = ("fc", "ft", "cohesion", "thickness")


def strengths(obj, at, fields=STRENGTH_FIELDS) -> dict:
    """The strengths ``obj`` gives, checked: numbers, fc and thickness > 0, ft and cohesion
    >= 0 (ft <= fc is checked per contact, once they are combined)."""
    out = {}
    for key in fields:
        if key in obj:
            value = number(obj[key], at, f"'{key}'", 0.0)
            if key in ("fc", "thickness") and value == 0:
                raise InputError(f"{at}: '{key}' is 0; expected a number > 0 (omit 'fc' for no crushing)")
            out[key] = value
    return out


def joint_strengths(spec, where, ids, body_strengths, ia, ib, defaults, fields=STRENGTH_FIELDS) -> dict:
    """Per contact (a planar contact, an interface in space) joining bodies ``ia``, ``ib``
    (indices into ``ids``), the strengths ``fields``: the file's, a body's (the smaller of
    the two), a joint's (``"joints": [{"between": [b1, b2], ...}]``, every contact of that
    pair); ``{}`` when the file gives none (a dry structure). ``defaults``: each field's."""
    top = strengths(spec, where, fields)
    joints = spec.get("joints", [])
    if not isinstance(joints, list):
        raise InputError(f"{where}: 'joints' is {json.dumps(joints)[:40]}; expected a list of "
                         "{\"between\": [body, body], ...} objects")
    if not top and not joints and not any(body_strengths):
        return {}
    out = {}
    for key in fields:
        # each body's value is its own, else the file's, else the default; a contact takes the
        # smaller of its two bodies' (a stronger body never lends its strength to a weaker one)
        mine = np.array([x.get(key, top.get(key, defaults[key])) for x in body_strengths], dtype=float)
        out[key] = np.minimum(mine[np.asarray(ia, dtype=int)], mine[np.asarray(ib, dtype=int)]) if len(ia) else \
            np.full(0, top.get(key, defaults[key]))
    pair = {}
    for k, (a, b) in enumerate(zip(ia, ib)):
        pair.setdefault(frozenset((ids[a], ids[b])), []).append(k)
    named = {}
    for pos, joint in enumerate(joints):
        at = f"{where}: joints[{pos}]"
        json_object(joint, at, "joint", ("between", *fields))
        between = joint.get("between")
        if not (isinstance(between, list) and len(between) == 2 and all(isinstance(x, (str, int)) for x in between)):
            raise InputError(f"{at}: 'between' is {json.dumps(between)[:40]}; expected the ids of its two bodies")
        ks = pair.get(frozenset(map(str, between)))
        if ks is None:
            raise InputError(f"{at}: '{between[0]}' and '{between[1]}' share no contact; expected two bodies "
                             "that touch")
        key_pair = frozenset(map(str, between))
        if key_pair in named:
            raise InputError(f"{at}: the joint between '{between[0]}' and '{between[1]}' again (joints[{named[key_pair]}]); "
                             "expected each joint once")
        named[key_pair] = pos
        given = strengths(joint, at, fields)
        if not given:
            warnings.warn(f"{at}: no strength given ({', '.join(fields)}); the joint keeps its bodies'", stacklevel=4)
        for key, value in given.items():
            out[key][ks] = value
    return out
