"""A masonry arch bridge as its assessor describes it (JSON, planar, one span or several on
piers), read and checked: every bad value is one line naming its field::

    {"name": "prestwood", "units": {"length": "m", "force": "kN"},
     "span": 6.55, "rise": 1.43, "width": 3.8,
     "ring": {"thickness": 0.22, "rings": 1, "voussoirs": 30, "unit_weight": 20, "mu": 0.6,
              "fc": 5000},
     "abutments": {"height": 1.0, "width": 1.5}, "backing": {"height": 0.6},
     "fill": {"depth": 0.2, "unit_weight": 18, "phi": 37, "lateral": "at_rest",
              "passive": 0.33, "spread": 30},
     "load": {"force": 100, "axles": [0], "patch": 0.3, "positions": [-2, 0, 2]}}

Lengths in the file's length unit, x = 0 at mid-span, y = 0 at the springings; the arch is
segmental (circular; ``rise = span / 2`` is semicircular), or with ``"shape"`` elliptical or
pointed. ``width`` is the bridge's width
out of the plane: every force is for the whole width (unit weights are per volume). The
abutments are rigid supports under each springing (``height`` deep, ``width`` wide), or
with ``"kind": "block"`` masonry blocks on a rigid ground, free to slide and overturn; the
backing is masonry blocks over the haunches up to ``height`` above the springings.
``load`` is an axle group (``force`` per axle, line loads across the width, each on a patch
``patch`` long on the road surface; ``axles``: offsets of the axles from the lead one) at
each lead-axle position of ``positions`` (default: across the span,
:data:`~lamodel.search.tuning.BRIDGE_POSITIONS` of them). The ring's ``fc`` is its masonry's
compressive strength (force per length squared; omitted: no crushing), which bounds every
joint of the ring and its seats on the abutments (:mod:`lamodel.formulation.joints`).
The ring's ``cohesion`` and ``ft`` are the mortar's bond between its rings (every ring
interface; the radial joints stay dry). Several spans: ``"spans": [{"span", "rise",
"shape"}, ..]`` left to right instead of ``span``, ``rise``, ``shape``, and ``"piers":
[{"height", "width", "kind"}, ..]``, one between each two (:mod:`.deck`); x = 0 is then the
middle of the bridge and ``fill.depth`` is over the highest crown.
``source`` (text, or an object of field -> citation) records where the numbers come from;
it is carried into the built file's description, never read as a value.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

from ..errors import InputError
from ..io.jsonfields import json_object, load_spec, number, units

TOP_FIELDS = ("name", "description", "source", "units", "shape", "span", "rise", "spans", "piers", "width", "skew", "ring",
              "abutments", "backing", "fill", "load")
SPAN_FIELDS = ("span", "rise", "shape", "ring")
#: What a span's own ``ring`` may change of the bridge's ring.
SPAN_RING_FIELDS = ("thickness", "rings", "voussoirs", "fc")
PIER_FIELDS = ("height", "width", "kind")
BACKING_FIELDS = ("height",)
RING_FIELDS = ("thickness", "rings", "voussoirs", "unit_weight", "mu", "fc", "cohesion", "ft")
ABUTMENT_FIELDS = ("height", "width", "kind")
#: Abutments and piers: rigid supports, or masonry blocks free to slide and turn on a rigid ground.
ABUTMENT_KINDS = ("rigid", "block")
FILL_FIELDS = ("depth", "unit_weight", "phi", "lateral", "passive", "spread", "dispersal")
#: How surface loads reach the extrados (lamodel.bridges.fill): spread at an angle, or
#: Boussinesq's stresses under a strip on an elastic half-space.
DISPERSAL = ("spread", "boussinesq")
LOAD_FIELDS = ("force", "axles", "patch", "positions")
#: The arch's shape: circular (semicircular when rise = span / 2), a semi-ellipse, or two
#: circular arcs meeting at the crown (rise > span / 2).
SHAPES = ("segmental", "elliptical", "pointed")
#: Horizontal earth pressure on the extrados as dead load: at rest (K0 = 1 - sin phi,
#: Jaky), active (Rankine's Ka) or none.
LATERAL = ("at_rest", "active", "none")


@dataclass(frozen=True)
class Pier:
    """A pier between two spans: ``height`` below the springings, ``width`` between the
    two intrados springings, rigid or a block on the ground."""

    height: float
    width: float
    kind: str = "rigid"


@dataclass
class Bridge:
    """A bridge: an arch ring on abutments under fill, one span or several on piers (module
    doc; with several, ``span`` is the length between the outer springings, ``rise`` the
    highest span's, and :meth:`part` each span)."""

    name: str
    span: float
    rise: float
    width: float
    thickness: float                 # the ring's (all rings together)
    shape: str = "segmental"
    skew: float = 0.0                # degrees: recorded, not modelled (a planar model)
    rings: int = 1
    voussoirs: int = 24              # per ring
    masonry_weight: float = 20.0     # unit weight of the ring (force / length^3)
    mu: float = 0.6                  # friction of the ring's joints
    fc: float | None = None          # the ring's compressive strength (None: no crushing)
    cohesion: float = 0.0            # mortar bond on the ring interfaces: shear cohesion
    ft: float = 0.0                  # and tensile strength (force / length^2)
    spans: tuple = ()                # several spans: (span, rise, shape, ring) each, left to right;
    #                                  ring: the span's own ring values, ((field, value), ...)
    piers: tuple = ()                # the Pier between each two spans
    abutment_height: float = 1.0
    abutment_width: float = 1.0
    abutment_kind: str = "rigid"
    backing: float = 0.0             # level of the backing's top above the springings (0: none)
    fill_depth: float = 0.0          # over the crown's extrados
    fill_weight: float = 18.0        # unit weight of the fill
    phi: float = 30.0                # the fill's angle of friction (degrees)
    lateral: str = "at_rest"
    passive: float = 0.33            # mobilised fraction of the passive pressure K_p sigma_v
    spread: float = 30.0             # dispersal angle of surface loads, from the vertical (degrees)
    dispersal: str = "spread"        # or "boussinesq" (lamodel.bridges.fill)
    force: float = 100.0             # per axle, whole width, downwards
    axles: tuple = (0.0,)
    patch: float = 0.0               # length of each axle's patch on the road surface
    positions: tuple | None = None   # lead axle abscissas
    units: dict = field(default_factory=dict)
    description: str = ""
    source: dict = field(default_factory=dict)   # field -> where its value comes from

    @property
    def radius(self) -> float:
        """The intrados radius of a segmental arch through the springings and the crown."""
        return (self.span ** 2 / 4 + self.rise ** 2) / (2 * self.rise)

    @property
    def least_radius(self) -> float:
        """The intrados' least radius of curvature (the ring must be thinner)."""
        if self.shape == "elliptical":
            a, b = self.span / 2, self.rise
            return min(a * a / b, b * b / a)
        if self.shape == "pointed":
            return (self.span ** 2 / 4 + self.rise ** 2) / self.span
        return self.radius

    @property
    def road(self) -> float:
        """The road surface's level (the highest crown's extrados plus the fill over it)."""
        if self.spans:
            return max(s[1] + dict(s[3]).get("thickness", self.thickness) for s in self.spans) + self.fill_depth
        return self.rise + self.thickness + self.fill_depth

    def mirrored(self) -> "Bridge":
        """The same bridge mirrored about x = 0: spans and piers in reverse order, loads at
        mirrored positions (each arch is symmetric)."""
        import dataclasses
        return dataclasses.replace(self, axles=tuple(-a for a in self.axles), spans=self.spans[::-1],
                                   piers=self.piers[::-1],
                                   positions=None if self.positions is None else tuple(-x for x in self.positions))

    def part(self, k: int) -> "Bridge":
        """Span k of several as a one-span bridge (x = 0 at its own mid-span), its fill depth
        such that the road is level over every span."""
        import dataclasses
        span, rise, shape, ring = self.spans[k]
        ring = dict(ring)
        thickness = ring.get("thickness", self.thickness)
        return dataclasses.replace(self, span=span, rise=rise, shape=shape, spans=(), piers=(), **ring,
                                   fill_depth=self.road - rise - thickness)


def _positive(obj, key, at, default=None, minimum=0.0, strict=True):
    if key not in obj:
        if default is None:
            raise InputError(f"{at} has no '{key}'; expected a number > 0")
        return default
    value = number(obj[key], at, f"'{key}'", minimum)
    if strict and value <= 0:
        raise InputError(f"{at}: '{key}' is {value:g}; expected a number > 0")
    return value


def _whole(obj, key, at, default, minimum):
    value = obj.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise InputError(f"{at}: '{key}' is {json.dumps(value)[:20]}; expected a whole number >= {minimum}")
    return value


def _numbers(obj, key, at, what):
    value = obj[key]
    if not isinstance(value, list) or not value:
        raise InputError(f"{at}: '{key}' is {json.dumps(value)[:40]}; expected a list of {what}")
    return tuple(number(v, at, f"an entry of '{key}'") for v in value)


def read_bridge(source) -> Bridge:
    """The :class:`Bridge` of a JSON file (path) or parsed dict; InputError naming the field."""
    spec, where = load_spec(source)
    json_object(spec, where, "the bridge", TOP_FIELDS)
    spans, piers = _spans(spec, where)
    span = sum(s[0] for s in spans) + sum(p.width for p in piers)   # springing to springing
    rise, shape = max(s[1] for s in spans), spans[0][2]
    width = _positive(spec, "width", where, 1.0)
    skew = _positive(spec, "skew", where, 0.0, strict=False)
    if skew >= 90:
        raise InputError(f"{where}: 'skew' is {skew:g}; expected an angle in degrees, below 90")
    if "ring" not in spec:
        raise InputError(f"{where} has no 'ring'; expected \"ring\": {{\"thickness\": ...}}")
    ring = json_object(spec["ring"], f"{where}: ring", "'ring'", RING_FIELDS)
    at = f"{where}: ring"
    if not piers and spans[0][3]:
        raise InputError(f"{where}: spans[0]: 'ring' in a bridge of one span; expected the bridge's own 'ring'")
    b = Bridge(name=str(spec.get("name", "bridge")), span=span, rise=rise, width=width, shape=shape, skew=skew,
               thickness=_positive(ring, "thickness", at),
               rings=_whole(ring, "rings", at, 1, 1), voussoirs=_whole(ring, "voussoirs", at, 24, 3),
               masonry_weight=_positive(ring, "unit_weight", at, Bridge.masonry_weight),
               mu=_positive(ring, "mu", at, Bridge.mu, strict=False),
               fc=_positive(ring, "fc", at, None) if "fc" in ring else None,
               cohesion=_positive(ring, "cohesion", at, 0.0, strict=False), ft=_positive(ring, "ft", at, 0.0, strict=False),
               spans=spans if piers else (), piers=piers,
               units=units(spec, where), description=str(spec.get("description", "")),
               source=_source(spec, where))
    for k in range(len(spans)):
        one = b.part(k) if piers else b
        here = f"{where}: spans[{k}]: ring" if piers and spans[k][3] else at
        if one.shape == "pointed" and one.voussoirs % 2:
            raise InputError(f"{here}: 'voussoirs' is {one.voussoirs}; expected an even number for a pointed arch (a "
                             "joint at the apex)")
        try:
            least = one.least_radius
        except OverflowError:
            raise InputError(f"{where}: the arch's span {one.span:g} and rise {one.rise:g} overflow its geometry; "
                             "expected the dimensions of a bridge") from None
        if one.thickness >= least:
            raise InputError(f"{here}: 'thickness' is {one.thickness:g}; expected less than the intrados' least radius "
                             f"of curvature {one.least_radius:.4g}")
    abut = json_object(spec.get("abutments", {}), f"{where}: abutments", "'abutments'", ABUTMENT_FIELDS)
    at = f"{where}: abutments"
    b.abutment_height = _positive(abut, "height", at, b.thickness * 2)
    b.abutment_width = _positive(abut, "width", at, b.thickness * 2)
    b.abutment_kind = abut.get("kind", "rigid")
    if b.abutment_kind not in ABUTMENT_KINDS:
        raise InputError(f"{at}: 'kind' is {json.dumps(b.abutment_kind)[:30]}; expected one of "
                         f"{', '.join(ABUTMENT_KINDS)}")
    back = json_object(spec.get("backing", {}), f"{where}: backing", "'backing'", BACKING_FIELDS)
    b.backing = _positive(back, "height", f"{where}: backing", 0.0, strict=False)
    if b.backing >= b.rise + b.thickness:
        raise InputError(f"{where}: backing: 'height' is {b.backing:g}; expected less than the crown's extrados "
                         f"{b.rise + b.thickness:g} (0: no backing)")
    _read_fill(b, json_object(spec.get("fill", {}), f"{where}: fill", "'fill'", FILL_FIELDS), f"{where}: fill")
    if "load" in spec:
        _read_load(b, json_object(spec["load"], f"{where}: load", "'load'", LOAD_FIELDS), f"{where}: load")
    return b


def _arch(obj: dict, at: str) -> tuple:
    """(span, rise, shape) of one arch, checked."""
    span, rise = _positive(obj, "span", at), _positive(obj, "rise", at)
    shape = obj.get("shape", "segmental")
    if shape not in SHAPES:
        raise InputError(f"{at}: 'shape' is {json.dumps(shape)[:30]}; expected one of {', '.join(SHAPES)}")
    if shape == "segmental" and rise > span / 2 * (1 + 1e-12):
        raise InputError(f"{at}: 'rise' is {rise:g}; expected at most span / 2 = {span / 2:g} (a segmental or "
                         "semicircular arch; \"shape\": \"pointed\" for a higher one)")
    if shape == "pointed" and rise <= span / 2:
        raise InputError(f"{at}: 'rise' is {rise:g}; expected more than span / 2 = {span / 2:g} for a pointed arch")
    return span, rise, shape


def _span_ring(ring, at: str) -> tuple:
    """A span's own ring values, ((field, value), ...): its thickness, rings, voussoirs or
    crushing strength instead of the bridge's ring's."""
    ring = json_object(ring, at, "the span's ring", SPAN_RING_FIELDS)
    out = []
    for key in SPAN_RING_FIELDS:
        if key in ring:
            value = (_whole(ring, key, at, None, 1 if key == "rings" else 3) if key in ("rings", "voussoirs")
                     else _positive(ring, key, at))
            out.append((key, value))
    return tuple(out)


def _spans(spec: dict, where: str) -> tuple:
    """The arches, left to right, and the piers between them: one span (``span``, ``rise``,
    ``shape``) or ``spans`` and ``piers``, one pier fewer than spans."""
    if "spans" not in spec:
        if "piers" in spec:
            raise InputError(f"{where}: 'piers' without 'spans'; expected \"spans\": [{{\"span\": ..., \"rise\": ...}}, "
                             "...] with a pier between each two")
        return ((*_arch(spec, where), ()),), ()
    given = [key for key in ("span", "rise", "shape") if key in spec]
    if given:
        raise InputError(f"{where}: '{given[0]}' beside 'spans'; expected it inside each entry of 'spans'")
    spans, piers = spec["spans"], spec.get("piers", [])
    if not isinstance(spans, list) or not spans:
        raise InputError(f"{where}: 'spans' is {json.dumps(spans)[:40]}; expected a list of {{\"span\", \"rise\"}}")
    if not isinstance(piers, list) or len(piers) != len(spans) - 1:
        raise InputError(f"{where}: 'piers' is {json.dumps(piers)[:40]}; expected a list of {len(spans) - 1} "
                         f"pier(s), one between each two of the {len(spans)} spans")
    arches = []
    for k, raw in enumerate(spans):
        at = f"{where}: spans[{k}]"
        s = json_object(raw, at, "a span", SPAN_FIELDS)
        arches.append((*_arch(s, at), _span_ring(s.get("ring", {}), f"{at}: ring")))
    arches = tuple(arches)
    out = []
    for k, raw in enumerate(piers):
        at = f"{where}: piers[{k}]"
        pier = json_object(raw, at, "a pier", PIER_FIELDS)
        kind = pier.get("kind", "rigid")
        if kind not in ABUTMENT_KINDS:
            raise InputError(f"{at}: 'kind' is {json.dumps(kind)[:30]}; expected one of {', '.join(ABUTMENT_KINDS)}")
        out.append(Pier(_positive(pier, "height", at), _positive(pier, "width", at), kind))
    return arches, tuple(out)


def _source(spec: dict, where: str) -> dict:
    """The file's ``source``: an object of field -> citation, or one text for all."""
    value = spec.get("source", {})
    if isinstance(value, str):
        return {"all": value}
    if not isinstance(value, dict) or not all(isinstance(v, str) for v in value.values()):
        raise InputError(f"{where}: 'source' is {json.dumps(value)[:40]}; expected a text or an object of "
                         "field -> citation")
    return dict(value)


def _read_fill(b: Bridge, fill: dict, at: str):
    b.fill_depth = _positive(fill, "depth", at, 0.0, strict=False)
    b.fill_weight = _positive(fill, "unit_weight", at, Bridge.fill_weight, strict=False)
    b.phi = _positive(fill, "phi", at, Bridge.phi, strict=False)
    if b.phi >= 90:
        raise InputError(f"{at}: 'phi' is {b.phi:g}; expected an angle of friction in degrees, below 90")
    b.lateral = fill.get("lateral", Bridge.lateral)
    if b.lateral not in LATERAL:
        raise InputError(f"{at}: 'lateral' is {json.dumps(b.lateral)[:30]}; expected one of {', '.join(LATERAL)}")
    b.passive = _positive(fill, "passive", at, Bridge.passive, strict=False)
    if b.passive > 1:
        raise InputError(f"{at}: 'passive' is {b.passive:g}; expected the mobilised fraction of the passive "
                         "pressure, from 0 to 1 (0.33 for a third)")
    b.spread = _positive(fill, "spread", at, Bridge.spread, strict=False)
    if b.spread >= 90:
        raise InputError(f"{at}: 'spread' is {b.spread:g}; expected an angle from the vertical in degrees, below 90")
    b.dispersal = fill.get("dispersal", Bridge.dispersal)
    if b.dispersal not in DISPERSAL:
        raise InputError(f"{at}: 'dispersal' is {json.dumps(b.dispersal)[:30]}; expected one of {', '.join(DISPERSAL)}")


def _read_load(b: Bridge, load: dict, at: str):
    b.force = _positive(load, "force", at, Bridge.force)
    if "axles" in load:
        b.axles = _numbers(load, "axles", at, "offsets of the axles from the lead one, e.g. [0, 1.2]")
    b.patch = _positive(load, "patch", at, 0.0, strict=False)
    if "positions" in load:
        b.positions = distinct_positions(_numbers(load, "positions", at, "abscissas of the lead axle"),
                                         f"{at}: 'positions'")


def case_name(x: float) -> str:
    """The load case of the lead axle at x (a token: no spaces)."""
    return f"x={x:.6g}"


def distinct_positions(xs, at: str) -> tuple:
    """The lead axle's positions, each a load case of its own (named to 6 digits,
    :func:`case_name`): InputError on one given twice (two axle
    groups in one case would be solved as one load)."""
    seen = {}
    for x in xs:
        if case_name(x) in seen:
            raise InputError(f"{at}: {seen[case_name(x)]:g} and {x:g} are the same position (to 6 digits); "
                             "expected each position once")
        seen[case_name(x)] = x
    return tuple(float(x) for x in xs)


def passive_coefficient(phi: float) -> float:
    """Rankine's K_p = (1 + sin phi) / (1 - sin phi)."""
    s = math.sin(math.radians(phi))
    return (1 + s) / (1 - s)


def lateral_coefficient(bridge: Bridge) -> float:
    """The coefficient of the horizontal dead pressure: K0 = 1 - sin phi, K_a = 1 / K_p, or 0."""
    if bridge.lateral == "none":
        return 0.0
    if bridge.lateral == "active":
        return 1.0 / passive_coefficient(bridge.phi)
    return 1.0 - math.sin(math.radians(bridge.phi))
