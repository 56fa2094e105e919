"""Two elastic bodies in one mesh, meshed independently (non-matching contact surfaces): linear triangles.

Each body is its own gmsh surface with its own points and curves, so the two contact surfaces share no node
and their nodes fall where each body's own sizes put them. Units mm.

Builders:

* :func:`build_stacked_blocks`: the contact patch test. A lower block ``[0, W] x [-H1, 0]`` under an upper block
  ``[0, W] x [0, H2]``, element sizes ``h_lower`` and ``h_upper`` (their ratio should not be rational with a small
  denominator: the nodes of the interface must not coincide).
* :func:`build_profile_blocks`: two half-planes with a profile (issue 25): a lower block
  ``[-W/2, W/2] x [-H, 0]`` under an upper block ``[-W/2, W/2] x [0, H]``, both flat at y = 0 (the gap profile is
  not meshed: it is the upper body's analytic reference height above its flat face,
  :class:`fem.two_body.geometry.ProfileSurface`); size ``h_contact`` on the lower block's top where
  ``|x| <= a (1 + margin)`` and ``size_ratio h_contact`` on the upper block's bottom over a window split
  unsymmetrically (:data:`ARC_SPLIT`), each growing away into its own block. With ``wedge_slope`` m the upper body
  is shaped instead: an elastic wedge whose faces ``y = m |x|`` are meshed (its apex a mesh corner at the origin);
  with ``parabola_radius`` R a parabolic body whose lower face ``y = x^2 / (2 R)`` is meshed (each segment of it a
  quadratic Bezier curve, which is that parabola exactly, so its mesh nodes lie on it to round-off).
* :func:`build_cylinder_on_block`: an elastic half disk of radius R (the lower half of the circle centred at
  ``(0, R)``, flat top at ``y = R``) on a block ``[-W/2, W/2] x [-H, 0]``; size ``h_contact`` on both contact
  surfaces where ``|x| <= a (1 + margin)``, growing away (as :mod:`meshes.block`), with another size on the disk
  (``disk_size_ratio``) so that the surfaces do not match. The disk's arc is split at angles off its lowest
  point, so no geometric point sits at the first-contact point.

Physical groups (names are the contract): cells ``lower`` and ``upper``; facets ``contact_lower`` (top of the
lower block), ``contact_upper`` (the upper body's surface that faces it), ``clamped`` (bottom of the lower
block), ``driven`` (top of the upper body), ``symmetry`` (x = 0 edges of both blocks: stacked blocks only),
``sides``.
"""

from __future__ import annotations

import math

from meshes.cache import DEFAULT_CACHE_DIR, MeshFiles
from meshes.pipeline import build_cached
from meshes.portable import GmshInputs
from meshes.sizing import apply_background, growth_field, validate_common

__all__ = ["build_stacked_blocks", "build_cylinder_on_block", "build_profile_blocks", "ARC_SPLIT"]

# The disk's refined central arc spans x = -ARC_SPLIT[0] b ... +ARC_SPLIT[1] b (b = a (1 + margin), the block's
# refined window): not symmetric, so its nodes do not fall on x = 0 where the block's might. (Until 2026-11 the split
# was at fixed angles, 23 and 29 degrees: a refined arc of 0.9 R, 18 a at a/R = 0.05, that made the disk 4x the
# block's cells at a/R = 0.05 and 17x at a/R = 0.0125.)
ARC_SPLIT = (1.0, 1.17)


def _far_size(*, ratio_name: str, ratio: float, width: float, h_contact: float, h_far: float | None,
              growth: float) -> float:
    """Check the two sides' size ratio (non-matching meshes) and the grading; the far size h_far (mm, default W/10)."""
    if not (0.2 < ratio < 5.0) or abs(ratio - 1.0) < 0.05:
        raise ValueError(f"{ratio_name} must be in (0.2, 5) and differ from 1 by >= 0.05, got {ratio}")
    h_far = max(width / 10.0 if h_far is None else float(h_far), h_contact)
    validate_common(h_contact=h_contact, h_far=h_far, growth=growth)
    return h_far


def _restricted(gmsh, fields) -> list[int]:
    """Each size field ``(field, surface, curves)`` restricted to its own body (the surface and its bounding
    curves), so that one body's refinement does not reach the other's: the Restrict fields' tags."""
    out = []
    for f, surf, curves in fields:
        r = gmsh.model.mesh.field.add("Restrict")
        gmsh.model.mesh.field.setNumber(r, "InField", f)
        gmsh.model.mesh.field.setNumbers(r, "SurfacesList", [surf])
        gmsh.model.mesh.field.setNumbers(r, "CurvesList", list(curves))
        out.append(r)
    return out


def _positive(**vals) -> None:
    for arg, val in vals.items():
        if not (val > 0.0 and math.isfinite(val)):
            raise ValueError(f"{arg} must be > 0 (mm), got {val}")


def build_stacked_blocks(*, width: float, height_lower: float, height_upper: float, h_lower: float,
                         h_upper: float, out_dir=DEFAULT_CACHE_DIR, name: str = "stacked_blocks",
                         write_xdmf: bool = False, stats_dir=None, comm=None) -> MeshFiles:
    """The patch-test mesh (module docstring): two blocks of width W, uniform sizes h_lower and h_upper."""
    _positive(width=width, height_lower=height_lower, height_upper=height_upper, h_lower=h_lower,
              h_upper=h_upper)
    if abs(h_lower - h_upper) <= 1e-9 * max(h_lower, h_upper):
        raise ValueError("h_lower and h_upper must differ (the patch test needs non-matching meshes)")
    gi = GmshInputs(scale=max(width, height_lower, height_upper))
    W, H1, H2 = gi.length(width), gi.length(height_lower), gi.length(height_upper)
    h1, h2 = gi.size(h_lower), gi.size(h_upper)
    params = dict(width=W, height_lower=H1, height_upper=H2, h_lower=h1, h_upper=h2)

    def make(gmsh):
        geo = gmsh.model.geo

        def block(y0, y1, h):
            p = [geo.addPoint(0.0, y0, 0.0, h), geo.addPoint(W, y0, 0.0, h), geo.addPoint(W, y1, 0.0, h),
                 geo.addPoint(0.0, y1, 0.0, h)]
            lines = [geo.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]  # bottom, right, top, left
            return lines, geo.addPlaneSurface([geo.addCurveLoop(lines)])

        (lb, lr, lt, ll), low = block(-H1, 0.0, h1)
        (ub, ur, ut, ul), up = block(0.0, H2, h2)
        geo.synchronize()
        pg = gmsh.model.addPhysicalGroup
        groups = {"contact_lower": (1, pg(1, [lt], name="contact_lower")),
                  "contact_upper": (1, pg(1, [ub], name="contact_upper")),
                  "clamped": (1, pg(1, [lb], name="clamped")),
                  "driven": (1, pg(1, [ut], name="driven")),
                  "symmetry": (1, pg(1, [ll, ul], name="symmetry")),
                  "sides": (1, pg(1, [lr, ur], name="sides")),
                  "lower": (2, pg(2, [low], name="lower")),
                  "upper": (2, pg(2, [up], name="upper"))}
        for opt, val in (("Mesh.Algorithm", 6), ("Mesh.ElementOrder", 1), ("General.NumThreads", 1),
                         ("Mesh.MaxNumThreads1D", 1), ("Mesh.MaxNumThreads2D", 1), ("Mesh.RandomSeed", 1),
                         ("Mesh.RandomFactor", 1e-9), ("Mesh.MeshSizeFromCurvature", 0)):
            gmsh.option.setNumber(opt, val)
        gmsh.model.mesh.generate(2)

        def window(mid):
            return mid[:, 0] >= -1.0

        return [lt], window, groups

    return build_cached(kind="stacked_blocks", params=params, name=name, out_dir=out_dir, make=make, inputs=gi,
                        body_size=gi.scale, geometry_source="parameters", write_xdmf=write_xdmf,
                        stats_dir=stats_dir, comm=comm)


def build_cylinder_on_block(*, radius: float, width: float, height: float, contact_half_width: float,
                            h_contact: float, disk_size_ratio: float = 0.77, h_far: float | None = None,
                            growth: float = 1.3, margin: float = 0.5, out_dir=DEFAULT_CACHE_DIR,
                            name: str = "cylinder_on_block", write_xdmf: bool = False, stats_dir=None,
                            comm=None, indenter: bool = True) -> MeshFiles:
    """The elastic half disk on the elastic block (module docstring).

    Args:
        radius: R (mm).  width, height: W and H of the block (mm), W > 2 a (1 + margin).
        contact_half_width: the contact half-width estimate a (mm).
        h_contact: size on the block's contact zone (mm); the disk's is ``disk_size_ratio h_contact``.
        disk_size_ratio: in (0.2, 5), not 1 (non-matching meshes).
        h_far, growth, margin: as :func:`meshes.block.build_block_mesh`.
        indenter: False meshes the block alone, node for node the same (its sizes depend on its own curves
            only): the mesh of the rigid-indenter twin (the rigid-limit test).
    """
    _positive(radius=radius, width=width, height=height, contact_half_width=contact_half_width,
              h_contact=h_contact)
    h_far = _far_size(ratio_name="disk_size_ratio", ratio=disk_size_ratio, width=width, h_contact=h_contact,
                      h_far=h_far, growth=growth)
    a = float(contact_half_width)
    b = a * (1.0 + margin)
    if not width / 2.0 > b or not radius > ARC_SPLIT[1] * b:
        raise ValueError(f"width / 2 must be > a (1 + margin) = {b} (mm) and radius > {ARC_SPLIT[1] * b} (mm)")
    gi = GmshInputs(scale=max(width, height, 2.0 * radius))
    R, W, H, a = gi.length(radius), gi.length(width), gi.length(height), gi.length(a)
    b = gi.length(a * (1.0 + margin))
    h_c, h_far, growth = gi.size(0.9 * h_contact), gi.size(h_far), gi.size(growth)
    h_d = gi.size(0.9 * h_contact * disk_size_ratio)
    params = dict(radius=R, width=W, height=H, a=a, b=b, h_contact=h_c, h_disk=h_d, h_far=h_far, growth=growth,
                  margin=float(margin), split=ARC_SPLIT, indenter=bool(indenter))
    angles = [-0.5 * math.pi - math.asin(min(1.0, ARC_SPLIT[0] * b / R)),
              -0.5 * math.pi + math.asin(min(1.0, ARC_SPLIT[1] * b / R))]
    arc_pts = [(gi.length(R * math.cos(t)), gi.length(R + R * math.sin(t))) for t in angles]

    def make(gmsh):
        geo = gmsh.model.geo
        # lower block, top edge split at +-b (no point at x = 0)
        p = [geo.addPoint(-W / 2, -H, 0.0), geo.addPoint(W / 2, -H, 0.0), geo.addPoint(W / 2, 0.0, 0.0),
             geo.addPoint(b, 0.0, 0.0), geo.addPoint(-b, 0.0, 0.0), geo.addPoint(-W / 2, 0.0, 0.0)]
        bottom, right = geo.addLine(p[0], p[1]), geo.addLine(p[1], p[2])
        top = [geo.addLine(p[2], p[3]), geo.addLine(p[3], p[4]), geo.addLine(p[4], p[5])]
        left = geo.addLine(p[5], p[0])
        low = geo.addPlaneSurface([geo.addCurveLoop([bottom, right, *top, left])])
        geo.synchronize()
        fields = [growth_field(gmsh, h0=h_c, h_max=h_far, growth=growth, curves=[top[1]], curve_length=2 * b,
                               sampling_size=gi.size(h_c / 4.0))]
        bodies = [(low, top)]
        pg = gmsh.model.addPhysicalGroup
        if indenter:
            # upper half disk: centre (0, R), arcs (-R, R) -> split left -> split right -> (R, R), flat top back
            c = geo.addPoint(0.0, R, 0.0)
            q_left, q_right = geo.addPoint(-R, R, 0.0), geo.addPoint(R, R, 0.0)
            s1, s2 = (geo.addPoint(x, y, 0.0) for x, y in arc_pts)
            arcs = [geo.addCircleArc(q_left, c, s1), geo.addCircleArc(s1, c, s2), geo.addCircleArc(s2, c, q_right)]
            flat = geo.addLine(q_right, q_left)
            up = geo.addPlaneSurface([geo.addCurveLoop([*arcs, flat])])
            geo.synchronize()
            fields.append(growth_field(gmsh, h0=h_d, h_max=h_far, growth=growth, curves=[arcs[1]],
                                       curve_length=R * (angles[1] - angles[0]),
                                       sampling_size=gi.size(h_d / 4.0)))
            bodies.append((up, arcs))
        else:
            geo.synchronize()
        # each body's refinement reaches only its own surface: restrict each field to its body
        apply_background(gmsh, _restricted(gmsh, [(f, surf, curves) for f, (surf, curves) in
                                                  zip(fields, bodies, strict=True)]), h_max=h_far)
        groups = {"contact_lower": (1, pg(1, top, name="contact_lower")),
                  "clamped": (1, pg(1, [bottom], name="clamped")),
                  "sides": (1, pg(1, [left, right], name="sides")),
                  "lower": (2, pg(2, [low], name="lower"))}
        if indenter:
            groups.update({"contact_upper": (1, pg(1, arcs, name="contact_upper")),
                           "driven": (1, pg(1, [flat], name="driven")),
                           "upper": (2, pg(2, [up], name="upper"))})
        gmsh.model.mesh.generate(2)

        def window(mid):
            return abs(mid[:, 0]) <= a * (1.0 + 1e-9)

        return top, window, groups

    return build_cached(kind="cylinder_on_block", params=params, name=name, out_dir=out_dir, make=make,
                        inputs=gi, body_size=gi.scale, geometry_source="parameters", write_xdmf=write_xdmf,
                        stats_dir=stats_dir, comm=comm)


def build_profile_blocks(*, width: float, height: float, contact_half_width: float, h_contact: float,
                         size_ratio: float = 0.77, h_far: float | None = None, growth: float = 1.3,
                         margin: float = 0.5, apex_factor: float | None = None, wedge_slope: float | None = None,
                         parabola_radius: float | None = None, parabola_cap: float | None = None,
                         out_dir=DEFAULT_CACHE_DIR, name: str = "profile_blocks", write_xdmf: bool = False,
                         stats_dir=None, comm=None) -> MeshFiles:
    """Two graded blocks W x H, one above the other, flat at y = 0 (module docstring): two half-planes.

    Args:
        width, height: W and H of each block (mm), W > 2 ARC_SPLIT[1] a (1 + margin).
        contact_half_width: the contact half-width estimate a (mm).
        h_contact: size on the lower block's contact window (mm); the upper block's is ``size_ratio h_contact``.
        size_ratio: in (0.2, 5), differing from 1 by >= 0.05 (non-matching meshes).
        h_far, growth, margin: as :func:`meshes.block.build_block_mesh`.
        apex_factor: None, or a wedge's apex: both contact lines get a node at x = 0 and each block's size there
            is ``apex_factor`` times its own contact size, growing away (as the block scene's apex refinement).
        wedge_slope: None (the upper block is flat at y = 0), or the face slope m > 0 of a shaped upper body: an
            elastic wedge whose lower faces are ``y = m |x|`` (apex at the origin, a corner of the mesh) up to
            ``|x| = W/2``, with vertical sides up to ``y = m W/2 + H`` (issue 25: the real geometry the
            half-plane theory idealises). Needs ``apex_factor``.
        parabola_radius: None, or R > 0 of a parabola-shaped upper body: its lower face is ``y = x^2 / (2 R)`` up to
            ``|x| = W/2``, vertical sides up to ``y = W^2 / (8 R) + H`` (the real geometry the parabolic gap of the
            half-plane theory idealises; ``workbench export`` of the halfplanes cases). Not with ``wedge_slope``.
        parabola_cap: None (the parabola up to ``|x| = W/2``), or x_c (mm, above the upper window's end
            ``ARC_SPLIT[1] a (1 + margin)`` and below W/2) with ``parabola_radius``: the parabola over ``|x| <= x_c``
            and flat beyond, at ``y = x_c^2 / (2 R)``, the sides up to ``y = x_c^2 / (2 R) + H``: a block with a
            parabolic bump, a half-plane with the profile meshed (the finite-strain runs, issue 39: the whole
            parabola up to W/2 is a nose W^2 / (8 R) tall, whose tip is laterally soft).
    """
    _positive(width=width, height=height, contact_half_width=contact_half_width, h_contact=h_contact)
    if apex_factor is not None and not 0.0 < apex_factor <= 1.0:
        raise ValueError(f"apex_factor must be in (0, 1], got {apex_factor}")
    if wedge_slope is not None and not (0.0 < wedge_slope <= 10.0 and apex_factor is not None):
        raise ValueError(f"wedge_slope must be in (0, 10] with an apex_factor, got {wedge_slope}")
    if parabola_radius is not None and not (wedge_slope is None and 0.0 < parabola_radius < math.inf):
        raise ValueError(f"parabola_radius must be a finite length > 0 (mm), without wedge_slope, got "
                         f"{parabola_radius}")
    h_far = _far_size(ratio_name="size_ratio", ratio=size_ratio, width=width, h_contact=h_contact, h_far=h_far,
                      growth=growth)
    a = float(contact_half_width)
    if not width / 2.0 > ARC_SPLIT[1] * a * (1.0 + margin):
        raise ValueError(f"width / 2 must be > {ARC_SPLIT[1]} a (1 + margin) = {ARC_SPLIT[1] * a * (1 + margin)} (mm)")
    if parabola_cap is not None and not (parabola_radius is not None
                                         and ARC_SPLIT[1] * a * (1.0 + margin) < parabola_cap < width / 2.0):
        raise ValueError(f"parabola_cap must be in ({ARC_SPLIT[1] * a * (1 + margin):g}, {width / 2.0:g}) mm, with "
                         f"parabola_radius, got {parabola_cap}")
    gi = GmshInputs(scale=max(width, height))
    W, H, a = gi.length(width), gi.length(height), gi.length(a)
    b = gi.length(a * (1.0 + margin))
    h_c, h_u = gi.size(0.9 * h_contact), gi.size(0.9 * h_contact * size_ratio)
    h_far, growth = gi.size(h_far), gi.size(growth)
    params = dict(width=W, height=H, a=a, b=b, h_contact=h_c, h_upper=h_u, h_far=h_far, growth=growth,
                  margin=float(margin), split=ARC_SPLIT)
    if apex_factor is not None:  # only then: the parabola's meshes keep their cache keys
        params["apex_factor"] = float(apex_factor)
    m = 0.0 if wedge_slope is None else float(wedge_slope)
    if wedge_slope is not None:  # only then: the flat blocks keep their cache keys
        params["wedge_slope"] = m
    R = None if parabola_radius is None else gi.length(parabola_radius)
    if R is not None:  # only then, as wedge_slope
        params["parabola_radius"] = R
    cap = None if parabola_cap is None else gi.length(parabola_cap)
    if cap is not None:  # only then, as wedge_slope
        params["parabola_cap"] = cap

    def face(x: float) -> float:
        """The upper body's lower face y(x): flat, the wedge m |x| or the parabola x^2 / (2 R) (flat beyond the
        cap)."""
        if R is None:
            return m * abs(x)
        return min(x * x, math.inf if cap is None else cap * cap) / (2.0 * R)

    # the upper window's length, to sample its distance field (the flat and wedge blocks keep their value)
    window_length = sum(ARC_SPLIT) * b * math.hypot(1.0, m)
    if R is not None:  # the parabola's arc is longer by its slope, at most b (ARC_SPLIT[1]) / R at the window's end
        window_length = gi.size(window_length * math.hypot(1.0, ARC_SPLIT[1] * b / R))

    def make(gmsh):
        geo = gmsh.model.geo

        def block(y_far, split, shaped=False):
            """A block between its near edge (``y = 0``, or the upper body's ``face(x)`` when ``shaped``) and y_far
            (above the near edge's ends), the near edge split at split[0] < split[1] (and at x = 0 for a wedge's
            apex); (surface, contact lines, refined lines, far edge, sides, apex point or None). A parabolic edge is
            one quadratic Bezier curve per segment: the control point where the end tangents meet makes it the
            parabola itself."""
            cuts = [split[0], 0.0, split[1]] if apex_factor is not None else list(split)
            capped = shaped and cap is not None
            if capped:
                cuts = [-cap, *cuts, cap]
            xs = [-W / 2, *cuts, W / 2]
            ys = [face(x) if shaped else 0.0 for x in xs]
            p = ([geo.addPoint(x, y, 0.0) for x, y in zip(xs, ys, strict=True)]
                 + [geo.addPoint(W / 2, ys[-1] + y_far, 0.0), geo.addPoint(-W / 2, ys[0] + y_far, 0.0)])
            n = len(cuts) + 2
            near = []
            for i in range(n - 1):
                flat_cap = capped and (i == 0 or i == n - 2)
                if shaped and R is not None and not flat_cap:
                    mid = geo.addPoint(0.5 * (xs[i] + xs[i + 1]), xs[i] * xs[i + 1] / (2.0 * R), 0.0)
                    near.append(geo.addBezier([p[i], mid, p[i + 1]]))
                else:
                    near.append(geo.addLine(p[i], p[i + 1]))
            right, far, left = geo.addLine(p[n - 1], p[n]), geo.addLine(p[n], p[n + 1]), geo.addLine(p[n + 1], p[0])
            surf = geo.addPlaneSurface([geo.addCurveLoop([*near, right, far, left])])
            k = 2 if capped else 1  # the refined lines: between the split points
            return surf, near, near[k:-k], far, [left, right], (p[k + 1] if apex_factor is not None else None)

        low, top, top_window, bottom, low_sides, low_apex = block(-H, (-b, b))
        up, under, under_window, lid, up_sides, up_apex = block(H, (-ARC_SPLIT[0] * b, ARC_SPLIT[1] * b),
                                                                wedge_slope is not None or R is not None)
        geo.synchronize()
        fields = [growth_field(gmsh, h0=h_c, h_max=h_far, growth=growth, curves=top_window, curve_length=2 * b,
                               sampling_size=gi.size(h_c / 4.0)),
                  growth_field(gmsh, h0=h_u, h_max=h_far, growth=growth, curves=under_window,
                               curve_length=window_length, sampling_size=gi.size(h_u / 4.0))]
        if apex_factor is not None:  # a field of its own per block, at its apex point (min with the window's)
            for k, (h0, pt) in enumerate(((h_c, low_apex), (h_u, up_apex))):
                apex = growth_field(gmsh, h0=gi.size(apex_factor * h0), h_max=h_far, growth=growth, points=[pt])
                both = gmsh.model.mesh.field.add("Min")
                gmsh.model.mesh.field.setNumbers(both, "FieldsList", [fields[k], apex])
                fields[k] = both
        apply_background(gmsh, _restricted(gmsh, [(fields[0], low, top), (fields[1], up, under)]), h_max=h_far)
        pg = gmsh.model.addPhysicalGroup
        groups = {"contact_lower": (1, pg(1, top, name="contact_lower")),
                  "contact_upper": (1, pg(1, under, name="contact_upper")),
                  "clamped": (1, pg(1, [bottom], name="clamped")),
                  "driven": (1, pg(1, [lid], name="driven")),
                  "sides": (1, pg(1, low_sides + up_sides, name="sides")),
                  "lower": (2, pg(2, [low], name="lower")),
                  "upper": (2, pg(2, [up], name="upper"))}
        gmsh.model.mesh.generate(2)

        def window(mid):
            return (abs(mid[:, 0]) <= a * (1.0 + 1e-9)) & (mid[:, 1] <= 0.0)

        return top, window, groups

    return build_cached(kind="profile_blocks", params=params, name=name, out_dir=out_dir, make=make,
                        inputs=gi, body_size=gi.scale, geometry_source="parameters", write_xdmf=write_xdmf,
                        stats_dir=stats_dir, comm=comm)
