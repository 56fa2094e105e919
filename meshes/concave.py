"""Elastic body with a concave B-spline top (the close-to-conformal paper's scenes): linear triangles.

Geometry: the top boundary is the design's clamped cubic B-spline, built in gmsh's OpenCASCADE kernel from
the SAME control points, degree and knot vector (open uniform: knots 0, 1/(m-3), ..., 1 with end
multiplicity 4), so the gmsh curve is the analytic curve and the mesh nodes of ``contact`` lie on it to
round-off (checked: ``stats["contact_node_deviation_max"]``, the largest |signed distance| of the contact
nodes to the analytic curve). The vertical sides at x_min / x_max run from the spline ends down to the
horizontal bottom y = y_bottom (``design.body_box``).

Refinement: the top spline is split (OCC fragment) at the ends of the refinement intervals; the size is
h_contact on those sub-curves and grows as h = h_contact + (growth - 1) d with the distance d, up to h_far.
By default the intervals are the geometric overlap zones of the rigid curves at the design's largest step
(between the curve intersections that bracket each plausible LCP pair, :func:`refine_intervals`), expanded by
``margin``; two intervals closer than a quarter of their length merge, so the region between two close pairs
is refined too (where the patches merge).

Portability: the control points handed to gmsh are the frozen table of the design (:mod:`meshes.frozen`), the
interval ends, sizes and cut points are rounded (:mod:`meshes.portable`), so the mesh does not depend on the
last bits numpy/OpenBLAS give the design on a given machine (``stats["fingerprint"]`` names the mesh).

Physical groups: ``contact`` (the whole spline), ``clamped`` (sides + bottom), ``body``.
"""

from __future__ import annotations

import hashlib

import numpy as np

from analytic.curves import BSpline
from meshes.cache import DEFAULT_CACHE_DIR, MeshFiles
from meshes.frozen import frozen_control_points
from meshes.pipeline import build_cached
from meshes.portable import GmshInputs
from meshes.sizing import apply_background, growth_field, validate_common

__all__ = ["build_concave_mesh", "refine_intervals", "SIZE_SAFETY"]

SIZE_SAFETY = 0.9  # contact target 0.9 h_contact: gmsh rounds the number of 1D subdivisions


def _resolve(design):
    from analytic.designs import ConcaveDesign
    from analytic.designs import design as get_design

    if isinstance(design, str):
        return get_design(design)
    if not isinstance(design, ConcaveDesign):
        raise ValueError(f"design must be a ConcaveDesign or a design name, got {type(design).__name__}")
    return design


def refine_intervals(design, *, d: float | None = None, margin: float = 0.25,
                     min_half_width: float = 0.5) -> list[tuple[float, float]]:
    """Parameter intervals (t_lo, t_hi) on ``design.concave`` to refine, from the LCP at displacement d.

    For each plausible pair at d (default: the largest Table 1 step) the interval is the overlap zone between
    the two curve intersections bracketing it (or +-min_half_width mm of arc around the pair when the curves
    do not overlap there), expanded on each side by ``margin`` times its length; overlapping or close
    intervals (gap < a quarter of the shorter one) are merged.
    """
    from analytic.designs import particle_at
    from analytic.lcp import find_contact_pairs

    des = _resolve(design)
    d = max(des.table1_d) if d is None else float(d)
    res = find_contact_pairs(des.concave, particle_at(des, d), n_samples=300)
    curve = des.concave
    s_of = curve.arc_length
    total = float(s_of([curve.t_max])[0])
    s_x = np.sort([float(s_of([c.t_a])[0]) for c in res.intersections])
    spans = []
    for p in res.pairs:
        sp = float(s_of([p.t_a])[0])
        lo = s_x[s_x < sp].max() if p.gap < 0 and (s_x < sp).any() else sp - min_half_width
        hi = s_x[s_x > sp].min() if p.gap < 0 and (s_x > sp).any() else sp + min_half_width
        lo, hi = min(lo, sp - min_half_width), max(hi, sp + min_half_width)
        ext = margin * (hi - lo)
        spans.append([max(0.0, lo - ext), min(total, hi + ext)])
    spans.sort()
    merged: list[list[float]] = []
    for lo, hi in spans:
        if merged and lo - merged[-1][1] < 0.25 * min(hi - lo, merged[-1][1] - merged[-1][0]):
            merged[-1][1] = max(merged[-1][1], hi)
        else:
            merged.append([lo, hi])
    # arc length -> parameter
    tt = np.linspace(curve.t_min, curve.t_max, 20001)
    ss = s_of(tt)
    return [(float(np.interp(lo, ss, tt)), float(np.interp(hi, ss, tt))) for lo, hi in merged]


def build_concave_mesh(*, design, h_contact: float, h_far: float | None = None, growth: float = 1.3,
                       refine_at=None, margin: float = 0.25, out_dir=DEFAULT_CACHE_DIR,
                       name: str | None = None, write_xdmf: bool = True, stats_dir=None,
                       comm=None) -> MeshFiles:
    """Build (or reuse from the cache) the mesh of the elastic body below ``design.concave``.

    Args:
        design: :class:`analytic.designs.ConcaveDesign` or a design name.
        h_contact: element size on the refinement intervals of the spline (mm).
        h_far: size far away (mm); default (x_max - x_min) / 10.
        growth: element-to-element size ratio, in (1, 3].
        refine_at: list of (t_lo, t_hi) parameter intervals on ``design.concave``; default
            :func:`refine_intervals` at the largest Table 1 step with the given ``margin``.
        margin: relative margin of the default intervals.
        out_dir: cache directory; name: file stem (default the design name).
        write_xdmf / stats_dir / comm: as in :func:`meshes.block.build_block_mesh`.
    """
    des = _resolve(design)
    x_min, x_max, y_bottom = map(float, des.body_box)
    h_far = (x_max - x_min) / 10.0 if h_far is None else float(h_far)
    h_far = max(h_far, h_contact)
    validate_common(h_contact=h_contact, h_far=h_far, growth=growth)
    curve = des.concave
    runtime_cp = np.asarray(curve.control_points, dtype=float)
    ends = curve.point([curve.t_min, curve.t_max])
    if not (abs(ends[0, 0] - x_min) < 1e-9 and abs(ends[1, 0] - x_max) < 1e-9):
        raise ValueError(f"design.concave must run from x_min={x_min} to x_max={x_max}, got {ends[:, 0]}")
    if not y_bottom < min(ends[:, 1].min(), curve.sample(2001)[:, 1].min()):
        raise ValueError(f"body_box y_bottom must lie below the concave curve, got {y_bottom}")
    if refine_at is None:
        refine_at = refine_intervals(des, margin=margin)
    intervals = sorted((float(a), float(b)) for a, b in refine_at)
    for a, b in intervals:
        if not (curve.t_min <= a < b <= curve.t_max):
            raise ValueError(f"refine_at intervals must satisfy {curve.t_min} <= lo < hi <= {curve.t_max}, "
                             f"got {(a, b)}")
    name = des.name if name is None else name
    # every float handed to gmsh, rounded to the portable grids (then perturbed when asked), in one funnel
    gi = GmshInputs(scale=x_max - x_min)  # the body width: a case constant (the grid must not depend on the machine)
    frozen = frozen_control_points(des.name, runtime_cp)
    source = "rounded" if frozen is None else "frozen"
    if frozen is None:
        cp = np.array([[gi.length(x), gi.length(y)] for x, y in runtime_cp])
    else:
        cp = np.array([[gi.exact(x), gi.exact(y)] for x, y in frozen])
    box = [gi.length(x_min), gi.length(x_max), gi.length(y_bottom)]
    h_c, h_far_g, growth_g = gi.size(h_contact), gi.size(h_far), gi.size(growth)
    h0 = gi.size(SIZE_SAFETY * h_c)
    sampling = gi.size(h_c / 4.0)
    length = gi.size(float(curve.length()))
    intervals = [(gi.param(a), gi.param(b)) for a, b in intervals]
    if any(not a < b for a, b in intervals):
        raise ValueError(f"refine_at intervals must be longer than 2**-24 in t, got {intervals}")
    cuts = sorted({t for iv in intervals for t in iv if curve.t_min < t < curve.t_max})
    # the knots: np.linspace (one multiply and one add per entry, each correctly rounded): machine-independent
    knots = [gi.fixed(k) for k in np.unique(curve.knots)]
    gmsh_curve = BSpline(cp, degree=curve.degree)  # the curve gmsh builds: cut points lie on it
    cut_xy = [(gi.length(x, perturb=False), gi.length(y, perturb=False)) for x, y in gmsh_curve.point(cuts)]
    params = dict(design=des.name, control_points_sha=hashlib.sha256(cp.tobytes()).hexdigest()[:16],
                  body_box=box, h_contact=h_c, h_far=h_far_g, growth=growth_g, refine_at=intervals,
                  geometry_source=source)

    def make(gmsh):
        occ = gmsh.model.occ
        deg = curve.degree
        mults = [deg + 1] + [1] * (len(knots) - 2) + [deg + 1]
        pts = [occ.addPoint(x, y, 0.0) for x, y in cp]
        spline = occ.addBSpline(pts, degree=deg, knots=knots, multiplicities=mults)
        p_bl = occ.addPoint(box[0], box[2], 0.0)
        p_br = occ.addPoint(box[1], box[2], 0.0)
        bottom = occ.addLine(p_bl, p_br)
        right = occ.addLine(p_br, pts[-1])
        left = occ.addLine(pts[0], p_bl)
        loop = occ.addCurveLoop([bottom, right, spline, left])
        surf = occ.addPlaneSurface([loop])
        # split the spline at the interval ends (mesh nodes there; sub-curves carry the refinement)
        if cut_xy:
            cut_pts = [occ.addPoint(x, y, 0.0) for x, y in cut_xy]
            occ.fragment([(2, surf)], [(0, p) for p in cut_pts])
        occ.synchronize()
        # remove free points (control points) left in the model
        surfaces = gmsh.model.getEntities(2)
        bnd = gmsh.model.getBoundary(surfaces, oriented=False)
        curves = [abs(c) for _, c in bnd]
        top, clamped, inside = [], [], []
        for c in curves:
            lo, hi = gmsh.model.getParametrizationBounds(1, c)
            mid = np.asarray(gmsh.model.getValue(1, c, [0.5 * (lo[0] + hi[0])]))[:2]
            proj = curve.project(mid.reshape(1, 2))
            if abs(proj.distance[0]) > 1e-6 * (x_max - x_min):  # a side or the bottom
                clamped.append(c)
                continue
            top.append(c)
            t_mid = float(proj.t[0])
            if any(a <= t_mid <= b for a, b in intervals):
                inside.append(c)
        fields = [growth_field(gmsh, h0=h0, h_max=h_far_g, growth=growth_g, curves=inside or top,
                               curve_length=length, sampling_size=sampling)]  # no interval: the whole spline
        apply_background(gmsh, fields, h_max=h_far_g)
        groups = {
            "contact": (1, gmsh.model.addPhysicalGroup(1, top, name="contact")),
            "clamped": (1, gmsh.model.addPhysicalGroup(1, clamped, name="clamped")),
            "body": (2, gmsh.model.addPhysicalGroup(2, [s for _, s in surfaces], name="body")),
        }
        gmsh.model.mesh.generate(2)

        def window(mid_pts):
            t = curve.project(mid_pts).t
            mask = np.zeros(len(t), dtype=bool)
            for a, b in intervals:
                mask |= (t >= a) & (t <= b)
            return mask

        return top, window, groups

    def deviation(points, tri, edges):  # noqa: ARG001
        nodes = np.unique(edges)
        dev = np.abs(curve.project(points[nodes, :2]).distance)
        return {"contact_node_deviation_max": float(dev.max())}

    return build_cached(kind="concave", params=params, name=name, out_dir=out_dir, make=make, inputs=gi,
                        body_size=gi.scale, geometry_source=source, write_xdmf=write_xdmf,
                        stats_dir=stats_dir, comm=comm, extra_stats=deviation)
