"""What a quasi-static report says of what a run lacks: a candidate table it did not store or lost, an
identification without a bound reading, a trial without every reading (tests split from
test_quasi_static_report.py, which passed 500 lines)."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from synthetic_runs import (
    PLANNERS,
    SHAPES,
    candidates,
    caption,
    make_run,
    md_table,
    ok_records,
    quasi_static_outputs,
    read_table,
    report_md,
)

from graspcampaign.analysis.vocabulary import label
from graspcampaign.report.build import build_reports

G, TAU_F = 9.81, 0.5  # core.statics.GRAVITY; τ_F of conf/evaluator/default.yaml
PAPER = {"heuristic": 67.6, "antipodal": 40.0, "random": 11.0, "centroid": 0.0}  # baseline_grid.yaml


@pytest.mark.parametrize(("params", "why"), [
    ({"candidate_sample": 0}, "this run stored no candidate table (params.candidate_sample=0 keeps none)"),
    ({}, "this run's candidate table (tables/candidates), which its ferrari_canny trials store, is missing; "
         "its records were stored before runs kept account of their tables, so `graspcampaign run` cannot "
         "redo it: restore it from a backup, or record a new run")])
def test_a_run_without_candidates_says_why_and_keeps_the_per_trial_rows(tmp_path, params, why):
    """A run that stored no candidate table (params.candidate_sample=0) or lost it (an older run, stored
    before runs kept account of their tables: the synthetic writer keeps none) said in its h_epsilon
    items "the records have no `trial_id` column" and, in the figure's, "UndefinedVariableError: name
    'trial_id' is not defined" (counted as an item whose code failed). The per-trial medians come from
    the records and stay; the pooled row and the figure say why they are absent, with no path."""
    root = tmp_path / "results"
    factors = {"shape": SHAPES[:2], "mass_kg": [0.2], "mu": [0.3], "planner": PLANNERS}
    store = make_run(root, "baseline_grid", "quasi_static", factors, seeds=3, paper=None,
                     outputs=quasi_static_outputs, params=params)
    batch = build_reports(["baseline_grid"], root=root)
    assert batch.broken[batch[0]][1] == []  # the data's reason, no failing code
    table = read_table(store, "h_epsilon").set_index("reading")
    fc = ok_records(store).query("planner == 'ferrari_canny'")
    assert list(table.index) == ["median per trial", "median per trial, force closure"]  # no pooled row
    assert table.loc["median per trial", "rho"] == pytest.approx(fc["spearman_h_epsilon"].median())
    assert table.loc["median per trial, force closure", "n_trials"] == len(fc)
    assert caption(store, "h_epsilon").endswith(f"; no pooled row: {why}** (`tables/h_epsilon.csv`)")
    text = report_md(store)
    assert f"*Figure h_epsilon not computed: {why}.*" in text
    assert "trial_id" not in text and str(tmp_path) not in text


def test_an_identification_without_a_bound_reading_is_not_counted_on_the_bound():
    """``astype(bool)`` read a missing ``at_bound_lambda1`` (NaN) as on the bound: 2 of 3 for the one
    recorded (``records.at_bound``, the pso report's rule, reads it as not on it)."""
    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.quasi_static import _bounds

    run = Run(pd.DataFrame(), {}, None)
    run.memo("prepared", lambda: pd.DataFrame({"lambda1": [0.05, 0.05, 1.0],
                                               "at_bound_lambda1": [True, np.nan, False]}))
    assert _bounds(run) == f"; on a PSO search bound: {label('parameter', 'lambda1')} = 0.05 in 1 of 3."


def test_the_readings_table_says_how_many_trials_a_missing_reading_left_out(tmp_path):
    """n of the readings table is the trials with every reading recorded; the executed trials without
    one (here the random planner's every other trial, no ``success_vertical``, as a file written before
    the column existed) were left out unsaid. They are now a column, shown only where some are."""
    state = {"k": 0}

    def outputs(factors, rng):
        out = quasi_static_outputs(factors, rng)
        if factors["planner"] == "random":
            state["k"] += 1
            out["success_vertical"] = out["success_vertical"] if state["k"] % 2 else None
        return out

    store = make_run(tmp_path / "results", "baseline_grid", "quasi_static", {
        "shape": SHAPES[:2], "mass_kg": [0.2], "mu": [0.3], "planner": PLANNERS}, seeds=3, paper=None,
        outputs=outputs, tables=candidates)
    build_reports(["baseline_grid"], root=tmp_path / "results")
    ok = ok_records(store)
    unread = ok["success_vertical"].isna().groupby(ok["planner"]).sum()
    assert unread["random"] == 3 and unread.drop("random").eq(0).all()
    shown = md_table(report_md(store), "readings").set_index("planner")
    assert list(shown.columns[:3]) == ["n", "a reading missing (left out)", "success % (Wilson 95%)"]
    named = unread.rename(lambda p: label("planner", p))  # the table's rows are the planners' labels
    assert shown["a reading missing (left out)"].astype(int).to_dict() == named.to_dict()
    assert shown["n"].astype(int).to_dict() == (ok.groupby("planner").size() - unread).rename(
        lambda p: label("planner", p)).to_dict()
    assert read_table(store, "readings").set_index("planner")["n_unread"].to_dict() == unread.to_dict()


def test_the_mechanism_table_and_the_grid_opening_leave_a_trial_without_a_reading_out(tmp_path):
    """A paper-law trial without ``rho`` counted as not passable (ρ·W < τ_F compares False) yet stayed in
    n: the proposed planner, its every trial with ρ·W ≥ τ_F unread here, looked capped below its paper
    rate (67.6%) by the ρ of trials that have none. Each count now leaves out the trials without its
    reading (ρ; every other random trial's ``n_released``; the centroid planner's ``support_share_max``, of
    failures only: no pass of one fingertip is left out), says how many in a column after it where any
    is, and the opening's released share and caps count the trials read."""
    state = {"k": 0}

    def outputs(factors, rng):
        out = quasi_static_outputs(factors, rng)
        if factors["planner"] == "heuristic" and out["rho"] * factors["mass_kg"] * G >= TAU_F:
            out["rho"] = None
        if factors["planner"] == "random":
            state["k"] += 1
            out["n_released"] = out["n_released"] if state["k"] % 2 else None
        if factors["planner"] == "centroid":
            out["support_share_max"] = None
        return out

    store = make_run(tmp_path / "results", "baseline_grid", "quasi_static", {
        "shape": SHAPES, "mass_kg": [0.2], "mu": [0.3], "planner": PLANNERS}, seeds=2, paper=None,
        outputs=outputs, tables=candidates)
    assert store.check()["config"]["evaluator"]["tau_f_n"] == TAU_F
    build_reports(["baseline_grid"], root=tmp_path / "results")
    ok = ok_records(store)
    by = ok["planner"]
    passable = (ok["rho"] * ok["mass_kg"] * G < TAU_F).groupby(by).sum()
    read = ok["rho"].notna().groupby(by).sum()
    assert 0 < passable["heuristic"] == read["heuristic"]  # every proposed triple read can pass
    assert 100 * passable["heuristic"] / (by == "heuristic").sum() < PAPER["heuristic"]  # of all: capped
    # the opening: shares of the triples read
    share = 100 * passable / read
    capped = int((share[list(PAPER)] < pd.Series(PAPER)).sum())
    assert share["heuristic"] == 100.0 and capped == 0  # by the trials read, no planner lies below its rate
    released, with_reading = int((ok["n_released"] >= 1).sum()), int(ok["n_released"].notna().sum())
    text = report_md(store).split("## What this shows\n\n", 1)[1].split("\n", 1)[0]
    assert f"(released in {released} of {with_reading} triples with an `n_released` reading, " \
           f"{100 * released / with_reading:.1f}%)" in text
    assert "cannot come from" not in text and "which caps" not in text  # it capped the proposed planner
    assert "only triples with ρ·W < τ_F can pass (table mechanism)." in text
    # the table: each count's trials without its reading, in a column after it where there are some
    unread = {"rho_passable": ok["rho"].isna(), "released": ok["n_released"].isna(),
              "single_fingertip": ok["support_share_max"].isna() & ok["success"]}
    counts = {k: v.groupby(by).sum() for k, v in unread.items()}
    assert counts["rho_passable"]["heuristic"] > 0 and counts["released"]["random"] > 0
    assert counts["single_fingertip"]["centroid"] == 0  # it never passes: no pass is left out
    table = read_table(store, "mechanism").set_index("planner")
    for k, c in counts.items():
        assert table[f"{k}_unread"].to_dict() == c.to_dict(), k
    shown = md_table(report_md(store), "mechanism").set_index("planner")
    assert list(shown.columns) == ["n", "released δ = 0", "released δ = 0: no reading (left out)",
                                   "released = upper", "released = upper: no reading (left out)",
                                   "median ρ", "ρ·W < τ_F", "ρ·W < τ_F: no reading (left out)", "passes",
                                   "passes on one fingertip", "passes, one loaded"]
    assert shown["ρ·W < τ_F: no reading (left out)"].astype(int).to_dict() == counts["rho_passable"].rename(
        lambda p: label("planner", p)).to_dict()


def test_the_h_epsilon_table_and_figure_read_one_selection_of_trials(tmp_path, monkeypatch):
    """The h_epsilon figure and ``analysis.quasi_static.h_epsilon_correlation`` each selected the
    paper-law ferrari_canny trials and raised the same message when there were none: one selection now
    (``ferrari_canny_trials``), so the table and the figure count the same trials, and its message."""
    import matplotlib.pyplot as plt

    from graspcampaign.analysis import quasi_static as qs
    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.quasi_static import h_epsilon_figure

    factors = {"shape": SHAPES[:2], "mass_kg": [0.2], "mu": [0.3], "planner": PLANNERS}
    store = make_run(tmp_path / "results", "baseline_grid", "quasi_static", factors, seeds=3, paper=None,
                     outputs=quasi_static_outputs, tables=candidates)
    run = Run(store.read().to_pandas(), store.check(), None, store)
    fc = ok_records(store).query("planner == 'ferrari_canny'")  # 2 shapes × 3 seeds, all executed
    assert sorted(qs.ferrari_canny_trials(run.records)["trial_id"]) == sorted(fc["trial_id"])
    with pytest.raises(ValueError, match="^no executed trial of the ferrari_canny planner$"):
        qs.ferrari_canny_trials(run.records.query("planner != 'ferrari_canny'"))
    first = fc[fc["shape"] == SHAPES[0]]  # a narrower selection narrows the table and the figure alike
    monkeypatch.setattr(qs, "ferrari_canny_trials", lambda records: first)
    table = qs.h_epsilon_correlation(run.records, run.aux("candidates")).set_index("reading")
    assert table.loc["median per trial", "n_trials"] == len(first) == 3
    fig = plt.figure()
    h_epsilon_figure(run, fig)
    counted = sum(bar.get_height() for bar in fig.axes[1].patches)  # panel (b): trials per ρ bin
    plt.close(fig)
    assert counted == first["spearman_h_epsilon"].notna().sum() == 3
