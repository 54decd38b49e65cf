"""Tests of the mesh_resolution report's N_max panel: its counts and its cross-check against the
baseline_grid records, where an outcome is missing (``records.flag``, ``records.known``)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pyarrow as pa

from graspcampaign.report.render import Run
from graspcampaign.report.studies import mesh_resolution as mr


def _n_max_run(budget_capped, store=None) -> Run:
    """An N_max panel: trials A, B, C failed at N_max (``budget_capped`` as given), D passed."""
    records = pd.DataFrame({
        "panel": "n_max", "status": "ok", "planner": "heuristic", "shape": "sphere", "mass_kg": 0.4,
        "mu": 0.3, "seed": [0, 1, 2, 3], "success": [False, False, False, True],
        "success_rerun": [True, False, False, True], "loop_capped": False, "budget_capped": budget_capped,
        "failure_check_rerun": "residual", "residual_z_rerun_n": 1.0, "residual_norm_rerun_n": 1.0,
        "residual_norm_n": [1.0, 2.0, 3.0, 0.1]})
    return Run(records, {}, SimpleNamespace(), store=store)


def test_a_failure_without_a_budget_cap_reading_is_not_counted_as_capped():
    """``astype(bool)`` read a missing ``budget_capped`` (NaN) as capped: 2 of 3 for the one recorded."""
    row = mr._n_max(_n_max_run([True, np.nan, False, False])).iloc[0]
    assert (row["failures_at_n_max"], row["budget_capped"]) == (3, 1)


def _cross_check(tmp_path, monkeypatch, success, residual) -> str:
    """The cross-check sentence of the run of :func:`_n_max_run` against a baseline_grid run beside it
    whose three trials (seeds 0-2) recorded ``success`` and ``residual`` (None: a null)."""
    baseline = pa.table({"status": ["ok"] * 3, "planner": ["heuristic"] * 3, "shape": ["sphere"] * 3,
                         "mass_kg": [0.4] * 3, "mu": [0.3] * 3, "seed": [0, 1, 2],
                         "success": pa.array(success, pa.bool_()),
                         "residual_norm_n": pa.array(residual, pa.float64())})

    class Stored:  # a baseline_grid run beside this one, read as RunStore reads one
        def __init__(self, path):
            self.path = path

        def check(self, parts):
            return {}

        def read(self):
            return baseline

    (tmp_path / "baseline_grid" / "run0").mkdir(parents=True)
    monkeypatch.setattr(mr, "RunStore", Stored)
    run = _n_max_run(False, store=SimpleNamespace(path=tmp_path / "mesh_resolution" / "run1"))
    return mr._cross_check(run)


def test_the_cross_check_compares_recorded_verdicts_only(tmp_path, monkeypatch):
    """A baseline record with no verdict (a null, read as None) had agreed with a re-derived failure
    (``astype(bool)``: False == False); it is now no comparison, and the sentence says so. Its "k of N"
    is over the compared trials: seeds 0 and 2 (re-derived False, False; baseline False, True) agree
    once, 1 of 2 (it said 1 of 3, the uncompared trial in N); the residuals, all recorded, 3 of 3."""
    assert _cross_check(tmp_path, monkeypatch, [False, None, True], [1.0, 2.0, 3.0]) == (
        "Cross-check against the baseline-grid study's records beside this run: 1 of 2 re-derived trials "
        "have the baseline's verdict (1 more not compared: no verdict recorded) and 3 of 3 its residual "
        "(relative 1e-9).")


def test_the_cross_check_compares_recorded_residuals_only(tmp_path, monkeypatch):
    """A baseline trial with no residual (null) is no comparison, as one with no verdict: the residuals
    of seeds 0 and 2 are compared (N 2) and the third is said apart, where it counted as "not close"
    in an N of 3 (a NaN is close to nothing). The verdicts, all recorded, are as before."""
    assert _cross_check(tmp_path, monkeypatch, [False, False, True], [1.0, None, 3.0]) == (
        "Cross-check against the baseline-grid study's records beside this run: 2 of 3 re-derived trials "
        "have the baseline's verdict and 2 of 2 its residual (relative 1e-9; 1 more not compared: no "
        "residual recorded).")


def test_the_cost_ratio_opening_says_the_verdicts_its_table_rows_hold():
    """The opening ran the verdict rule again on the cost ratio the cost_ratio table had judged (and the
    speed target likewise): one verdict per value now, the rows'. A row reworded by hand shows in the
    opening as worded (the verdict's word, the text before its reason; the target row's words whole); the
    median repeats, context in the table (not compared), are judged against the target once, there."""
    from test_sensitivity_mesh_surrogate_report import _timings

    run = _timings([1.1, 1.2, 1.3], [1.1, 1.2, 1.3])
    table = run.tables["cost_ratio"].set_index("quantity")
    assert table.loc["cost ratio, 1750 / 144 nodes, fastest repeats", "verdict"] == \
        "differs by −0.75: paper outside our 95% CI"  # 1.20 − 1.95, the trials' interval 1.10–1.30
    assert "(paper 1.95: differs by −0.75; within this tool's speed target ≤ 1.50, not a paper value;" \
        in mr.finding(run)
    table.loc["cost ratio, 1750 / 144 nodes, fastest repeats", "verdict"] = "as the row says: its reason"
    table.loc["cost ratio, 1750 / 144 nodes, fastest repeats, against this tool's speed target (≤ 1.5; not "
              "a paper value)", "verdict"] = "within the row's target"
    run.tables["cost_ratio"] = table.reset_index()
    assert "(paper 1.95: as the row says; within the row's target, not a paper value; table cost_ratio)" \
        in mr.finding(run)
