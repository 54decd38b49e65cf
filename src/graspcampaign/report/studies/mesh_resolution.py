"""Report of ``mesh_resolution`` (paper Sec. 6.7, Fig. 20; Sec. 11): three panels.

``resolution``: runtime per evaluation and final residual against node count; the cost ratio
largest/smallest mesh is the median of the ratios each trial measured against the reference mesh
interleaved in the same process (``cost_ratio_vs_reference``, so machine load cancels) -- the
report times nothing itself. ``budget``: success against the candidate budget N_cand with the
reference search. ``n_max``: the baseline grid's failures re-evaluated at a doubled N_max, checked
against the ``baseline_grid`` records beside this run when there are any.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from graspcampaign.analysis.records import Estimate, rate
from graspcampaign.analysis.vocabulary import OTHER_COLOURS, PROPOSED, colour
from graspcampaign.campaign.records import RunStore
from graspcampaign.report import style
from graspcampaign.report.document import Col
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Claims, Figure, Finding, ReportSpec, Table, Text, Value


def _panel(run: Run, name: str) -> pd.DataFrame:
    return run.ok[run.ok["panel"] == name] if "panel" in run.ok else run.ok.iloc[:0]


def _rate_cols(g: pd.DataFrame, col: str, prefix: str) -> dict:
    e = rate(g, outcome=col)
    return {f"{prefix}_pct": e.value, f"{prefix}_low_pct": e.low, f"{prefix}_high_pct": e.high}


def _runtime(run: Run) -> pd.DataFrame:
    rows, paper_ms = [], run.paper.runtime_ms
    for nodes, g in _panel(run, "resolution").groupby("nodes", sort=True):
        t = 1e3 * g["eval_time_s"].to_numpy(float)
        rows.append({"nodes": int(nodes), "faces": int(g["n_faces"].iloc[0]), "trials": len(g),
                     "eval_median_ms": float(np.median(t)), "eval_p25_ms": np.quantile(t, 0.25),
                     "eval_p75_ms": np.quantile(t, 0.75),
                     "cost_ratio_vs_reference": float(g["cost_ratio_vs_reference"].median()),
                     "search_median_ms": 1e3 * float(g["search_time_s"].median()),
                     "equilibrium_median_ms": 1e3 * float(g["equilibrium_time_s"].median()),
                     "paper_runtime_ms": paper_ms.get(str(int(nodes))),
                     "residual_median_n": float(g["residual_norm_n"].median()),
                     "loop_at_n_max": int(g["loop_capped"].sum()),
                     **_rate_cols(g, "success", "success")})
    return pd.DataFrame(rows)


def _cost_ratio(run: Run) -> Estimate:
    res = _panel(run, "resolution")
    top = res.loc[res["nodes"] == res["nodes"].max(), "cost_ratio_vs_reference"].to_numpy(float)
    if not top.size:
        raise ValueError("no resolution trial")
    return Estimate(float(np.median(top)), n=top.size)


def _budget(run: Run) -> pd.DataFrame:
    bud = _panel(run, "budget")
    ref = bud[bud["planner"] == "reference"].set_index(["shape", "nodes"])
    rows = []
    for (nodes, n_cand), g in bud.groupby(["nodes", "n_cand"]):
        is_ref = (g["planner"] == "reference").all()
        same = ref.loc[list(zip(g["shape"], g["nodes"], strict=True))] if len(ref) else None
        found = [set(a) == set(b) for a, b in zip(
            g[["vertex_1", "vertex_2", "vertex_3"]].to_numpy(),
            same[["vertex_1", "vertex_2", "vertex_3"]].to_numpy(), strict=True)] \
            if same is not None else []
        rows.append({"nodes": int(nodes), "n_cand": int(n_cand), "trials": len(g),
                     "planner": "reference" if is_ref else PROPOSED,
                     **_rate_cols(g, "success", "success"),
                     **_rate_cols(g, "success_vertical", "vertical"),
                     "h_mean": float(g["h_planner"].mean()),
                     "h_gap_to_reference": float(np.mean(g["h_planner"].to_numpy()
                                                         - same["h_planner"].to_numpy()))
                     if same is not None else np.nan,
                     "reference_argmin_found_pct": 100 * float(np.mean(found)) if found
                     else np.nan})
    return pd.DataFrame(rows).sort_values(["nodes", "planner", "n_cand"]).reset_index(drop=True)


def _n_max(run: Run) -> pd.DataFrame:
    rows = []
    for planner, g in _panel(run, "n_max").groupby("planner", sort=False):
        failed = g[~g["success"]]
        rows.append({"planner": planner, "trials": len(g), "failures_at_n_max": len(failed),
                     "failures_loop_still_moving": int(failed["loop_capped"].sum()),
                     "budget_capped": int(failed["budget_capped"].astype(bool).sum()),
                     **_rate_cols(g, "success", "success"),
                     **_rate_cols(g, "success_rerun", "rerun"),
                     "residual_median_failures_rerun_n":
                         float(failed["residual_norm_rerun_n"].median())})
    return pd.DataFrame(rows)


def _cross_check(run: Run) -> str:
    nm = _panel(run, "n_max")
    base_dir = Path(run.store.path).parents[1] / "baseline_grid" if run.store else None
    frames = [RunStore(d).read().to_pandas().assign(baseline_run=d.name)
              for d in sorted(base_dir.iterdir()) if RunStore(d).exists()] \
        if base_dir is not None and base_dir.is_dir() and len(nm) else []
    if not frames:
        return ("No `baseline_grid` records beside this run: the re-derived trials were not "
                "cross-checked against them.") if len(nm) else ""
    base = pd.concat(frames, ignore_index=True)
    merged = nm.merge(base[base["status"] == "ok"], suffixes=("", "_baseline"),
                      on=["shape", "mass_kg", "mu", "planner", "seed"])
    same = (merged["success"].astype(bool) == merged["success_baseline"].astype(bool)).sum()
    close = np.isclose(merged["residual_norm_n"], merged["residual_norm_n_baseline"],
                       rtol=1e-9).sum()
    return (f"Cross-check against the `baseline_grid` records beside this run: {same} of "
            f"{len(merged)} re-derived trials have the baseline's verdict and {close} its "
            "residual (relative 1e-9).")


def finding(run: Run) -> str:
    p, text = run.paper, []
    if len(_panel(run, "resolution")):
        r = _cost_ratio(run)
        text.append(f"The cost of one evaluation grows {r.value:.2f}-fold from the smallest to "
                    f"the largest mesh (paper {p.runtime_ratio_1750_144}, target ≤ "
                    f"{p.runtime_ratio_target}): neither stage touches the mesh, since the "
                    "candidate search scores a fixed N_cand of vertex triples from precomputed "
                    "data and Algorithm 2 works on three contacts, while the paper's growth "
                    "comes from per-candidate collision queries (Sec. 6.7).")
    if len(_panel(run, "n_max")):
        t = _n_max(run)
        text.append(f"Of {int(t['failures_at_n_max'].sum())} baseline-grid failures, "
                    f"{int(t['budget_capped'].sum())} pass at the doubled N_max: what remains is "
                    "the horizontal part of the normal-only residual, which Algorithm 2 does not "
                    "act on, so more iterations cannot remove it (the paper did not run this).")
    return " ".join(text) + (" (`docs/decisions.md`, *Sensitivity, mesh resolution, surrogate "
                             "(issue 7)*.)")


def fig20(run: Run, fig) -> None:
    res, tab = _panel(run, "resolution"), _budget(run) if len(_panel(run, "budget")) else None
    axes = list(np.atleast_1d(fig.subplots(1 + (tab is not None), 2)).ravel())
    c, p = colour("planner", PROPOSED), run.paper
    if len(res):
        ax, per = axes.pop(0), _runtime(run)
        ax.scatter(res["nodes"], 1e3 * res["eval_time_s"], s=10, alpha=0.35, color=c,
                   label="ours, single trials")
        ax.plot(per["nodes"], per["eval_median_ms"], marker="o", color=c, label="ours, median")
        ref = 1e3 * float(res["eval_time_reference_s"].median())
        ax.plot(per["nodes"], ref * per["cost_ratio_vs_reference"], marker="s",
                color=OTHER_COLOURS[1], label="ours, load-corrected (interleaved ratio)")
        n0, t0 = per["nodes"].iloc[0], per["eval_median_ms"].iloc[0]
        grid = np.geomspace(per["nodes"].min(), per["nodes"].max(), 50)
        ax.plot(grid, t0 * grid / n0, color="#888888", linestyle="-.", label="O(n) guide")
        ax.plot(grid, t0 * np.sqrt(grid / n0), color="#888888", linestyle=":", label="O(√n)")
        xs, ys = zip(*sorted((int(k), v) for k, v in p.runtime_ms.items()), strict=True)
        ax.plot(xs, ys, linestyle="none", marker="D", color=style.PAPER, label="paper (MATLAB)")
        ax.set(xscale="log", yscale="log", xlabel="mesh nodes n [–]",
               ylabel="runtime per evaluation [ms]", title="(a) runtime per evaluation")
        ax.legend(loc="upper left", ncol=2, fontsize=6.5)
        ax = axes.pop(0)
        ax.scatter(res["nodes"], res["residual_norm_n"], s=10, alpha=0.35, color=c,
                   label="ours, single trials")
        tau = float(run.config["evaluator"]["tau_f_n"])
        ax.axhline(tau, color=style.CRITERION, linestyle="--", label=f"τ_F = {tau:g} N")
        lo, hi = p.residual_scatter_n
        ax.axhspan(lo, hi, color=style.PAPER, alpha=0.12, label=f"paper's scatter {lo}–{hi} N")
        ax.set(xscale="log", yscale="log", xlabel="mesh nodes n [–]",
               ylabel="final force residual ‖R‖ [N]", title="(b) final residual")
        ax.legend(loc="best", fontsize=6.5)
    if tab is not None:
        ax_c, ax_d = axes[:2]
        for i, (nodes, g) in enumerate(tab.groupby("nodes")):
            heur, col = g[g["planner"] != "reference"], OTHER_COLOURS[i % len(OTHER_COLOURS)]
            ax_c.errorbar(heur["n_cand"], heur["success_pct"], yerr=np.vstack([
                heur["success_pct"] - heur["success_low_pct"],
                heur["success_high_pct"] - heur["success_pct"]]), marker="o", color=col,
                capsize=2, label=f"{nodes} nodes, ‖R‖ check (Wilson 95%)")
            ax_c.plot(heur["n_cand"], heur["vertical_pct"], marker="s", linestyle="--",
                      color=col, label=f"{nodes} nodes, |R_z| reading")
            ax_d.plot(heur["n_cand"], np.maximum(heur["h_gap_to_reference"], 1e-4), marker="o",
                      color=col, label=f"{nodes} nodes")
        lo, hi = p.effective_budget_triples
        ax_d.axvspan(lo, hi, color=style.PAPER, alpha=0.12, label=f"paper: {lo}–{hi} triples")
        ax_c.set(xscale="log", ylim=(-2, 102), xlabel="candidate budget N_cand [triples]",
                 ylabel="success rate [%]", title="(c) success against N_cand")
        ax_d.set(xscale="log", yscale="log", xlabel="candidate budget N_cand [triples]",
                 ylabel="mean H(G) − reference H [–]", title="(d) gap to the reference search")
        ax_c.legend(fontsize=6.2)
        ax_d.legend(fontsize=6.5)


SPEC = ReportSpec("mesh_resolution", [
    Finding(finding),
    Table("mesh_resolution_runtime", "Runtime per evaluation (wall clock during the run; the "
          "paper's is MATLAB on a workstation) and final residual per node count beside "
          "Fig. 20", _runtime, [
              Col("nodes", "nodes"), Col("faces", "faces"), Col("trials", "trials"),
              Col("paper_runtime_ms", "paper [ms]", 0),
              Col("eval_median_ms", "ours median [ms]", sig=3),
              Col("cost_ratio_vs_reference", "cost / reference mesh", 2),
              Col("search_median_ms", "search [ms]", sig=3),
              Col("equilibrium_median_ms", "Algorithm 2 [ms]", sig=3),
              Col("residual_median_n", "median ‖R‖ [N]", sig=3),
              Col("success_pct", "success % (95%)", 1, low="success_low_pct",
                  high="success_high_pct"), Col("loop_at_n_max", "loop at N_max")]),
    Claims("cost_ratio", "Per-evaluation cost ratio, largest against smallest mesh (median of "
           "the per-trial ratios measured interleaved in the same process, so machine load "
           "cancels; no interval)", [Value("cost ratio, largest / reference mesh", "Sec. 6.7", _cost_ratio,
                             lambda p: p.runtime_ratio_1750_144, digits=2),
                       Value("cost ratio against the paper's target (≤)", "Sec. 11",
                             _cost_ratio, lambda p: (0.0, p.runtime_ratio_target), digits=2)]),
    Table("success_vs_n_cand", "Success (‖R‖ check and |R_z| reading, Wilson 95%) against "
          "N_cand (the paper's future work, Sec. 11); mean H(G) of the chosen triple, its gap to "
          "the reference search on the same body, and how often the sampled search found the "
          "reference argmin", _budget, [
              Col("nodes", "nodes"), Col("planner", "planner"), Col("n_cand", "N_cand"),
              Col("trials", "trials"),
              Col("success_pct", "success % (95%)", 1, low="success_low_pct",
                  high="success_high_pct"),
              Col("vertical_pct", "|R_z| reading % (95%)", 1, low="vertical_low_pct",
                  high="vertical_high_pct"),
              Col("h_mean", "mean H", 3), Col("h_gap_to_reference", "H gap", sig=3),
              Col("reference_argmin_found_pct", "reference argmin found [%]", 0)],
          empty="the run has no budget panel"),
    Table("n_max_rerun", "Baseline-grid failures at N_max and re-evaluated at the doubled "
          "budget (budget-capped = fails at N_max, passes at the doubled budget)", _n_max, [
              Col("planner", "planner"), Col("trials", "trials"),
              Col("failures_at_n_max", "failures"),
              Col("failures_loop_still_moving", "loop still moving"),
              Col("budget_capped", "budget-capped"),
              Col("success_pct", "success at N_max %", 1, low="success_low_pct",
                  high="success_high_pct"),
              Col("rerun_pct", "at doubled N_max %", 1, low="rerun_low_pct",
                  high="rerun_high_pct"),
              Col("residual_median_failures_rerun_n", "failures' median ‖R‖ after [N]",
                  sig=3)], empty="the run has no n_max panel"),
    Text(_cross_check),
    Figure("fig20_mesh_resolution", "Fig. 20 (ours) and the N_cand curve: (a) runtime per "
           "evaluation with O(n), O(√n) guides and the paper's points; (b) final residual with "
           "τ_F and the paper's scatter band; (c) success against N_cand; (d) H gap to the "
           "reference search", fig20, (10.0, 7.8)),
])
