"""Portable gmsh inputs: every float that reaches gmsh is rounded to a grid, (optionally) perturbed, recorded.

Why: the geometry handed to gmsh is computed with numpy/scipy (B-spline fits, LCP, arc lengths), whose last
bits depend on the machine (OpenBLAS picks AVX-512 or AVX2 kernels, numpy its SIMD loops). gmsh's
Frontal-Delaunay mesher turns a last-bit change of its input into a different (equally valid) mesh. Rounding
every input to a grid far coarser than a ULP and far finer than any mesh length makes the gmsh input, and so
the mesh, a function of the case (the concave control points are snapped to a frozen table instead, see
:mod:`meshes.frozen`).

Grids (binary, so the rounding itself is exact in floating point):
    ``length``: absolute grid ``2**(ceil(log2(scale)) - LENGTH_BITS)`` mm, ``scale`` the body size (a 30 mm
        body: 2**-35 = 2.9e-11 mm, 1e-12 of the body; a machine difference is ~1e-14 mm).
    ``param``: curve parameter t in [0, 1], grid ``2**-PARAM_BITS`` (6e-8, ~2e-6 mm of arc on a 30 mm curve).
    ``size``: element sizes and sizing parameters (h, h_far, growth), ``SIZE_BITS`` significant bits
        (relative 1e-6: a size is a target, gmsh rounds the number of edges anyway).
A machine that differs from ours by delta gives a different rounded value only when the value lies within
delta of a rounding midpoint. Measured spread between OpenBLAS kernels / numpy SIMD levels: <= 2.6e-14 in t
(the refinement interval ends), <= 3.8e-12 relative in h_contact (from the LCP's patch estimate), i.e.
delta / grid <= 4e-6: the chance that one value straddles a midpoint is ~1e-5, and it is checked, not
assumed: ``mesh.json`` records ``gmsh_input_rounding_margin``, the smallest distance of any rounded input to its
rounding midpoint in grid units (0.5: on a grid point; 0: on a midpoint), and the shipped CI meshes are tested to
keep it > 1e-3, i.e. > 250 times the measured machine spread. The control points of the concave splines are not
rounded but snapped to a frozen table (:mod:`meshes.frozen`, capture radius 1e-9 mm), which has no midpoint to
fall on.

Perturbation hook (emulates another machine): ``WORKBENCH_MESH_PERTURB = amp`` (a float in [0, 1e-6]) multiplies
every rounded value by ``1 + amp * s_i`` with s_i in [-1, 1] a fixed pseudo-random number of the value's
index i (splitmix64, integer arithmetic only), after the rounding. The amplitude is part of the mesh cache key
and of the fingerprint.
"""

from __future__ import annotations

import hashlib
import math
import os

__all__ = ["GmshInputs", "perturb_amplitude", "PERTURB_ENV", "PERTURB_MAX", "LENGTH_BITS", "PARAM_BITS",
           "SIZE_BITS", "round_length", "round_param", "round_size"]

PERTURB_ENV = "WORKBENCH_MESH_PERTURB"
PERTURB_MAX = 1e-6
LENGTH_BITS = 40
PARAM_BITS = 24
SIZE_BITS = 20


def perturb_amplitude(environ=None) -> float:
    """The relative perturbation amplitude from ``WORKBENCH_MESH_PERTURB`` (0.0 when unset or empty).

    Raises:
        ValueError: one line ``WORKBENCH_MESH_PERTURB = ...; allowed: ...`` when not a finite float in
            [0, PERTURB_MAX].
    """
    env = os.environ if environ is None else environ
    text = env.get(PERTURB_ENV, "").strip()
    if not text:
        return 0.0
    try:
        amp = float(text)
    except ValueError:
        amp = math.nan
    if not (math.isfinite(amp) and 0.0 <= amp <= PERTURB_MAX):
        raise ValueError(f"{PERTURB_ENV} = {text!r}; allowed: a finite float in [0, {PERTURB_MAX:g}] "
                         "(relative amplitude of the gmsh input perturbation; unset or 0: none)")
    return amp


def _grid_round(x: float, q: float) -> tuple[float, float]:
    """(x rounded to the grid q (a power of two), distance of x/q to the nearest rounding midpoint)."""
    r = x / q  # exact: q is a power of two
    n = math.floor(r + 0.5)
    return n * q, abs(abs(r - n) - 0.5)


def round_length(x: float, *, scale: float) -> float:
    """``x`` (mm) on the absolute grid 2**(ceil(log2(scale)) - LENGTH_BITS)."""
    return _grid_round(float(x), _length_grid(scale))[0]


def round_param(t: float) -> float:
    """Curve parameter ``t`` on the grid 2**-PARAM_BITS."""
    return _grid_round(float(t), 2.0**-PARAM_BITS)[0]


def round_size(h: float) -> float:
    """``h`` (> 0) rounded to SIZE_BITS significant bits."""
    return _round_size(float(h))[0]


def _length_grid(scale: float) -> float:
    if not (scale > 0 and math.isfinite(scale)):
        raise ValueError(f"scale must be a finite length > 0 (mm), got {scale}")
    return 2.0 ** (math.ceil(math.log2(scale)) - LENGTH_BITS)


def _round_size(h: float) -> tuple[float, float]:
    if h == 0.0 or not math.isfinite(h):
        return h, 0.5
    _, e = math.frexp(abs(h))  # |h| = m 2**e, m in [0.5, 1)
    return _grid_round(h, 2.0 ** (e - SIZE_BITS))


def _unit(i: int) -> float:
    """Deterministic pseudo-random number in [-1, 1] of the integer i (splitmix64, integers only)."""
    mask = (1 << 64) - 1
    z = (i * 0x9E3779B97F4A7C15 + 0x632BE59BD9B4E019) & mask
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & mask
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & mask
    z ^= z >> 31
    return (z >> 11) * 2.0**-52 - 1.0


class GmshInputs:
    """Funnel of every float a builder hands to gmsh: round (by kind), perturb, record.

    Args:
        scale: body size (mm), sets the length grid.
        perturb: relative perturbation amplitude (default: :func:`perturb_amplitude` of the environment).

    ``digest()`` is the SHA-256 (16 hex digits) of the recorded values (hex floats, in call order) and
    ``margin`` the smallest distance of a rounded value to its rounding midpoint (grid units, in [0, 0.5]).
    """

    def __init__(self, *, scale: float, perturb: float | None = None):
        self.scale = float(scale)
        self.q_length = _length_grid(scale)
        self.perturb = perturb_amplitude() if perturb is None else float(perturb)
        self.values: list[float] = []
        self.margin = 0.5

    def _take(self, rounded: float, margin: float, perturb: bool = True) -> float:
        i = len(self.values)
        if self.perturb and perturb:
            rounded = rounded * (1.0 + self.perturb * _unit(i))
        self.values.append(rounded)
        self.margin = min(self.margin, margin)
        return rounded

    def length(self, x: float, *, perturb: bool = True) -> float:
        """A coordinate (mm); ``perturb=False`` for a point evaluated on an already perturbed curve (it must
        stay on it, within gmsh's geometry tolerance)."""
        return self._take(*_grid_round(float(x), self.q_length), perturb=perturb)

    def param(self, t: float) -> float:
        """A curve parameter in [0, 1] (rounded, never perturbed out of [0, 1])."""
        v, m = _grid_round(float(t), 2.0**-PARAM_BITS)
        return min(1.0, max(0.0, self._take(v, m)))

    def size(self, h: float) -> float:
        """An element size or sizing parameter (relative rounding)."""
        return self._take(*_round_size(float(h)))

    def exact(self, x: float) -> float:
        """A value already machine-independent (e.g. a frozen table entry): perturbed and recorded only."""
        return self._take(float(x), 0.5)

    def fixed(self, x: float) -> float:
        """A value that is machine-independent and must not move (e.g. B-spline knots): recorded only."""
        return self._take(float(x), 0.5, perturb=False)

    def digest(self) -> str:
        text = ",".join(v.hex() for v in self.values)
        return hashlib.sha256(text.encode()).hexdigest()[:16]
