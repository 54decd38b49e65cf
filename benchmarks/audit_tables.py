"""Recompute every cell of the report tables of sixteen studies from their Parquet records, as an outsider:
pandas, scipy and statsmodels from docs/records.md's column meanings and the paper's statistics
(Wilson intervals, McNemar, percentile bootstraps, medians, OLS, CVs), never graspcampaign's code;
the paper column against the study files' ``paper:`` blocks, and each verdict's words against its
``differs`` (the rule of report/format.py). Prints every cell that differs and a count per table.

    python benchmarks/audit_tables.py RESULTS_ROOT [study ...]

Studies: test1_bench, test2_grasp, test3_disturbance (``_audit_test1.py``, ``_audit_test2.py``,
``_audit_test3.py``), friction_mass (the dynamic grasp), dynamic_check, sensitivity, pso_repeatability,
gravity_settle; the quasi-static shapes, ablation, baseline_grid and grip_laws (``_audit_quasi_static.py``);
smoke, heuristic_weights, wrench_balance, mesh_resolution and surrogate (``_audit_small.py``; its surrogate
part in ``_audit_surrogate.py``, which refits the stored models with scikit-learn); the opening paragraphs
of all but test1_bench, test3_disturbance, friction_mass, dynamic_check, sensitivity and pso_repeatability.
A bootstrap interval depends on the order of its values: the records are taken in design order
(``trial_index``), as the report takes them.
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pandas as pd
from _audit_common import (
    PSO_PARAMS,
    RADIUS_MM,
    SUMMARY,
    aux,
    check_opening,
    compare,
    judge,
    paper,
    records,
    sig3_decimals,
    table,
    wilson,
)
from _audit_quasi_static import audit_quasi_static, config
from _audit_small import STUDIES as SMALL
from _audit_test1 import audit_test1
from _audit_test2 import audit_test2
from _audit_test3 import audit_test3
from scipy import stats

# ---------------------------------------------------------------- pso_repeatability (Sec. 6.8, Fig. 21)
PSO_TABLE3 = {"lambda1": "lambda1", "lambda2": "lambda2", "n_exp": "n", "b": "b", "k": "k", "c": "c"}


def audit_pso() -> None:
    study, rec, ref = "pso_repeatability", records("pso_repeatability"), paper("pso_repeatability")
    ok = rec[rec["status"] == "ok"].sort_values("trial_index")  # design order: a bootstrap depends on it
    two = ok["budget"].nunique() > 1
    rep = ok[ok["budget"] == "repeatability"] if two else ok
    conv = ok[ok["budget"] != "repeatability"] if two else ok
    named = ok["flat_parameters"].dropna()
    flat = set(str(named.iloc[0]).split(",")) if len(named) else set()
    rows = []
    for p in PSO_PARAMS:
        v = rep[p].dropna().to_numpy(float)
        cv = v.std(ddof=1) / v.mean()
        low = high = math.nan
        if v.size >= 3 and np.ptp(v) > 0:
            ci = stats.bootstrap((v,), lambda x, axis=-1: np.std(x, axis=axis, ddof=1) / np.mean(x,
                                                                                                 axis=axis),
                                 n_resamples=10_000, method="percentile", rng=np.random.default_rng(608),
                                 vectorized=True).confidence_interval
            low, high = ci.low, ci.high
        name = PSO_TABLE3[p]
        cvs = ref["cv_pct"]
        pcv = cvs["n"] if p == "n_exp" else cvs["lambda_approx"] if p.startswith("lambda") \
            else None
        bound = int(rep.loc[rep[p].notna(), f"at_bound_{name}"].astype(bool).sum())
        differs = None if p in flat else judge(100 * cv, pcv, 1, 100 * low, 100 * high)
        rows.append({"parameter": p, "n": v.size, "cv_pct": 100 * cv, "mean": v.mean(), "sd": v.std(ddof=1),
                     "low_pct": 100 * low, "high_pct": 100 * high, "paper_cv_pct": pcv,
                     "paper_text": f"\u2248 {pcv:g}" if pcv is not None else  # the paper's "about 19%"
                     "{:.1f}\u2013{:.1f} (range)".format(*cvs["others_range"]),
                     "digits": sig3_decimals(ref["table3"][name]), "at_bound": bound,
                     "at_bound_pct": 100 * bound / v.size, "differs": differs,
                     "difference": None if differs is None else 100 * cv - pcv})
    compare(study, "cv", pd.DataFrame(rows), ["parameter"])
    best = conv[conv["best_cost"] == conv["best_cost"].min()]  # every run at the lowest J
    rows = []
    for p in PSO_PARAMS:
        v, pv, name = conv[p].dropna().to_numpy(float), ref["table3"][PSO_TABLE3[p]], PSO_TABLE3[p]
        bound = int(conv.loc[conv[p].notna(), f"at_bound_{name}"].astype(bool).sum())
        rows.append({"parameter": p, "paper": pv, "digits": sig3_decimals(pv), "ours_mean": v.mean(),
                     "ours_median": np.median(v),
                     "ours_best_run": best[p].iloc[0] if best[p].nunique() == 1 else None,
                     "best_run_why": None if best[p].nunique() == 1 else
                     f"{len(best)} runs tie at the best J = "
                     f"{best['best_cost'].iloc[0]:.4g}", "difference_mean": v.mean() - pv,
                     "n": v.size, "relative_difference_pct": 100 * (v.mean() - pv) / pv, "at_bound": bound,
                     "at_bound_pct": 100 * bound / v.size})
    compare(study, "table3", pd.DataFrame(rows), ["parameter"])
    trace = aux(study, "tables", "pso_trace")
    trace = trace[trace["trial_id"].isin(rep["trial_id"])]
    rows = []
    for it, g in trace.groupby("iteration"):
        c = g["best_cost"].to_numpy(float)
        rows.append({"iteration": it, "n_runs": len(g), "n_evaluations": g["n_evaluations"].mean(),
                     "mean": c.mean(), **{f"p{q}": np.percentile(c, q) for q in (10, 25, 75, 90)}})
    compare(study, "convergence", pd.DataFrame(rows), ["iteration"])
    compare(study, "status", rec.groupby("status").size().rename("n").reset_index(), ["status"])


# ---------------------------------------------------------------- sensitivity (Sec. 6.6, Fig. 19)
AXES = {"mu_mass": ("mu", "mass_kg"), "lambda": ("lambda1", "lambda2"), "n_b": ("n_exp", "b")}


def wilson_pct(flags: pd.Series) -> dict:
    k, n = int(flags.sum()), len(flags)
    low, high = wilson(k, n)
    return {"value": 100 * k / n if n else math.nan, "low": 100 * low, "high": 100 * high, "n": n}


def bools(frame: pd.DataFrame, column: str) -> pd.Series:
    return frame[column].fillna(False).astype(bool)


def audit_sensitivity() -> None:
    study, rec, ref = "sensitivity", records("sensitivity"), paper("sensitivity")
    ok = rec[rec["status"] == "ok"]
    rows, gate = [], []
    for panel, (x, y) in AXES.items():
        g = ok[ok["panel"] == panel]
        if not len(g):
            continue
        deep = g["delta_max_mm"] > RADIUS_MM
        s, v = wilson_pct(bools(g, "success")), wilson_pct(bools(g, "success_vertical"))
        rows.append({"panel": panel, "cells": len(g[[x, y]].drop_duplicates()), "trials": len(g),
                     "loop_at_n_max_pct": 100 * bools(g,
                                                      "loop_capped").mean(), "beyond_radius": int(deep.sum()),
                     "beyond_radius_pct": 100 * deep.mean(),
                     "delta_max_median_mm": g.loc[~deep, "delta_max_mm"].median(),
                     "runtime_median_ms": g["runtime_ms"].median(),
                     # Sec. 6.6's reading: friction carries no load, so slip never binds first
                     "eta_median": g["eta"].abs().median(),
                     "slip_first": int((g["failure_check"] == "slip").sum()),
                     "success_pct": s["value"], "success_low_pct": s["low"], "success_high_pct": s["high"],
                     "vertical_pct": v["value"], "vertical_low_pct": v["low"],
                     "vertical_high_pct": v["high"]})
        unb = g[bools(g, "success_unbounded")]
        removed = ~bools(unb, "success")
        r = wilson_pct(removed) if len(unb) else {"value": math.nan, "low": math.nan, "high": math.nan}
        gate.append({"panel": panel, "n": len(g), "success_unbounded": len(unb),
                     "removed": int(removed.sum()),
                     "removed_pct": r["value"], "removed_low_pct": r["low"], "removed_high_pct": r["high"],
                     "success": int(bools(g, "success").sum()),
                     "invalid_geometry": int((~bools(g, "valid_geometry")).sum())})
    compare(study, "sensitivity_panels", pd.DataFrame(rows), ["panel"])
    compare(study, "gate_removed", pd.DataFrame(gate), ["panel"])
    a, b = ok[ok["panel"] == "mu_mass"], ok[ok["panel"] == "lambda"]
    inside = (a["mu"] >= ref["stable_mu_min"] - 1e-9) & (a["mass_kg"] <= ref["stable_mass_max_kg"] + 1e-9)
    low_mu = a["mu"] < ref["stable_mu_min"] - 1e-9
    heavy = a["mass_kg"] > ref["stable_mass_max_kg"] + 1e-9
    below = b["lambda1"] <= ref["lambda1_stable_below"] + 1e-9
    strip = b["lambda1"] >= ref["nonconvergence_strip_lambda1_from"] - 1e-9
    rate = lambda part, col="success": wilson_pct(bools(part, col))  # noqa: E731
    claims = {
        "(a) stable region: success inside it": rate(a[inside]),
        "(a) stable region: success outside it": rate(a[~inside]),
        "(a) stable region: |R_z| reading inside it": rate(a[inside], "success_vertical"),
        "(a) μ < the friction limit, m ≤ the mass limit: success there": rate(a[low_mu & ~heavy]),
        "(a) sharp drop above the mass limit when μ < the friction limit": rate(a[low_mu & heavy]),
        "(b) stable for λ1 below the paper's boundary: success there": rate(b[below]),
        "(b) success above the boundary": rate(b[~below]),
        "(b) non-convergence strip: loop still moving at N_max inside it": rate(b[strip], "loop_capped"),
        "(b) loop still moving at N_max outside the strip": rate(b[~strip], "loop_capped"),
    }
    cells = a[["shape", "mass_kg", "mu"]].drop_duplicates()
    bodies = aux(study, "prepared", "").merge(cells, on=["shape", "mass_kg", "mu"])  # one PSO per cell
    low = bodies["mu"] < 0.1 - 1e-9
    for words, part in (("< 0.1", bodies[low]), ("≥ 0.1", bodies[~low])):
        claims[f"(a) median identified λ1 at μ {words}"] = {"value": part["lambda1"].median(),
                                                            "low": math.nan, "high": math.nan, "n": len(part)}
        claims[f"(a) identified λ1 on its PSO search bound at μ {words}"] = rate(part, "at_bound_lambda1")
    seed = int(config("sensitivity")["seed"])
    for factor, column in (("mass", "mass_kg"), ("friction", "mu")):  # Fig. 19a: success over each axis
        g = a.groupby(column)["success"].agg(["sum", "size"])
        counts = np.column_stack([g["sum"], g["size"] - g["sum"]])
        p = math.nan
        if 0 < g["sum"].sum() < g["size"].sum():  # Pearson's χ², Monte Carlo where an expected count < 5
            mc = stats.contingency.expected_freq(counts).min() < 5
            p = stats.chi2_contingency(counts, correction=False, method=stats.MonteCarloMethod(
                n_resamples=9999, rng=np.random.default_rng(seed)) if mc else None).pvalue
        claims[f"(a) equal success at every {factor} level: p"] = {  # no test, no n: one outcome throughout
            "value": p, "low": math.nan, "high": math.nan, "n": math.nan if math.isnan(p) else len(a)}
    c = ok[ok["panel"] == "n_b"]
    for axis, column in (("n", "n_exp"), ("b", "b")):
        med = c.groupby(column)["runtime_ms"].median()
        claims[f"(c) runtime max/min over {axis} levels"] = {"value": med.max() / med.min(), "low": math.nan,
                                                             "high": math.nan, "n": math.nan}
    # the paper's words: higher/lower where the two Wilson intervals lie apart, else not shown
    words = (("(a) stable region: success inside it", "(a) stable region: success outside it", True),
             ("(b) stable for λ1 below the paper's boundary: success there", "(b) success above the boundary",
              True),
             ("(b) non-convergence strip: loop still moving at N_max inside it",
              "(b) loop still moving at N_max outside the strip", True),
             ("(a) sharp drop above the mass limit when μ < the friction limit",
              "(a) μ < the friction limit, m ≤ the mass limit: success there", False),
             ("(a) identified λ1 on its PSO search bound at μ < 0.1", 50.0, True),
             ("(a) identified λ1 on its PSO search bound at μ ≥ 0.1",
              "(a) identified λ1 on its PSO search bound at μ < 0.1", False))
    frame = pd.DataFrame([{"quantity": q, **v} for q, v in claims.items()])
    frame["differs"] = None
    for row, other, higher in words:
        r = claims[row]
        o = {"value": other, "low": other, "high": other} if isinstance(other, float) else claims[other]
        if any(pd.isna(x["value"]) for x in (r, o)):
            continue
        above, under = r["low"] > o["high"], r["high"] < o["low"]
        frame.loc[frame["quantity"] == row, "differs"] = False if (above if higher else under) else \
            True if (above or under) else None
    compare(study, "sensitivity_claims", frame, ["quantity"])
    compare(study, "status", rec.groupby("status").size().rename("n").reset_index(), ["status"])


# ---------------------------------------------------------------- dynamic_check (Sec. 6.1's claim)
PAIRS = {"source": ("qs_success", "success"), "preset": ("qs_preset_success", "success"),
         "source_unbounded": ("qs_success_unbounded", "success_unbounded"),
         "preset_unbounded": ("qs_preset_success_unbounded", "success_unbounded")}


def agreement_row(g: pd.DataFrame, qs: str, dyn: str) -> dict:
    settled = g[g["dynamic_status"] != "not_settled"]
    both = settled[settled[qs].notna() & settled[dyn].notna()]
    a, b = both[qs].astype(bool).to_numpy(), both[dyn].astype(bool).to_numpy()
    t = np.array([[np.sum(a & b), np.sum(a & ~b)], [np.sum(~a & b), np.sum(~a & ~b)]])
    n = int(t.sum())
    row = {"n": n, "not_settled": len(g) - len(settled), "unlabelled": len(settled) - n,
           "both_success": t[0, 0], "qs_only": t[0, 1], "dynamic_only": t[1, 0], "both_failure": t[1, 1]}
    if not n:
        return row | dict.fromkeys(["qs_success_rate", "dynamic_success_rate", "agreement", "agreement_low",
                                    "agreement_high", "kappa", "kappa_std_error", "kappa_low", "kappa_high",
                                    "expected_agreement"], math.nan)
    po, pe = np.trace(t) / n, (t.sum(1) @ t.sum(0)) / n**2
    low, high = wilson(int(np.trace(t)), n)
    kappa = std = math.nan
    if pe < 1:
        kappa = (po - pe) / (1 - pe)
        constant = t.sum(1).min() == 0 or t.sum(0).min() == 0
        if not constant:
            from statsmodels.stats.inter_rater import cohens_kappa
            std = cohens_kappa(t, return_results=True).std_kappa
    z = stats.norm.ppf(0.975)
    row |= {"qs_success_rate": t[0].sum() / n, "dynamic_success_rate": t[:, 0].sum() / n,
            "agreement": po, "agreement_low": low, "agreement_high": high, "kappa": kappa,
            "kappa_std_error": std, "kappa_low": kappa - z * std, "kappa_high": kappa + z * std,
            "expected_agreement": pe}
    return row | {f"{c}_pct": 100 * row[c] for c in ("agreement", "agreement_low", "agreement_high",
                                                     "qs_success_rate", "dynamic_success_rate")}


def audit_dynamic_check() -> None:
    study, rec = "dynamic_check", records("dynamic_check")
    ok = rec[(rec["status"] == "ok")]
    for by in ("planner", "shape"):
        rows = [{"model_preset": p, by: v, "comparison": "source", **agreement_row(g, *PAIRS["source"])}
                for (p, v), g in ok.groupby(["model_preset", by])]
        compare(study, f"agreement_by_{by}", pd.DataFrame(rows), ["model_preset", by])
    rows = []
    for scope, part in (("sphere", ok[ok["shape"] == "sphere"]), ("all shapes", ok)):
        for pair, cols in PAIRS.items():
            for p, g in part.groupby("model_preset"):
                r = agreement_row(g, *cols)
                judged = scope == "sphere" and r["n"] > 0  # the claim is the sphere's: 100 % agreement
                pct = 100 * r["agreement"]
                differs = judge(pct, 100.0, 1, 100 * r["agreement_low"], 100 * r["agreement_high"]) \
                    if judged else None
                rows.append({"model_preset": p, "scope": scope, "comparison": pair, **r, "agreement_pct": pct,
                             "paper_pct": 100.0 if scope == "sphere" else None, "differs": differs,
                             "difference": pct - 100 if judged else None})
    compare(study, "kappa", pd.DataFrame(rows), ["model_preset", "scope", "comparison"])
    status = pd.crosstab([ok["model_preset"], ok["planner"]], ok["dynamic_status"]).reset_index()
    compare(study, "dynamic_status", status, ["model_preset", "planner"])
    compare(study, "status", rec.groupby("status").size().rename("n").reset_index(), ["status"])


# ---------------------------------------------------------------- friction_mass (dynamic grasp, Sec. 5.5)
PRESET_LABEL = {"table2": "Tables 2–3 constants", "firm": "firm preset (Shore 30A/50A, Hertz)"}


def audit_friction_mass() -> None:
    study, rec, ref = "friction_mass", records("friction_mass"), paper("friction_mass")
    ok = rec[rec["status"] == "ok"].copy()
    ok["success"] = ok["success"].fillna(False).astype(bool)
    rows = []
    for preset, g in ok.groupby("model_preset"):
        k, n = int(g["success"].sum()), len(g)
        low, high = wilson(k, n)
        pct = 100 * k / n
        rows.append({"model_preset": preset, "paper_pct": 100.0, "n": n, "successes": k, "rate_pct": pct,
                     "wilson_low_pct": 100 * low, "wilson_high_pct": 100 * high, "difference": pct - 100,
                     "differs": judge(pct, 100.0, 1, 100 * low, 100 * high)})
    compare(study, "stable_by_preset", pd.DataFrame(rows), ["model_preset"])
    # the record tables: every shown column is the record's own value (labels_agree derived)
    shown = {"friction_mass": ["dynamic_status", "final_phase", "success", "delta_max_mm",
                               "delta_required_mm", "fingertip_radius_mm", "final_residual_z_n",
                               "wrench_force_norm_n", "wrench_torque_norm_nm", "normal_force_1_n",
                               "normal_force_2_n", "normal_force_3_n", "paper"],
             "phases": ["closure_start_s", "touch_1_s", "touch_2_s", "touch_3_s", "closure_end_s",
                        "lift_end_s", "hold_start_s", "hold_end_s", "simulated_time_s"],
             "like_for_like": ["dynamic_status", "success", "qs_success", "labels_agree",
                               "qs_success_unbounded", "qs_failure_check", "qs_residual_norm_n",
                               "qs_delta_max_mm"],
             "friction_cone": ["lp_status", "lp_status_mu0", "lp_mu0_reason", "lp_mu0_force_only_status",
                               "lp_mu0_torque_residual_nm", "normal_off_radial_max_deg",
                               "lp_status_mu0_ideal"]}
    settled = ok["dynamic_status"] != "not_settled"
    ok["labels_agree"] = (ok["success"] == ok["qs_success"].astype(bool)).where(settled)
    ok["paper"] = "stable"
    for name, columns in shown.items():
        compare(study, name, ok[["trial_id", *columns]], ["trial_id"])
    # Sec. 5.5 values: penetrations over the runs past closure; the rest at the representative case
    steps = aux(study, "tables", "steps").sort_values("time_s")
    last_pen = 1e3 * steps.groupby("trial_id")["total_penetration_m"].last()
    below = 1e3 * ref["total_penetration_below_m"]
    mu, mass = ref["representative_mu"], ref["representative_mass_kg"]
    rows = []
    for preset in ["table2", "firm"]:
        g, name = ok[ok["model_preset"] == preset], PRESET_LABEL[preset]
        lifted = g[g["final_phase"] != "closure"]
        tot, deep = lifted["trial_id"].map(last_pen).max(), lifted["delta_max_mm"].max()
        rows += [{"quantity": f"{name}: final total penetration Σδ, largest over its lifted runs",
                  "value": tot, "paper": f"≤ {below:.2f}", "differs": judge(tot, (None, below), 2)},
                 {"quantity": f"{name}: deepest contact δmax, largest over its lifted runs (paper: the "
                  "design limit per contact)", "value": deep, "paper": "≤ 1.00",
                  "differs": judge(deep, (None, 1.0), 2)}]
        r = g[np.isclose(g["mu"], mu) & np.isclose(g["mass_kg"], mass)].iloc[0]
        held = r["dynamic_status"] == "stable"
        s = steps[steps["trial_id"] == r["trial_id"]]
        s = s[s["time_s"].between(r["hold_start_s"], r["hold_end_s"])]
        vals = {"steps before the settled window": (np.round(r["hold_start_s"] / r["dt_s"]),
                                                    ref["settle_within_iterations"]),
                "largest |R_z| in the settled window (paper: internal units)": (
                    s["residual_z_n"].abs().max(), ref["residual_amplitude_internal_units"])}
        for j in (1, 2, 3):
            vals[f"finger {j} normal force at the end (paper: internal units)"] = (
                r[f"normal_force_{j}_n"], ref["finger_forces_internal_units"][f"finger{j}"])
        rows += [{"quantity": f"{name}, μ = {mu:g}, m = {mass:g} kg: {q}", "value": v if held else None,
                  "paper": pv, "differs": None} for q, (v, pv) in vals.items()]  # not compared
    compare(study, "paper_values", pd.DataFrame(rows), ["quantity"])
    compare(study, "status", rec.groupby("status").size().rename("n").reset_index(), ["status"])


# ---------------------------------------------------------------- gravity_settle (Sec. 5.4, Fig. 10)
def audit_gravity_settle() -> None:
    """Each settle and audit cell from the records' definitions and the trace tables: squash ratio from the
    settled node heights, shape difference from the node positions, the last settle-trace sample, the
    observed order from the step study, the energy audit's balance from its energy columns."""
    study, rec = "gravity_settle", records("gravity_settle")
    ok = rec[rec["status"] == "ok"].set_index("integrator").loc[["rk4", "implicit"]].reset_index()
    shape, settle = aux(study, "tables", "shape"), aux(study, "tables", "settle")
    conv, energy = aux(study, "tables", "step_convergence"), aux(study, "tables", "energy_audit")
    first = shape[shape["trial_id"] == ok["trial_id"].iloc[0]].set_index("node")[["x_m", "y_m", "z_m"]]
    rows = []
    for _, r in ok.iterrows():
        t = r["trial_id"]
        s = shape[shape["trial_id"] == t].set_index("node")
        trace = settle[settle["trial_id"] == t].sort_values("time_s")
        c = conv[conv["trial_id"] == t].sort_values("dt_s", ascending=False)
        en = energy[(energy["trial_id"] == t) & (energy["step"] == "dt")].sort_values("time_s")
        half = energy[(energy["trial_id"] == t) & (energy["step"] == "dt/2")]
        dt, err = c["dt_s"].to_numpy(float), c["max_position_error_m"].to_numpy(float)
        kinds = en[["kinetic_energy_j", "elastic_energy_j", "gravitational_energy_j"]].to_numpy()
        mech, scale = kinds.sum(axis=1), np.abs(kinds).max()  # mechanical energy over the sampled steps
        rows.append({
            "integrator": r["integrator"], "nodes": len(s), "mass_kg": 0.4, "paper_settles": True,
            "squash_ratio": np.ptp(s["z_m"]) / np.ptp(s["z0_m"]),
            "shape_difference_max_mm": 1e3 * np.linalg.norm(s[["x_m", "y_m", "z_m"]] - first, axis=1).max(),
            "simulated_time_s": trace["time_s"].iloc[-1], "final_kinetic_energy_uj": 1e6 * trace[
                "kinetic_energy_j"].iloc[-1], "max_kinetic_energy_j": trace["kinetic_energy_j"].max(),
            "n_steps": round(trace["time_s"].iloc[-1] / r["dt_s"]), "dt_us": 1e6 * r["dt_s"],
            "expected_order": {"rk4": 4, "implicit": 2}[r["integrator"]],
            "observed_order": math.log(err[-2] / err[-1]) / math.log(dt[-2] / dt[-1]),
            "error_at_settle_dt_um": 1e6 * err[np.isclose(dt, r["dt_s"])][0],
            "energy_audit_span_s": en["time_s"].iloc[-1] - en["time_s"].iloc[0],
            "energy_increases": int(np.sum(np.diff(mech) > 1e-12 * scale)),
            "lu_factorizations": 0 if r["integrator"] == "rk4" else r["lu_factorizations"],
            # msd.settle_on_floor's stop: kinetic energy below 1e-7 m g H0 (H0 the undeformed height)
            "settled": bool(trace["kinetic_energy_j"].iloc[-1]
                            < 1e-7 * r["mass_kg"] * 9.81 * np.ptp(s["z0_m"]))})
        for col, part in (("energy_balance_rel_error", en), ("energy_balance_rel_error_half_dt", half)):
            energies = part[["kinetic_energy_j", "elastic_energy_j", "gravitational_energy_j",
                             "dissipated_energy_j"]].abs().to_numpy()  # the largest energy of any kind
            rows[-1][col] = part["balance_error_j"].abs().max() / energies.max()
        rows[-1]["energy_audit_steps"] = round(rows[-1]["energy_audit_span_s"] / r["dt_s"])
        print(f"   {t}: last settle-trace height ratio {trace['height_ratio'].iloc[-1]:.6g}; "
              "final KE / max KE "
              f"{trace['kinetic_energy_j'].iloc[-1] / trace['kinetic_energy_j'].max():.2g} (settled: "
              f"{r['settled']}); not recomputable from the traces: max_floor_penetration_mm (a maximum over "
              "time), newton_iterations_per_step")
    rk4 = ok[ok["integrator"] == "rk4"].iloc[0]
    for row, (_, r) in zip(rows, ok.iterrows(), strict=True):  # one RK4 stable step for both
        row["dt_over_rk4_limit"] = r["dt_s"] * rk4["dt_over_rk4_limit"] / rk4["dt_s"]
    expected = pd.DataFrame(rows)
    for name in ("settle", "integrator_audit"):
        got = table(study, name)
        cols = [c for c in expected.columns if c in got.columns and c != "integrator"]
        compare(study, name, expected[["integrator", *cols]], ["integrator"], rtol=1e-6)
    settled = table(study, "settle")
    words = {True: "settles", False: "**does not settle**"}
    names = {"rk4": "RK4 (explicit, the paper's)", "implicit": "implicit midpoint"}
    parts = [f"{names[i]} {words[z]} "
             f"within {t:.3f} s at {x:.2f}× RK4's stable step" for i, z, t, x in zip(
                 ok["integrator"], expected["settled"], expected["simulated_time_s"], ok["dt_over_rk4_limit"],
                 strict=True)]
    widest = float(f"{expected.shape_difference_max_mm.max():.3g}")
    parts += [f"the final shapes differ by at most {widest:g} mm",
              f"finds {int(settled['energy_increases'].sum())} energy increases",
              f"{'as' if expected['settled'].all() else 'unlike'} the paper's Fig. 10"]
    check_opening(study, parts)


STUDIES = {"test1_bench": audit_test1, "test3_disturbance": audit_test3,
           "friction_mass": audit_friction_mass, "dynamic_check": audit_dynamic_check,
           "sensitivity": audit_sensitivity, "pso_repeatability": audit_pso, "test2_grasp": audit_test2,
           "gravity_settle": audit_gravity_settle, **SMALL,
           **{s: lambda s=s: audit_quasi_static(s)
              for s in ("shapes", "ablation", "baseline_grid", "grip_laws")}}

if __name__ == "__main__":
    for s in sys.argv[2:] or STUDIES:
        STUDIES[s]()
    print("\nstudy / table: cells checked, mismatches")
    for s, t, n, b in SUMMARY:
        print(f"  {s} / {t}: {n}, {b}")
