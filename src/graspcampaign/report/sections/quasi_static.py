"""Report sections for the quasi-static studies (paper Sec. 6.2, 6.3, 6.5).

One entry point, :func:`section`, chooses the study's section by the study name in the manifest
(``shapes``, ``ablation``, ``baseline_grid``); any other quasi-static study gets the planner
comparison. ``mesh_resolution`` and ``sensitivity`` have kinds and sections of their own. Every
section reads the record columns of docs/records.md (``quasi_static``) and the paper's values
from the manifest's ``config.paper`` block; none runs a trial.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import pandas as pd

from graspcampaign.campaign.records import RunStore
from graspcampaign.report import figure
from graspcampaign.report import table as tbl
from graspcampaign.report.document import Report

PROPOSED = "heuristic"
RESIDUAL_LIMIT_N = 0.5  # tau_F of Algorithm 1 (SPEC Sec. 2.7); only used to draw the criterion


@dataclass
class Context:
    """What every section needs: the report, the records, the manifest and the run's store."""

    report: Report
    records: pd.DataFrame
    manifest: dict
    store: RunStore | None

    @property
    def config(self) -> dict:
        return self.manifest.get("config") or {}

    @property
    def paper(self) -> dict:
        return self.config.get("paper") or {}

    def levels(self, factor: str) -> list:
        """Return the design's levels of ``factor`` in config order (for table order)."""
        return list((self.config.get("factors") or {}).get(factor, []))

    @property
    def order(self) -> dict[str, list]:
        return {f: self.levels(f) for f in ("planner", "shape", "mu", "mass_kg", "nodes")}

    @property
    def bootstrap(self) -> tbl.BootstrapSpec:
        """Shape-clustered bootstrap seeded by the study seed (reproducible, stated)."""
        return tbl.BootstrapSpec(cluster="shape", seed=int(self.config.get("seed", 0)))

    def planners(self) -> list[str]:
        found = list(dict.fromkeys(self.records["planner"].dropna())) if "planner" in self.records \
            else []
        order = self.levels("planner")
        return [p for p in order if p in found] + [p for p in found if p not in order]


def section(report: Report, records: pd.DataFrame, manifest: dict, store: RunStore | None) -> None:
    """Write the section of a quasi-static study, chosen by the study name."""
    ctx = Context(report, records, manifest, store)
    handler = STUDY_SECTIONS.get(manifest.get("study"), planner_comparison)
    report.text(tbl.status_note(records))
    handler(ctx)
    contact_parameters(ctx)


# --------------------------------------------------------------------------------------------
# Pieces shared by the studies
# --------------------------------------------------------------------------------------------


def _paper_rate(mapping: dict | None, overall: dict | None = None) -> Callable[[tuple], Any]:
    """Return key -> paper rate [%]; the first key element is the planner.

    A planner whose overall paper rate is exactly 0% or 100% has that rate on every subset
    (e.g. the centroid baseline's 0% "at every mu", Sec. 6.5), so it is carried to subgroups.
    """
    mapping = mapping or {}
    overall = overall or {}

    def lookup(key: tuple) -> Any:
        planner = key[0]
        if planner in mapping:
            return mapping[planner]
        value = overall.get(planner)
        return value if value in (0, 0.0, 100, 100.0) else None
    return lookup


def add_rates(ctx: Context, name: str, by: list[str], caption: str,
              paper: Callable[[tuple], Any] | None, bootstrap: bool = True) -> tbl.TablePair:
    """Add a success-rate table (with its differences in words) and return it."""
    spec = ctx.bootstrap if bootstrap and "shape" in ctx.records else None
    pair = tbl.rate_table(ctx.records, by, paper_pct=paper, bootstrap=spec, order=ctx.order)
    note = f" Intervals: Wilson 95% per row; {spec.note()}." if spec else " Intervals: Wilson 95%."
    ctx.report.table(name, pair.full, caption + "." + note, pair.display)
    ctx.report.text(tbl.differences_in_words(pair.full, by))
    return pair


def add_paired(ctx: Context, planners: list[str]) -> None:
    """McNemar of the proposed planner against every other planner on matched scenes."""
    others = [p for p in planners if p != PROPOSED]
    if PROPOSED not in planners or not others or "scene_id" not in ctx.records:
        return
    pair = tbl.mcnemar_table(ctx.records, PROPOSED, others)
    ctx.report.table(
        "mcnemar", pair.full,
        "Paired comparison, McNemar (1947) on occurrence-matched pairs (rows paired by scene_id: "
        "same shape, mass, friction and seed); χ² with continuity correction, exact binomial p, "
        "discordant-pair odds ratio (> 1 favours the proposed planner) with its exact 95% "
        "interval. The paper reports no paired test for this study", pair.display)


def add_design_limit(ctx: Context, by: list[str]) -> None:
    if "delta_max_mm" not in ctx.records:
        return
    pair = tbl.design_limit_table(ctx.records, by, ctx.order)
    ctx.report.table(
        "design_limit", pair.full,
        "Penetration against the paper's 1 mm design limit (Sec. 4): how often the deepest "
        "contact δmax exceeds 1 mm, executed trials, Wilson 95%. SPEC Sec. 2.7: our SI "
        "evaluation keeps Algorithm 2 as published, so this is reported, never rescaled",
        pair.display)
    if len(pair.full):
        worst = pair.full.loc[pair.full["exceeds_pct"].idxmax()]
        label = ", ".join(str(worst[c]) for c in by)
        ctx.report.text(
            f"The 1 mm design limit is exceeded in {int(pair.full['exceeds_1mm'].sum())} of "
            f"{int(pair.full['n'].sum())} executed trials; most often for {label} "
            f"({tbl.format_number(worst['exceeds_pct'])}%). The paper keeps every contact within "
            "1 mm.")


def add_failure_checks(ctx: Context, by: list[str],
                       paper: Callable[[tuple], str] | None = None) -> None:
    if "failure_check" not in ctx.records:
        return
    pair = tbl.failure_check_table(ctx.records, by, ctx.order, paper)
    ctx.report.table(
        "failure_checks", pair.full,
        "First failing check of Algorithm 1 (none = success; residual ‖R‖ ≥ 0.5 N, torque, "
        "slip margin ≤ 0), executed trials", pair.display)


def contact_parameters(ctx: Context) -> None:
    """Identified contact parameters of the run's soft bodies (``prepared/``) beside Table 3."""
    if ctx.store is None:
        return
    prepared = ctx.store.read("prepared").to_pandas()
    if not len(prepared):
        return
    from graspcampaign.report.sections.pso import add_table3

    add_table3(ctx.report, prepared, ctx.manifest, name="identifications",
               label="PSO identifications of this run's soft bodies (prepared/)")


# --------------------------------------------------------------------------------------------
# Sec. 6.2, Fig. 15: shapes
# --------------------------------------------------------------------------------------------


def shapes(ctx: Context) -> None:
    """Per-shape outcome and grasp metrics beside the paper's Fig. 15."""
    ok = tbl.executed(ctx.records)
    paper_success = ctx.paper.get("success") or {}
    paper_check = ctx.paper.get("failure_check") or {}
    errors = ctx.records[ctx.records["status"] == "error"].groupby("shape").size()
    metric_cols = ["h_total", "residual_norm_n", "torque_norm_nm", "slip_margin_n",
                   "delta_max_mm"]
    rows = []
    shapes_order = ctx.levels("shape") or sorted(ctx.records["shape"].unique())
    for shape in [s for s in shapes_order if s in set(ctx.records["shape"])]:
        grp = ok[ok["shape"] == shape]
        n, k = len(grp), int(grp["success"].sum())
        paper = paper_success.get(shape)
        paper_fc = paper_check.get(shape, "none" if paper else None)
        checks = grp["failure_check"].value_counts() if "failure_check" in grp else pd.Series()
        row: dict[str, Any] = {"shape": shape, "paper_success": paper,
                               "paper_failure_check": paper_fc, "n": n, "successes": k,
                               "n_error": int(errors.get(shape, 0)),
                               "success_rate": k / n if n else math.nan,
                               "failure_check": ", ".join(f"{c} {v}" for c, v in checks.items())}
        for col in metric_cols:
            row[col] = float(grp[col].median()) if col in grp and n else math.nan
        row["exceeds_1mm"] = int((grp["delta_max_mm"] > tbl.DESIGN_LIMIT_MM).sum()) \
            if "delta_max_mm" in grp else 0
        row["verdict"] = _shape_verdict(paper, paper_fc, k, n, checks)
        rows.append(row)
    full = pd.DataFrame(rows)
    if full.empty:
        return
    display = pd.DataFrame({
        "shape": full["shape"],
        "paper": [_outcome(p, c) for p, c in zip(full["paper_success"],
                                                 full["paper_failure_check"], strict=True)],
        "ours": [_ours_outcome(k, n, fc) for k, n, fc in
                 zip(full["successes"], full["n"], full["failure_check"], strict=True)],
        "n": full["n"], "errors": full["n_error"],
        "H(G)": [tbl.format_number(v, 3) for v in full["h_total"]],
        "‖R‖ [N]": [tbl.format_number(v, 3) for v in full["residual_norm_n"]],
        "‖τ‖ [N·m]": [tbl.format_number(v, 4) for v in full["torque_norm_nm"]],
        "slip margin [N]": [tbl.format_number(v, 3) for v in full["slip_margin_n"]],
        "δmax [mm]": [tbl.format_number(v, 2) for v in full["delta_max_mm"]],
        "> 1 mm": full["exceeds_1mm"], "verdict": full["verdict"],
    })
    ctx.report.table("shapes", full, "Outcome and grasp metrics per shape beside Fig. 15 "
                     "(medians over the shape's executed trials; one trial per shape at the "
                     "default seed)", display)
    disagree = full[full["verdict"].str.startswith("differs")]
    ctx.report.text(
        "Every shape's outcome agrees with the paper." if disagree.empty else
        "**Where we differ from the paper.**\n\n" + "\n".join(
            f"- **{r.shape}:** {r.verdict}." for r in disagree.itertuples()))
    h_range = ctx.paper.get("h_range")
    if h_range and "h_total" in ok and len(ok):
        lo, hi = float(ok["h_total"].min()), float(ok["h_total"].max())
        inside = h_range[0] <= lo and hi <= h_range[1]
        h_table = pd.DataFrame([{
            "quantity": "H(G) of the chosen grasps, min–max over shapes",
            "paper": f"{h_range[0]}–{h_range[1]}", "ours_min": lo, "ours_max": hi,
            "n": len(ok), "verdict": "inside the paper's range" if inside else
            "differs from the paper: outside its range"}])
        ctx.report.table("h_range", h_table, "Heuristic value range across shapes (Fig. 15 caption)",
                         h_table.assign(ours_min=tbl.format_number(lo, 3),
                                        ours_max=tbl.format_number(hi, 3)))
    ctx.report.figure("fig15_shape_metrics",
                      figure.fig15_shape_metrics(full, h_range, RESIDUAL_LIMIT_N),
                      "Fig. 15 (ours): grasp metrics per shape; green = success, red = failure; "
                      "tick labels give our outcome and the paper's")
    add_design_limit(ctx, ["shape"])
    add_failure_checks(ctx, ["shape"], lambda k: paper_check.get(
        k[0], "none" if paper_success.get(k[0]) else "not reported"))


def _outcome(success, check) -> str:
    if success is None or (isinstance(success, float) and math.isnan(success)):
        return "not reported"
    return "success" if success else f"failure ({check or 'check not stated'})"


def _ours_outcome(k: int, n: int, checks: str) -> str:
    if n == 0:
        return "no executed trial"
    if n == 1:
        return "success" if k else f"failure ({checks.split(' ')[0]})"
    return f"{k}/{n} succeed ({checks})"


def _shape_verdict(paper, paper_fc, k: int, n: int, checks: pd.Series) -> str:
    if n == 0:
        return "no executed trial"
    if paper is None:
        return "the paper reports no outcome for this shape"
    ours_success = k / n >= 0.5
    ours = "success" if ours_success else "failure"
    if ours_success != bool(paper):
        return (f"differs from the paper: the paper reports "
                f"{'success' if paper else f'failure ({paper_fc})'}, ours is {ours} ({k}/{n})")
    if not paper and paper_fc and len(checks):
        main = checks.drop("none", errors="ignore")
        ours_fc = main.idxmax() if len(main) else "none"
        if ours_fc != paper_fc:
            return (f"differs from the paper in the failing check: paper {paper_fc}, ours "
                    f"{ours_fc} (both fail)")
    return f"agrees with the paper ({ours}, {k}/{n})"


# --------------------------------------------------------------------------------------------
# Sec. 6.3, Fig. 16: ablation; Sec. 6.5, Fig. 18: baseline grid; any other planner comparison
# --------------------------------------------------------------------------------------------


def ablation(ctx: Context) -> None:
    """Success per ablation variant, Fig. 16, paired tests, design limit, failing checks."""
    planners = ctx.planners()
    paper = ctx.paper.get("success_pct") or {}
    pair = add_rates(ctx, "success_by_planner", ["planner"],
                     f"Success per variant beside Fig. 16 (paper: "
                     f"{ctx.paper.get('trials_per_variant', 'n not stated')} trials per variant)",
                     _paper_rate(paper))
    proposed = pair.full[pair.full["planner"] == PROPOSED]
    if len(proposed) and proposed["n"].iloc[0]:
        r = proposed.iloc[0]
        ctx.report.text(
            f"Power: at n = {r['n']} our 95% Wilson interval on the full heuristic spans "
            f"{tbl.format_number(r['wilson_low_pct'])}–{tbl.format_number(r['wilson_high_pct'])}% "
            f"(half-width ≈ {tbl.format_number((r['wilson_high_pct'] - r['wilson_low_pct']) / 2)} "
            "pp); the paper quotes roughly ±12 pp at 50 trials per variant (Sec. 6.3).")
    ctx.report.figure("fig16_ablation", figure.fig16_ablation(pair.full),
                      "Fig. 16 (ours): success per variant with Wilson 95% bars; black marks are "
                      "the paper's values")
    add_paired(ctx, planners)
    add_design_limit(ctx, ["planner"])
    add_failure_checks(ctx, ["planner"])


def baseline_grid(ctx: Context) -> None:
    """Success per planner and per shape (Fig. 18), by friction and mass, paired tests."""
    planners = ctx.planners()
    paper = ctx.paper.get("success_pct") or {}
    pair = add_rates(ctx, "success_by_planner", ["planner"],
                     f"Success per planner beside Fig. 18a (paper: "
                     f"{ctx.paper.get('trials_per_planner', 'n not stated')} trials per planner)",
                     _paper_rate(paper))
    by_shape_paper = ctx.paper.get("success_by_shape_pct") or {}
    shape_pair = add_rates(
        ctx, "success_by_shape", ["shape", "planner"],
        "Success per shape and planner beside Fig. 18b (the paper prints only the rounded cube's "
        "values; a planner at 0% overall is 0% on every shape)",
        lambda k: _paper_rate(by_shape_paper.get(k[0]), paper)((k[1],)), bootstrap=False)
    by_shape = shape_pair.full
    ctx.report.figure("fig18_baselines", figure.fig18_baselines(pair.full, by_shape),
                      "Fig. 18 (ours): (a) overall success per planner, (b) per shape; Wilson 95% "
                      "bars; black marks are the paper's values")
    add_paired(ctx, planners)
    for factor, label in (("mu", "friction coefficient μ"), ("mass_kg", "object mass")):
        if factor in ctx.records and ctx.records[factor].nunique() > 1:
            add_rates(ctx, f"success_by_{factor}", ["planner", factor],
                      f"Success per planner and {label} (not printed in the paper except where a "
                      "planner's overall rate is 0% or 100%)",
                      _paper_rate({}, paper), bootstrap=True)
    add_design_limit(ctx, ["planner"])
    add_failure_checks(ctx, ["planner"], lambda k: (
        "residual (normal forces stay at seed level, Sec. 6.5)" if k[0] == "centroid"
        else "not reported"))


def planner_comparison(ctx: Context) -> None:
    """Any other quasi-static study: success per planner (or shape), tests, limits, checks."""
    planners = ctx.planners()
    by = ["planner"] if len(planners) > 1 else ["shape"] if "shape" in ctx.records else None
    if by is None:
        return
    paper = ctx.paper.get("success_pct") or {}
    add_rates(ctx, "success_rates", by, f"Success per {by[0]}",
              _paper_rate(paper) if by == ["planner"] else None)
    add_paired(ctx, planners)
    add_design_limit(ctx, by)
    add_failure_checks(ctx, by)


STUDY_SECTIONS: dict[str, Callable[[Context], None]] = {
    "shapes": shapes,
    "ablation": ablation,
    "baseline_grid": baseline_grid,
}
