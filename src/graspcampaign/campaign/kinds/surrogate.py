"""``surrogate``: the simulator-generated grasp dataset of Appendix A (one trial = one scenario).

Each trial draws its scenario from its own random stream: a shape (uniform over
``params.shapes``), mass, friction, lambda1, lambda2 and nodal damping b uniform in their ranges
(the PSO bounds of Sec. 11 for lambda1, lambda2, b); the exponent n is the configured model's
(Table 3), since Appendix A does not sample it. The heuristic planner (Algorithm 1) chooses the
grasp on the 390-node mesh and the quasi-static evaluator judges it under the drawn parameters.
Each trial also times a brief PSO pre-screening call (about 25 evaluations, Appendix A) on its own
contact set: the cost the surrogate is meant to replace.

The models themselves (64-32 MLP, 100-tree random forest) are fitted, scored and timed by
:func:`finalize` once every scenario is recorded, and stored in ``summary/``; the report only
reads those tables. scikit-learn is needed for that, and the study refuses to run without it
(exit 2) so that no dataset is generated that could not be analysed.
"""

from __future__ import annotations

import socket
import time
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from graspcampaign.analysis.agreement import auc_interval
from graspcampaign.analysis.rates import wilson_interval
from graspcampaign.analysis.records import executed, flag
from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common
from graspcampaign.campaign.kinds.sensitivity import check_range, plan_and_evaluate
from graspcampaign.campaign.schema import NODES, config_field
from graspcampaign.core.plausible import PLAUSIBLE
from graspcampaign.errors import UserInputError

ML_MISSING = ("the surrogate study needs scikit-learn, which is not installed: install the `ml` "
              "extra (pip install 'graspcampaign[ml]') and run it again.")


def sklearn_available() -> bool:
    """Return whether scikit-learn can be imported."""
    try:
        import sklearn  # noqa: F401
    except ImportError:
        return False
    return True


@dataclass
class SurrogateParams:
    """Scenario distribution of Appendix A and the brief PSO call's budget."""

    nodes: int = config_field(common.DEFAULT_NODES, **NODES)
    planner: str = config_field("heuristic", choices="planner")
    shapes: list[str] = config_field(["sphere", "ellipsoid", "rounded_cube", "pear", "handle"])
    mass_range_kg: list[float] = config_field([0.1, 0.8], **PLAUSIBLE["mass_kg"].meta())  # Appendix A
    mu_range: list[float] = config_field([0.05, 0.6], **PLAUSIBLE["mu"].meta())  # Appendix A
    lambda1_range: list[float] = config_field([0.05, 1.5])  # Sec. 11 bounds
    lambda2_range: list[float] = config_field([0.05, 1.5])  # Sec. 11 bounds
    b_range: list[float] = config_field([0.1, 2.0])  # Sec. 11 bounds (internal units)
    pso_particles: int = config_field(5, ge=1)  # 5 x 5 = 25 evaluations
    pso_iterations: int = config_field(5, ge=1)
    test_fraction: float = config_field(0.2, gt=0.0, le=0.5)  # 80/20 split
    hidden_layers: list[int] = config_field([64, 32])  # Appendix A
    n_trees: int = config_field(100, ge=1)  # Appendix A

    def __post_init__(self) -> None:
        # Here, not in ``design``: params are validated by `run` before anything is written, but
        # not by `list`/`show`, which must keep working without the extra.
        if not sklearn_available():
            raise UserInputError(ML_MISSING)
        check_range("params.mass_range_kg", self.mass_range_kg, lower=1e-9)
        check_range("params.mu_range", self.mu_range)
        check_range("params.lambda1_range", self.lambda1_range, lower=1e-9)
        check_range("params.lambda2_range", self.lambda2_range, lower=1e-9)
        check_range("params.b_range", self.b_range)


def draw_scenario(params: SurrogateParams, rng: np.random.Generator) -> dict[str, Any]:
    """Draw one scenario of Appendix A from ``rng`` (the trial's stream)."""
    return {
        "shape": str(params.shapes[int(rng.integers(len(params.shapes)))]),
        "mass_kg": float(rng.uniform(*params.mass_range_kg)),
        "mu": float(rng.uniform(*params.mu_range)),
        "lambda1": float(rng.uniform(*params.lambda1_range)),
        "lambda2": float(rng.uniform(*params.lambda2_range)),
        "msd_b": float(rng.uniform(*params.b_range)),
    }


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Draw a scenario, plan and evaluate it, and time a brief PSO call on its contacts."""
    from graspcampaign.core.identify import identify_body

    study, params = inp.study, inp.params
    scenario = draw_scenario(params, rng)
    contact = common.contact_params(study, lambda1=scenario["lambda1"],
                                    lambda2=scenario["lambda2"])
    ctx, plan, out = plan_and_evaluate(study, scenario["shape"], params.nodes,
                                       scenario["mass_kg"], scenario["mu"], contact,
                                       params.planner, rng)
    start = time.perf_counter()
    pso = identify_body(plan.points, plan.normals, ctx.centroid, ctx.mass, ctx.mu, rng,
                        material=common.contact_params(study), evaluator=ctx.evaluator,
                        n_particles=params.pso_particles, n_iterations=params.pso_iterations)
    pso_time = time.perf_counter() - start
    out.update(scenario)
    out.update({
        "n_exp": contact.n, "nodes": params.nodes,
        "abs_residual_z_n": abs(out["residual_z_n"]),
        "pso_time_s": pso_time, "pso_n_evaluations": int(pso.pso.n_evaluations),
        "pso_best_cost": float(pso.best_cost), "pso_at_bound": ",".join(pso.at_bound),
    })
    return out


# -- the models (Appendix A), fitted once every scenario is recorded ------------------------------
NUMERIC = ["mass_kg", "mu", "lambda1", "lambda2", "msd_b"]
"""Appendix A's sampled inputs besides the shape (n is fixed, so it is not a feature)."""
MIN_POSITIVES = 10
"""Fewer positives (or negatives) than this and a classifier is not fitted: AUC would be noise."""
LOG_FLOOR = 1e-3  # floor before log10 of a residual [N] or a penetration [mm] that may be 0
LABELS = ("success", "success_unbounded", "success_vertical")
"""The configured check (with the validity gate), Algorithm 1 as published (no gate: the paper's
label) and the |R_z| reading (docs/records.md)."""
PAPER_LABEL = "success_unbounded"
"""Appendix A's "binary label": its one 80/20 split, stratified on it, also holds out the regressors'."""


def features(df: pd.DataFrame, shapes: list[str]) -> pd.DataFrame:
    """Return the model inputs: one 0/1 column per shape and the numeric scenario values."""
    out = df[NUMERIC].astype(float).copy()
    for shape in shapes:
        out[f"shape_{shape}"] = (df["shape"] == shape).astype(float)
    return out


def targets(df: pd.DataFrame) -> dict[str, np.ndarray]:
    """Regression targets: the paper's vertical residual, and log10 of ‖R‖ and δ_max."""
    def log(c):
        return np.log10(np.maximum(df[c].to_numpy(float), LOG_FLOOR))
    return {"abs_residual_z_n": df["abs_residual_z_n"].to_numpy(dtype=float),
            "log10_residual_norm_n": log("residual_norm_n"),
            "log10_delta_max_mm": log("delta_max_mm")}


def models(params: SurrogateParams, seed: int, regression: bool) -> dict[str, Any]:
    """The standardised 64-32 MLP and the 100-tree random forest of Appendix A."""
    from sklearn.ensemble import RandomForestClassifier, RandomForestRegressor
    from sklearn.neural_network import MLPClassifier, MLPRegressor
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler

    mlp = (MLPRegressor if regression else MLPClassifier)(
        hidden_layer_sizes=tuple(params.hidden_layers), max_iter=2000, random_state=seed)
    forest = (RandomForestRegressor if regression else RandomForestClassifier)(
        n_estimators=params.n_trees, random_state=seed, n_jobs=1)
    return {"mlp": make_pipeline(StandardScaler(), mlp),
            "random_forest": make_pipeline(StandardScaler(), forest)}


def prediction_time_s(model, row: np.ndarray, repeats: int = 200, budget_s: float = 0.5
                      ) -> tuple[float, int]:
    """Median wall time of one single-row prediction [s] over up to ``repeats`` calls (at
    least 5, then within ``budget_s``), and the number of calls timed."""
    predict = getattr(model, "predict_proba", model.predict)
    predict(row)  # warm-up
    times: list[float] = []
    stop = time.perf_counter() + budget_s
    while len(times) < repeats and (len(times) < 5 or time.perf_counter() < stop):
        start = time.perf_counter()
        predict(row)
        times.append(time.perf_counter() - start)
    return float(np.median(times)), len(times)


def _fit(model, x, y):
    """Return ``model`` fitted on ``(x, y)``."""
    from sklearn.exceptions import ConvergenceWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return model.fit(x, y)


def _fit_all(jobs: list[tuple[Any, np.ndarray, np.ndarray]], n_jobs: int) -> list[Any]:
    """Fit every ``(model, x, y)`` of ``jobs``, in ``n_jobs`` processes (joblib loky) when more
    than one; every model has its own ``random_state``, so the fits do not depend on that."""
    if n_jobs == 1 or len(jobs) < 2:
        return [_fit(*job) for job in jobs]
    from joblib import Parallel, delayed

    return Parallel(n_jobs=n_jobs)(delayed(_fit)(*job) for job in jobs)


def finalize(study, params: SurrogateParams, records: pd.DataFrame, store=None
             ) -> dict[str, list[dict[str, Any]]]:
    """Fit, score and time Appendix A's surrogates on the run's executed scenarios.

    Features: the shape one-hot and m, μ, λ1, λ2, b (standardised in the pipeline). A label's
    examples are the trials with it recorded (``trials``; one an older file lacks is left out). For
    each label of :data:`LABELS` with at least :data:`MIN_POSITIVES` of either class, its own
    ``1 - test_fraction`` / ``test_fraction`` split stratified on that label (``random_state`` =
    study seed) trains both classifiers; the held-out trials give ROC AUC (with its
    :func:`~graspcampaign.analysis.agreement.auc_interval`, seed = study seed, or the reason it has
    none), accuracy (with its Wilson 95 % interval), the majority-class accuracy and the ROC curve.
    Both regressors predict |R_z|, log10 ‖R‖ and log10 δ_max on Appendix A's one split, the
    :data:`PAPER_LABEL`'s (an unstratified split of every executed trial, same seed, when that label
    is not fitted), R² held out. Every row records its split (``split_label``: the label it is
    stratified on, "" for none; ``split_seed``). One single-row prediction of the first fitted
    label's classifiers (else of the |R_z| regressors) is timed here, beside the median of the brief
    PSO calls timed in the trials.

    Returns
    -------
    dict
        ``surrogate_classification``, ``surrogate_regression``, ``surrogate_importance``
        (random-forest impurity importances), ``surrogate_roc`` (curve points),
        ``surrogate_scores`` (each held-out trial's label and predicted probability, which the
        AUC and its interval are computed from),
        ``surrogate_parity`` (the MLP's held-out log10 ‖R‖ against the simulated one) and
        ``surrogate_timing`` (the PSO call, then one prediction per model), stored in
        ``summary/<name>/``.
    """
    import sklearn
    from sklearn.metrics import r2_score, roc_auc_score, roc_curve
    from sklearn.model_selection import train_test_split

    ok, seed = executed(records), int(study.seed)
    frame = features(ok, list(params.shapes))
    x = frame.to_numpy()  # plain arrays: what a deployed surrogate would be fed
    out: dict[str, list[dict[str, Any]]] = {k: [] for k in (
        "surrogate_classification", "surrogate_regression", "surrogate_importance",
        "surrogate_roc", "surrogate_scores", "surrogate_parity", "surrogate_timing")}
    # the splits first, then every model fitted at once (over the run's cores), then scored
    splits, timed = {}, {}
    # a trial without the label (null where an older file of the run lacks it) is no example: each
    # label's split, fit and scores are over the trials that have it (positions in ``ok``)
    labelled = {label: np.flatnonzero(ok[label].notna().to_numpy()) for label in LABELS}
    flags = {label: flag(ok, label).to_numpy() for label in LABELS}  # read at ``labelled`` alone
    for label, rows in labelled.items():
        y = flags[label][rows]
        if min(y.sum(), len(y) - y.sum()) >= MIN_POSITIVES:
            splits[label] = train_test_split(rows, test_size=params.test_fraction,
                                             stratify=y, random_state=seed)
    # the regressors' split: Appendix A's one split, stratified on its binary label
    on = PAPER_LABEL if PAPER_LABEL in splits else ""
    regression_split = splits[on] if on else train_test_split(
        np.arange(len(ok)), test_size=params.test_fraction, random_state=seed)
    held = {"split_seed": seed}
    jobs = [(model, x[fit_on], flags[label][fit_on])
            for label, (fit_on, _) in splits.items()
            for model in models(params, seed, regression=False).values()]
    jobs += [(model, x[regression_split[0]], values[regression_split[0]])
             for values in targets(ok).values()
             for model in models(params, seed, regression=True).values()]
    fitted = iter(_fit_all(jobs, study.runner.workers()))
    for label in LABELS:
        y = flags[label]
        known = y[labelled[label]]
        base = {"label": label, "positives": int(known.sum()), "trials": len(known),
                "class_balance_pct": 100 * float(known.mean()) if len(known) else np.nan}
        if label not in splits:
            out["surrogate_classification"].append({**base, "note": (
                f"not fitted: fewer than {MIN_POSITIVES} trials of one class")})
            continue
        test = splits[label][1]
        first = not timed
        for name in models(params, seed, regression=False):
            model = next(fitted)
            if first:
                timed[name] = (model, f"{label} probability")
            score = model.predict_proba(x[test])[:, 1]
            fpr, tpr, _ = roc_curve(y[test], score)
            out["surrogate_roc"] += [{"label": label, "model": name, "fpr": float(a),
                                      "tpr": float(b)} for a, b in zip(fpr, tpr, strict=True)]
            out["surrogate_scores"] += [{"label": label, "model": name, "positive": bool(a),
                                         "score": float(b)} for a, b in zip(y[test], score, strict=True)]
            hits = int(np.sum(model.predict(x[test]) == y[test]))
            w, ci = wilson_interval(hits, len(test)), auc_interval(score[y[test]], score[~y[test]], seed=seed)
            out["surrogate_classification"].append({
                **base, "model": name, "test_trials": len(test),
                "test_positives": int(y[test].sum()), "split_label": label, **held,
                "roc_auc": float(roc_auc_score(y[test], score)),
                "roc_auc_low": ci.low, "roc_auc_high": ci.high, "roc_auc_interval": ci.method,
                "roc_auc_resamples": ci.n_resamples, "roc_auc_interval_note": ci.reason,
                "accuracy_pct": 100 * w.estimate,
                "accuracy_low_pct": 100 * w.low, "accuracy_high_pct": 100 * w.high,
                "majority_class_accuracy_pct": 100 * max(y[test].mean(), 1 - y[test].mean()),
                "note": ""})
            if name == "random_forest" and not out["surrogate_importance"]:
                out["surrogate_importance"] = [
                    {"label": label, "feature": f, "importance": float(v)} for f, v in sorted(
                        zip(frame.columns, model[-1].feature_importances_, strict=True),
                        key=lambda fv: -fv[1])]
    train, test = regression_split
    fallback = not timed  # no classifier fitted: time the regressors of the paper's target
    for target, values in targets(ok).items():
        for name in models(params, seed, regression=True):
            model = next(fitted)
            predicted = model.predict(x[test])
            # R² divides by the held-out variance: undefined when the target is constant to
            # round-off (|R_z| of force-closed grasps is 0 up to 1e-15 N)
            flat = np.ptp(values[test]) <= 1e-9 * max(1.0, float(np.abs(values).max()))
            out["surrogate_regression"].append({
                "target": target, "model": name, "test_trials": len(test), "split_label": on, **held,
                "r2": np.nan if flat else float(r2_score(values[test], predicted)),
                "note": "held-out target constant to round-off: R² undefined" if flat else ""})
            if name == "mlp" and target == "log10_residual_norm_n":
                out["surrogate_parity"] = [{"target": target, "model": name, "simulated": float(
                    a), "predicted": float(b)} for a, b in zip(values[test], predicted,
                                                               strict=True)]
            if fallback and target == "abs_residual_z_n":
                timed[name] = (model, target)
    host = socket.gethostname()
    out["surrogate_timing"] = [{
        "what": "pso_call", "predicts": "", "time_s": float(ok["pso_time_s"].median()),
        "n_timed": len(ok), "evaluations": int(ok["pso_n_evaluations"].median()),
        "host": host, "sklearn_version": sklearn.__version__}]
    for name, (model, predicts) in timed.items():
        t, n = prediction_time_s(model, x[:1])
        out["surrogate_timing"].append({"what": name, "predicts": predicts, "time_s": t,
                                        "n_timed": n, "evaluations": 0, "host": host,
                                        "sklearn_version": sklearn.__version__})
    return out


SURROGATE = TrialKind(
    name="surrogate",
    run=run,
    params=SurrogateParams,
    seconds_per_trial=0.03,
    finalize=finalize,
    description="Appendix A dataset: sampled scenarios through the evaluator (+ a brief PSO call)",
    stages="the fits of Appendix A's surrogates after the trials",
    optional_factors=(),  # it samples its scenarios from params, reading no factor
)
