"""The table audit of Test 1 (``audit_tables.py``): test1_bench's tables recomputed from its records, its
``attempts`` and ``waveforms`` tables and its ``summary/`` tables, beside the paper's Tables 4-5 and
Sec. 7."""

from __future__ import annotations

import numpy as np
import pandas as pd
from _audit_common import (
    PSO_PARAMS,
    RADIUS_MM,
    SUMMARY,
    aux,
    compare,
    judge,
    paper,
    records,
    sig3_decimals,
    table,
    wilson,
)
from scipy import stats

FAMILY_ORDER = ["gel", "silicone_soft", "bio_foam", "silicone_ref"]
T1_KEY = ["material", "specimen", "environment"]


def audit_test1() -> None:
    study, rec, ref = "test1_bench", records("test1_bench"), paper("test1_bench")
    f = rec[(rec["status"] == "ok") & (rec["event_status"] == "completed")].copy()
    for c in ("fit_ok", "accepted", "slipped_measured"):
        f[c] = f[c].fillna(False).astype(bool)
    normal = f[f["block"] == "normal"]
    acc = normal[normal["fit_ok"] & normal["accepted"]]
    sliding = f[(f["block"] == "sliding") & f["fit_ok"]]
    relax = f[(f["block"] == "relaxation") & f["fit_ok"]]
    summ = lambda name: aux(study, "summary", name)  # noqa: E731
    truths = summ("truths")
    # counts
    att, wav = aux(study, "tables", "attempts"), aux(study, "tables", "waveforms")
    rows = [("commanded attempts", len(att), ref["events_commanded"]),
            ("aborted attempts (re-run, not fitted)", int((att["attempt_status"] == "aborted").sum()),
             ref["events_aborted"]),
            ("completed events (fitted)", len(f), ref["events_completed"]),
            ("normal-indentation fits", len(normal), ref["normal_fits"]),
            ("normal fits accepted", int(normal["accepted"].sum()), ref["normal_fits_accepted"]),
            ("oblique events", int((f["block"] == "oblique").sum()), ref["oblique_events"]),
            ("cycle measurements", int((f["block"] == "cyclic").sum()), ref["cycle_measurements"]),
            ("events with full traces kept", wav["event_id"].nunique(), ref["retained_trace_events"]),
            ("trace samples kept", len(wav), ref["retained_trace_samples"])]
    compare(study, "test1_counts", pd.DataFrame([{"quantity": q, "ours": v, "paper": x, "difference": v - x,
                                                  "differs": judge(v, x,
                                                                   0)} for q, v, x in rows]), ["quantity"])
    # table 4
    fit = f[f["fit_ok"]]
    nf = fit[(fit["block"] == "normal") & fit["accepted"]]
    rows = []
    for m in [m for m in FAMILY_ORDER if m in set(nf["material"]) | set(fit["material"])]:
        g, sl, rl = nf[nf["material"] == m], fit[(fit["block"] == "sliding") & (fit["material"] == m)], \
            fit[(fit["block"] == "relaxation") & (fit["material"] == m)]
        e = truths[truths["material"] == m].drop_duplicates(["material", "specimen"])["modulus_kpa"]
        rows.append({"material": m, "row": "ours", "modulus_kpa": e.mean(), "modulus_sd_kpa": e.std(ddof=1),
                     "n_exp": g["n_exp"].mean(), "k_n_per_mm_n": g["k_n_per_mm_n"].mean(),
                     "f05_n": g["f05_n"].mean(), "c_n_s_per_m": g["c_n_s_per_m"].median(),
                     "c_negative": int((g["c_n_s_per_m"] < 0).sum()),
                     "n_accepted_fits": len(g), "mu_s": sl["mu_s"].mean(), "mu_k": sl["mu_k"].mean(),
                     "k_t_n_per_mm": sl["k_t_n_per_mm"].mean(), "rho": rl["rho"].mean(),
                     "tau_s": rl["tau_s"].mean()})
        t4 = ref["table4"][m]
        rows.append({"material": m, "row": "paper", **{("n_exp" if k == "exponent_n" else k): v for k,
                                                       v in t4.items()}})
    compare(study, "table4", pd.DataFrame(rows), ["material", "row"])
    # oblique margins: calibrated mu_s = median breakaway of the specimen's slides in that environment
    mu = f[f["block"] == "sliding"].groupby(T1_KEY)["mu_s"].median().rename("mu_cal")
    ob = f[f["block"] == "oblique"].join(mu, on=T1_KEY)
    # the friction-cone slip margin μs fn − |ft| (Eqs. 15-16)
    ob["margin"] = ob["mu_cal"] * ob["peak_normal_force_n"] - ob["peak_tangential_force_n"].abs()
    rows = []
    for a, g in ob.groupby("angle_deg"):
        pv = ref["oblique_margin_n"].get(f"{a:g}")
        rows.append({"angle_deg": a, "events": len(g), "mean_n": g["margin"].mean(),
                     "sd_n": g["margin"].std(ddof=1),
                     "paper_n": pv, "difference": None if pv is None else g["margin"].mean() - pv,
                     "differs": judge(g["margin"].mean(), pv, 2)})
    compare(study, "oblique_margin", pd.DataFrame(rows), ["angle_deg"])
    predicted = np.tan(np.radians(ob["angle_deg"])) > ob["mu_cal"]
    # cycles: K/K1 = f0.5 over cycle 1's, permanent set = onset shift from cycle 1
    cy = f[f["block"] == "cyclic"].sort_values(["material", "specimen", "cycle_index"])
    first = cy.groupby(T1_KEY)[["f05_n", "onset_mm"]].transform("first")
    cy = cy.assign(k_ratio=cy["f05_n"] / first["f05_n"], pset=cy["onset_mm"] - first["onset_mm"])
    last = cy.sort_values("cycle_index").groupby("specimen_id").tail(1)
    # claims
    t4 = ref["table4"]
    fam = lambda frame, col: frame.groupby("material")[col].mean()  # noqa: E731

    def val(v, paper, digits, n):
        return {"value": v, "paper": paper, "n": n, "differs": judge(v, paper, digits), "digits": digits}

    def shr(flags, paper, digits=1):
        k, n = int(np.sum(flags)), len(flags)
        low, high = wilson(k, n)
        return {"value": 100 * k / n, "low": 100 * low, "high": 100 * high, "n": n, "paper": paper,
                "differs": judge(100 * k / n, paper, digits, 100 * low, 100 * high), "digits": digits}
    rng = lambda col: (min(v[col] for v in t4.values()), max(v[col] for v in t4.values()))  # noqa: E731
    flagged = normal[~normal["accepted"]]
    c = {"contact exponent n, accepted fits: mean": val(acc["n_exp"].mean(), ref["n_exp_mean"], 2, len(acc)),
         "contact exponent n, accepted fits: SD": val(acc["n_exp"].std(ddof=1), ref["n_exp_sd"], 2, len(acc)),
         "mean n per family: lowest family": val(fam(acc, "n_exp").min(), ref["n_exp_family_range"], 2,
                                                 len(acc)),
         "mean n per family: highest family": val(fam(acc, "n_exp").max(), ref["n_exp_family_range"], 2,
                                                  len(acc)),
         "force-fit RMSE, accepted fits: mean": val(acc["rmse_pct"].mean(), ref["rmse_pct_accepted"], 2,
                                                    len(acc)),
         "force-fit RMSE, all normal fits: mean": val(normal["rmse_pct"].mean(), ref["rmse_pct_all"], 2,
                                                      len(normal)),
         "RMSE of the review-flagged fits: lowest fit": val(flagged["rmse_pct"].min(),
                                                            ref["flagged_rmse_pct_range"], 1, len(flagged)),
         "RMSE of the review-flagged fits: highest fit": val(flagged["rmse_pct"].max(),
                                                             ref["flagged_rmse_pct_range"], 1, len(flagged)),
         "loop area: median": val(normal["loop_area_mj"].median(), ref["loop_area_median_mj"], 3,
                                  len(normal)),
         # §7.2 prints "median loading work 0.54 mJ, median unloading 0.42 mJ": two decimals
         "loading work: median": val(normal["loading_work_mj"].median(), ref["loading_work_median_mj"], 2,
                                     len(normal)),
         "unloading work: median": val(normal["unloading_work_mj"].median(), ref["unloading_work_median_mj"],
                                       2, len(normal)),
         "per-event C: median (paper: Table 4's family range)": val(normal["c_n_s_per_m"].median(),
                                                                    rng("c_n_s_per_m"), 3, len(normal)),
         "standard error of per-event C: median": val(normal["c_se_n_s_per_m"].median(), None, 2,
                                                      len(normal))}
    for env, words in (("cool_dry", "cool/dry"), ("warm_humid", "warm/humid")):
        g = sliding[sliding["environment"] == env]
        c[f"μs {words}: campaign mean"] = val(g["mu_s"].mean(), ref["mu_s_environment"][env], 2, len(g))
    fam_s, fam_k = fam(sliding, "mu_s"), fam(sliding, "mu_k")
    c["μs > μk in every family"] = {"value": bool((fam_s > fam_k).all()), "paper": True, "differs": False,
                                    "n": None, "digits": 2}
    # §7.3: k_t "in the 2 N mm^-1 to 5 N mm^-1 range": whole N/mm (Table 4's gel 1.97 inside as printed)
    c["kt per family: lowest family"] = val(fam(sliding, "k_t_n_per_mm").min(), ref["k_t_range_n_per_mm"], 0,
                                            len(sliding))
    c["kt per family: highest family"] = val(fam(sliding, "k_t_n_per_mm").max(), ref["k_t_range_n_per_mm"], 0,
                                             len(sliding))
    c["Coulomb prediction = sign of the slip margin"] = shr(predicted == (ob["margin"] < 0),
                                                            ref["oblique_classification_match_pct"])
    c["Coulomb prediction = slip on the bench"] = shr(predicted == ob["slipped_measured"], None)
    c["ρ per family: lowest family"] = val(fam(relax, "rho").min(), rng("rho"), 2, len(relax))
    c["ρ per family: highest family"] = val(fam(relax, "rho").max(), rng("rho"), 2, len(relax))
    c["τ per family: lowest family"] = val(fam(relax, "tau_s").min(), rng("tau_s"), 1, len(relax))
    c["τ per family: highest family"] = val(fam(relax, "tau_s").max(), rng("tau_s"), 1, len(relax))
    c["K/K1 at the last measured cycle: lowest specimen (paper: above the target)"] = val(
        last["k_ratio"].min(), (ref["k_ratio_target"], None), 3, len(last))  # one-sided: Sec. 7.4
    c["permanent set after cycling: lowest family mean"] = val(fam(last, "pset").min(),
                                                               ref["permanent_set_mm"], 2, len(last))
    c["permanent set after cycling: highest family mean"] = val(fam(last, "pset").max(),
                                                                ref["permanent_set_mm"], 2, len(last))
    frame = pd.DataFrame([{"quantity": q, **v} for q, v in c.items()])
    compare(study, "test1_claims", frame.drop(columns=["paper"]), ["quantity"])
    # table 5: converged runs, mean (Student-t 95%), SD, CV
    runs = summ("pso_runs")
    ok = runs[runs["converged"].astype(bool)]
    rows = []
    for col, name in zip(PSO_PARAMS, ["lambda1", "lambda2", "n", "b", "k", "c"], strict=True):
        v = ok[col].to_numpy(float)
        half = stats.t.ppf(0.975, v.size - 1) * v.std(ddof=1) / np.sqrt(v.size)
        t5 = ref["table5"][name]
        digits = sig3_decimals(min(t5["simulation"], t5["mean"]))
        cv = 100 * v.std(ddof=1) / v.mean()
        rows.append({"parameter": name, "mean": v.mean(), "sd": v.std(ddof=1), "n_runs": v.size,
                     "mean_low": v.mean() - half, "mean_high": v.mean() + half, "cv_pct": cv,
                     "n_at_bound": int(sum(name in str(b).split(",") for b in ok["at_bound"])),
                     "paper_simulation": t5["simulation"], "paper_mean": t5["mean"], "paper_sd": t5["sd"],
                     "paper_cv_pct": t5["cv_pct"], "digits": digits, "difference": cv - t5["cv_pct"],
                     "differs": judge(cv, t5["cv_pct"], 1)})
    compare(study, "table5", pd.DataFrame(rows), ["parameter"])
    mean_differs = {r["parameter"]: judge(r["mean"], r["paper_mean"], r["digits"], r["mean_low"],
                                          r["mean_high"])
                    for r in rows}
    got = table(study, "table5").set_index("parameter")["mean_verdict"]
    bad = [p for p, dv in mean_differs.items() if got[p].startswith("differs") != dv]
    SUMMARY.append((study, "table5 mean_verdict", len(mean_differs), len(bad)))
    print(f"{study} / table5 mean_verdict: {len(mean_differs)} cells checked, {len(bad)} mismatches {bad}")
    tr = summ("pso_transfer")
    conv = tr.loc[tr["converged"].astype(bool), "rmse_mean_pct"]
    ps = {"PSO runs logged": val(len(runs), ref["pso_runs_logged"], 0, None),
          "PSO runs converged": val(int(runs["converged"].astype(bool).sum()), ref["pso_runs_converged"], 0,
                                    None),
          "n over the converged runs: median": val(ok["n_exp"].median(), ref["pso_n_run_median"], 3, None)}
    for w, k in (("mean", "mean"), ("median", "median"), ("worst run", "max")):
        ps[f"held-out RMSE of the converged runs: {w}"] = val(conv.agg(k), ref["pso_transfer_rmse_pct"][k], 1,
                                                              None)
    bad_runs = tr.loc[~tr["converged"].astype(bool), "rmse_mean_pct"]
    if len(bad_runs):
        for w, k in (("best run", "min"), ("worst run", "max")):
            ps[f"held-out RMSE of the diverged runs: {w}"] = val(
                bad_runs.agg(k), ref["pso_diverged_transfer_rmse_pct"], 1, None)
    summary = pd.DataFrame([{"quantity": q, **v} for q, v in ps.items()]).drop(columns=["n"])
    compare(study, "pso_summary", summary, ["quantity"])
    # transfer
    te = summ("transfer")
    tp = ref["transfer_pct"]
    rows = []
    for (q, split), g in te.groupby(["quantity", "split"]):
        # §7.6: "2.58% (training) to 2.58% (unseen specimen) and 3.64% (unseen speed)" (two decimals),
        # "3.1%", "4.3%" (one); the friction error "stays near or below ~1%" across unseen load, specimen
        # and speed: an upper bound, at the whole percent it prints (none given for the training split)
        friction = tp["friction_max"] if split != "train" else None
        pv = tp["normal_force"][split] if q == "normal_force" else friction \
            if q == "friction" else tp.get(q)
        e = g["error_pct"]
        judged = judge(e.mean(), (None, pv), 0) if q == "friction" and pv is not None else \
            judge(e.mean(), pv, 2 if q == "normal_force" else 1)
        rows.append({"quantity": q, "split": split, "events": len(g), "mean_error_pct": e.mean(),
                     "median_error_pct": e.median(), "p95_error_pct": np.percentile(e, 95), "paper_pct": pv,
                     "differs": judged})
    compare(study, "transfer", pd.DataFrame(rows), ["quantity", "split"])
    # damage depth per family
    true = truths[[*T1_KEY, "damage_depth_mm"]]
    dd = summ("damage_depth").merge(true, how="left", on=T1_KEY, suffixes=("", "_true"))
    rows = []
    for m, g in dd.groupby("material"):
        error = (g["damage_depth_mm"] - g["damage_depth_mm_true"]).abs()  # against the bench's truth
        rows.append({"material": m, "specimens": len(g), "damage_depth_mean_mm": g["damage_depth_mm"].mean(),
                     "damage_depth_min_mm": g["damage_depth_mm"].min(),
                     "damage_depth_max_mm": g["damage_depth_mm"].max(),
                     "set_limited": int((g["criterion"] == "set").sum()),
                     "extrapolated": int(g["extrapolated"].astype(bool).sum()),
                     "beyond_radius": int((g["damage_depth_mm"] > RADIUS_MM).sum()),
                     "abs_error_median_mm": error.median()})
    compare(study, "damage_depth", pd.DataFrame(rows), ["material"])
    compare(study, "status", rec.groupby("status").size().rename("n").reset_index(), ["status"])
