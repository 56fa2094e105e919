"""Numpy-only measures of a sampled contact pressure (:mod:`measures.contact`); no dolfinx."""

from measures.contact import (
    Patch,
    SurfaceSamples,
    contact_edges,
    find_patches,
    moment_half_width,
    rms_error,
    trapezoid_weights,
)

__all__ = ["SurfaceSamples", "Patch", "contact_edges", "find_patches", "moment_half_width", "rms_error",
           "trapezoid_weights"]
