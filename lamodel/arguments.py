"""The argument types of the command line: whole numbers, seeds, seconds, tolerances and
lists of numbers, each refused in one line that says what was expected."""
from __future__ import annotations

import argparse


def number(kind, check, expected: str):
    """An argparse type: ``kind(text)`` when ``check`` accepts it, else one line naming
    what was ``expected``."""
    def parse(text):
        try:
            if check(value := kind(text)):
                return value
        except (ValueError, OverflowError):
            pass
        raise argparse.ArgumentTypeError(f"expected {expected}, got '{text}'")
    parse.__name__ = expected
    return parse


def whole(minimum: int, maximum: int | None = None):
    """An argparse type: a whole number in [minimum, maximum]."""
    top = f" and < 2**{maximum.bit_length()}" if maximum else ""
    return number(int, lambda v: v >= minimum and (maximum is None or v <= maximum), f"a whole number >= {minimum}{top}")


#: A GA seed: numpy's generators take seeds >= 0, summary.csv stores a 64-bit integer.
SEED = whole(0, 2**63 - 1)
#: A time limit.
seconds = number(float, lambda v: 0 < v < float("inf"), "a number of seconds > 0")
#: A comparison tolerance.
tolerance = number(float, lambda v: 0 <= v < float("inf"), "a finite tolerance >= 0")


#: A joint's strength (a stress, in the structure's force per length squared).
strength = number(float, lambda v: 0 <= v < float("inf"), "a finite stress >= 0")
#: A compressive strength.
positive_strength = number(float, lambda v: 0 < v < float("inf"), "a finite stress > 0")


def strength_arguments(a):
    """The what-ifs on the joints' strengths (``a``: a parser's add_argument)."""
    a("--fc", type=positive_strength, metavar="STRESS", help="compressive strength of every joint (crushing), in the "
      "instance's force per length squared; replaces the file's")
    a("--ft", type=strength, metavar="STRESS", help="tensile strength of every joint; replaces the file's")
    a("--cohesion", type=strength, metavar="STRESS", help="cohesion of every joint; replaces the file's")


def numbers(count: int | None = None, what: str = "comma-separated numbers"):
    """An argparse type: finite numbers separated by commas (``count`` of them, if given)."""
    split = lambda t: [float(x) for x in t.replace(" ", "").split(",") if x != ""]  # noqa: E731
    finite = lambda v: v and all(abs(x) < float("inf") for x in v) and (count is None or len(v) == count)  # noqa: E731
    return number(split, finite, what)


def rolling_arguments(a):
    """The options of a rolling load across the top (``a``: a parser's add_argument)."""
    a("--rolling", metavar="FX,FY", type=numbers(2, "two numbers FX,FY"), help="a rolling point load (per axle) "
      "moved across the top; it replaces the file's live loads")
    a("--axles", metavar="D1,D2,...", type=numbers(), help="offsets of the axles from the lead axle (default 0)")
    a("--positions", metavar="X1,X2,...", type=numbers(), help="positions of the lead axle (default: the file's, "
      "else the midpoints of the top edges)")
