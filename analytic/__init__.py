"""Half-plane contact theory in pure numpy/scipy (never imports dolfinx).

Modules (each with one job):
    materials       elastic constants: E*, compliance A = 2/E*, Kolosov kappa, Dundurs alpha/beta
    hertz           2D Hertz line contact, Table 1 data of the close-to-conformal paper
    wedge           classical frictionless rigid wedge on a half-plane
    convective      Ciavarella & Hills convective correction: closed forms + nonlinear solver
    halfplane       any symmetric profile (exact circle, parabola, wedge), classical and convective
    fit             least-squares semi-elliptical fit of sampled pressures
    superposition   sum of independent Hertz patches along the arc length of a concave surface
    curves, lcp, designs   (convex/concave curves and the local contact problem; another module owner)
    chebyshev_kernels   exact log and Cauchy kernel integrals against the bounded Chebyshev pressure series
    interacting_patches all contact patches on a half-plane solved together (real gap, log coupling)
    westergaard     the periodic wavy contact, exact and by the periodic kernel (the multi-patch reference)
    design_family   the paper's two designs as members of a family of interference numbers (LCP-checked)
    force_law, force_law_eval   P(d) and patches of a design (``workbench forcelaw``); the copyable evaluator

Units everywhere: mm, N, MPa; loads per unit thickness (N/mm). Pressure positive in compression.
Command line: ``python -m analytic {hertz,wedge,convective,halfplane,table1,lcp} ... [--json]``.
"""

__all__ = ["convective", "fit", "halfplane", "hertz", "materials", "superposition", "wedge"]


def __getattr__(name: str):
    # Lazy submodule access (``analytic.hertz``) without importing everything at package import.
    import importlib

    if name in __all__ or name in ("curves", "lcp", "designs"):
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
