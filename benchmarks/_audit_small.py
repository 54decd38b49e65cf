"""The table audit of five smaller studies (``audit_tables.py``): smoke (Sec. 3.1), heuristic_weights
(Sec. 5.2), wrench_balance (Sec. 6.4, Fig. 17), mesh_resolution (Sec. 6.7, Fig. 20) and surrogate
(Appendix A, ``_audit_surrogate.py``), each table recomputed from the run's records, trace tables and
stored fits with pandas, scipy and statsmodels, beside the paper's text; and the numbers of each
report's opening paragraph. Nothing here imports graspcampaign."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
from _audit_common import ROOT, SUMMARY, aux, compare, judge, paper, records, table, wilson
from scipy import stats

RESAMPLES = 10_000  # the reports' captions: "10000 resamples"
SHAPES = ["sphere", "ellipsoid", "rounded_cube", "pear", "handle"]  # the study files' (vocabulary) order


def config(study: str) -> dict:
    return json.loads((ROOT / study / "default" / "manifest.json").read_text())["config"]


def executed(study: str) -> pd.DataFrame:
    """The executed trials in design order (a bootstrap depends on the order of its values)."""
    rec = records(study)
    return rec[rec["status"] == "ok"].sort_values("trial_index").reset_index(drop=True)


def flags(frame: pd.DataFrame, column: str) -> pd.Series:
    return frame[column].astype("boolean").fillna(False).astype(bool)


def rate(frame: pd.DataFrame, column: str, prefix: str) -> dict:
    """Wilson 95 % rate columns over the rows with ``column`` recorded."""
    g = frame[frame[column].notna()]
    k, n = int(g[column].astype(bool).sum()), len(g)
    low, high = wilson(k, n)
    return {f"{prefix}_pct": 100 * k / n if n else math.nan, f"{prefix}_low_pct": 100 * low,
            f"{prefix}_high_pct": 100 * high, f"n_{prefix}": n}


def median_ci(values, seed: int) -> tuple[float, float, float]:
    """The median and its percentile-bootstrap 95 % interval (from 3 values on; the captions' rule)."""
    v = np.asarray(values, float)
    if v.size < 3:
        return float(np.median(v)), math.nan, math.nan
    ci = stats.bootstrap((v,), np.median, n_resamples=RESAMPLES, method="percentile",
                         rng=np.random.default_rng(seed), vectorized=True).confidence_interval
    return float(np.median(v)), float(ci.low), float(ci.high)


def status(study: str) -> None:
    compare(study, "status", records(study).groupby("status").size().rename("n").reset_index(), ["status"])


def opening(study: str, expected: list[str]) -> None:
    """Each expected phrase (our numbers, in the report's words) in the report's opening paragraph."""
    text = (ROOT / study / "default" / "report" / "report.md").read_text()
    para = text.split("## What this shows", 1)[1].strip().split("\n\n")[0]
    bad = [e for e in expected if e not in para]
    SUMMARY.append((study, "opening paragraph", len(expected), len(bad)))
    print(f"{study} / opening paragraph: {len(expected)} numbers checked, {len(bad)} mismatches")
    for b in bad:
        print(f"    not said: {b!r}\n    paragraph: {para[:600]}")


def order(study: str, name: str, keys: list[str], expected: pd.DataFrame) -> None:
    """The report's rows in the expected order."""
    got = table(study, name)[keys].astype(str).agg("/".join, axis=1).tolist()
    want = expected[keys].astype(str).agg("/".join, axis=1).tolist()
    SUMMARY.append((study, f"{name} row order", 1, int(got != want)))
    print(f"{study} / {name} row order: {'as expected' if got == want else f'{got} != {want}'}")


def gate(study: str, ok: pd.DataFrame, by: str) -> None:
    rows = []
    for key, g in ok.groupby(by, sort=False):
        won = g[flags(g, "success_unbounded")]
        removed = ~won["success"].astype(bool)
        low, high = wilson(int(removed.sum()), len(won))
        read = g[g["valid_geometry"].notna()]
        rows.append({by: key, "n": len(g), "success_unbounded": len(won), "removed": int(removed.sum()),
                     "removed_pct": 100 * removed.mean() if len(won) else math.nan,
                     "removed_low_pct": 100 * low, "removed_high_pct": 100 * high,
                     "success": int(flags(g, "success").sum()), "n_valid_geometry": len(read),
                     "invalid_geometry": int((~read["valid_geometry"].astype(bool)).sum())})
    compare(study, "gate_removed", pd.DataFrame(rows), [by])


# ---------------------------------------------------------------- smoke (Sec. 3.1)
def audit_smoke() -> None:
    study, ok, ref, feat = "smoke", executed("smoke"), paper("smoke"), config("smoke")["features"]
    ok["node_count_error_pct"] = 100 * (ok["n_nodes"] - ok["nodes"]) / ok["nodes"]  # recomputed, not read
    shown = ["n_nodes", "n_faces", "node_count_error_pct", "watertight", "n_sharp_vertex", "n_sharp_edge",
             "max_vertex_defect_rad", "max_edge_deviation_deg", "build_time_s"]
    compare(study, "meshes", ok[["shape", "nodes", *shown]], ["shape", "nodes"])
    rank = ok["shape"].map({s: i for i, s in enumerate(SHAPES)})
    order(study, "meshes", ["shape", "nodes"], ok.assign(r=rank).sort_values(["r", "nodes"]))
    # consistency the counts must have: a closed triangle mesh has 3F = 2E, so V − F/2 = χ = 2 for
    # the five shapes (each a closed surface without a hole through it: the handle is a concave solid of
    # revolution, Sec. 6.2); a count is 0 exactly when the largest value is at most the threshold
    # (resolution-aware thresholds change that on coarse meshes: skipped then)
    chi = ok["n_nodes"] - ok["n_faces"] / 2
    bad = int((ok["watertight"].astype(bool) & (chi != 2)).sum())
    if not feat.get("resolution_aware"):
        bad += int(((ok["n_sharp_vertex"] > 0) != (ok["max_vertex_defect_rad"] > feat["vertex_defect_rad"]))
                   .sum())
        bad += int(((ok["n_sharp_edge"] > 0) != (ok["max_edge_deviation_deg"] > feat["edge_dihedral_deg"]))
                   .sum())
    SUMMARY.append((study, "meshes: Euler characteristic and thresholds", 3 * len(ok), bad))
    print(f"{study} / meshes: Euler characteristic and thresholds: {3 * len(ok)} checked, {bad} mismatches")
    # Sec. 3.1: the thresholds "cleanly separate the smooth test meshes" (every shape but the rounded
    # cube and the handle, whose features it names): 0 sharp vertices + edges on each, per resolution;
    # the 390-node sphere's defects "≈ 0.03 rad"; its dihedral deviations "below about 15°" at 144 nodes
    label = {"sphere": "sphere", "ellipsoid": "ellipsoid", "pear": "pear"}
    smooth = ok[ok["shape"].isin(label)].assign(sharp=lambda m: m["n_sharp_vertex"] + m["n_sharp_edge"])
    rows = [{"quantity": f"sharp vertices and edges, {label[m.shape]}, {m.nodes} nodes",
             "paper": ref["smooth_sharp_features"][m.shape], "value": float(m.sharp),
             "differs": judge(int(m.sharp), ref["smooth_sharp_features"][m.shape], 0)}
            for m in smooth.itertuples()]
    sphere = ok[ok["shape"] == "sphere"].set_index("nodes")
    for what, nodes, column, ref_value, digits in (
            ("largest angular defect", ref["sphere_defect_nodes"], "max_vertex_defect_rad",
             ref["sphere_defect_rad"], 2),
            ("largest dihedral departure", ref["sphere_dihedral_nodes"], "max_edge_deviation_deg",
             (None, ref["sphere_dihedral_below_deg"]), 1)):
        v = float(sphere.loc[nodes, column]) if nodes in sphere.index else math.nan
        rows.append({"quantity": f"{what}, sphere, {nodes} nodes", "value": v,
                     "differs": judge(v, ref_value, digits)})
    compare(study, "paper_comparison", pd.DataFrame(rows), ["quantity"], ["value", "differs"])
    status(study)
    sharp = smooth[smooth["sharp"] > 0]
    closed = f"{int(flags(ok, 'watertight').sum())} of {len(ok)} meshes are closed"
    opening(study, [closed, f"across {ok['shape'].nunique()} shapes and {ok['nodes'].nunique()} resolution",
                    *[f"the {label[m.shape]} at {m.nodes} nodes has {int(m.n_sharp_vertex)} sharp vert"
                      for m in sharp.itertuples()]] if len(sharp) else [closed, "no sharp vertex or edge"])


# ---------------------------------------------------------------- heuristic_weights (Sec. 5.2)
def audit_weights() -> None:
    study, ok, ref = "heuristic_weights", executed("heuristic_weights"), paper("heuristic_weights")
    seed = int(config(study)["seed"])
    rows = []
    for s, g in ok.groupby("weight_scale"):
        p = ref["h_at_scale"].get(str(float(s)))
        h = g["h_reachable"]
        rows.append({"weight_scale": s, "paper_h_reachable": p, "h_reachable": h.median(),
                     "h_reachable_per_scale": h.median() / s, "h_reachable_spread": np.ptp(h.to_numpy()),
                     "h_total_median": g["h_total"].median(),
                     "h_total_per_scale_median": (g["h_total"] / s).median(), "n": len(g),
                     "difference": h.median() - p if p is not None else None,
                     "differs": judge(h.median(), p, 3)})
    scale = pd.DataFrame(rows)
    compare(study, "h_by_scale", scale, ["weight_scale"])
    off = (ok["weight_scale"] - 1.0).abs()
    unit = ok[off == off.min()]
    invariant = bool((ok.groupby("scene_id")["argmin_key"].nunique() == 1).all())
    per = ok["h_total"] / ok["weight_scale"]
    spread = per.groupby(ok["scene_id"]).agg(lambda v: (v.max() - v.min()) / max(abs(v.max()), 1e-300))
    proportional, seeds = bool((spread <= 1e-9).all()), ok["scene_id"].nunique()
    rows = []
    for i in (1, 2, 3):
        v, lo, hi = median_ci(unit[f"s{i}_reachable"], seed)
        rows.append({"quantity": f"S{i} of the reachable set at unit weights", "paper": ref[f"s{i}"],
                     "value": v, "low": lo, "high": hi, "n": len(unit),
                     "differs": judge(v, ref[f"s{i}"], 2, lo, hi)})
    pen = int((ok["n_c"] + ok["n_e"]).max())
    rows += [{"quantity": "penalised contacts n_c + n_e on the sphere (largest over trials)",
              "paper": ref["sphere_penalised_contacts"], "value": pen, "n": len(ok),
              "differs": judge(pen, ref["sphere_penalised_contacts"], 0)},
             {"quantity": "argmin the same at every scale, in every seed", "paper": ref["argmin_invariant"],
              "value": invariant, "n": seeds, "differs": invariant != ref["argmin_invariant"]},
             {"quantity": "H/scale the same at every scale, in every seed",
              "paper": ref["h_scales_with_weights"], "value": proportional, "n": seeds,
              "differs": proportional != ref["h_scales_with_weights"]}]
    compare(study, "components", pd.DataFrame(rows), ["quantity"])
    first = ok.assign(off=off).sort_values("off", kind="stable").drop_duplicates("scene_id")
    rows = []
    for c in [c for c in ok if c.startswith("argmin_key_ratio_")]:
        moves = first[c] != first["argmin_key"]
        low, high = wilson(int(moves.sum()), len(first))
        rows.append({"weights_w1_w2_w3": c.removeprefix("argmin_key_ratio_").replace("_", ":"),
                     "n": len(first), "argmin_moves": int(moves.sum()),
                     "argmin_moves_pct": 100 * moves.mean(), "argmin_moves_low_pct": 100 * low,
                     "argmin_moves_high_pct": 100 * high})
    compare(study, "ratio_sweep", pd.DataFrame(rows), ["weights_w1_w2_w3"])
    status(study)
    u = scale.iloc[(scale["weight_scale"] - 1).abs().argmin()]
    differ = int((scale["differs"] == True).sum())  # noqa: E712
    where = f"differs from the paper's at {differ}" if differ else \
        f"matches the paper's at {int((scale['differs'] == False).sum())}"  # noqa: E712
    opening(study, [f"{'leaves' if invariant else 'does not always leave'} the chosen triple unchanged "
                    f"({seeds} seeds)", f"{'scales' if proportional else 'does not always scale'} H",
                    f"{where} of {len(scale)} scales",
                    f"({u['h_reachable']:.3f} at unit weights, paper {u['paper_h_reachable']:.3f}"])


# ---------------------------------------------------------------- wrench_balance (Sec. 6.4, Fig. 17)
def settles_from(residual: np.ndarray, iterations: np.ndarray, tau: float) -> float:
    """The first iteration of the trace's last run below tau that lasts to its end (nan: none)."""
    below = residual < tau
    if not below[-1]:
        return math.nan
    start = len(below) - np.argmin(below[::-1]) if not below.all() else 0  # after the last one above
    return float(iterations[start])


def audit_wrench() -> None:
    study, ok, ref, cfg = "wrench_balance", executed("wrench_balance"), paper("wrench_balance"), \
        config("wrench_balance")
    tau, r_mm = float(cfg["evaluator"]["tau_f_n"]), 1e3 * float(cfg["model"]["fingertip_radius_m"])
    tau_t = float(cfg["evaluator"]["tau_t_nm"])
    assert ref["torque_residual_nm"] == 0, "the paper block's torque is §3.7's 'essentially zero'"
    trace = aux(study, "tables", "iterations").merge(ok[["trial_id", "mu"]], on="trial_id")
    rows = []
    for mu, tr in trace.sort_values(["mu", "iteration"]).groupby("mu"):
        rec = ok[ok["mu"] == mu]
        settle = settles_from(tr["residual_norm_n"].to_numpy(float), tr["iteration"].to_numpy(), tau)
        window = tuple(ref["residual_settles_within_iterations"])
        margin = (ref["slip_margin_saturates_above"], 1.0) if mu >= ref["slip_margin_saturates_from_mu"] \
            else None
        last, torque = tr.iloc[-1], tr["torque_norm_nm"].max()
        cells = [(f"iteration from which ‖R‖ stays < {tau:g} N", window, settle, 0,
                  judge(math.inf if math.isnan(settle) else settle, window, 0)),
                 ("final slip margin (μf_n − ‖f_t‖)/(μf_n) [–]", margin, last["slip_margin_ratio"], 2,
                  judge(last["slip_margin_ratio"], margin, 2)),
                 ("final finger-1 normal force [N]", ref["finger_force_command_n"],
                  last["normal_force_1_n"], 0, None),  # the command itself: not compared
                 # §3.7: τ_T "is not binding in any reported campaign: torque residuals are essentially
                 # zero ... (Fig. 17b)": the paper's 0 is a residual that never reaches the run's τ_T
                 ("largest torque residual ‖τ‖ [N·m] (paper: essentially zero)", (None, tau_t), torque, 3,
                  judge(torque, (None, tau_t), 3)),
                 ("final residual ‖R‖ of the record [N]", (0.0, tau), rec["residual_norm_n"].median(), 2,
                  judge(rec["residual_norm_n"].median(), (0.0, tau), 2))]
        for q, p, v, d, differs in cells:
            text = p if not isinstance(p, tuple) else f"≤ {p[1]:g}" if p[0] is None else \
                f"{p[0]}–{p[1]}" if d == 0 else f"{p[0]:.{d}f}–{p[1]:.{d}f}"
            rows.append({"mu": mu, "quantity": q, "paper": text, "ours": v, "digits": d, "n": len(rec),
                         "differs": differs,
                         "difference": v - p if differs is not None and not isinstance(p, tuple) else None})
    per = pd.DataFrame(rows)
    compare(study, "wrench_balance", per, ["mu", "quantity"])
    rows = []
    for mu, g in ok.groupby("mu"):
        d = g["delta_max_mm"].to_numpy(float)
        over, beyond = d > 1.0, d > r_mm
        low, high = wilson(int(over.sum()), len(g))
        shown = d[~beyond]
        rows.append({"mu": mu, "n": len(g), "exceeds": int(over.sum()), "exceeds_pct": 100 * over.mean(),
                     "wilson_low_pct": 100 * low, "wilson_high_pct": 100 * high,
                     "successes_exceeding": int((over & flags(g, "success").to_numpy()).sum()),
                     "beyond_radius": int(beyond.sum()),
                     "delta_max_median_mm": np.median(shown) if shown.size else math.nan,
                     "delta_max_p95_mm": np.percentile(shown, 95) if shown.size else math.nan,
                     "delta_max_max_mm": shown.max() if shown.size else math.nan, "paper": "within 1 mm"})
    compare(study, "design_limit", pd.DataFrame(rows), ["mu"])
    gate(study, ok, "mu")
    status(study)
    settle = per[per["quantity"].str.startswith("iteration")]
    judged = per["differs"].notna()
    deep = trace.loc[trace["depth_1_mm"] > r_mm, "iteration"] if "depth_1_mm" in trace else None
    differ = int(per.loc[judged, "differs"].astype(bool).sum())
    said = [f"settles below τ_F = {tau:g} N at {int(settle['ours'].notna().sum())} of {len(settle)} friction",
            f"(paper: all by iteration {ref['residual_settles_within_iterations'][1]})",
            f"{differ} of {int(judged.sum())} compared quantities differ"]
    if deep is not None and len(deep):
        deepest = ok["delta_max_mm"].max() / 1e3
        said += [f"{float(f'{deepest:.3g}'):g} m deep", f"from iteration {deep.min():.0f} on"]
    opening(study, said)


# ---------------------------------------------------------------- mesh_resolution (Sec. 6.7, Fig. 20)
def audit_mesh() -> None:
    study, ok, ref = "mesh_resolution", executed("mesh_resolution"), paper("mesh_resolution")
    seed = int(config(study)["seed"])
    res, bud, nm = (ok[ok["panel"] == p] for p in ("resolution", "budget", "n_max"))
    fastest = "eval_time_reference_min_s" in res and res["eval_time_reference_min_s"].notna().all()
    # fastest repeats: the min over min (docs/records.md); median repeats: eval / eval_reference
    ratio = {"fastest": res["eval_time_min_s"] / res["eval_time_reference_min_s"] if fastest else None,
             "median": res["eval_time_s"] / res["eval_time_reference_s"]}
    main = "fastest" if fastest else "median"
    rows = []
    for nodes, g in res.groupby("nodes"):
        v, lo, hi = median_ci(ratio[main][g.index], seed)  # each mesh's ratio, the reference's to itself too
        rows.append({"nodes": nodes, "faces": g["n_faces"].iloc[0], "trials": len(g),
                     **{f"eval_{k}_ms": 1e3 * np.percentile(g["eval_time_s"], q)
                        for k, q in (("median", 50), ("p25", 25), ("p75", 75))},
                     "cost_ratio_vs_reference": v, "cost_ratio_low": lo, "cost_ratio_high": hi,
                     "search_median_ms": 1e3 * g["search_time_s"].median(),
                     "equilibrium_median_ms": 1e3 * g["equilibrium_time_s"].median(),
                     "paper_runtime_ms": ref["runtime_ms"].get(str(nodes)),
                     "residual_median_n": g["residual_norm_n"].median(),
                     "loop_at_n_max_pct": 100 * flags(g, "loop_capped").mean(),
                     **rate(g, "success", "success")})
    compare(study, "mesh_resolution_runtime", pd.DataFrame(rows), ["nodes"])
    top, refn = int(res["nodes"].max()), int(res["reference_nodes"].iloc[0])
    paper_meshes = (top, refn) == (1750, 144)
    est = {r: median_ci(ratio[r][res["nodes"] == top], seed)
           for r in ([main, "median"] if fastest else [main])}
    rows = []
    for target in (False, True):
        for i, r in enumerate(est):
            v, lo, hi = est[r]
            # the ≤ 1.5 target is issue 7's speed target for this tool, not a paper value (Sec. 6.7 and
            # 11 state none): shown, never counted as a difference from the paper
            rows.append({"quantity": f"cost ratio, {top} / {refn} nodes, {r} repeats" + (
                             f", against this tool's speed target (≤ {ref['runtime_ratio_target']:g}; not a "
                             "paper value)" if target else ""),
                         "value": v, "low": lo, "high": hi, "n": int((res["nodes"] == top).sum()),
                         "differs": judge(v, ref["runtime_ratio_1750_144"], 2, lo, hi)
                         if paper_meshes and i == 0 and not target else None})
    compare(study, "cost_ratio", pd.DataFrame(rows), ["quantity"])
    # the budget panel: each body's reference row (exhaustive or sampled) against the sampled search
    reference = bud[bud["planner"] == "reference"].set_index(["shape", "nodes"])
    v = ["vertex_1", "vertex_2", "vertex_3"]
    rows = []
    for (nodes, n_cand), g in bud.groupby(["nodes", "n_cand"]):
        other = reference.loc[list(zip(g["shape"], g["nodes"], strict=True))]
        found = [set(a) == set(b) for a, b in zip(g[v].to_numpy(), other[v].to_numpy(), strict=True)]
        is_ref = (g["planner"] == "reference").all()
        rows.append({"nodes": nodes, "n_cand": n_cand, "trials": len(g),
                     "n_cand_label": "every triple (exhaustive)" if is_ref else str(n_cand),
                     "planner": "reference" if is_ref else "heuristic",
                     **rate(g, "success", "success"), **rate(g, "success_vertical", "vertical"),
                     "h_mean": g["h_planner"].mean(),
                     "h_gap_to_reference": (g["h_planner"].to_numpy() - other["h_planner"].to_numpy()).mean(),
                     "reference_argmin_found_pct": 100 * np.mean(found)})
    compare(study, "success_vs_n_cand", pd.DataFrame(rows), ["nodes", "n_cand"])
    rows = []
    for planner, g in nm.groupby("planner", sort=False):
        failed = g[~g["success"].astype(bool)]
        flat = (failed["failure_check_rerun"] == "residual") & \
            (failed["residual_z_rerun_n"].abs() <= 0.01 * failed["residual_norm_rerun_n"])
        rows.append({"planner": planner, "trials": len(g), "failures_at_n_max": len(failed),
                     "failures_loop_still_moving": int(flags(failed, "loop_capped").sum()),
                     "budget_capped": int(flags(failed, "budget_capped").sum()),
                     "horizontal_residual_rerun": int(flat.sum()), **rate(g, "success", "success"),
                     **rate(g, "success_rerun", "rerun"),
                     "residual_median_failures_rerun_n": failed["residual_norm_rerun_n"].median()})
    nmax = pd.DataFrame(rows)
    compare(study, "n_max_rerun", nmax, ["planner"])
    gate(study, ok, "panel")
    status(study)
    said = [f"One evaluation on the largest mesh ({top} nodes) costs {est[main][0]:.2f} times one on the "
            f"{refn}-node reference mesh"]
    if not math.isnan(est[main][1]):
        said.append(f"95% interval {est[main][1]:.2f}–{est[main][2]:.2f}")
    if len(nm):
        said.append(f"Of {int(nmax['failures_at_n_max'].sum())} baseline-grid failures, "
                    f"{int(nmax['budget_capped'].sum())} pass at the doubled N_max and "
                    f"{int(nmax['horizontal_residual_rerun'].sum())} still fail there on a horizontal "
                    "residual")
        base = pd.concat([pd.read_parquet(f) for f in sorted((ROOT / "baseline_grid").glob(
            "*/records/*.parquet"))], ignore_index=True)
        key = ["shape", "mass_kg", "mu", "planner", "seed"]
        base = base[base["status"] == "ok"].drop_duplicates(key)
        m = nm.merge(base, on=key, suffixes=("", "_b"))
        same = int((m["success"].astype(bool) == m["success_b"].astype(bool)).sum())
        close = int(np.isclose(m["residual_norm_n"], m["residual_norm_n_b"], rtol=1e-9).sum())
        text = (ROOT / study / "default" / "report" / "report.md").read_text()
        want = f"{same} of {len(m)} re-derived trials have the baseline's verdict and {close} its residual"
        SUMMARY.append((study, "cross-check text", 1, int(want not in text)))
        print(f"{study} / cross-check text: {'as recomputed' if want in text else 'not said: ' + want}")
    opening(study, said)


def audit_surrogate() -> None:
    from _audit_surrogate import audit_surrogate as audit  # its own module: this one stays under 500 lines
    audit(config)


STUDIES = {"smoke": audit_smoke, "heuristic_weights": audit_weights, "wrench_balance": audit_wrench,
           "mesh_resolution": audit_mesh, "surrogate": audit_surrogate}
