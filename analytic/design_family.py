"""A family of particle/concavity designs parametrised by the few numbers that govern interference (issue 40, 1).

A member (:class:`FamilyMember`, mm) is one of two kinds, the constructions of :mod:`analytic.designs`:

* ``symmetric``: two mirror pairs on the flanks of a cup (the paper's "symmetrical" configuration);
* ``close_to_conformal``: a primary pair and a secondary pair to its right behind a non-plausible pair.

Its numbers, all measured at FIRST TOUCH (the particle moved along the design direction until the primary
pair's gap is zero; LCP of :mod:`analytic.lcp`):

    radius_convex, radius_concave   the primary pair's Hertz radii (convex > 0, concave < 0; eq. 7 gives R)
    pair_separation                 distance between the two pairs' points on the concave surface
    central_gap                     symmetric: the clearance between the particle and the concave surface on
                                    the axis (x = 0); close_to_conformal: the secondary pair's gap
    depth                           the elastic body's depth below its top at x = 0 (the half-plane's r_ref)

Derived: the relative radius R and, at a load P, the separation against the Hertz contact size,
pair_separation / (2 a), a = sqrt(4 P R / (pi E*)).

:func:`build` turns a member into a :class:`analytic.designs.ConcaveDesign` (the construction's knobs:
symmetric: the radii, a central flat and a deeper groove found by two Newton corrections on the measured
separation and central gap; close_to_conformal: the radii, the secondary abscissa and gap, directly), and
checks it with the LCP before anyone meshes it (:func:`check`): at first touch the expected plausible pairs
(two), a positive relative radius at each, and no crossing of the two curves. :data:`PAPER_MEMBERS` are the
paper's two designs, their numbers measured from :func:`analytic.designs.design` (rounded to 4-5 digits);
:func:`build` of one of them IS that design, float for float (tested).
"""

from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import numpy as np
from scipy import optimize

from analytic.designs import (
    ConcaveDesign,
    ConformalKnobs,
    SymmetricKnobs,
    build_design,
    particle_at,
)
from analytic.lcp import ContactPair, LCPResult, find_contact_pairs

__all__ = ["FAMILY_NUMBERS", "FamilyMember", "KINDS", "SYMMETRIC_TOLERANCE", "PAPER_MEMBERS", "DesignMeasure",
           "build", "check", "measure", "member", "parse_family"]

KINDS = ("symmetric", "close_to_conformal")
FAMILY_NUMBERS = ("radius_convex", "radius_concave", "pair_separation", "central_gap", "depth")  # the last optional
SYMMETRIC_TOLERANCE = (0.05, 0.005)  # mm: (pair_separation, central_gap) the symmetric constructor meets


@dataclasses.dataclass(frozen=True, kw_only=True)
class FamilyMember:
    """The numbers of one design (mm; see the module docstring for where each is measured)."""

    name: str
    kind: str
    radius_convex: float
    radius_concave: float
    pair_separation: float
    central_gap: float
    depth: float = 20.0

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"kind = {self.kind!r} out of range: need one of {KINDS}")
        for field in ("radius_convex", "pair_separation", "central_gap", "depth"):
            v = getattr(self, field)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"{field} = {v!r} out of range: need 0 < {field} < inf (mm)")
        if not (math.isfinite(self.radius_concave) and self.radius_concave < -self.radius_convex):
            raise ValueError(f"radius_concave = {self.radius_concave!r} out of range: need radius_concave < "
                             f"-radius_convex = {-self.radius_convex:.6g} mm (a concave flank less curved than "
                             "the particle: 1/R = 1/R_convex + 1/R_concave > 0)")

    @property
    def relative_radius(self) -> float:
        return 1.0 / (1.0 / self.radius_convex + 1.0 / self.radius_concave)

    def separation_over_contact(self, *, P: float, E_star: float) -> float:
        """pair_separation / (2 a) with Hertz's a = sqrt(4 P R / (pi E*)) at the load P (N/mm) of one pair."""
        return self.pair_separation / (2.0 * math.sqrt(4.0 * P * self.relative_radius / (math.pi * E_star)))


PAPER_MEMBERS: dict[str, FamilyMember] = {
    "symmetric": FamilyMember(name="symmetric", kind="symmetric", radius_convex=2.9605, radius_concave=-6.8100,
                              pair_separation=8.2730, central_gap=1.3131, depth=20.0),
    "close_to_conformal": FamilyMember(name="close_to_conformal", kind="close_to_conformal", radius_convex=41.279,
                                       radius_concave=-50.107, pair_separation=2.4037, central_gap=0.0059758,
                                       depth=20.0),
}
"""The paper's two designs as family members: numbers measured from :func:`analytic.designs.design` at first
touch (the paper quotes 2.96 / -6.81 and 41 / -50: the spline fit moves them by < 1 %)."""


class DesignMeasure(NamedTuple):
    """What :func:`measure` reads off a design at first touch: the numbers, the touch displacement d_touch
    (mm along the design direction), the primary and secondary pairs and the LCP result there."""

    numbers: FamilyMember
    d_touch: float
    primary: ContactPair
    secondary: ContactPair | None
    lcp: LCPResult


_MARGIN = 1e-5  # mm: the LCP reads the pairs this far before first touch (at |gap| < ~1e-6 a pair is a crossing)


def _touch(design: ConcaveDesign, *, n_samples: int) -> tuple[float, float, LCPResult]:
    """(d_touch, d_eval, LCP at d_eval): d_eval puts the smallest plausible gap at _MARGIN (Newton on the LCP gap,
    the gap's rate along the path -e.n), and d_touch = d_eval + _MARGIN / rate closes it."""
    e = np.asarray(design.direction, dtype=float)
    d = 0.0
    for _ in range(12):
        res = find_contact_pairs(design.concave, particle_at(design, d), n_samples=n_samples)
        if not res.pairs:
            raise ValueError(f"design {design.name!r} out of range: the LCP finds no plausible pair at d = {d:.6g}")
        p = res.pairs[0]
        rate = -float(e @ p.normal)  # -d(gap)/dd
        if not rate > 0:
            raise ValueError(f"design {design.name!r} out of range: its path does not close the primary pair")
        if abs(p.gap - _MARGIN) < 1e-3 * _MARGIN:
            return d + p.gap / rate, d, res
        d += (p.gap - _MARGIN) / rate
    raise ValueError(f"design {design.name!r}: first touch not found (last gap {p.gap:.3g} mm)")


def _y_on_axis(curve, *, lowest: bool, x0: float = 0.0) -> float:
    """y (mm) where the curve crosses x = x0 (the lowest or highest crossing)."""
    t = np.linspace(curve.t_min, curve.t_max, 4001)
    x = curve.point(t)[:, 0] - x0
    idx = np.flatnonzero(np.sign(x[:-1]) * np.sign(x[1:]) <= 0)
    ys = []
    for i in idx:
        ti = optimize.brentq(lambda s: curve.point([s])[0, 0] - x0, t[i], t[i + 1], xtol=1e-15) \
            if x[i] != x[i + 1] else t[i]
        ys.append(float(curve.point([ti])[0, 1]))
    return min(ys) if lowest else max(ys)


def measure(design: ConcaveDesign, *, kind: str, n_samples: int = 400) -> DesignMeasure:
    """The family numbers of a design (module docstring), read by the LCP at first touch."""
    d_touch, d, res = _touch(design, n_samples=n_samples)
    e = np.asarray(design.direction, dtype=float)
    primary = res.pairs[0]
    if kind == "symmetric":
        others = [p for p in res.pairs[1:] if abs(p.gap - primary.gap) < 1e-9]  # its mirror image
        if not others:
            raise ValueError(f"design {design.name!r} out of range: no mirror pair touches with the primary")
        secondary = others[0]
        part = particle_at(design, d)
        central = _y_on_axis(part, lowest=True) - _y_on_axis(design.concave, lowest=False) + e[1] * (d_touch - d)
    else:
        rest = [p for p in res.pairs[1:] if np.linalg.norm(p.point_a - primary.point_a) > 0.1]  # not the primary
        if not rest:
            raise ValueError(f"design {design.name!r} out of range: no secondary pair at first touch")
        secondary = rest[0]
        central = secondary.gap + float(e @ secondary.normal) * (d_touch - d)  # its gap at d_touch
    sep = float(np.linalg.norm(secondary.point_a - primary.point_a))
    depth = _y_on_axis(design.concave, lowest=False) - float(design.body_box[2])
    numbers = FamilyMember(name=design.name, kind=kind, radius_convex=primary.radius_b,
                           radius_concave=primary.radius_a, pair_separation=sep, central_gap=float(central),
                           depth=depth)
    return DesignMeasure(numbers, d_touch, primary, secondary, res)


def check(design: ConcaveDesign, *, kind: str, n_samples: int = 400) -> DesignMeasure:
    """The LCP check before use: two plausible pairs with R > 0 at first touch and no crossing there."""
    m = measure(design, kind=kind, n_samples=n_samples)
    for label, p in (("primary", m.primary), ("secondary", m.secondary)):
        if not (p.plausible and p.relative_radius > 0):
            raise ValueError(f"design {design.name!r} out of range: its {label} pair is not a plausible convex "
                             f"contact (R = {p.relative_radius:.6g} mm)")
    if m.lcp.intersections:
        raise ValueError(f"design {design.name!r} out of range: the curves cross at first touch "
                         f"(x = {m.lcp.intersections[0].point[0]:.6g} mm)")
    return m


def _is_paper(mem: FamilyMember) -> bool:
    ref = PAPER_MEMBERS.get(mem.kind)
    return ref is not None and dataclasses.replace(mem, name=ref.name) == ref


def _symmetric_knobs(mem: FamilyMember) -> SymmetricKnobs:
    """Radii and clearance first (the line of centres keeps the paper's direction and centre-distance clearance
    (R2 - R1) - |v|), then the central flat w and the groove extra e from the linear model
    separation = S + 2 w + sqrt(2) e, central gap = G + e / sqrt(2), corrected by Broyden steps on the measured
    design to :data:`SYMMETRIC_TOLERANCE` (the spline fit's curvature ripple moves the measured pair points by
    a few 0.01 mm from one knob setting to the next: measured +-0.04 mm for knob steps of 0.006 mm)."""
    base = SymmetricKnobs()
    clearance = (base.r_concave - base.r_convex) - math.hypot(*base.v)
    r1, r2 = mem.radius_convex, -mem.radius_concave
    length = (r2 - r1) - clearance
    if not length > 0:
        raise ValueError(f"radius_concave = {mem.radius_concave!r} out of range: need -radius_concave > "
                         f"radius_convex + {clearance:.4g} mm (the particle must fit the flank)")
    v = tuple(c * length / math.hypot(*base.v) for c in base.v)
    knobs = SymmetricKnobs(r_convex=r1, r_concave=r2, v=v, depth=mem.depth)
    x = np.zeros(2)  # (w, e)
    J = np.array([[2.0, math.sqrt(2.0)], [0.0, 1.0 / math.sqrt(2.0)]])  # d(separation, gap)/d(w, e), model
    target = np.array([mem.pair_separation, mem.central_gap])
    prev = None
    for _ in range(8):
        got = measure(build_design(knobs, name=mem.name), kind="symmetric").numbers
        f = np.array([got.pair_separation, got.central_gap]) - target
        if abs(f[0]) < SYMMETRIC_TOLERANCE[0] and abs(f[1]) < SYMMETRIC_TOLERANCE[1]:
            break
        if prev is not None:  # Broyden's update of the model Jacobian from the last step
            dx, df = x - prev[0], f - prev[1]
            J += np.outer(df - J @ dx, dx) / float(dx @ dx)
        prev = (x.copy(), f)
        x = x - np.linalg.solve(J, f)
        if x[1] < -0.6 or x[0] < 0.0:
            raise ValueError(f"pair_separation, central_gap = {mem.pair_separation!r}, {mem.central_gap!r} out of "
                             "range: the symmetric groove cannot place the pairs so close together at this gap "
                             f"(needs a central flat {x[0]:.4g} >= 0 mm and a groove straight {0.6 + x[1]:.4g} >= 0 "
                             f"mm; at these radii the pairs are at least {got.pair_separation - 2 * x[0]:.4g} mm "
                             "apart)")
        knobs = knobs._replace(centre_flat=float(x[0]), groove_extra=float(x[1]))
    return knobs


def build(mem: FamilyMember, *, n_samples: int = 400) -> tuple[ConcaveDesign, DesignMeasure]:
    """The design of a member and its LCP check (ValueError, one line, if the check fails)."""
    if _is_paper(mem):
        knobs = SymmetricKnobs() if mem.kind == "symmetric" else ConformalKnobs()
        des = build_design(knobs, name=mem.kind)
    elif mem.kind == "symmetric":
        des = build_design(_symmetric_knobs(mem), name=mem.name)
        got = check(des, kind=mem.kind, n_samples=n_samples)
        miss = (got.numbers.pair_separation - mem.pair_separation, got.numbers.central_gap - mem.central_gap)
        if abs(miss[0]) > SYMMETRIC_TOLERANCE[0] or abs(miss[1]) > SYMMETRIC_TOLERANCE[1]:
            raise ValueError(f"pair_separation, central_gap = {mem.pair_separation!r}, {mem.central_gap!r} out of "
                             f"range: the symmetric construction misses them by {miss[0]:.3g}, {miss[1]:.3g} mm")
        return des, got
    else:
        knobs = ConformalKnobs(r_convex=mem.radius_convex, r_concave=-mem.radius_concave, x2=mem.pair_separation,
                               eps=mem.central_gap, depth=mem.depth)
        if not 0.5 <= mem.pair_separation <= 6.0:
            raise ValueError(f"pair_separation = {mem.pair_separation!r} out of range: the close-to-conformal "
                             "construction needs 0.5 <= pair_separation <= 6 mm")
        if not mem.central_gap < 0.015:
            raise ValueError(f"central_gap = {mem.central_gap!r} out of range: the close-to-conformal construction "
                             "needs central_gap < 0.015 mm (the non-plausible hump between the pairs)")
        des = build_design(knobs, name=mem.name)
    return des, check(des, kind=mem.kind, n_samples=n_samples)


def member(name: str) -> FamilyMember:
    """A named member: one of :data:`PAPER_MEMBERS`."""
    if name not in PAPER_MEMBERS:
        raise ValueError(f"design = {name!r} out of range: need one of {sorted(PAPER_MEMBERS)}")
    return PAPER_MEMBERS[name]


def parse_family(kind: str, text: str, *, field: str = "family") -> FamilyMember:
    """The member of kind ``kind`` named by its numbers ``text`` = ``key=value,...`` (keys :data:`FAMILY_NUMBERS`,
    each once, mm; ``depth`` optional, 20). The one parser of a member's numbers: a case file's
    ``geometry.family`` and ``workbench forcelaw KIND:...`` both come here. Its name ``<kind>_family_<hash>``
    (the hash of the kind and the sorted numbers) names its meshes and its force-law folder. ValueError (one line
    naming ``field``): an unknown kind, an unknown, repeated or valueless key, a non-number, a missing number."""
    import hashlib

    if kind not in KINDS:
        raise ValueError(f"{field} kind = {kind[:40]!r} out of range: need one of {KINDS}")
    values: dict[str, float] = {}
    for item in filter(None, (t.strip() for t in text.split(","))):
        key, eq, val = item.partition("=")
        key = key.strip()
        if key not in FAMILY_NUMBERS or not eq or key in values:
            raise ValueError(f"{field} item {item[:40]!r} out of range: need key=value once per key, "
                             f"keys in {FAMILY_NUMBERS}")
        try:
            values[key] = float(val)
        except ValueError:
            raise ValueError(f"{field} {key} = {val.strip()[:40]!r} out of range: need a number (mm)") from None
    missing = [k for k in FAMILY_NUMBERS[:4] if k not in values]
    if missing:
        raise ValueError(f"{field} lacks {', '.join(missing)}: need all of {FAMILY_NUMBERS[:4]} "
                         "(depth optional, 20 mm)")
    tag = hashlib.sha256(repr((kind, sorted(values.items()))).encode()).hexdigest()[:10]
    return FamilyMember(name=f"{kind}_family_{tag}", kind=kind, **values)
