"""Report section of the ``mesh_resolution`` kind: Fig. 20, the N_cand curve and the N_max re-run.

Reads the records only (and, when present, the ``baseline_grid`` records beside this run, to check
that the ``n_max`` panel re-derived the baseline grid's trials exactly). The per-evaluation cost
ratio largest/smallest mesh is the median over the largest mesh's trials of the ratio each trial
measured against the reference mesh, interleaved in the same process (``cost_ratio_vs_reference``).
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib as mpl
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from graspcampaign import stats
from graspcampaign.report.build import LegacyReport as Report
from graspcampaign.report.sections import executed, rate_cell
from graspcampaign.report.sections.sensitivity import RC

OURS = "#1f5aa6"
PAPER = "black"
NODE_COLOURS = ("#1f5aa6", "#e08a1e", "#2e7d32", "#7b4ea3")  # one per resolution, panels (c, d)
RESIDUAL_LIMIT_N = 0.5  # tau_F (Sec. 3.7); only drawn


def section(report: Report, records: pd.DataFrame, manifest: dict, store=None) -> None:
    """Write the mesh-resolution section (Fig. 20, success vs N_cand, N_max = 200 re-run)."""
    config = manifest.get("config") or {}
    paper = config.get("paper") or {}
    ok = executed(records)
    if "panel" not in ok or not len(ok):
        report.text("No executed mesh-resolution trials to report.")
        return
    panels = set(ok["panel"])
    if "resolution" in panels:
        _resolution(report, ok[ok["panel"] == "resolution"], config, paper)
    if "budget" in panels:
        _budget(report, ok[ok["panel"] == "budget"], paper)
    if "n_max" in panels:
        _n_max(report, ok[ok["panel"] == "n_max"], paper, store)
    if "resolution" in panels or "budget" in panels:
        _figure(report, ok, paper)


# -- Fig. 20a/b: runtime and residual against node count ---------------------------------------
def cost_ratio(res: pd.DataFrame) -> dict:
    """Per-evaluation cost ratio of the largest mesh against the reference mesh.

    Returns the median of the per-trial ratios measured at the largest resolution, their range,
    and the ratio of the across-trial medians (largest / smallest resolution) for comparison.
    """
    hi = int(res["nodes"].max())
    lo = int(res["nodes"].min())
    at_hi = res.loc[res["nodes"] == hi, "cost_ratio_vs_reference"].to_numpy(dtype=float)
    ref = int(res["reference_nodes"].iloc[0])
    across = (res.loc[res["nodes"] == hi, "eval_time_s"].median()
              / res.loc[res["nodes"] == lo, "eval_time_s"].median())
    return {"nodes": hi, "reference_nodes": ref, "ratio": float(np.median(at_hi)),
            "ratio_min": float(at_hi.min()), "ratio_max": float(at_hi.max()), "n": int(at_hi.size),
            "ratio_across_trials": float(across), "smallest_nodes": lo}


def _resolution(report: Report, res: pd.DataFrame, config: dict, paper: dict) -> None:
    params = config.get("params") or {}
    paper_ms = {int(k): float(v) for k, v in (paper.get("runtime_ms") or {}).items()}
    rows = []
    for nodes, grp in res.groupby("nodes", sort=True):
        t = 1e3 * grp["eval_time_s"].to_numpy(dtype=float)
        rows.append({
            "nodes": int(nodes), "faces": int(grp["n_faces"].iloc[0]), "trials": len(grp),
            "eval_median_ms": float(np.median(t)), "eval_p25_ms": float(np.quantile(t, 0.25)),
            "eval_p75_ms": float(np.quantile(t, 0.75)),
            "reference_median_ms": 1e3 * float(grp["eval_time_reference_s"].median()),
            "cost_ratio_vs_reference": float(grp["cost_ratio_vs_reference"].median()),
            "search_median_ms": 1e3 * float(grp["search_time_s"].median()),
            "equilibrium_median_ms": 1e3 * float(grp["equilibrium_time_s"].median()),
            "paper_runtime_ms": paper_ms.get(int(nodes), math.nan),
            "residual_median_n": float(grp["residual_norm_n"].median()),
            "residual_min_n": float(grp["residual_norm_n"].min()),
            "residual_max_n": float(grp["residual_norm_n"].max()),
            "success": rate_cell(int(grp["success"].sum()), len(grp)),
            "loop_at_n_max": f"{int(grp['loop_capped'].sum())}/{len(grp)}",
        })
    table = pd.DataFrame(rows)
    report.text(
        f"**Resolution panel (Fig. 20).** {params.get('shape', 'sphere')} at "
        f"{len(table)} resolutions, {config.get('seeds')} seeds each, m = {params.get('mass_kg')} "
        f"kg, μ = {params.get('mu')}; contact parameters identified once on the "
        f"{params.get('identify_nodes')}-node mesh (λ1 = {res['contact_lambda1'].iloc[0]:.3g}, "
        f"n = {res['contact_n_exp'].iloc[0]:.3g}) and held fixed, as the paper does (Sec. 12). "
        f"One evaluation = Algorithm 1 with its N_cand = {int(res['n_cand'].iloc[0])} candidate "
        f"search and Algorithm 2 on the chosen triple; the per-body preparation (features, "
        f"heuristic context) is built once per body and excluded. Each trial timed it "
        f"{int(res['timing_repeats'].iloc[0])} times interleaved with the same evaluation on the "
        f"{int(res['reference_nodes'].iloc[0])}-node mesh (medians). Wall clock on "
        f"this machine; the paper's times are MATLAB on a workstation.")
    report.table("mesh_resolution_runtime", table,
                 "Runtime per evaluation and final residual per node count beside Fig. 20 "
                 "(paper: 37 ms at 144, 43 ms at 390, 72 ms at 1750 nodes)")
    r = cost_ratio(res)
    target = paper.get("runtime_ratio_target", 1.5)
    paper_ratio = paper.get("runtime_ratio_1750_144")
    summary = pd.DataFrame([{
        "quantity": f"per-evaluation cost ratio {r['nodes']}/{r['reference_nodes']} nodes",
        "ours": r["ratio"], "ours_min": r["ratio_min"], "ours_max": r["ratio_max"],
        "trials": r["n"], "target": target, "paper": paper_ratio,
        "meets_target": bool(r["ratio"] <= float(target)),
        "ratio_of_medians_across_trials": r["ratio_across_trials"],
    }])
    report.table("cost_ratio", summary,
                 "Per-evaluation cost ratio (median of per-trial ratios measured in the same "
                 "process; min–max over trials)")
    report.text(
        f"**Per-evaluation cost ratio {r['nodes']}/{r['reference_nodes']} nodes: "
        f"{r['ratio']:.2f}** (per-trial range {r['ratio_min']:.2f}–{r['ratio_max']:.2f}, "
        f"{r['n']} trials; target ≤ {target}, paper {paper_ratio}). "
        f"{'Meets' if r['ratio'] <= float(target) else 'Misses'} the target. The ratio of "
        f"across-trial medians is {r['ratio_across_trials']:.2f}; it includes the machine's load "
        f"drift between trials, which the interleaved ratio cancels. Our cost is flat because "
        f"neither stage touches the mesh: the candidate search scores a fixed N_cand of triples "
        f"from precomputed per-vertex data, and Algorithm 2 works on three contacts "
        f"(median {table['search_median_ms'].median():.2f} ms search, "
        f"{table['equilibrium_median_ms'].median():.2f} ms equilibrium loop). The paper's growth "
        f"comes from per-candidate collision queries (Sec. 6.7), which this evaluator does not "
        f"make (contacts are mesh vertices). Final residual: median "
        f"{table['residual_median_n'].min():.2f}–{table['residual_median_n'].max():.2f} N per "
        f"resolution, against the paper's single-run scatter of "
        f"{'–'.join(map(str, paper.get('residual_scatter_n', [])))} N; the loop was still moving "
        f"at N_max in {int(res['loop_capped'].sum())} of {len(res)} trials.")


# -- Sec. 11: success against N_cand -------------------------------------------------------------
def budget_table(bud: pd.DataFrame) -> pd.DataFrame:
    """Per (nodes, N_cand): success under both readings, mean H and its gap to the reference."""
    ref = bud[bud["planner"] == "reference"].set_index(["shape", "nodes"])
    rows = []
    for (nodes, n_cand), grp in bud[bud["planner"] != "reference"].groupby(["nodes", "n_cand"]):
        same_body = ref.loc[list(zip(grp["shape"], grp["nodes"], strict=True))]
        h_ref = same_body["h_planner"]
        key_ref = same_body[["vertex_1", "vertex_2", "vertex_3"]].to_numpy()
        same = [set(a) == set(b) for a, b in zip(
            grp[["vertex_1", "vertex_2", "vertex_3"]].to_numpy(), key_ref, strict=True)]
        rows.append({"nodes": int(nodes), "n_cand": int(n_cand), **_success_columns(grp),
                     "h_mean": float(grp["h_planner"].mean()),
                     "h_gap_to_reference": float(np.mean(grp["h_planner"].to_numpy()
                                                         - h_ref.to_numpy())),
                     "reference_argmin_found_pct": 100 * float(np.mean(same))})
    for nodes, grp in bud[bud["planner"] == "reference"].groupby("nodes"):
        rows.append({"nodes": int(nodes), "n_cand": -1, **_success_columns(grp),
                     "h_mean": float(grp["h_planner"].mean()), "h_gap_to_reference": 0.0,
                     "reference_argmin_found_pct": 100.0,
                     "exhaustive": bool(grp["exhaustive"].all()),
                     "n_scored": int(grp["n_scored"].median())})
    return pd.DataFrame(rows).sort_values(["nodes", "n_cand"]).reset_index(drop=True)


def _success_columns(grp: pd.DataFrame) -> dict:
    """Trials, success under the configured check (Wilson 95 %) and the |R_z| reading [%]."""
    ci = stats.wilson_interval(int(grp["success"].sum()), len(grp))
    vertical = stats.wilson_interval(int(grp["success_vertical"].sum()), len(grp))
    return {"trials": len(grp), "success_pct": 100 * ci.estimate,
            "success_low_pct": 100 * ci.low, "success_high_pct": 100 * ci.high,
            "success_vertical_pct": 100 * vertical.estimate,
            "success_vertical_low_pct": 100 * vertical.low,
            "success_vertical_high_pct": 100 * vertical.high}


def _budget(report: Report, bud: pd.DataFrame, paper: dict) -> None:
    table = budget_table(bud)
    shapes = ", ".join(dict.fromkeys(bud["shape"]))
    report.text(
        f"**Success against the candidate budget (Sec. 11, future work in the paper).** Shapes "
        f"{shapes}; heuristic planner with N_cand ∈ "
        f"{sorted(int(v) for v in set(bud['n_cand']) if v > 0)}; every budget of one seed draws "
        f"from the same stream (nested candidates). `n_cand = -1` rows are the `reference` "
        f"search (exhaustive where `exhaustive` is true: all C(n, 3) triples). The paper bounds "
        f"its effective budget at {paper.get('effective_budget_triples', [15, 30])} triples but "
        f"never measured this curve.")
    report.table("success_vs_n_cand", table,
                 "Success (configured check, Wilson 95 %) and the |R_z| reading against N_cand; "
                 "mean H(G) of the chosen triple, its gap to the reference search's H on the same "
                 "body, and how often the sampled search found the reference argmin")
    heur = table[table["n_cand"] > 0]
    ref = table[table["n_cand"] < 0]
    words = []
    for nodes, grp in heur.groupby("nodes"):
        r = ref[ref["nodes"] == nodes]
        words.append(
            f"{nodes} nodes: H gap to the reference falls from {grp['h_gap_to_reference'].iloc[0]:.2f} "
            f"(N_cand = {grp['n_cand'].iloc[0]}) to {grp['h_gap_to_reference'].iloc[-1]:.3f} "
            f"(N_cand = {grp['n_cand'].iloc[-1]}); success {grp['success_pct'].min():.0f}–"
            f"{grp['success_pct'].max():.0f} % across budgets"
            + (f", reference search {r['success_pct'].iloc[0]:.0f} %" if len(r) else ""))
    first = heur[heur["n_cand"] == heur["n_cand"].min()]["success_pct"].mean()
    last = heur[heur["n_cand"] == heur["n_cand"].max()]["success_pct"].mean()
    lead = ("A lower H does not buy a higher success rate under this evaluator"
            if last <= first else f"Success rises from {first:.0f} % to {last:.0f} % with the budget")
    report.text(lead + ": " + "; ".join(words) + ".")


# -- Sec. 11: the doubled iteration budget --------------------------------------------------------
def _baseline_records(store) -> pd.DataFrame | None:
    """The baseline grid's records next to this run (any run of it), if present."""
    if store is None:
        return None
    from graspcampaign.campaign.records import RunStore

    root = Path(store.path).parents[1] / "baseline_grid"
    if not root.is_dir():
        return None
    frames = []
    for run_dir in sorted(p for p in root.iterdir() if p.is_dir()):
        other = RunStore(run_dir)
        if other.exists():
            df = other.read().to_pandas()
            if len(df):
                frames.append(df.assign(baseline_run=run_dir.name))
    return pd.concat(frames, ignore_index=True) if frames else None


def _n_max(report: Report, nm: pd.DataFrame, paper: dict, store) -> None:
    n_max = int(nm["n_max"].iloc[0])
    rerun = int(nm["n_max_rerun"].iloc[0])
    rows = []
    for planner, grp in nm.groupby("planner", sort=False):
        failed = grp[~grp["success"].astype(bool)]
        rows.append({
            "planner": planner, "trials": len(grp), "failures_at_n_max": len(failed),
            "failures_loop_still_moving": int(failed["loop_capped"].sum()),
            "budget_capped": int(failed["budget_capped"].sum()),
            "budget_capped_pct_of_failures": (100 * float(failed["budget_capped"].mean())
                                              if len(failed) else math.nan),
            "success_at_n_max": rate_cell(int(grp["success"].sum()), len(grp)),
            "success_at_rerun": rate_cell(int(grp["success_rerun"].sum()), len(grp)),
            "new_failures_at_rerun": int((grp["success"].astype(bool)
                                          & ~grp["success_rerun"].astype(bool)).sum()),
            "residual_median_failures_n": float(failed["residual_norm_n"].median()),
            "residual_median_failures_rerun_n": float(failed["residual_norm_rerun_n"].median()),
        })
    table = pd.DataFrame(rows)
    capped = int(table["budget_capped"].sum())
    failures = int(table["failures_at_n_max"].sum())
    failed = nm[~nm["success"].astype(bool)]
    rz = float(failed["residual_z_rerun_n"].abs().median()) if len(failed) else math.nan
    rn = float(failed["residual_norm_rerun_n"].median()) if len(failed) else math.nan
    report.text(
        f"**Doubled iteration budget (Sec. 11).** The baseline grid's trials (Sec. 6.5, "
        f"{len(nm)} trials) were re-derived deterministically -- same study seed "
        f"({int(nm['baseline_seed'].iloc[0])}), scene and identification streams and evaluator "
        f"-- so each re-derived trial is the baseline grid's trial, and its grasp was evaluated "
        f"again with N_max = {rerun}. The paper did not run this and writes that budget-capped "
        f"non-settling 'contributes some of the grid failures'.")
    report.table("n_max_rerun", table,
                 f"Baseline-grid failures at N_max = {n_max} and their re-run at N_max = {rerun} "
                 "(budget-capped = failed at the paper's budget, passes at the doubled one)")
    report.text(
        f"**{capped} of {failures} failures ({100 * capped / max(failures, 1):.1f} %) were "
        f"budget-capped**; the loop was still moving at N_max = {n_max} in "
        f"{int(table['failures_loop_still_moving'].sum())} of them, but the extra iterations "
        f"{'did not' if capped == 0 else 'only rarely'} turn a failure into a pass. After "
        f"{rerun} iterations the failures' median ‖R‖ is {rn:.3g} N with a median |R_z| of "
        f"{rz:.2g} N: what remains is the horizontal part of the normal-only residual, which "
        f"Algorithm 2 does not act on, so more iterations cannot remove it.")
    base = _baseline_records(store)
    if base is None:
        report.text("No `baseline_grid` records beside this run: the cross-check of the "
                    "re-derived trials against them was skipped.")
        return
    keys = ["shape", "mass_kg", "mu", "planner", "seed"]
    merged = nm.merge(base[base["status"] == "ok"], on=keys, suffixes=("", "_baseline"))
    if not len(merged):
        report.text("The `baseline_grid` records beside this run share no trial with it.")
        return
    same = (merged["success"].astype(bool) == merged["success_baseline"].astype(bool))
    close = np.isclose(merged["residual_norm_n"], merged["residual_norm_n_baseline"], rtol=1e-9)
    report.text(
        f"Cross-check against the `baseline_grid` records "
        f"({', '.join(sorted(set(merged['baseline_run'])))}): "
        f"{int(same.sum())} of {len(merged)} matched trials have the same verdict and "
        f"{int(close.sum())} the same residual (relative 1e-9).")


# -- the figure ------------------------------------------------------------------------------------
def _figure(report: Report, ok: pd.DataFrame, paper: dict) -> None:
    res = ok[ok["panel"] == "resolution"]
    bud = ok[ok["panel"] == "budget"]
    tiles = (2 if len(res) else 0) + (2 if len(bud) else 0)
    with mpl.rc_context(RC):
        fig = Figure(figsize=(10.0, 3.9 * tiles / 2), layout="constrained")
        axes = list(np.atleast_1d(fig.subplots(tiles // 2, 2)).ravel())
        if len(res):
            _runtime_axes(axes.pop(0), res, paper)
            _residual_axes(axes.pop(0), res, paper)
        if len(bud):
            table = budget_table(bud)
            _budget_axes(axes.pop(0), table)
            _gap_axes(axes.pop(0), table, paper)
        report.figure("fig20_mesh_resolution", fig,
                      "Fig. 20 (ours) and the N_cand curve: (a) runtime per evaluation against "
                      "node count with O(n), O(√n) guides and the paper's points; (b) final force "
                      "residual with the 0.5 N criterion and the paper's scatter band; (c) success "
                      "against N_cand with the reference search; (d) H(G) gap to the reference "
                      "search against N_cand")


def _runtime_axes(ax, res: pd.DataFrame, paper: dict) -> None:
    per = res.groupby("nodes")
    med = 1e3 * per["eval_time_s"].median()
    ax.scatter(res["nodes"], 1e3 * res["eval_time_s"], s=10, alpha=0.35, color=OURS,
               label="ours, single trials")
    ax.plot(med.index, med.to_numpy(), marker="o", color=OURS, label="ours, median")
    ref_nodes = int(res["reference_nodes"].iloc[0])
    ref_ms = 1e3 * float(res["eval_time_reference_s"].median())
    ax.plot(med.index, ref_ms * per["cost_ratio_vs_reference"].median().to_numpy(), marker="s",
            color="#e08a1e", label=f"ours, load-corrected (ratio to {ref_nodes} nodes)")
    ax.plot(med.index, 1e3 * per["search_time_s"].median().to_numpy(), color=OURS,
            linestyle="--", linewidth=1.0, label="ours: candidate search")
    ax.plot(med.index, 1e3 * per["equilibrium_time_s"].median().to_numpy(), color=OURS,
            linestyle=":", linewidth=1.0, label="ours: Algorithm 2")
    n0, t0 = float(med.index[0]), float(med.iloc[0])
    grid = np.geomspace(med.index.min(), med.index.max(), 50)
    ax.plot(grid, t0 * grid / n0, color="#888888", linestyle="-.", label="O(n) guide")
    ax.plot(grid, t0 * np.sqrt(grid / n0), color="#888888", linestyle=(0, (1, 1)),
            label="O(√n) guide")
    paper_ms = {int(k): float(v) for k, v in (paper.get("runtime_ms") or {}).items()}
    if paper_ms:
        xs, ys = zip(*sorted(paper_ms.items()), strict=True)
        ax.plot(xs, ys, linestyle="none", marker="D", color=PAPER, label="paper (MATLAB)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("mesh nodes n [–]")
    ax.set_ylabel("runtime per evaluation [ms]")
    ax.set_title("(a) runtime per evaluation", loc="left")
    ax.legend(loc="upper left", ncol=2, fontsize=6.5)


def _residual_axes(ax, res: pd.DataFrame, paper: dict) -> None:
    med = res.groupby("nodes")["residual_norm_n"].median()
    ax.scatter(res["nodes"], res["residual_norm_n"], s=10, alpha=0.35, color=OURS,
               label="ours, single trials")
    ax.plot(med.index, med.to_numpy(), marker="o", color=OURS, label="ours, median")
    ax.axhline(RESIDUAL_LIMIT_N, color="#333333", linestyle="--",
               label=f"criterion τ_F = {RESIDUAL_LIMIT_N} N")
    band = paper.get("residual_scatter_n")
    if band:
        ax.axhspan(band[0], band[1], color=PAPER, alpha=0.12,
                   label=f"paper's scatter {band[0]}–{band[1]} N")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("mesh nodes n [–]")
    ax.set_ylabel("final force residual ‖R‖ [N]")
    ax.set_title("(b) final force-balance residual", loc="left")
    ax.legend(loc="best", fontsize=6.5)


def _budget_axes(ax, table: pd.DataFrame) -> None:
    for i, (nodes, grp) in enumerate(table.groupby("nodes")):
        heur = grp[grp["n_cand"] > 0]
        ref = grp[grp["n_cand"] < 0]
        c = NODE_COLOURS[i % len(NODE_COLOURS)]
        err = np.vstack([heur["success_pct"] - heur["success_low_pct"],
                         heur["success_high_pct"] - heur["success_pct"]])
        ax.errorbar(heur["n_cand"], heur["success_pct"], yerr=err, marker="o", color=c,
                    capsize=2, label=f"{nodes} nodes, ‖R‖ check (Wilson 95 %)")
        ax.plot(heur["n_cand"], heur["success_vertical_pct"], marker="s", color=c,
                linestyle="--", linewidth=1.0, label=f"{nodes} nodes, |R_z| reading")
        if len(ref):
            x_ref = heur["n_cand"].max() * 4
            kind = "exhaustive" if bool(ref["exhaustive"].iloc[0]) else "sampled 2e5"
            ax.plot([x_ref], ref["success_pct"], marker="*", markersize=11, color=c,
                    linestyle="none", label=f"{nodes} nodes, reference ({kind})")
            ax.plot([x_ref], ref["success_vertical_pct"], marker="*", markersize=9, color=c,
                    markerfacecolor="white", linestyle="none")
    ax.set_xscale("log")
    ax.set_ylim(-2, 100)
    ax.set_xlabel("candidate budget N_cand [triples] (★ reference search)")
    ax.set_ylabel("success rate [%]")
    ax.set_title("(c) success against the candidate budget", loc="left")
    ax.legend(loc="upper right", fontsize=6.2)


def _gap_axes(ax, table: pd.DataFrame, paper: dict) -> None:
    for i, (nodes, grp) in enumerate(table.groupby("nodes")):
        heur = grp[grp["n_cand"] > 0]
        ax.plot(heur["n_cand"], np.maximum(heur["h_gap_to_reference"], 1e-4), marker="o",
                color=NODE_COLOURS[i % len(NODE_COLOURS)], label=f"{nodes} nodes")
    band = paper.get("effective_budget_triples")
    if band:
        ax.axvspan(band[0], band[1], color=PAPER, alpha=0.12,
                   label=f"paper's effective budget {band[0]}–{band[1]}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("candidate budget N_cand [triples]")
    ax.set_ylabel("mean H(G) − H of the reference search [–]")
    ax.set_title("(d) distance of the sampled argmin from the reference", loc="left")
    ax.legend(loc="upper right", fontsize=6.5)
