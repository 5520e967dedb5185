"""Command-line options of the 3D inputs that carry no mechanical data (COMPAS assemblies,
meshes): declared once here, so that every command reading a structure offers the same ones.

``add_input_arguments(parser)`` declares them; ``input_options(args)`` gives the keyword
arguments of :func:`lamodel.io.read` (only those given: the readers' defaults stay theirs);
``check_build_options(args, spatial)`` refuses what ``lamodel build`` cannot honour;
``check_input_options(options)`` refuses a value no reader can take, naming the option (it
came from the command line or the caller, not from the file).
"""
from __future__ import annotations

import math
from numbers import Real

from ..errors import InputError


def _finite(value) -> bool:
    return isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(value)


def _listed(value) -> bool:
    return not isinstance(value, (str, bytes, dict)) and hasattr(value, "__iter__")


def _three(value) -> bool:
    return _listed(value) and len(v := list(value)) == 3 and all(map(_finite, v)) and any(v)


def _shown(value) -> str:
    if _listed(value):
        return " ".join(map(_shown, value))
    return f"{value:g}" if isinstance(value, Real) and not isinstance(value, bool) else repr(value)


#: What each numeric option of :func:`lamodel.io.read` must be: (the test, what was expected).
_EXPECTED = {
    "mu": (lambda v: _finite(v) and v >= 0, "a finite friction coefficient >= 0"),
    "unit_weight": (lambda v: _finite(v) and v > 0, "a finite weight per unit volume > 0"),
    "live_load": (_three, "three finite numbers X Y Z, not all zero (alpha multiplies this load)"),
    "supports_below": (_finite, "a finite height Z"),
    "tolerance": (lambda v: _finite(v) and v >= 0, "a finite tolerance >= 0 (relative to the structure's size)"),
}


def flag(key: str) -> str:
    """The command-line option of a :func:`lamodel.io.read` option: ``unit_weight`` -> ``--unit-weight``."""
    return "--" + key.replace("_", "-")


def check_input_options(options: dict) -> dict:
    """``options`` (the keyword arguments of :func:`lamodel.io.read`) when every value is one
    the readers can take; else InputError, one line naming the option (``--mu is nan;
    expected ...``), never the file: the value is not the file's."""
    for key, (ok, expected) in _EXPECTED.items():
        value = options.get(key)
        if value is not None and not ok(value):
            raise InputError(f"{flag(key)} is {_shown(value)}; expected {expected}")
    if options.get("contact_points") is not None:
        from ..geometry.interfaces3d import CONTACT_POINTS, parse_contact_points
        try:
            parse_contact_points(options["contact_points"])
        except InputError:
            raise InputError(f"--contact-points is {options['contact_points']!r}; expected {CONTACT_POINTS}") from None
    return options


def add_input_arguments(p):
    """Declare --mu, --unit-weight, --live-load, --supports-below, --supports, --length-unit,
    --force-unit, --tolerance and --contact-points on the argparse parser ``p``."""
    g = p.add_argument_group("3D inputs without mechanical data (COMPAS assemblies, OBJ/PLY/STL/glTF meshes)")
    g.add_argument("--mu", type=float, default=None, help="friction coefficient of every contact (default 0.6)")
    g.add_argument("--unit-weight", type=float, default=None, help="weight per unit volume (default 1)")
    g.add_argument("--live-load", type=float, nargs=3, default=None, metavar=("X", "Y", "Z"),
                   help="live force per unit weight (default 1 0 0: horizontal, equal to the weight)")
    g.add_argument("--supports-below", type=float, default=None, metavar="Z",
                   help="blocks whose lowest point is below Z are supports")
    g.add_argument("--supports", default=None, metavar="ID,ID,...", help="ids of the blocks that are supports")
    g.add_argument("--length-unit", default=None, help="unit of the coordinates, e.g. m (tables and pictures)")
    g.add_argument("--force-unit", default=None, help="unit of forces, e.g. kN")
    g.add_argument("--tolerance", type=float, default=None,
                   help="geometric tolerance relative to the structure's size (default 1e-6)")
    g.add_argument("--contact-points", default=None, metavar="vertices|grid:n",
                   help="contact points of an interface: its polygon's vertices (default), or those plus an "
                        "n x n interior grid")


def input_options(args) -> dict:
    """Keyword arguments for :func:`lamodel.io.read` from parsed options (those given only)."""
    out = {}
    for key in ("mu", "unit_weight", "live_load", "supports_below", "tolerance", "contact_points"):
        value = getattr(args, key, None)
        if value is not None:
            out[key] = value
    if getattr(args, "supports", None):
        out["supports"] = [s.strip() for s in args.supports.split(",") if s.strip()]
    units = {k: v for k, v in (("length", getattr(args, "length_unit", None)),
                               ("force", getattr(args, "force_unit", None))) if v}
    if units:
        out["units"] = units
    return check_input_options(out)


def check_build_options(args, spatial: bool):
    """InputError for ``lamodel build`` options that do not apply to its input: a .dat
    instance's (--output, --name) for a structure in space, the 3D inputs' for a planar one."""
    if spatial and (args.output or args.name):
        raise InputError(f"{'--output' if args.output else '--name'}: a structure in space has no .dat instance "
                         "(build prints its contacts summary); expected a planar geometry with it")
    given = input_options(args)
    if not spatial and given:
        raise InputError(f"{flag(sorted(given)[0])}: applies to 3D inputs (COMPAS assemblies, "
                         "meshes); expected a planar input without it")
