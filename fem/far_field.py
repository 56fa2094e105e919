"""Far-field support ``halfplane``: the outer boundary of a block moves as the half-plane under the line load.

A finite block clamped at its bottom is not the half-plane of contact theory: measured, its contact quantities
carry a truncation error ~ (a/W)^2 (Hertz peak and width) and ~ a/W (the convective ratio, interior stresses).
The support kind ``halfplane`` prescribes instead, on every component of the outer boundary's dofs (the block's
``clamped`` bottom and ``sides``), the displacement of the half-plane under a line load P at the contact centre
(the origin of the block mesh, surface y = 0, body y <= 0): Flamant's field,
:func:`analytic.flamant.flamant_displacement`. The pressure's resultant is exactly P; what the line load leaves
out is the second moment (``M2 = int p x^2 dx``), whose field decays like a^2 / r^2 relative to the line load's
(first moment: 0 by symmetry). Measured (h_c = a/80, docs/error_budget.md): the truncation left falls like
(a/W)^4 (Hertz: 7.4e-6 at W = 20 a, 4.9e-7 at 40 a) and (a/W)^3 (wedge convective ratio: 4.8e-5, 5.1e-6).

Load: force control only. The boundary data are Flamant's field at the load level ``P_k`` (N/mm, full body) the
stepper is solving for (:meth:`HalfPlaneFarField.set_load`; the last level and its force corrections: the target).
Within a level the data are fixed, so the problem is as linear in (u, d) for a fixed active set as the clamped
one, and the converged target state is the half-plane state at the target load (frictionless elastic contact is
path independent). With the data fixed at the target for every level instead, the first levels are far from a
half-plane state and the wedge's secant in d lost contact (measured). Under displacement control the load is an
unknown of the solve and the data would need a fixed point on P: refused, :func:`check_far_field`.

Rigid-motion reference: the 2D field grows like ln r and is defined up to a rigid motion. u_x has no
translation and no rotation (the field is symmetric about x = 0, as are the block scenes); u_y = 0 at the depth
``r_ref`` = the block height H on the axis, i.e. the bottom centre. Another r_ref adds a uniform u_y that the
indenter's approach d absorbs under force control: the contact quantities do not depend on it (tested).
"""

from __future__ import annotations

import numpy as np

from analytic.flamant import flamant_displacement

# dolfinx and MPI are imported where used: the support vocabulary and its checks serve the case wiring too

__all__ = ["HALFPLANE", "OUTER_GROUPS", "HalfPlaneFarField", "check_far_field", "far_field_supports",
           "fill_halfplane_values", "reference_depth"]

HALFPLANE = "halfplane"
OUTER_GROUPS = ("clamped", "sides")  # the block's bottom and sides (meshes/block.py)


def far_field_supports(*, far_field: str, symmetric_half: bool) -> dict | None:
    """The ``supports`` of a block for ``far_field`` ``"clamped"`` (None: the default, bottom clamped, sides
    free) or ``"halfplane"`` (bottom and sides on Flamant's field; symmetry edge roller_x for a half model)."""
    if far_field == "clamped":
        return None
    if far_field != HALFPLANE:
        raise ValueError(f"far_field must be 'clamped' or 'halfplane', got {far_field!r}")
    supports = {g: HALFPLANE for g in OUTER_GROUPS}
    if symmetric_half:
        supports["symmetry"] = "roller_x"
    return supports


def check_far_field(*, supports: dict | None, control: str, obstacle) -> None:
    """ValueError unless a ``halfplane`` support comes with force control and a load along -y."""
    if not supports or HALFPLANE not in supports.values():
        return
    if control != "force":
        raise ValueError(f"supports {HALFPLANE!r} needs control='force' (the far field is scaled by the load "
                         f"level), got control={control!r}")
    direction = np.asarray(obstacle.direction, dtype=float)
    if not (abs(direction[0]) < 1e-14 and direction[1] < 0):
        raise ValueError(f"supports {HALFPLANE!r} needs an obstacle pushing along -y (a block scene), "
                         f"got direction {tuple(direction)}")


def reference_depth(mesh) -> float:
    """The block height H (mm): the depth of the lowest mesh point, the default ``r_ref``."""
    from mpi4py import MPI

    y = mesh.geometry.x[:, 1]
    local = float(-np.min(y)) if y.size else -np.inf
    return mesh.comm.allreduce(local, op=MPI.MAX)


class HalfPlaneFarField:
    """The boundary values of the ``halfplane`` supports of one problem, scaled by the load level.

    :meth:`value_function` makes the Dirichlet value Function of one component (Flamant's field at unit load kept
    aside); :meth:`set_load` sets every value Function to ``P`` times it. The load stepper calls ``set_load`` with
    each force level ``P_k`` before solving it (:class:`fem.stepping.LoadStepper`), so every converged level is a
    half-plane state; a problem without ``halfplane`` supports ignores it.
    """

    def __init__(self, *, mesh, E: float, nu: float, r_ref: float | None = None):
        self.mesh, self.E, self.nu, self._r_ref = mesh, float(E), float(nu), r_ref
        self._unit: list = []  # (value Function, its unit-load values)
        self.load = 0.0

    @property
    def active(self) -> bool:
        """True when some support is ``halfplane``."""
        return bool(self._unit)

    def value_function(self, Vc, component: int):
        """The Dirichlet value Function (collapsed sub-space ``Vc``) of component 0 (x) or 1 (y), at load 0."""
        if self._r_ref is None:
            self._r_ref = reference_depth(self.mesh)
        import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

        import dolfinx

        g = dolfinx.fem.Function(Vc)
        fill_halfplane_values(g, component, P=1.0, E=self.E, nu=self.nu, r_ref=self._r_ref)
        self._unit.append((g, g.x.array.copy()))
        g.x.array[:] = 0.0
        return g

    def set_load(self, P: float) -> None:
        """Scale the boundary values to the load P (N/mm, full body)."""
        self.load = float(P)
        for g, unit in self._unit:
            g.x.array[:] = self.load * unit


def fill_halfplane_values(g, component: int, *, P: float, E: float, nu: float,
                          r_ref: float) -> None:
    """Interpolate component ``component`` (0: x, 1: y) of Flamant's displacement (mm) at load P (N/mm) into
    ``g`` (a dolfinx Function of a collapsed scalar sub-space; only its boundary dofs are used)."""

    def value(X):
        # the contact centre (0, 0) is an interior-side dof of the top edge, never a support dof: any finite value
        at_centre = (X[0] == 0.0) & (X[1] == 0.0)
        u = flamant_displacement(np.where(at_centre, 1.0, X[0]), X[1], P=P, E=E, nu=nu, r_ref=r_ref)[component]
        return np.where(at_centre, 0.0, u)

    g.interpolate(value)
