"""The reference theory of a benchmark at the case's target load, as plain numbers (the spec's ``reference``).

Every value comes from :mod:`analytic` (one formula in one place); this module only names them. The moment
half-width is ``2 sqrt(M2/M0)`` of the pressure (``M_k = int p x^k dx`` about the centre): Hertz's a, the classical
wedge's 2 b / sqrt(6), the exact circle's slightly less than its b. Units mm, N/mm, MPa.
"""

from __future__ import annotations

from analytic import convective, wedge
from analytic.circle import circle_contact
from analytic.hertz import hertz
from workbench.scenes.budget_theory import circle_moment_half_width, curve_moment_half_width

__all__ = ["hertz_values", "circle_values", "wedge_values", "convective_values", "AT_MEASURED_LOAD"]

AT_MEASURED_LOAD = ("In 2D there is no load-indentation law independent of the bodies' size, so the score evaluates "
                    "the theory at the load each result carries (its P_N_per_mm column, else the integral of its "
                    "pressure), never at the target below: these numbers say what to expect.")


def hertz_values(P: float, R: float, E_star: float) -> dict:
    """Hertz line contact (a parabolic profile of radius R): half-width a, peak p0, moment half-width a."""
    c = hertz(P, R, E_star)
    return {"theory": "hertz", "formula": "a = sqrt(4 P R / (pi E*)), p0 = 2 P / (pi a), p = p0 sqrt(1 - x^2/a^2)",
            "P": c.P, "R": R, "E_star": E_star, "half_width": c.half_width, "p_max": c.p0,
            "half_width_moment": c.half_width}


def circle_values(P: float, R: float, E_star: float) -> dict:
    """The exact circle's half-plane contact (:mod:`analytic.circle`; Hertz is its parabolic approximation)."""
    c = circle_contact(P, R, E_star)
    return {"theory": "exact_circle", "formula": "P = E* R [K(b/R) - E(b/R)] (complete elliptic integrals of the "
            "parameter (b/R)^2); p(x) from the Chebyshev series of analytic/circle.py",
            "P": c.P, "R": R, "E_star": E_star, "half_width": c.half_width, "p_max": c.p0,
            "half_width_moment": 2.0 * circle_moment_half_width(b=c.half_width, R=R, E_star=E_star)}


def wedge_values(P: float, m: float, E_star: float) -> dict:
    """The classical wedge of face slope m: b = P / (E* m), log-singular at the apex (no peak)."""
    b = wedge.wedge_half_width(P, m, E_star)
    return {"theory": "wedge", "formula": "b = P / (E* m), p = (E* m / pi) ln[(b + sqrt(b^2 - x^2)) / |x|]",
            "P": float(P), "m": m, "E_star": E_star, "half_width": b, "p_mean": P / (2.0 * b),
            "half_width_moment": 2.0 * wedge.wedge_moment_half_width(b), "p_max": None,
            "p_max_note": "log-singular at the apex: no peak to compare"}


def convective_values(*, kind: str, size: float, b0: float, beta: float) -> dict:
    """Ciavarella and Hills's convective ratio b/b0 at Dundurs' ``beta`` for the wedge (``size`` = m) or the parabola
    (``size`` = R, at b0/R), with the moment ratio (convective over classical 2 sqrt(M2/M0))."""
    profile = convective.wedge_profile(size) if kind == "wedge" else convective.parabola_profile(b0 / size)
    sol = convective.solve(profile, beta=beta, n_plot=8001)
    w_class = curve_moment_half_width(sol.x, sol.p_classical)
    return {"theory": "convective", "source": "Ciavarella and Hills; analytic/convective.py (65536 Gauss-Chebyshev "
            "nodes)", "beta": beta, ("m" if kind == "wedge" else "b0_over_R"): size if kind == "wedge" else b0 / size,
            "b_over_b0_converged": sol.b_over_b0_converged, "b_over_b0_first_order": sol.b_over_b0_first_order,
            "b_over_b0_first_iterate": sol.b_over_b0_first_iterate,
            "b_over_b0_moment_converged": curve_moment_half_width(sol.x, sol.p_converged) / w_class,
            "b_over_b0_moment_first_order": curve_moment_half_width(sol.x, sol.p_first_order) / w_class,
            "half_width_converged": sol.b_over_b0_converged * b0,
            "how": "b/b0: the convective run's half-width over the small run's, each over the classical half-width "
                   "at its own measured load (the two runs at one load)"}

