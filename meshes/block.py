"""Rectangular elastic block for the flat-surface scenes (Hertz cylinder, wedge): linear triangles.

Geometry (mm): x in [-W/2, W/2] (half model: [0, W/2]), y in [-H, 0]; the contact surface is the top edge
y = 0 centred at x = 0. The top edge is split at x = 0, +-a and +-a(1 + margin) so that the apex and the
predicted contact edges are mesh nodes.

Size field (see :mod:`meshes.sizing`): h = h_contact on the top edge |x| <= a(1 + margin), growing linearly
with the distance d from that segment, h = h_contact + (growth - 1) d (element ratio ~ growth), up to h_far
(the contact target is SIZE_SAFETY * h_contact = 0.9 h_contact).
Optional refinements (each also with the same growth): h_contact * edge_factor at the points (+-a, 0), and
h_contact * apex_factor at the apex (0, 0) (log-singular wedge pressure).

Physical groups (names are the contract, tags are arbitrary): ``contact`` (whole top edge), ``clamped``
(bottom), ``sides`` (left + right; right only for the half model), ``symmetry`` (x = 0, half model), ``body``.
"""

from __future__ import annotations

import math

from meshes.cache import DEFAULT_CACHE_DIR, MeshFiles
from meshes.pipeline import build_cached
from meshes.portable import GmshInputs
from meshes.sizing import apply_background, growth_field, validate_common

__all__ = ["build_block_mesh", "SIZE_SAFETY"]

# gmsh rounds the number of 1D subdivisions, so a target h can come out a few % longer; aiming at
# 0.9 h_contact keeps every contact edge <= h_contact (checked in the stats: contact_h_max).
SIZE_SAFETY = 0.9


def build_block_mesh(*, width: float, height: float, contact_half_width: float, h_contact: float,
                     h_far: float | None = None, growth: float = 1.3, margin: float = 0.5,
                     half_model: bool = False, apex_refinement: bool = False, edge_refinement: bool = True,
                     apex_factor: float = 0.25, edge_factor: float = 0.5, out_dir=DEFAULT_CACHE_DIR,
                     name: str = "block", write_xdmf: bool = True, stats_dir=None, comm=None) -> MeshFiles:
    """Build (or reuse from the cache) the block mesh.

    Args:
        width: W (mm), > 2 a (1 + margin).
        height: H (mm), > 0.
        contact_half_width: a, the analytic contact half-width estimate (mm), > 0.
        h_contact: element size on |x| <= a (1 + margin) of the top edge (mm).
        h_far: size far away (mm); default W / 10.
        growth: element-to-element size ratio, in (1, 3].
        margin: relative margin of the uniformly refined zone beyond a, >= 0.
        half_model: model x >= 0 only, with a ``symmetry`` edge at x = 0.
        apex_refinement: refine to apex_factor * h_contact at (0, 0).
        edge_refinement: refine to edge_factor * h_contact at (+-a, 0).
        out_dir: cache directory of the mesh files.
        name: file stem.
        write_xdmf: also write XDMF (needs dolfinx).
        stats_dir: when given, write ``<stats_dir>/mesh.json``.
        comm: optional MPI communicator (rank 0 builds).

    Returns:
        MeshFiles(msh, xdmf, stats, key, cached).
    """
    for arg, val in (("width", width), ("height", height), ("contact_half_width", contact_half_width)):
        if not (val > 0.0 and math.isfinite(val)):
            raise ValueError(f"{arg} must be > 0 (mm), got {val}")
    a = float(contact_half_width)
    h_far = float(width) / 10.0 if h_far is None else float(h_far)
    h_far = max(h_far, h_contact)
    validate_common(h_contact=h_contact, h_far=h_far, growth=growth)
    if not margin >= 0.0:
        raise ValueError(f"margin must be >= 0, got {margin}")
    b = a * (1.0 + margin)
    if not width / 2.0 > b:
        raise ValueError(f"width must be > 2 a (1 + margin) = {2 * b} (mm), got {width}")
    for arg, val in (("apex_factor", apex_factor), ("edge_factor", edge_factor)):
        if not 0.0 < val <= 1.0:
            raise ValueError(f"{arg} must be in (0, 1], got {val}")
    # every float handed to gmsh goes through one funnel: lengths on the portable grid, sizes to SIZE_BITS
    # (meshes.portable), then the optional perturbation; coordinates are computed from the rounded parameters
    gi = GmshInputs(scale=max(float(width), float(height)))
    width, height, a = gi.length(width), gi.length(height), gi.length(a)
    h_c, h_far, growth = gi.size(h_contact), gi.size(h_far), gi.size(growth)
    b = gi.length(a * (1.0 + margin))
    params = dict(width=width, height=height, a=a, h_contact=h_c, h_far=h_far,
                  growth=growth, margin=float(margin), half_model=bool(half_model),
                  apex_refinement=bool(apex_refinement), edge_refinement=bool(edge_refinement),
                  apex_factor=float(apex_factor), edge_factor=float(edge_factor))
    half_w = width / 2.0
    x_left = 0.0 if half_model else -half_w
    top_x = [half_w, b, a, 0.0] if half_model else [half_w, b, a, 0.0, -a, -b, -half_w]
    top_x = sorted(set(top_x), reverse=True)  # right to left (counter-clockwise loop)
    top_g = [gi.length(x) for x in top_x]  # as handed to gmsh (perturbed when asked); top_x names them
    corners = [(gi.length(x_left), gi.length(-height)), (gi.length(half_w), gi.length(-height))]
    h0 = gi.size(SIZE_SAFETY * h_c)
    sampling = gi.size(h_c / 4.0)
    h_edge, h_apex = gi.size(edge_factor * h_c), gi.size(apex_factor * h_c)

    def make(gmsh):
        geo = gmsh.model.geo
        p_bl = geo.addPoint(*corners[0], 0.0)
        p_br = geo.addPoint(*corners[1], 0.0)
        top_pts = [geo.addPoint(x, 0.0, 0.0) for x in top_g]
        bottom = geo.addLine(p_bl, p_br)
        right = geo.addLine(p_br, top_pts[0])
        top = [geo.addLine(p, q) for p, q in zip(top_pts[:-1], top_pts[1:], strict=True)]
        left = geo.addLine(top_pts[-1], p_bl)
        loop = geo.addCurveLoop([bottom, right, *top, left])
        surf = geo.addPlaneSurface([loop])
        geo.synchronize()

        central = [c for c, (x0, x1) in zip(top, zip(top_x[:-1], top_x[1:], strict=True), strict=True)
                   if max(abs(x0), abs(x1)) <= b * (1 + 1e-12)]
        fields = [growth_field(gmsh, h0=h0, h_max=h_far, growth=growth, curves=central,
                               curve_length=b, sampling_size=sampling)]
        pt_at = dict(zip(top_x, top_pts, strict=True))
        if edge_refinement:
            edge_pts = [pt_at[x] for x in (a, -a) if x in pt_at]
            fields.append(growth_field(gmsh, h0=h_edge, h_max=h_far, growth=growth,
                                       points=edge_pts))
        if apex_refinement:
            fields.append(growth_field(gmsh, h0=h_apex, h_max=h_far, growth=growth,
                                       points=[pt_at[0.0]]))
        apply_background(gmsh, fields, h_max=h_far)

        groups = {
            "contact": (1, gmsh.model.addPhysicalGroup(1, top, name="contact")),
            "clamped": (1, gmsh.model.addPhysicalGroup(1, [bottom], name="clamped")),
            "sides": (1, gmsh.model.addPhysicalGroup(1, [right] if half_model else [right, left],
                                                     name="sides")),
        }
        if half_model:
            groups["symmetry"] = (1, gmsh.model.addPhysicalGroup(1, [left], name="symmetry"))
        groups["body"] = (2, gmsh.model.addPhysicalGroup(2, [surf], name="body"))
        gmsh.model.mesh.generate(2)

        def window(mid):
            return abs(mid[:, 0]) <= a * (1.0 + 1e-9)

        return top, window, groups

    return build_cached(kind="block", params=params, name=name, out_dir=out_dir, make=make, inputs=gi,
                        body_size=gi.scale, geometry_source="parameters", write_xdmf=write_xdmf,
                        stats_dir=stats_dir, comm=comm)
