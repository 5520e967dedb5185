"""Command-line options of the 3D inputs that carry no mechanical data (COMPAS assemblies,
meshes): declared once here, so that every command reading a structure offers the same ones.

``add_input_arguments(parser)`` declares them; ``input_options(args)`` gives the keyword
arguments of :func:`lamodel.io.read` (only those given: the readers' defaults stay theirs);
``check_build_options(args, spatial)`` refuses what ``lamodel build`` cannot honour.
"""
from __future__ import annotations

from ..errors import InputError


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
    if getattr(args, "mu", None) is not None and args.mu < 0:
        raise InputError(f"--mu {args.mu}: expected a friction coefficient >= 0")
    if getattr(args, "supports", None):
        out["supports"] = [s.strip() for s in args.supports.split(",") if s.strip()]
    units = {k: v for k, v in (("length", getattr(args, "length_unit", None)),
                               ("force", getattr(args, "force_unit", None))) if v}
    if units:
        out["units"] = units
    return out


def check_build_options(args, spatial: bool):
    """InputError for ``lamodel build`` options that do not apply to its input: a .dat
    instance's (--output, --name) for a structure in space, the 3D inputs' for a planar one."""
    if spatial and (args.output or args.name):
        raise InputError(f"{'--output' if args.output else '--name'}: a structure in space has no .dat instance "
                         "(build prints its contacts summary); expected a planar geometry with it")
    given = input_options(args)
    if not spatial and given:
        raise InputError(f"--{sorted(given)[0].replace('_', '-')}: applies to 3D inputs (COMPAS assemblies, "
                         "meshes); expected a planar input without it")
