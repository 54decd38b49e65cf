"""Report of ``surrogate`` (Appendix A, Fig. A.1): the scenarios, and the models the run's finalize stage
fitted, scored and timed (``summary/surrogate_*``); nothing is fitted or timed here (a run finalized
before finalize computed the AUC interval gets it from its stored held-out scores)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from graspcampaign.analysis.agreement import AUC_INTERVAL_MIN_CLASS, auc_interval
from graspcampaign.analysis.rates import BOOTSTRAP_RESAMPLES
from graspcampaign.analysis.records import beyond_radius, flag
from graspcampaign.analysis.vocabulary import colour, label, ordered
from graspcampaign.report import format as fmt
from graspcampaign.report import style
from graspcampaign.report.document import Col, cols, pct_col
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Figure, Finding, ReportSpec, Table, rate_cols, verdicts

LABELS = ("success", "success_unbounded", "success_vertical")


def name(key: str) -> str:
    """The readable name of a label, target or feature (``shape_<s>``: the shape's label)."""
    return f"shape: {label('shape', key[6:])}" if key.startswith("shape_") else label("variable", key)


PAPER_LABEL = "success_unbounded"  # Algorithm 1 as published, no validity gate: the paper's label
WHY = ("`docs/decisions.md`, *Contact law, evaluator, planners, PSO* and *Physical validity, grip laws, "
       "Ferrari–Canny ε*")


def _read(run: Run, name: str, *need: str) -> pd.DataFrame:
    """The run's finalize table ``summary/surrogate_<name>`` with the ``need`` columns (absent: the sentence
    of :meth:`~graspcampaign.report.render.Run.stored`, or empty when ``need`` names no column)."""
    t = run.stored(f"summary/surrogate_{name}") if need else run.part(f"summary/surrogate_{name}")
    t = t.assign(**{c: t.get(c) for c in need})
    key = t.get("model", t.get("what"))
    return t if key is None else t.assign(model_label=[label("model", m) if isinstance(m, str) else "—"
                                                       for m in key])


def _dataset(run: Run) -> pd.DataFrame:
    rows = []
    for group in ["all", *ordered("shape", run.ok["shape"])]:
        g = run.ok if group == "all" else run.ok[run.ok["shape"] == group]
        won = flag(g, "success_unbounded")
        deep = beyond_radius(g, run.radius_mm)
        rows.append({"group_label": label("shape", group), "n": len(g),
                     "paper_pct": run.paper.class_balance_pct if group == "all" else None,
                     # the opening's why: the residual check alone, the published algorithm's successes
                     # (counted, not recovered from the rounded rate) and the non-physical depths
                     "n_unbounded_successes": int(won.sum()),
                     "n_residual_ok": int(flag(g, "residual_ok").sum()), "n_deeper": int(deep.sum()),
                     "n_success_unbounded_deeper": int((deep & won).sum()),
                     **{k: v for o in LABELS for k, v in rate_cols(g, o, o).items()}})
    return verdicts(pd.DataFrame(rows), "success_unbounded_pct", "paper_pct", "success_unbounded_low_pct",
                    "success_unbounded_high_pct", unit="%")


def _auc_intervals(run: Run, t: pd.DataFrame) -> pd.DataFrame:
    """The AUC intervals: the run's; for a run finalized before finalize computed them (no
    ``roc_auc_interval_note``), computed here from its stored held-out scores by the run's rule."""
    scores = run.part("summary/surrogate_scores")
    t = t.assign(interval_from_stored_scores=False)
    if t["roc_auc_interval_note"].notna().any() or not len(scores):
        return t
    for i, r in t[t["roc_auc"].notna()].iterrows():
        g = scores[(scores["label"] == r["label"]) & (scores["model"] == r["model"])]
        ci = auc_interval(g.loc[g["positive"], "score"], g.loc[~g["positive"], "score"], seed=run.seed)
        t.loc[i, ["roc_auc_low", "roc_auc_high", "roc_auc_interval_note"]] = ci.low, ci.high, ci.reason
        t.loc[i, "interval_from_stored_scores"] = pd.isna(r["roc_auc_low"]) and not ci.reason
    return t


def _classification(run: Run) -> pd.DataFrame:
    t, p = _read(run, "classification", "model", "roc_auc", "roc_auc_low", "roc_auc_high", "accuracy_pct",
                 "accuracy_low_pct", "test_trials", "test_positives", "majority_class_accuracy_pct",
                 "accuracy_high_pct", "roc_auc_interval_note"), run.paper
    t = _auc_intervals(run, t)
    main = t["label"] == PAPER_LABEL
    t["paper_auc"] = [p.auc.get(m) if ok else None for m, ok in zip(t["model"], main, strict=True)]
    t["paper_accuracy"] = [p.accuracy_pct if ok else None for ok in main]  # a range: (low, high)
    for i, end in enumerate(("low", "high")):
        t[f"paper_accuracy_{end}_pct"] = [r[i] if r else None for r in t["paper_accuracy"]]
    t["fit"] = ["not fitted" if isinstance(n, str) and n else "" for n in t["note"]]  # its reason: AUC cell
    acc = verdicts(t.copy(), "accuracy_pct", "paper_accuracy", "accuracy_low_pct", "accuracy_high_pct",
                   unit="%", why="fit")
    t["too_few"] = [f"not compared: {n}" if isinstance(n, str) and n else ""
                    for n in t["roc_auc_interval_note"]]
    return verdicts(t, "roc_auc", "paper_auc", "roc_auc_low", "roc_auc_high", digits=2, why="fit",
                    because="too_few").assign(
        accuracy_verdict=acc["verdict"], label_name=t["label"].map(name)).drop(
        columns=["paper_accuracy", "fit", "too_few"])


def _regression(run: Run) -> pd.DataFrame:
    t = _read(run, "regression", "r2")
    t["paper_r2"] = [run.paper.residual_r2 if (g, m) == ("abs_residual_z_n", "mlp") else None
                     for g, m in zip(t["target"], t["model"], strict=True)]
    return verdicts(t, "r2", "paper_r2", digits=2, why="note").assign(target_name=t["target"].map(name))


def _regression_caption(run: Run) -> str:
    """The regressors' caption: the split that held their scenarios out, as the run recorded it."""
    t = run.part("summary/surrogate_regression")
    on = t["split_label"].iloc[0] if "split_label" in t and len(t) else None
    split = ("split not recorded: a run finalized before it was" if on is None else
             f"Appendix A's one split, stratified on {name(on)}, seed "
             f"{fmt.number(int(t['split_seed'].iloc[0]))}" if on
             else f"an unstratified split, seed {fmt.number(int(t['split_seed'].iloc[0]))}: "
                  f"{name(PAPER_LABEL)} was not fitted")
    return (f"Regression R² on the held-out scenarios ({split}; the paper's is the MLP on the vertical "
            "residual |R_z|)")


def _importance(run: Run) -> pd.DataFrame:
    t = _read(run, "importance")
    return t.assign(label_name=t["label"].map(name), feature_name=t["feature"].map(name)) if len(t) else t


def _predicts(stored):
    """What a timed model predicts, in words: a label's probability, or a regression target (the
    run falls back to one when no classifier was fitted)."""
    if not isinstance(stored, str) or not stored:
        return stored
    return f"P(success), {name(stored.split()[0])}" if stored.endswith(" probability") else name(stored)


def _timing(run: Run) -> pd.DataFrame:
    t, p = _read(run, "timing", "time_s"), run.paper
    t["paper_time_s"] = t["what"].map({"pso_call": p.pso_call_time_s, "mlp": p.prediction_time_ms * 1e-3})
    # the paper's times in its own units and digits (App. A: "0.06 ms, versus 0.99 s"); ours with the
    # prefix that fits each (fmt.scaled: 1.64 ms, 185 µs; in µs alone the 0.99 s printed 990000)
    said = {"pso_call": f"{fmt.number(p.pso_call_time_s)} s", "mlp": f"{fmt.number(p.prediction_time_ms)} ms"}
    t = t.assign(time_ms=1e3 * t["time_s"], time_us=1e6 * t["time_s"], paper_time_us=1e6 * t["paper_time_s"],
                 predicts=t["predicts"].map(_predicts), time=[fmt.scaled(v, "s") for v in t["time_s"]],
                 paper_time=t["what"].map(said))
    pso = t["what"] == "pso_call"  # the ratios' reference: its ratio to itself is no result
    t["speedup"] = (float(t.loc[pso, "time_s"].iloc[0]) / t["time_s"]).where(~pso)
    t["paper_speedup"] = t["what"].map({"mlp": p.speedup})
    t["why"] = pso.map({True: "the reference of the PSO/this ratios, not compared", False: ""})
    return verdicts(t, "speedup", "paper_speedup", digits=0, ratio="faster")


def finding(run: Run) -> str:
    d, p, t = run.tables["surrogate_dataset"].iloc[0], run.paper, run.tables  # d: the "all" row
    n, labelled = int(d["n"]), int(d["n_success_unbounded"])  # the rate's own n: the trials labelled
    of = ("", "") if labelled == n else (f", {labelled} with Algorithm 1's label recorded ({n - labelled} "
                                         "without: no training example)", f"of those {labelled} ")
    text = (f"{n} scenarios (paper {p.n_scenarios}){of[0]}: {fmt.number(d['success_unbounded_pct'], 1)}% "
            f"{of[1]}succeed under Algorithm 1 as published (paper {fmt.number(p.class_balance_pct, 1)}%; "
            "table surrogate_dataset)")
    cls = t["surrogate_classification"].query(f"label == '{PAPER_LABEL}'")
    fit = cls[cls["roc_auc"].notna()]
    held = [f"on {fmt.number(r['test_trials'], 0)} held out ({fmt.number(r['test_positives'], 0)} positive, "
            f"{fmt.number(r['test_trials'] - r['test_positives'], 0)} negative"
            f"{'; ' + note if isinstance(note := r['roc_auc_interval_note'], str) and note else ''})"
            for _, r in fit.iterrows()]
    one = len(held) > 1 and len(set(held)) == 1  # the same held-out set and note for each model: said once
    aucs = fmt.listed([  # as the table prints them, with the held-out classes and why no interval
        f"{r['model_label']} {fmt.estimate(r['roc_auc'], r['roc_auc_low'], r['roc_auc_high'], 2)}"
        f"{'' if one else ' ' + h}" for (_, r), h in zip(fit.iterrows(), held, strict=True)])
    papers = fmt.listed([fmt.number(v, 2) for v in fit["paper_auc"]])
    text += (f"; classifier AUC {aucs} (paper {papers}{f') {held[0]} (' if one else '; '}table "
             "surrogate_classification). " if len(fit)
             else f"; the success classifiers were {cls['note'].iloc[0]}. ")
    if len(reg := t["surrogate_regression"].dropna(subset=["r2"])):
        best = reg.loc[reg["r2"].idxmax()]
        text += (f"The best regression R² is {fmt.number(best['r2'], 2)} ({name(best['target'])}, "
                 f"{best['model_label']}; paper {fmt.number(p.residual_r2, 2)} for |R_z|)" + (
                     ", worse than predicting the held-out mean. " if best["r2"] < 0 else ". "))
    if "mlp" in (tm := t["surrogate_timing"].set_index("what")).index:
        # each call's time beside its own paper time, as table surrogate_timing prints them
        us = [f"{tm.loc[w, 'time']}; paper {tm.loc[w, 'paper_time']}" for w in ("mlp", "pso_call")]
        text += (f"An MLP prediction ({us[0]}) is {fmt.number(tm.loc['mlp', 'speedup'], sig=3)}× faster "
                 f"than the brief PSO call ({us[1]}); the paper's is "
                 f"{fmt.number(tm.loc['mlp', 'paper_speedup'], 0)}× (table surrogate_timing). ")
    check = "|R_z|" if (run.config.get("evaluator") or {}).get("residual_check") == "vertical" else "‖R‖"
    # the why's counts as table surrogate_dataset prints them (the residual check alone; missing: not)
    passed, deep, deep_won, won = (int(d[c]) for c in (
        "n_residual_ok", "n_deeper", "n_success_unbounded_deeper", "n_unbounded_successes"))
    if passed == n and not deep:  # nothing non-physical, every scenario passes: no why
        return text
    of_won = f"; {deep_won} of the {won} published-algorithm successes" if won else ""
    return text + (f"Why: in SI, Algorithm 2 as published passes the {check} check in {passed or 'none'} of "
                   f"{n} and buries a fingertip deeper than its radius r = {fmt.number(run.radius_mm)} mm in "
                   f"{deep} (non-physical{of_won}; {WHY}).")


def _classification_caption(run: Run) -> str:
    """The classifiers' caption: the split, and who computed the AUC interval (if anyone could)."""
    t = run.part("summary/surrogate_classification")
    stored = "roc_auc_interval_note" in t or ("roc_auc_low" in t and t["roc_auc_low"].notna().any())
    scores = len(run.part("summary/surrogate_scores"))
    by = ("computed by the run" if stored else
          "computed by this report from the held-out scores the run stored" if scores else "")
    fitted = "roc_auc" in t and t["roc_auc"].notna().any()
    point = ", so its verdicts are judged on the point value" if fitted else ""
    interval = (f"its 95% percentile interval ({BOOTSTRAP_RESAMPLES} resamples of the held-out positives "
                f"and, apart, negatives, {by}; none, and no verdict, below {AUC_INTERVAL_MIN_CLASS} "
                "of either)"
                if by else f"no interval (the run stored none){point}")
    held_out = 100 * run.params.get("test_fraction", 0.2)
    return (f"Success classifiers scored by the run on its held-out {fmt.number(held_out)}% (each label's "
            f"own split, stratified on it, seed {run.seed}); AUC with {interval}, accuracy with its Wilson "
            "95% interval")


NOISE = ("lambda2", "msd_b")  # inputs a quasi-static outcome does not depend on


def _importance_caption(run: Run) -> str:
    """The importances' caption: which inputs the forest ranks above the larger noise input's share."""
    t = _read(run, "importance")
    text = ("Random-forest impurity importances of the first fitted classifier (λ2 and b cannot affect a "
            "quasi-static outcome: their share is what a forest gives to noise")
    if not len(t):
        return text + ")"
    noise = t.loc[t["feature"].isin(NOISE), "importance"].max()
    above = [name(f) for f in t.loc[t["importance"] > noise, "feature"]]
    noise = fmt.number(noise, fmt.decimals(t["importance"]))  # as the importance table prints it
    return text + f"; above the larger of the two ({noise}): {fmt.listed(above, 'no input')})"


LINES = dict(zip(LABELS, ("-", "--", ":"), strict=True))


def _caption(run: Run) -> str:
    """Fig. A.1's caption: the curves drawn in (a), by line style, and the labels not fitted."""
    cls = run.tables.get("surrogate_classification", pd.DataFrame(columns=["label", "roc_auc"]))
    fitted = [lab for lab in LABELS if cls.loc[cls["label"] == lab, "roc_auc"].notna().any()]
    words = {"-": "solid", "--": "dashed", ":": "dotted"}
    won = flag(run.ok, "success_unbounded")
    buried = int((won & beyond_radius(run.ok, run.radius_mm)).sum())
    return ("Fig. A.1 (ours): (a) ROC curves of the fitted classifiers (" + (", ".join(
        f"{words[LINES[lab]]}: {name(lab)}" for lab in fitted) or "none fitted") + (
        "; not fitted, fewer than 10 trials of one class: " + ", ".join(
            name(lab) for lab in LABELS if lab not in fitted) if len(fitted) < len(LABELS) else "") +
        ")" + (f", whose {buried} of {int(won.sum())} positives of Algorithm 1 as published have a "
               "contact deeper than the fingertip radius (non-physical)" if PAPER_LABEL in fitted and buried
               else "") +
        "; (b) parity of the MLP regressor for log10 ‖R‖; (c) one prediction against a brief PSO call "
        "(the paper's values in black)")


def figA1(run: Run, fig) -> None:
    ax_a, ax_b, ax_c = fig.subplots(1, 3)
    roc, cls = _read(run, "roc"), run.tables["surrogate_classification"].set_index(["label", "model"])
    for (lab, m), g in roc.groupby(["label", "model"], sort=False) if len(roc) else ():
        ax_a.plot(g["fpr"], g["tpr"], color=colour("model", m), ls=LINES[lab],
                  label=f"{label('model', m)}, {name(lab)}: AUC {fmt.number(cls.loc[(lab, m), 'roc_auc'], 2)}"
                        f" ({int(cls.loc[(lab, m), 'test_positives'])} held-out positives)")
    if not len(roc):
        # in the corner, clear of the chance line
        ax_a.text(0.05, 0.95, "not fitted:\ntoo few trials of one class", va="top", transform=ax_a.transAxes)
    ax_a.plot([0, 1], [0, 1], color=style.CRITERION, ls=":", label="chance")
    ax_a.plot([], [], " ", label="paper AUC: " + ", ".join(f"{label('model', m)} {fmt.number(v)}" for m, v in
                                                          run.paper.auc.items()))
    ax_a.set(xlabel="false positive rate [–]", ylabel="true positive rate [–]",
             title="(a) ROC, success classifiers (held out)")
    ax_a.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2))
    par, r2 = _read(run, "parity"), run.tables["surrogate_regression"].set_index(["target", "model"])
    if len(par):
        fit = fmt.number(r2.loc[("log10_residual_norm_n", "mlp"), "r2"], 2)
        ax_b.scatter(par["simulated"], par["predicted"], s=8, alpha=0.5, color=colour("model", "mlp"),
                     label=f"MLP, held out: R² {fit}")
        lim = [par[["simulated", "predicted"]].min().min(), par[["simulated", "predicted"]].max().max()]
        ax_b.plot(lim, lim, color="black", lw=1.0, label="parity")
        tau = float(run.config["evaluator"]["tau_f_n"])
        ax_b.axvline(math.log10(tau), color=style.CRITERION, ls="--", lw=1.0,
                     label=f"τ_F = {fmt.number(tau)} N")
    ax_b.plot([], [], " ", label=f"paper: R² {fmt.number(run.paper.residual_r2)} (|R_z|)")
    ax_b.set(xlabel="simulated log10 ‖R‖ [log10 N]", ylabel="predicted log10 ‖R‖ [log10 N]",
             title="(b) MLP regressor, force residual")
    ax_b.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2)  # clear of τ_F
    t = run.tables["surrogate_timing"]
    x, ms = np.arange(len(t)), 1e3 * t["time_s"].to_numpy(float)
    ax_c.bar(x, ms, color=[colour("model", w) for w in t["what"]])
    style.paper_marks(ax_c, x, list(1e3 * t["paper_time_s"]), 0.8)
    for xi, v in zip(x, ms, strict=True):
        ax_c.annotate(f"{fmt.number(v, sig=3)} ms", (xi, v), xytext=(0, 3), textcoords="offset points",
                      ha="center", fontsize=7)
    ax_c.set_xticks(x, t["model_label"])
    ax_c.set(yscale="log", ylabel="wall time of one call [ms]",
             title="(c) one prediction vs a brief PSO call")
    ax_c.legend(handles=[style.paper_handle()], loc="upper right")


SPEC = ReportSpec("surrogate", [
    Finding(finding),
    Table("surrogate_dataset", "Class balance of the scenarios (Wilson 95%): Algorithm 1 as published "
          "(the paper's label) beside the paper's positives; the configured check (a contact deeper than "
          "the fingertip radius is invalid) and the |R_z| reading", _dataset,
          [Col("group_label", "group"), Col("n", "scenarios"), Col("paper_pct", "paper %", 1),
           *(pct_col(o, name(o)) for o in LABELS), *(Col(f"n_{o}", f"n ({name(o)})") for o in LABELS[1:]),
           Col("n_unbounded_successes", "Algorithm 1 successes"),
           Col("n_residual_ok", "residual check passed"), Col("n_deeper", "contact deeper than r"),
           Col("n_success_unbounded_deeper", "of them Algorithm 1 successes"),
           Col("difference", "difference [pp]", 1, signed=True), Col("verdict", "verdict")]),
    Table("surrogate_classification", _classification_caption, _classification, [
              Col("label_name", "label"), Col("model_label", "model"), Col("positives", "positives"),
              Col("trials", "trials"), Col("test_trials", "held out"),
              Col("test_positives", "held-out positives"), Col("paper_auc", "paper AUC", 2),
              Col("roc_auc", "AUC (95%)", 2, low="roc_auc_low", high="roc_auc_high", why="note"),
              Col("verdict", "AUC verdict"),
              Col("paper_accuracy_low_pct", "paper accuracy %", 1, low="paper_accuracy_low_pct",
                  high="paper_accuracy_high_pct"),
              pct_col("accuracy", "accuracy"),
              Col("majority_class_accuracy_pct", "majority class %", 1), Col("accuracy_verdict", "verdict")]),
    Table("surrogate_regression", _regression_caption, _regression, [
              Col("target_name", "target"), Col("model_label", "model"), *cols("test_trials"),
              Col("paper_r2", "paper R²", 2), Col("r2", "R²", 2, why="note"), *cols("verdict")]),
    Table("surrogate_feature_importance", _importance_caption, _importance,
          [Col("label_name", "label"), Col("feature_name", "feature"),
           Col("importance", "importance", sig=3)],
          empty="no classifier was fitted (too few trials of one class)"),
    Table("surrogate_timing", "Wall time of one call, measured by the run: the brief PSO call (median over "
          "the trials; each swarm iteration is one vectorised evaluator call) and one single-row prediction "
          "per model (median of up to 200)", _timing, [
              Col("model_label", "call"), *cols("predicts"), Col("paper_time", "paper time"),
              Col("time", "time (ours)"), *cols("n_timed"),
              Col("paper_speedup", "paper PSO/this [×]", 0),
              Col("speedup", "ours PSO/this [×]", fmt.EACH, sig=3),  # each ratio as the finding says it
              *cols("verdict", "host", "sklearn_version")]),
    Figure("figA1_surrogate", _caption, figA1, (10.5, 4.0)),
])
