"""The table audit of ``surrogate`` (Appendix A, Fig. A.1; part of ``_audit_small.py``): the class balance
from the records; AUC, accuracy and its Wilson interval from the held-out scores the run stored
(``summary/surrogate_scores``), the AUC's percentile-bootstrap interval redrawn with scipy; the stored
fits against a refit with scikit-learn of the same models on each label's own stratified split (scores,
importances) and, for the regression R², on Appendix A's one split, stratified on the paper's label; the
timing ratios; and the report's opening paragraph. Nothing here imports graspcampaign."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pandas as pd
from _audit_common import SUMMARY, aux, compare, judge, paper, records, sig3_text, table, wilson
from scipy import stats
from sklearn.metrics import r2_score, roc_auc_score

LABELS = ["success", "success_unbounded", "success_vertical"]  # configured, as published, |R_z|
PAPER_LABEL = "success_unbounded"  # Appendix A's label: Algorithm 1 line 6 as published, no gate
NUMERIC = ["mass_kg", "mu", "lambda1", "lambda2", "msd_b"]  # Appendix A's sampled inputs
SHAPE_LABEL = {"all": "all", "sphere": "sphere", "ellipsoid": "ellipsoid", "rounded_cube": "rounded cube",
               "pear": "pear", "handle": "concave handle"}
MODEL_LABEL = {"mlp": "MLP 64-32", "random_forest": "random forest"}  # as the report names them
MIN_CLASS = 10  # the caption: no interval (and no verdict) below 10 held-out trials of either class


def _si(seconds: float) -> str:
    """A time to three significant digits with the SI prefix that puts it in [1, 1000): 0.00164 s
    reads "1.64 ms" (the report's reader prints times so; written here from that rule alone)."""
    for factor, prefix in ((1.0, ""), (1e-3, "m"), (1e-6, "µ"), (1e-9, "n")):
        if float(f"{seconds:.2e}") >= factor:
            return f"{seconds / factor:#.3g}".rstrip(".") + f" {prefix}s"
    return f"{seconds:.3g} s"


def tally(study: str, name: str, checked: int, bad: list[str]) -> None:
    SUMMARY.append((study, name, checked, len(bad)))
    print(f"{study} / {name}: {checked} checked, {len(bad)} mismatches")
    for b in bad[:10]:
        print("   ", b)


def auc_ci(pos: np.ndarray, neg: np.ndarray, seed: int) -> tuple[float, float]:
    """The AUC's percentile-bootstrap 95 % interval, positives and negatives resampled apart."""
    def auc(p, n, axis=-1):  # Mann-Whitney U / (n_pos n_neg) from mid-ranks: ties count one half
        p, n = np.moveaxis(p, axis, -1), np.moveaxis(n, axis, -1)
        ranks = stats.rankdata(np.concatenate([p, n], axis=-1), axis=-1)[..., :p.shape[-1]]
        return (ranks.sum(axis=-1) - p.shape[-1] * (p.shape[-1] + 1) / 2) / (p.shape[-1] * n.shape[-1])
    ci = stats.bootstrap((pos, neg), auc, paired=False, vectorized=True, n_resamples=10_000,
                         method="percentile", rng=np.random.default_rng(seed)).confidence_interval
    return float(ci.low), float(ci.high)


def refit(ok: pd.DataFrame, seed: int, cfg: dict):
    """The run's models refitted with scikit-learn on its split: per fitted label the held-out scores
    of each classifier and the forest's importances; per regression target each model's held-out R²."""
    from sklearn.ensemble import RandomForestClassifier, RandomForestRegressor
    from sklearn.exceptions import ConvergenceWarning
    from sklearn.model_selection import train_test_split
    from sklearn.neural_network import MLPClassifier, MLPRegressor
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler
    p = cfg["params"]
    x = pd.concat([ok[NUMERIC].astype(float), *[(ok["shape"] == s).astype(float).rename(f"shape_{s}")
                                                for s in p["shapes"]]], axis=1)
    names, x = list(x.columns), x.to_numpy()

    def pair(regression):
        mlp = (MLPRegressor if regression else MLPClassifier)(hidden_layer_sizes=tuple(p["hidden_layers"]),
                                                               max_iter=2000, random_state=seed)
        forest = (RandomForestRegressor if regression else RandomForestClassifier)(
            n_estimators=p["n_trees"], random_state=seed, n_jobs=1)
        return {"mlp": make_pipeline(StandardScaler(), mlp),
                "random_forest": make_pipeline(StandardScaler(), forest)}
    scores, importance, r2, splits = {}, None, {}, {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        for label in LABELS:
            rows = np.flatnonzero(ok[label].notna().to_numpy())
            y = ok[label].astype("boolean").fillna(False).to_numpy(bool)
            if min(y[rows].sum(), (~y[rows]).sum()) < MIN_CLASS:
                continue
            train, test = train_test_split(rows, test_size=p["test_fraction"], stratify=y[rows],
                                           random_state=seed)
            splits[label] = train, test
            for name, model in pair(False).items():
                model.fit(x[train], y[train])
                scores[label, name] = (y[test], model.predict_proba(x[test])[:, 1])
                if name == "random_forest" and importance is None:
                    importance = pd.DataFrame({"label": label, "feature": names,
                                               "importance": model[-1].feature_importances_})
        # Appendix A: "An 80/20 train/test split is used with stratification on the binary label" -- one
        # split, the paper's label's, holds the regressors out too (unstratified when it cannot be drawn)
        train, test = splits.get(PAPER_LABEL) or train_test_split(
            np.arange(len(ok)), test_size=p["test_fraction"], random_state=seed)
        floor = lambda c: np.log10(np.maximum(ok[c].to_numpy(float), 1e-3))  # noqa: E731
        for target, v in (("abs_residual_z_n", ok["abs_residual_z_n"].to_numpy(float)),
                          ("log10_residual_norm_n", floor("residual_norm_n")),
                          ("log10_delta_max_mm", floor("delta_max_mm"))):
            for name, model in pair(True).items():
                flat = np.ptp(v[test]) <= 1e-9 * max(1.0, float(np.abs(v).max()))
                r2[target, name] = math.nan if flat else r2_score(v[test], model.fit(x[train], v[train])
                                                                  .predict(x[test]))
    return scores, importance, r2


def audit_surrogate(config) -> None:
    study, ref, cfg = "surrogate", paper("surrogate"), config("surrogate")
    seed = int(cfg["seed"])
    raw = records(study)
    ok = raw[raw["status"] == "ok"].reset_index(drop=True)  # file order: the order finalize fitted in
    rows = []
    for group in ["all", *[s for s in SHAPE_LABEL if s in set(ok["shape"])]]:
        g = ok if group == "all" else ok[ok["shape"] == group]
        row = {"group_label": SHAPE_LABEL[group], "n": len(g), "paper_pct": ref["class_balance_pct"]
               if group == "all" else None}
        for lab in LABELS:
            k_g = g[g[lab].notna()]
            k, n = int(k_g[lab].astype(bool).sum()), len(k_g)
            low, high = wilson(k, n)
            row |= {f"{lab}_pct": 100 * k / n, f"{lab}_low_pct": 100 * low, f"{lab}_high_pct": 100 * high,
                    f"n_{lab}": n}
            if lab == PAPER_LABEL:  # the count the opening says ("of the k published-algorithm successes")
                row["n_unbounded_successes"] = k
        row["differs"] = judge(row[f"{PAPER_LABEL}_pct"], row["paper_pct"], 1, row[f"{PAPER_LABEL}_low_pct"],
                               row[f"{PAPER_LABEL}_high_pct"])
        rows.append(row)
    dataset = pd.DataFrame(rows)
    compare(study, "surrogate_dataset", dataset, ["group_label"])
    # the classifiers from the stored held-out scores (the finalize stage's), then refitted
    try:  # a run that fitted no classifier stored no held-out scores
        stored = aux(study, "summary", "surrogate_scores")
    except FileNotFoundError:
        stored = pd.DataFrame(columns=["label", "model", "positive", "score"])
    fits, importance, r2 = refit(ok, seed, cfg)
    rows, bad, checked, acc_words = [], [], 0, {}
    for lab in LABELS:
        known = ok[ok[lab].notna()][lab].astype(bool)
        base = {"label": lab, "positives": int(known.sum()), "trials": len(known),
                "class_balance_pct": 100 * known.mean()}
        fitted = stored[stored["label"] == lab]
        for model, s in fitted.groupby("model", sort=False):
            y, score = s["positive"].to_numpy(bool), s["score"].to_numpy(float)
            auc = roc_auc_score(y, score)
            few = min(y.sum(), (~y).sum()) < MIN_CLASS
            low, high = (math.nan, math.nan) if few else auc_ci(score[y], score[~y], seed)
            hits = int(((score > 0.5) == y).sum())  # predict: the class of larger probability
            a_low, a_high = wilson(hits, len(y))
            p_auc = ref["auc"].get(model) if lab == PAPER_LABEL else None
            p_acc = tuple(ref["accuracy_pct"]) if lab == PAPER_LABEL else None
            rows.append({**base, "model": model, "model_label": MODEL_LABEL[model], "test_trials": len(y),
                         "test_positives": int(y.sum()),
                         "roc_auc": auc, "roc_auc_low": low, "roc_auc_high": high,
                         "accuracy_pct": 100 * hits / len(y), "accuracy_low_pct": 100 * a_low,
                         "accuracy_high_pct": 100 * a_high, "majority_class_accuracy_pct":
                         100 * max(y.mean(), 1 - y.mean()), "paper_auc": p_auc,
                         "paper_accuracy_low_pct": p_acc[0] if p_acc else None,
                         "paper_accuracy_high_pct": p_acc[1] if p_acc else None,
                         "differs": None if few else judge(auc, p_auc, 2, low, high)})
            acc_words[lab, model] = judge(100 * hits / len(y), p_acc, 1)
            ry, rs = fits.get((lab, model), (None, None))
            checked += 1
            if ry is None or not (np.array_equal(ry, y) and np.allclose(rs, score, rtol=1e-9, atol=1e-12)):
                bad.append(f"{lab}/{model}: the refit's held-out scores differ from the stored ones")
        if not len(fitted):
            rows.append(base | {"model_label": "—"})  # the report's row of a label not fitted: no model
    compare(study, "surrogate_classification", pd.DataFrame(rows), ["label", "model_label"])
    got = table(study, "surrogate_classification")
    for _, r in got[got["model"].notna()].iterrows():  # the accuracy verdict's words
        checked += 1
        d = acc_words.get((r["label"], r["model"]))
        if (d is True) != str(r["accuracy_verdict"]).startswith("differs"):
            bad.append(f"{r['label']}/{r['model']}: accuracy verdict {r['accuracy_verdict']!r}, differs {d}")
    stored_cls = aux(study, "summary", "surrogate_classification")
    stored_cls = stored_cls.assign(model=stored_cls.get("model"))  # absent when no label was fitted
    for _, r in stored_cls[stored_cls["model"].notna()].iterrows():  # the stored table itself
        checked += 1
        y, s = fits.get((r["label"], r["model"]), (None, None))
        if y is None or not math.isclose(r["roc_auc"], roc_auc_score(y, s), rel_tol=1e-9):
            bad.append(f"{r['label']}/{r['model']}: stored AUC {r['roc_auc']} against the refit's")
    # regression: the refit's R² beside the stored table; the parity table's R² is the log10 ‖R‖ MLP's
    reg = aux(study, "summary", "surrogate_regression")
    for _, r in reg.iterrows():
        checked += 1
        want = r2[r["target"], r["model"]]
        if not (math.isclose(r["r2"], want, rel_tol=1e-6) or (math.isnan(want) and math.isnan(r["r2"]))):
            bad.append(f"{r['target']}/{r['model']}: stored R² {r['r2']}, refit {want}")
    parity = aux(study, "summary", "surrogate_parity")
    if len(parity):
        checked += 1
        if not math.isclose(r2_score(parity["simulated"], parity["predicted"]),
                            r2["log10_residual_norm_n", "mlp"], rel_tol=1e-6):
            bad.append("the parity table's R² is not the log10 ‖R‖ MLP's")
    tally(study, "stored fits against a scikit-learn refit", checked, bad)
    rows = [{"target": t, "model": m, "test_trials": int(reg["test_trials"].iloc[0]), "r2": v,
             "paper_r2": ref["residual_r2"] if (t, m) == ("abs_residual_z_n", "mlp") else None,
             "differs": judge(v, ref["residual_r2"], 2) if (t, m) == ("abs_residual_z_n", "mlp")
             and not math.isnan(v) else None} for (t, m), v in r2.items()]
    compare(study, "surrogate_regression", pd.DataFrame(rows), ["target", "model"], rtol=1e-6)
    if importance is not None:
        compare(study, "surrogate_feature_importance", importance, ["feature"], rtol=1e-9)
    timing = aux(study, "summary", "surrogate_timing")
    pso = float(ok["pso_time_s"].median())
    rows = [{"what": "pso_call", "time_s": pso, "n_timed": len(ok), "speedup": None, "differs": None,
             "paper_time_us": 1e6 * ref["pso_call_time_s"]}]
    for _, r in timing[timing["what"] != "pso_call"].iterrows():
        sp = pso / r["time_s"]
        p = ref["speedup"] if r["what"] == "mlp" else None
        rows.append({"what": r["what"], "time_s": r["time_s"], "n_timed": r["n_timed"], "speedup": sp,
                     "paper_speedup": p,
                     "paper_time_us": 1e3 * ref["prediction_time_ms"] if r["what"] == "mlp" else None,
                     "differs": judge(sp, p, 0)})
    compare(study, "surrogate_timing", pd.DataFrame(rows), ["what"])
    compare(study, "status", raw.groupby("status").size().rename("n").reset_index(), ["status"])
    # the opening paragraph
    from _audit_small import opening
    d, won = dataset.iloc[0], ok[PAPER_LABEL].astype("boolean").fillna(False).astype(bool)
    deep = ok["delta_max_mm"] > 1e3 * float(cfg["model"]["fingertip_radius_m"])
    said = [f"{len(ok)} scenarios (paper {ref['n_scenarios']})",
            f"{d[f'{PAPER_LABEL}_pct']:.1f}% succeed under Algorithm 1 as published (paper "
            f"{ref['class_balance_pct']:.1f}%"]
    for (lab, model), (y, s) in fits.items():
        if lab == PAPER_LABEL:
            name = MODEL_LABEL[model]
            said.append(f"{name} {roc_auc_score(y, s):.2f}")
            said.append(f"on {len(y)} held out ({int(y.sum())} positive, {int((~y).sum())} negative")
    best = max(((v, t, m) for (t, m), v in r2.items() if not math.isnan(v)), default=None)
    if best:
        said.append(f"The best regression R² is {best[0]:.2f}".replace("-", "−"))  # the report's minus
    mlp = timing[timing["what"] == "mlp"]
    if len(mlp):
        ratio = pso / mlp["time_s"].iloc[0]
        said.append(f"is {sig3_text(ratio)}× faster than the brief PSO call")  # 3 significant digits
        # each call's time and its paper time in one bracket (Appendix A: 0.06 ms a prediction, 0.99 s a call)
        said += [f"({_si(mlp['time_s'].iloc[0])}; paper {ref['prediction_time_ms']:g} ms)",
                 f"({_si(pso)}; paper {ref['pso_call_time_s']:g} s)"]
    passed = int(ok["residual_ok"].astype("boolean").fillna(False).sum())
    said += [f"passes the ‖R‖ check in {passed or 'none'} of {len(ok)}",
             f"deeper than its radius r = {1e3 * float(cfg['model']['fingertip_radius_m']):g} mm in "
             f"{int(deep.sum())} ("]
    if won.any():
        said.append(f"{int((deep & won).sum())} of the {int(won.sum())} published-algorithm successes")
    opening(study, said)
