"""Report section of the ``surrogate`` kind: the models of Appendix A fitted on the run's records.

The dataset is the run's records (one scenario per trial). Here, in the report, the 64-32 MLP and
the 100-tree random forest are fitted with scikit-learn on the paper's inputs (shape one-hot,
mass, friction, lambda1, lambda2, b; standardised) with a stratified 80/20 split seeded by the
study seed: success classification (ROC AUC, accuracy, class balance) and regression of the
residual and the penetration (R^2). One prediction is timed here; the brief PSO call it is
compared with was timed inside every trial of the run (``pso_time_s``). Fitting is
deterministic for a given scikit-learn version; timings are not.
"""

from __future__ import annotations

import math
import socket
import time

import matplotlib as mpl
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from graspcampaign import stats
from graspcampaign.report.build import LegacyReport as Report
from graspcampaign.report.sections import executed, paper_value, rate_cell
from graspcampaign.report.style import RC

NUMERIC = ["mass_kg", "mu", "lambda1", "lambda2", "msd_b"]
"""Appendix A's sampled inputs besides the shape (n is fixed, so it is not a feature)."""

MIN_POSITIVES = 10
"""Fewer positives (or negatives) than this and a classifier is not fitted: AUC would be noise."""

LOG_FLOOR = 1e-3  # floor before log10 of a residual [N] or a penetration [mm] that may be 0

COLOURS = {"mlp": "#1f5aa6", "random_forest": "#e08a1e", "pso": "#7b4ea3"}



def _accuracy_columns(truth: np.ndarray, predicted: np.ndarray) -> dict:
    """Test-set accuracy with its n and Wilson 95 % interval [%]."""
    ci = stats.wilson_interval(int(np.sum(truth == predicted)), len(truth))
    return {"accuracy_pct": 100 * ci.estimate, "accuracy_low_pct": 100 * ci.low,
            "accuracy_high_pct": 100 * ci.high}

def features(df: pd.DataFrame, shapes: list[str]) -> pd.DataFrame:
    """Return the model inputs: one column per shape (0/1) and the numeric scenario values."""
    out = df[NUMERIC].astype(float).copy()
    for shape in shapes:
        out[f"shape_{shape}"] = (df["shape"] == shape).astype(float)
    return out


def targets(df: pd.DataFrame) -> dict[str, np.ndarray]:
    """Regression targets: the paper's vertical residual, and log10 of ‖R‖ and δ_max."""
    return {
        "abs_residual_z_n": df["abs_residual_z_n"].to_numpy(dtype=float),
        "log10_residual_norm_n": np.log10(np.maximum(df["residual_norm_n"].to_numpy(float),
                                                     LOG_FLOOR)),
        "log10_delta_max_mm": np.log10(np.maximum(df["delta_max_mm"].to_numpy(float), LOG_FLOOR)),
    }


def _models(params: dict, seed: int, regression: bool):
    from sklearn.ensemble import RandomForestClassifier, RandomForestRegressor
    from sklearn.neural_network import MLPClassifier, MLPRegressor
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler

    layers = tuple(int(v) for v in params.get("hidden_layers", [64, 32]))
    trees = int(params.get("n_trees", 100))
    mlp = (MLPRegressor if regression else MLPClassifier)(hidden_layer_sizes=layers,
                                                          max_iter=2000, random_state=seed)
    forest = (RandomForestRegressor if regression else RandomForestClassifier)(
        n_estimators=trees, random_state=seed, n_jobs=1)
    return {"mlp": make_pipeline(StandardScaler(), mlp),
            "random_forest": make_pipeline(StandardScaler(), forest)}


def prediction_time_s(model, row: np.ndarray, repeats: int = 200, budget_s: float = 0.5) -> float:
    """Median wall time of one single-row prediction [s] (``repeats`` calls or ``budget_s``)."""
    predict = getattr(model, "predict_proba", model.predict)
    predict(row)  # warm-up
    times: list[float] = []
    stop = time.perf_counter() + budget_s
    while len(times) < repeats and (len(times) < 5 or time.perf_counter() < stop):
        start = time.perf_counter()
        predict(row)
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def fit_surrogates(ok: pd.DataFrame, params: dict, seed: int) -> dict:
    """Fit classifiers (per label) and regressors; return metrics, curves and fitted models."""
    import warnings

    from sklearn.exceptions import ConvergenceWarning
    from sklearn.metrics import r2_score, roc_auc_score, roc_curve
    from sklearn.model_selection import train_test_split

    shapes = list(params.get("shapes") or sorted(set(ok["shape"])))
    frame = features(ok, shapes)
    x = frame.to_numpy()  # plain arrays: what a deployed surrogate would be fed (no pandas cost)
    test_fraction = float(params.get("test_fraction", 0.2))
    out = {"classification": [], "roc": {}, "regression": [], "parity": None, "models": {},
           "x": x, "columns": list(frame.columns), "importance": None}
    primary = None
    for label in ("success", "success_vertical"):
        y = ok[label].astype(bool).to_numpy()
        n_pos = int(y.sum())
        if min(n_pos, len(y) - n_pos) < MIN_POSITIVES:
            out["classification"].append({"label": label, "model": "–", "positives": n_pos,
                                          "trials": len(y), "note": f"fewer than "
                                          f"{MIN_POSITIVES} of one class: not fitted"})
            continue
        idx_train, idx_test = train_test_split(np.arange(len(y)), test_size=test_fraction,
                                               stratify=y, random_state=seed)
        if primary is None:
            primary = (idx_train, idx_test)
        for name, model in _models(params, seed, regression=False).items():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                model.fit(x[idx_train], y[idx_train])
            score = model.predict_proba(x[idx_test])[:, 1]
            fpr, tpr, _ = roc_curve(y[idx_test], score)
            out["roc"][(label, name)] = (fpr, tpr)
            out["models"][(label, name)] = model
            majority = max(y[idx_test].mean(), 1 - y[idx_test].mean())
            out["classification"].append({
                "label": label, "model": name, "positives": n_pos, "trials": len(y),
                "class_balance_pct": 100 * n_pos / len(y),
                "test_trials": len(idx_test), "test_positives": int(y[idx_test].sum()),
                "roc_auc": float(roc_auc_score(y[idx_test], score)),
                **_accuracy_columns(y[idx_test], model.predict(x[idx_test])),
                "majority_class_accuracy_pct": 100 * float(majority), "note": ""})
            if name == "random_forest" and label == "success" or (
                    name == "random_forest" and out["importance"] is None):
                forest = model[-1]
                out["importance"] = pd.DataFrame({
                    "feature": frame.columns, "importance": forest.feature_importances_,
                    "label": label}).sort_values("importance", ascending=False)
    if primary is None:  # no label could be stratified: a plain seeded split for regression
        primary = train_test_split(np.arange(len(ok)), test_size=test_fraction,
                                   random_state=seed)
    idx_train, idx_test = primary
    for target, values in targets(ok).items():
        for name, model in _models(params, seed, regression=True).items():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                model.fit(x[idx_train], values[idx_train])
            predicted = model.predict(x[idx_test])
            out["regression"].append({"target": target, "model": name,
                                      "test_trials": len(idx_test),
                                      "r2": float(r2_score(values[idx_test], predicted))})
            if name == "mlp" and target == "log10_residual_norm_n":
                out["parity"] = (values[idx_test], predicted)
            out["models"][(target, name)] = model
    return out


def section(report: Report, records: pd.DataFrame, manifest: dict, store=None) -> None:
    """Write the surrogate section (Appendix A, Fig. A.1)."""
    config = manifest.get("config") or {}
    paper = config["paper"]  # the typed paper values (build._legacy)
    params = config.get("params") or {}
    seed = int(config.get("seed", 0))
    ok = executed(records)
    if not len(ok):
        report.text("No executed surrogate trials to report.")
        return
    _dataset(report, ok, paper, config)
    try:
        import sklearn
    except ImportError:
        report.text("scikit-learn is not installed here, so the surrogates were not fitted: "
                    "install the `ml` extra (pip install 'graspcampaign[ml]') and rebuild the "
                    "report.")
        return
    fit = fit_surrogates(ok, params, seed)
    cls = pd.DataFrame(fit["classification"])
    test_pct = 100 * float(params.get("test_fraction", 0.2))
    report.table("surrogate_classification", cls,
                 f"Success classifiers on a stratified {100 - test_pct:.0f}/{test_pct:.0f} split "
                 f"(seed {seed}); "
                 f"paper: AUC {paper.auc}, accuracy {paper.accuracy_pct} %, "
                 f"class balance {paper.class_balance_pct} %")
    reg = pd.DataFrame(fit["regression"])
    report.table("surrogate_regression", reg,
                 f"Regression R² on the held-out trials (paper: R² = {paper.residual_r2} "
                 "for the vertical force residual)")
    if fit["importance"] is not None:
        report.table("surrogate_feature_importance", fit["importance"],
                     "Random-forest feature importances (impurity decrease) of the success "
                     "classifier")
    timing = _timing(ok, fit, paper, manifest)
    report.table("surrogate_timing", timing,
                 "One surrogate prediction against a brief PSO call on the same scenario")
    report.text(_words(cls, reg, timing, fit, paper, sklearn.__version__))
    _figure(report, fit, timing, paper)


def _dataset(report: Report, ok: pd.DataFrame, paper: dict, config: dict) -> None:
    check = (config.get("evaluator") or {}).get("residual_check", "norm")
    rows = [{"group": "all", "scenarios": len(ok),
             "success": rate_cell(int(ok["success"].sum()), len(ok)),
             "success_vertical": rate_cell(int(ok["success_vertical"].sum()), len(ok)),
             "paper_class_balance_pct": paper.class_balance_pct}]
    for shape, grp in ok.groupby("shape"):
        rows.append({"group": shape, "scenarios": len(grp),
                     "success": rate_cell(int(grp["success"].sum()), len(grp)),
                     "success_vertical": rate_cell(int(grp["success_vertical"].sum()), len(grp)),
                     "paper_class_balance_pct": None})
    report.text(
        f"**Dataset.** {len(ok)} scenarios (paper {paper.n_scenarios}), each a shape, mass, "
        f"friction, λ1, λ2 and b drawn uniformly (n = {ok['n_exp'].iloc[0]:.3g} fixed, as the "
        f"paper samples no exponent) and the heuristic planner's grasp judged by the "
        f"quasi-static evaluator. `success` is the configured check (`{check}`), "
        f"`success_vertical` the |R_z| reading. λ2 (damping of Eq. 14) and b (MSD constant) "
        f"cannot influence a quasi-static outcome: they are inputs because the paper uses them.")
    report.table("surrogate_dataset", pd.DataFrame(rows),
                 "Class balance of the dataset (Wilson 95 %) beside the paper's 8.7 % positives")


def _timing(ok: pd.DataFrame, fit: dict, paper: dict, manifest: dict) -> pd.DataFrame:
    row = fit["x"][:1]
    rows = [{"what": f"brief PSO call ({int(ok['pso_n_evaluations'].median())} evaluations), "
                     "median over the run's trials",
             "time_s": float(ok["pso_time_s"].median()),
             "paper_time_s": paper_value(paper, "pso_call_time_s"),
             "host": (manifest.get("host") or {}).get("name")}]
    for (label, name), model in fit["models"].items():
        if label != "success" or name not in ("mlp", "random_forest"):
            continue
        rows.append({"what": f"one {name} prediction (success probability), median of up to 200",
                     "time_s": prediction_time_s(model, row),
                     "paper_time_s": (paper_value(paper, "prediction_time_ms") or math.nan) * 1e-3
                     if name == "mlp" else math.nan,
                     "host": socket.gethostname()})
    table = pd.DataFrame(rows)
    table["pso_over_this"] = table["time_s"].iloc[0] / table["time_s"]
    return table


def _words(cls, reg, timing, fit, paper, version: str) -> str:
    out = [f"**Ours beside the paper** (scikit-learn {version})."]
    fitted = cls[cls["model"] != "–"] if "model" in cls else cls.iloc[0:0]
    for label, grp in fitted.groupby("label", sort=False):
        parts = ", ".join(f"{r['model']} AUC {r['roc_auc']:.2f}, accuracy {r['accuracy_pct']:.1f} % "
                          f"({r['accuracy_low_pct']:.1f}–{r['accuracy_high_pct']:.1f}, Wilson 95 %, "
                          f"n = {int(r['test_trials'])} test trials)"
                          for _, r in grp.iterrows())
        first = grp.iloc[0]
        out.append(f"`{label}`: {first['class_balance_pct']:.1f} % positives, "
                   f"{first['test_positives']} in the {first['test_trials']} held-out trials "
                   f"(so few make the AUC uncertain) "
                   f"(majority-class accuracy {first['majority_class_accuracy_pct']:.1f} %); "
                   f"{parts}. Paper: {paper.class_balance_pct} % positives, AUC "
                   f"{paper.auc}, accuracy {paper.accuracy_pct} %.")
    for _, r in cls[cls["model"] == "–"].iterrows() if "model" in cls else []:
        out.append(f"`{r['label']}`: {r['note']} ({r['positives']} positives of {r['trials']}).")
    if len(reg):
        best = reg.loc[reg.groupby("target")["r2"].idxmax()]
        out.append("Regression R² (best model per target): " + "; ".join(
            f"{r['target']} {r['r2']:.2f} ({r['model']})" for _, r in best.iterrows())
            + f". Paper: R² = {paper.residual_r2} for the vertical residual. Our vertical "
              "residual is driven to ~0 by Algorithm 2 in most scenarios, so its R² says little; "
              "the check quantity ‖R‖ and the penetration are regressed on a log scale.")
    if len(timing) > 1:
        mlp = timing[timing["what"].str.contains("mlp")]
        if len(mlp):
            out.append(f"One MLP prediction takes {1e3 * mlp['time_s'].iloc[0]:.3f} ms against "
                       f"{timing['time_s'].iloc[0]:.3f} s for the brief PSO call: "
                       f"{mlp['pso_over_this'].iloc[0]:.0f}× (paper: "
                       f"{paper.prediction_time_ms} ms vs {paper.pso_call_time_s} s, "
                       f"{paper.speedup}×). Our PSO call is cheaper than the paper's "
                       f"because one swarm iteration is a single vectorised evaluator call; the "
                       f"PSO time was measured in the run, the prediction time in this report "
                       f"(hosts in the table).")
    if fit["importance"] is not None:
        imp = fit["importance"].set_index("feature")["importance"]
        inert = ", ".join(f"{k} {imp[k]:.2f}" for k in ("lambda2", "msd_b") if k in imp)
        out.append(f"Importances of the two inputs that cannot matter: {inert} (of 1 in total): "
                   "what a forest assigns to pure noise.")
    return "\n\n".join(out)


def _figure(report: Report, fit: dict, timing: pd.DataFrame, paper: dict) -> None:
    with mpl.rc_context(RC):
        fig = Figure(figsize=(12.0, 3.9), layout="constrained")
        ax_a, ax_b, ax_c = fig.subplots(1, 3)
        auc = {(r["label"], r["model"]): r.get("roc_auc") for r in fit["classification"]}
        for (label, name), (fpr, tpr) in fit["roc"].items():
            ax_a.plot(fpr, tpr, color=COLOURS[name],
                      linestyle="-" if label == "success" else "--",
                      label=f"{name}, {label}: AUC {auc[(label, name)]:.2f}")
        ax_a.plot([0, 1], [0, 1], color="#999999", linestyle=":", label="chance")
        paper_auc = paper_value(paper, "auc")
        if paper_auc:
            ax_a.plot([], [], " ", label="paper: " + ", ".join(f"{k} {v}"
                                                                for k, v in paper_auc.items()))
        ax_a.set_xlabel("false positive rate [–]")
        ax_a.set_ylabel("true positive rate [–]")
        ax_a.set_title("(a) ROC, success classifiers (held-out)", loc="left")
        ax_a.legend(loc="lower right", fontsize=6.5)
        if not fit["roc"]:
            ax_a.text(0.5, 0.5, "not fitted: too few positives", ha="center",
                      transform=ax_a.transAxes)
        if fit["parity"] is not None:
            truth, pred = fit["parity"]
            r2 = next(r["r2"] for r in fit["regression"]
                      if r["model"] == "mlp" and r["target"] == "log10_residual_norm_n")
            ax_b.scatter(truth, pred, s=8, alpha=0.4, color=COLOURS["mlp"],
                         label=f"MLP, held-out: R² {r2:.2f}")
            lo, hi = float(min(truth.min(), pred.min())), float(max(truth.max(), pred.max()))
            ax_b.plot([lo, hi], [lo, hi], color="black", linewidth=1.0, label="parity")
            ax_b.axvline(math.log10(0.5), color="#333333", linestyle="--", linewidth=1.0,
                         label="τ_F = 0.5 N")
            ax_b.plot([], [], " ", label=f"paper: R² {paper.residual_r2} (vertical residual)")
        ax_b.set_xlabel("simulated log10 ‖R‖ [log10 N]")
        ax_b.set_ylabel("predicted log10 ‖R‖ [log10 N]")
        ax_b.set_title("(b) MLP regressor, force residual", loc="left")
        ax_b.legend(loc="upper left", fontsize=6.5)
        labels = ["PSO call" if i == 0 else ("MLP" if "mlp" in w else "random forest")
                  for i, w in enumerate(timing["what"])]
        colours = [COLOURS["pso"]] + [COLOURS["mlp"] if "mlp" in w else COLOURS["random_forest"]
                                      for w in timing["what"].iloc[1:]]
        ax_c.bar(labels, 1e3 * timing["time_s"], color=colours, label="ours")
        paper_ms = 1e3 * timing["paper_time_s"].astype(float)
        ax_c.plot(labels, paper_ms, linestyle="none", marker="D", color="black", label="paper")
        for i, v in enumerate(1e3 * timing["time_s"]):
            ax_c.annotate(f"{v:.3g} ms", (i, v), xytext=(0, 3), textcoords="offset points",
                          ha="center", fontsize=7)
        ax_c.set_yscale("log")
        ax_c.set_ylabel("wall time [ms]")
        ax_c.set_title("(c) one prediction vs a brief PSO call", loc="left")
        ax_c.legend(loc="upper right")
        report.figure("figA1_surrogate", fig,
                      "Fig. A.1 (ours): (a) ROC curves of the success classifiers (solid: "
                      "configured check, dashed: |R_z| reading); (b) parity of the MLP regressor "
                      "for log10 ‖R‖; (c) wall time of one prediction against a brief PSO call, "
                      "the paper's values as black diamonds")
