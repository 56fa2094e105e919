"""Summary report: ``results/report.md`` and ``results/report.html``.

Verdict first (issue 22): the page opens with "N of M cases PASS", then one figure (issue 37, ``forest.png``:
every case's judged quantities over their theory, with their bands, :mod:`workbench.reports.forest`), so the
verdict is seen before it is read, then one line per failing check (the check, its value against its tolerance,
or the band check's own reason), before any table. Then one row per scene with
its verdict, headline numbers and a link to the case report (narrow enough for a 1400 px window), the error
budget (long; below the verdicts), the paper-claims table, and links to the studies (convergence, stability,
benchmark) when they have been run. It reads only what the
runs wrote (``results/<case>/metrics.json``), so it works when only some cases exist yet. Writing it also
draws every case report again from its saved JSON, and writes an HTML twin of every study report.
"""

from __future__ import annotations

import json
from pathlib import Path

from cases import case_names
from workbench.atomic import write_root_text, write_text
from workbench.owned import check_dir, check_root_file, record_root_files
from workbench.reports.forest import forest_caption, forest_rows
from workbench.reports.markdown import fmt, markdown_to_html

__all__ = ["FOREST_PNG", "STUDY_REPORTS", "check_summary_writes", "load_metrics", "failing_checks", "forest_markdown",
           "verdict_markdown", "summary_markdown", "trust_markdown", "write_summary"]

STUDY_REPORTS = ("convergence/report.md", "stability/report.md", "bench/report.md", "analytic/convective.md",
                 "validity/report.md", "ci_report.md")
"""The reports (Markdown) below the output folder other than the summary and the cases' (the studies and the CI
report); writing the summary gives each an HTML twin."""

FOREST_PNG = "forest.png"
"""The summary's opening figure (:mod:`workbench.reports.forest_plot`), at the top of the output folder."""

_HEADLINE = ("p_max", "half_width", "rms", "load_balance", "b_over_b0")


def load_metrics(results: Path) -> dict[str, dict]:
    """The metrics of every case that has run, by case name."""
    out = {}
    for name in case_names():
        f = results / name / "metrics.json"
        if f.is_file():
            out[name] = json.loads(f.read_text())
    return out


def _fmt(v) -> str:
    return fmt(v, 3)


def failing_checks(m: dict) -> list[str]:
    """One line per failing check of a case's metrics: ``check: value > tolerance`` for a tolerance check, the
    band check's own reason for a band check; the pass flag alone if nothing more specific failed."""
    errs, tol = m.get("errors", {}), m.get("tolerances", {})
    out = []
    for k, ok in (m.get("checks") or {}).items():
        if not ok:
            v, t = errs.get(k), tol.get(k)
            out.append(f"`{k}` {_fmt(v)} > tolerance {_fmt(t)}" if t is not None else f"`{k}` failed")
    for k, c in (m.get("band_checks") or {}).items():
        if not c.get("passed", True):
            out.append(f"`{k}`: {c.get('reason') or 'outside its band'}")
    if not out and not m.get("pass"):
        out.append("the case did not pass (see its report)")
    return out


def verdict_markdown(metrics: dict[str, dict]) -> list[str]:
    """The opening lines: "N of M cases PASS", then each failing case with its failing checks, one line each."""
    names = case_names()
    passed = [n for n in names if n in metrics and metrics[n].get("pass")]
    failed = [n for n in names if n in metrics and not metrics[n].get("pass")]
    missing = [n for n in names if n not in metrics]
    verdict = "PASS" if not failed and not missing else "FAIL" if failed else "incomplete"
    lines = [f"**{len(passed)} of {len(names)} cases PASS** ({verdict}).", ""]
    for n in failed:
        checks = failing_checks(metrics[n])
        lines.append(f"- FAIL **{n}** ([report]({n}/report.md)): {checks[0]}")
        lines += [f"  - {c}" for c in checks[1:]]
    if missing:
        lines.append(f"- Not run yet: {', '.join(missing)}.")
    return lines + ([""] if failed or missing else [])


def forest_markdown(metrics: dict[str, dict]) -> list[str]:
    """The opening figure (:data:`FOREST_PNG`) and its caption; nothing when no case has a judged quantity."""
    rows = forest_rows(metrics)
    if not rows:
        return []
    return [f"![every judged quantity against its theory]({FOREST_PNG})", "", f"*{forest_caption(rows)}*", ""]


def _budget_markdown(metrics: dict[str, dict]) -> list[str]:
    """The error budgets (issue 12) of the cases that have one: quantities with a theory, one row each (a row
    whose band could not be computed is listed as undefined, not left out), the band checks, and each case's
    ``budget.png`` (every quantity against h with its band)."""
    rows, plots, bands = [], [], []
    for name, m in metrics.items():
        budget = m.get("error_budget") or {}
        if budget:
            plots += [f"### {name}", "", f"![{name} error budget]({name}/budget.png)", ""]
        for q, r in budget.items():
            if r.get("theory") is None:
                continue
            if r.get("gci") is None or r.get("extrapolated") is None:
                rows.append(f"| {name} | {q} | undefined | {r.get('status', '')} | undefined | {r['theory']:.7f} | "
                            "- | n/a | - |")
                continue
            band = r.get("uncertainty", r["gci"] + (r.get("truncation") or 0.0))
            alt = "-" if "alt_in_band" not in r else ("in band" if r["alt_in_band"] else "outside")
            err = r.get("error_vs_theory")
            rows.append(f"| {name} | {q} | {r['extrapolated']:.7f} | {r['status']} | {band:.2e} | {r['theory']:.7f} | "
                        f"{'-' if err is None else format(err, '.1e')} | {'yes' if r['theory_in_band'] else 'no'} | "
                        f"{alt} |")
        for k, c in (m.get("band_checks") or {}).items():
            why = c["reason"] or "; ".join(c.get("unresolved", {}).values()) or "-"
            bands.append(f"| {name} | {k} | {len(c['rows'])} | {'PASS' if c['passed'] else 'FAIL'} | {why} |")
    if not rows and not plots:
        return []
    out = ["", "## Error budget (three grids, block size extrapolated; block values over the classical value)",
           "", "| case | quantity | extrapolated | status | band (uncertainty, rel.) | theory | error "
           "| theory in band | other theory |", "|---|---|---|---|---|---|---|---|---|", *rows, ""]
    if bands:
        out += ["Band checks (tolerance = the band):", "", "| case | check | rows | verdict | why |",
                "|---|---|---|---|---|", *bands, ""]
    out += ["Per case: `metrics.json[\"error_budget\"]` and the table in its report.", "", *plots]
    return out


_TRUST_THEORIES = (("cylinder", "hertz", "moment", "Hertz"), ("cylinder", "exact_circle", "moment", "exact circle"),
                   ("cylinder", "ch_circle", "moment", "Ciavarella-Hills (circle)"),
                   ("cylinder", "ch_first_order", "half_width", "C-H first order (cylinder)"),
                   ("wedge", "wedge", "moment", "classical wedge"),
                   ("wedge", "ch_wedge", "moment", "Ciavarella-Hills (wedge)"),
                   ("wedge", "ch_first_order", "half_width", "C-H first order (wedge)"),
                   ("halfplanes", "hertz", "moment", "Hertz (two elastic half-planes, beta of both signs)"),
                   ("halfplanes", "ch_converged", "moment", "Ciavarella-Hills converged (two half-planes)"),
                   ("halfplanes", "ch_first_order", "moment", "C-H first order (two half-planes)"))


def trust_markdown(results: Path) -> list[str]:
    """The section "How far the theory can be trusted", from ``validity/validity.json`` (or how to make it)."""
    lines = ["## How far the theory can be trusted", ""]
    f = Path(results) / "validity" / "validity.json"
    if not f.is_file():
        return lines + ["Not measured yet: run `make validity`.", ""]
    data = json.loads(f.read_text())
    pts, cfg = data.get("points", []), data.get("config", {})
    thr = cfg.get("thresholds", [1e-3, 1e-2, 5e-2])
    bands = [f"<{100 * t:g}%" for t in thr] + [f">{100 * thr[-1]:g}%", "unresolved"]
    lines += ["Each theory against the most complete FEM model (finite strain where it runs, else the traction "
              "along the indenter's normal with the convective gap) at every point of the validity study: the "
              "cylinder over a/R, the wedge over theta, each over beta (through nu). Cells: the band of the "
              "difference (moment half-width; the first-order forms: the zero-crossing half-width), `unresolved` "
              "where the FEM uncertainty is not well below it. Details: [validity report](validity/report.md).", "",
              "![cylinder](validity/map_cylinder.png)", "", "![wedge](validity/map_wedge.png)", ""]
    if any(p["scene"] == "halfplanes" for p in pts):
        lines += ["Two elastic half-planes (beta of both signs, the moment ratio convective over small): "
                  "![halfplanes](validity/map_halfplanes.png)", ""]
    lines += ["| theory | points | " + " | ".join(bands) + " |", "|---|---|" + "---|" * len(bands)]
    for scene, name, q, label in _TRUST_THEORIES:
        got = [p["bands"].get(name, {}).get(q, {}).get("band") for p in pts if p["scene"] == scene]
        got = [g for g in got if g]
        if got:
            lines.append(f"| {label} | {len(got)} | " + " | ".join(str(got.count(b)) for b in bands) + " |")
    hp = [p for p in pts if p["scene"] == "halfplanes" and p.get("bands")]
    if hp:
        def inside(name):
            return sum(bool(p["bands"].get(name, {}).get("moment", {}).get("inside")) for p in hp)

        lines += ["", f"Two elastic half-planes: the FEM moment ratio's uncertainty U contains converged "
                  f"Ciavarella-Hills at {inside('ch_converged')} of {len(hp)} points and its first order at "
                  f"{inside('ch_first_order')}."]
    splits = [p for p in pts if p.get("split") and p["scene"] != "halfplanes"]
    if splits:
        worst = max(splits, key=lambda p: abs(p["split"]["total"]["value"]))
        s = worst["split"]

        def pc(k):
            v = s[k]["value"]
            return "not run" if v is None else f"{100 * v:+.2f} %"

        lines += ["", f"Largest gap to classical theory: {worst['scene']} at parameter {worst['param']:.4g}, beta = "
                  f"{worst['beta']:.3g}: {pc('total')} = profile {pc('profile')} + convective {pc('convective')} + "
                  f"traction direction {pc('traction')} + finite strain {pc('finite_strain')} (moment half-width)."]
    v = (data.get("claim_elastic_wedge") or {}).get("verdict")
    if v:
        lines += ["", f"The paper's internal-stress claim (theta < pi/5, 0.5 %), as it states it: {v['text']}."]
    v = (data.get("claim") or {}).get("verdict")
    if v:
        lines += ["", f"A rigid wedge, the traction's direction (face normal against vertical; not the paper's "
                      f"problem): {v['text']}."]
    s = data.get("summary", {})
    lines += ["", f"{s.get('runs')} runs ({s.get('failed')} failed), wall time {s.get('wall_time_s', 0):.0f} s.", ""]
    return lines


def summary_markdown(results: Path) -> str:
    """The summary report as Markdown."""
    from workbench.reports.external_summary import scored_markdown
    from workbench.reports.paper_claims import claims_markdown

    metrics = load_metrics(results)
    verdict = verdict_markdown(metrics)  # the count, then the figure, then the failing checks
    lines = ["# Contact verification workbench: summary", "", *verdict[:2], *forest_markdown(metrics), *verdict[2:]]
    lines += [
        "## Cases",
        "",
        "Errors are relative, measured against the theory evaluated at the load the FEM actually carries "
        "(virtual-work reaction). Times are wall-clock seconds of the whole case (meshing, JIT if cold, solve).",
        "",
        "| case | verdict | method | ndofs | time (s) | P (N/mm) | errors (✓/✗: within/outside the case tolerance) |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, m in metrics.items():
        errs, tol, checks = m.get("errors", {}), m.get("tolerances", {}), m.get("checks", {})
        cells = []
        for k in (*[k for k in _HEADLINE if errs.get(k) is not None], *[k for k in checks if k not in _HEADLINE]):
            ok = checks.get(k, errs.get(k) is not None and k in tol and errs[k] <= tol[k])
            mark = "" if k not in tol and k not in checks else (" ✓" if ok else " ✗")
            cells.append(f"{k}{mark}" if errs.get(k) is None else f"{k} {_fmt(errs[k])}{mark}")
        runs = len(m.get("runs", [])) or 1
        method = f"{m.get('method')}, {m.get('kinematics')}" + (f", {runs} runs" if runs > 1 else "")
        lines.append(
            f"| [{name}]({name}/report.md) | {'PASS' if m.get('pass') else 'FAIL'} | {method} | "
            f"{_fmt(m.get('ndofs'))} | {_fmt(m.get('wall_time_s'))} | {_fmt(m.get('P'))} | "
            + (", ".join(cells) or "-") + " |"
        )
    lines += ["", "✓/✗: within/outside the case tolerance (see each case report for the tolerances).", ""]
    for name, m in metrics.items():
        if m.get("headline"):
            lines.append(f"- **{name}**: {m['headline']}")
    if all(n in metrics and metrics[n].get("steps") for n in ("concave_symmetric", "close_to_conformal")):
        lines += ["## Load against indentation (close-to-conformal paper, Fig. 3)", "",
                  "![P against delta](p_delta.png)", "",
                  "Indentation delta from the LCP of the rigid curves at each displacement step; P is the FEM load of "
                  "the whole contact (both patches of the symmetric configuration). Hollow markers: the paper's "
                  "Table 1 as printed (its symmetric P is one patch's load, see the claims table). Its geometry and "
                  "body size are not published, and in 2D the load at a given indentation "
                  "depends on the whole body, so only the trend (close-to-conformal stiffer) is comparable.", ""]
    lines += scored_markdown(results)
    lines += _budget_markdown(metrics)
    lines += [""] + trust_markdown(results)
    lines += ["", claims_markdown(results), ""]
    studies = [("convergence", "Error against run time"), ("stability", "Numerical stability sweep"),
               ("validity", "Validity of the half-plane theories"),
               ("bench", "Performance benchmark"), ("analytic", "Analytic convective table")]
    lines += ["## Studies", ""]
    for folder, title in studies:
        for candidate in ("report.md", "convective.md"):
            if (results / folder / candidate).is_file():
                lines.append(f"- [{title}]({folder}/{candidate})")
                break
        else:
            lines.append(f"- {title}: not run yet (`make {folder if folder != 'analytic' else 'run'}`)")
    from workbench.reports.study_times import study_times_markdown

    lines += [""] + study_times_markdown(results)
    return "\n".join(lines) + "\n"


def check_summary_writes(results: Path, *, case_reports: bool = True) -> None:
    """Refuse (:class:`workbench.paths.OutputError`, one line) before :func:`write_summary` writes anything into a
    folder or over a file that the workbench did not write: the summary files at the top of ``results``, the
    case folders whose reports it draws again, the study folders that get an HTML twin."""
    results = Path(results)
    for name in ("report.md", "report.html", "p_delta.png", FOREST_PNG):
        check_root_file(results, name)
    if case_reports:
        for name in case_names():
            if (results / name / "metrics.json").is_file() or (results / name).is_symlink():
                check_dir(results / name)
    for study in STUDY_REPORTS:
        f = results / study
        if f.is_file():
            if f.parent == results:
                check_root_file(results, f.with_suffix(".html").name)
            else:
                check_dir(f.parent)


def write_summary(results: Path, *, case_reports: bool = True) -> None:
    """Write ``report.md`` and ``report.html`` in ``results``, and an HTML twin of each study report.

    Args:
        results: The output folder.
        case_reports: Also draw every case report again from its saved ``metrics.json`` and ``series.json``
            (:func:`workbench.reports.case_report.write_case_reports`).
    """
    results = Path(results)
    check_summary_writes(results, case_reports=case_reports)  # refuse before anything is written (issue 23)
    if case_reports:
        from workbench.reports.case_report import write_case_reports

        redone = write_case_reports(results, case_names())
        if redone:
            print(f"redrew {len(redone)} case report(s): {', '.join(f.name for f in redone)}")
    metrics = load_metrics(results)
    if all(n in metrics and metrics[n].get("steps") for n in ("concave_symmetric", "close_to_conformal")):
        from workbench.reports.plots import plot_load_indentation

        curves = {n.replace("_", " "): ([st["delta_lcp"] for st in metrics[n]["steps"]],
                                         [st["P"] for st in metrics[n]["steps"]])
                  for n in ("concave_symmetric", "close_to_conformal")}
        from analytic.hertz import TABLE1

        paper = {f"paper Table 1, {label}": ([r.delta for r in TABLE1 if r.config == cfg],
                                             [r.P for r in TABLE1 if r.config == cfg])
                 for cfg, label in (("symmetrical", "symmetrical (P as printed: one patch)"),
                                    ("close_to_conformal", "close to conformal"))}
        record_root_files(results, ["p_delta.png"])
        plot_load_indentation(curves, results / "p_delta.png", title="Load against indentation (our designs)",
                              reference=paper)
    rows = forest_rows(metrics)
    if rows:
        from workbench.reports.forest_plot import plot_forest

        record_root_files(results, [FOREST_PNG])
        passed = sum(bool(m.get("pass")) for m in metrics.values())
        plot_forest(rows, results / FOREST_PNG, title=f"Every judged quantity against its theory ({passed} of "
                                                        f"{len(case_names())} cases PASS)")
    md = summary_markdown(results)
    write_root_text(results, "report.md", md)
    # the summary links the Markdown reports; its HTML twin links their HTML twins
    write_root_text(results, "report.html", markdown_to_html(md, title="Contact workbench summary",
                                                             link_suffixes={".md": ".html"}))
    for study in STUDY_REPORTS:
        f = results / study
        if f.is_file():  # an HTML twin of each study report, so the summary's links work in a browser
            html = markdown_to_html(f.read_text(), title=f.parent.name, link_suffixes={".md": ".html"})
            if f.parent == results:
                write_root_text(results, f.with_suffix(".html").name, html)
            else:
                write_text(f.with_suffix(".html"), html)
    print(f"wrote {results / 'report.md'} and {results / 'report.html'}")
