"""Tests for analysis.quasi_static (the numbers behind the quasi-static report paragraphs).

Expected counts are read off the hand-written rows below; intervals come from statsmodels and
rank correlations from scipy, never from the code under test.
"""

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats
from statsmodels.stats.proportion import proportion_confint

from graspcampaign.analysis.quasi_static import (
    epsilon_table,
    grip_need,
    h_epsilon_correlation,
    mechanism,
    readings,
    weighted_spearman,
)

INF = float("inf")


def records():
    """Nine hand-written rows: two planners x (paper, slip, oracle); t8 is an errored trial."""
    return pd.DataFrame({
        "trial_id": [f"t{i}" for i in range(9)],
        "status": ["ok"] * 8 + ["error"],
        "planner": ["heuristic", "heuristic", "random", "random", "heuristic", "random",
                    "ferrari_canny", "centroid", "random"],
        "grip_law": ["paper"] * 4 + ["slip", "oracle", "paper", "oracle", "paper"],
        "mass_kg": [0.2, 0.6, 0.2, 0.4, 0.2, 0.2, 0.4, 0.2, 0.2],
        "success": [True, False, True, False, True, False, False, True, True],
        "success_unbounded": [True, True, True, False, True, False, False, True, True],
        "success_vertical": [True, True, True, True, True, False, False, True, True],
        "success_no_torque": [True, False, True, True, True, False, False, True, True],
        "n_released": [1, 2, 0, 1, 0, 0, 1, 0, 0],
        "n_upper": [1, 2, 0, 1, 1, 0, 1, 0, 0],
        "n_loaded": [1, 1, 2, 2, 3, 3, 2, 3, 3],
        "support_share_max": [1.0, 1.0, 0.97, 0.6, 0.34, 0.4, 0.7, 0.3, 0.5],
        # rho * m * g < 0.5 N: t0 (0.1*0.2*9.81 = 0.196) yes, t1 (0.3*0.6*9.81 = 1.77) no,
        # t2 (0.2*0.2*9.81 = 0.392) yes, t3 (0.9*0.4*9.81 = 3.53) no, t6 (0.2*0.4*9.81 = 0.785) no
        "rho": [0.1, 0.3, 0.2, 0.9, 0.0, 0.0, 0.2, 0.0, 9.9],
        "epsilon_fc": [0.0, 0.02, 0.0, 0.0, 0.0, 0.0, 0.05, 0.1, 1.0],
        "grip_capped": [False, False, False, False, True, True, False, True, False],
        "grip_needed_n": [np.nan] * 4 + [3.0, INF, np.nan, 12.0, np.nan],
        "contact_normal_z_1": [0.1, 0.5, -0.9, 0.0, 0.6, -0.2, 0.0, 0.0, 0.0],
        "contact_normal_z_2": [-0.7, 0.0, 0.3, 0.0, -0.3, 0.8, 0.0, 0.0, 0.0],
        "contact_normal_z_3": [0.2, 0.1, 0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 0.0],
        "spearman_h_epsilon": [np.nan] * 6 + [-0.3, np.nan, np.nan],
        "spearman_h_epsilon_fc": [np.nan] * 6 + [-0.5, np.nan, np.nan],
    })


def test_mechanism_counts_the_paper_law_ok_rows():
    m = mechanism(records(), tau_f_n=0.5, order={"planner": ["random", "heuristic"]}).set_index("planner")
    # the vocabulary's order, whatever the study's (docs/decisions.md, "Planners in the vocabulary's order")
    assert list(m.index) == ["heuristic", "random", "ferrari_canny"]
    assert m.loc["heuristic", ["n", "released", "upper_released", "rho_passable"]].tolist() == [2, 2, 2, 1]
    assert m.loc["random", ["n", "released", "rho_passable", "successes"]].tolist() == [2, 1, 1, 1]
    # passes: t0 (share 1.0, one loaded) and t2 (share 0.97, two loaded)
    assert m.loc["heuristic", ["single_fingertip", "single_loaded"]].tolist() == [1, 1]
    assert m.loc["random", ["single_fingertip", "single_loaded"]].tolist() == [1, 0]
    assert m.loc["heuristic", "rho_median"] == pytest.approx(0.2)
    strict = mechanism(records(), tau_f_n=0.5, threshold=0.99).set_index("planner")
    assert strict.loc["random", "single_fingertip"] == 0


@pytest.mark.parametrize("missing", [np.nan, None])
def test_mechanism_leaves_a_trial_without_a_reading_out_of_that_count(missing):
    """A trial without the reading a count compares stayed in n and counted as its negation (a missing
    ρ as not passable). Paper-law rows above: t1 (heuristic, fails, ρ·W = 1.77 N) loses ``rho`` and its
    ``support_share_max`` (a failure: in no one-fingertip count); t3 (random, n_released 1 = n_upper)
    ``n_released``; t0 (heuristic, passes, share 1.0) ``support_share_max``; t2 (random, passes, 2 loaded)
    ``n_loaded``. Each count keeps what it counted and says how many it left out."""
    rows = records().astype({"rho": object, "n_released": object, "support_share_max": object,
                             "n_loaded": object})
    rows.loc[1, ["rho", "support_share_max"]] = missing
    rows.loc[3, "n_released"] = missing
    rows.loc[0, "support_share_max"] = missing
    rows.loc[2, "n_loaded"] = missing
    m = mechanism(rows.infer_objects(), tau_f_n=0.5).set_index("planner")
    counts = ["n", "released", "upper_released", "rho_passable", "successes", "single_fingertip",
              "single_loaded"]
    assert m.loc["heuristic", counts].tolist() == [2, 2, 2, 1, 1, 0, 1]  # ρ passable: 1 of the 1 read
    assert m.loc["random", counts].tolist() == [2, 0, 1, 1, 1, 1, 0]
    unread = [f"{c}_unread" for c in ("released", "upper_released", "rho_passable", "single_fingertip",
                                      "single_loaded")]
    assert m.loc["heuristic", unread].tolist() == [0, 0, 1, 1, 0]  # t1's share: not a pass, not counted
    assert m.loc["random", unread].tolist() == [1, 1, 0, 0, 1]
    assert m.loc["ferrari_canny", unread].tolist() == [0] * 5
    assert m.loc["heuristic", "rho_median"] == pytest.approx(0.1)  # of t0's alone
    assert (mechanism(records(), tau_f_n=0.5)[unread] == 0).all().all()  # every trial read


def test_readings_counts_rates_and_removed_passes():
    r = readings(records(), ["grip_law", "planner"]).set_index(["grip_law", "planner"])
    row = r.loc[("paper", "heuristic")]
    assert row[["n", "success", "success_unbounded", "success_vertical", "success_no_torque"]].tolist() == [
        2, 1, 2, 2, 1]
    assert (row["gate_removed"], row["torque_binds"]) == (1, 0)
    assert r.loc[("paper", "random"), "torque_binds"] == 1  # t3 fails torque only
    assert ("paper", "random") in r.index and r.loc[("paper", "random"), "n"] == 2  # error row excluded
    # statsmodels.stats.proportion.proportion_confint(1, 2, method="wilson")
    low, high = proportion_confint(1, 2, method="wilson")
    assert row["success_pct"] == 50.0
    assert (row["success_low_pct"], row["success_high_pct"]) == pytest.approx((100 * low, 100 * high))


@pytest.mark.parametrize("missing", [np.nan, None])
def test_a_trial_missing_a_reading_enters_no_reading(missing):
    """t0 (paper, heuristic: a pass under every reading) with no ``success_no_torque`` recorded was read
    as failing with the torque check off (``fillna(False)``): τ_T "removed" -1 passes and n was 2. The
    group is now t1 alone (a failure, a pass without the gate): n 1, success 0, without the gate 1."""
    rows = records()
    rows["success_no_torque"] = rows["success_no_torque"].astype(object)
    rows.loc[0, "success_no_torque"] = missing
    table = readings(rows, ["grip_law", "planner"]).set_index(["grip_law", "planner"])
    row = table.loc[("paper", "heuristic")]
    assert row[["n", "success", "success_unbounded", "success_no_torque"]].tolist() == [1, 0, 1, 0]
    assert (row["gate_removed"], row["torque_binds"]) == (1, 0)


def test_readings_count_the_trials_left_out_for_a_reading_missing():
    """The rows above: t0 (paper, heuristic) lacks ``success_vertical``, t7 (oracle, centroid, the
    group's one trial) ``success_unbounded``; t8 errored (no reading, not executed: in no count). n was
    the trials read with the others dropped unsaid, and a group with none read was no row at all."""
    rows = records().astype(dict.fromkeys(["success", "success_unbounded", "success_vertical",
                                           "success_no_torque"], object))
    rows.loc[0, "success_vertical"] = None
    rows.loc[7, "success_unbounded"] = np.nan
    rows.loc[8, ["success", "success_unbounded", "success_vertical", "success_no_torque"]] = None
    table = readings(rows, ["grip_law", "planner"]).set_index(["grip_law", "planner"])
    assert table["n_unread"].to_dict() == {  # executed trials per group (rows above) minus those read
        ("paper", "heuristic"): 1, ("paper", "random"): 0, ("paper", "ferrari_canny"): 0,
        ("slip", "heuristic"): 0, ("oracle", "random"): 0, ("oracle", "centroid"): 1}
    assert table.loc[("paper", "heuristic"), ["n", "success", "success_vertical"]].tolist() == [1, 0, 1]
    lost = table.loc[("oracle", "centroid")]
    assert lost[["n", "success", "success_unbounded", "gate_removed"]].tolist() == [0, 0, 0, 0]
    assert math.isnan(lost["success_pct"]) and math.isnan(lost["success_unbounded_low_pct"])
    assert list(table.columns[:3]) == ["n", "n_unread", "success"]
    assert (readings(records(), ["planner"])["n_unread"] == 0).all()  # every trial read


def test_grip_need_and_epsilon():
    need = grip_need(records(), {"grip_law": ["slip", "oracle"]}).set_index(["grip_law", "planner"])
    assert list(need.index) == [("slip", "heuristic"), ("oracle", "centroid"), ("oracle", "random")]
    counts = ["holdable", "no_equal_grip", "capped_passes"]
    assert need.loc[("oracle", "random"), counts].tolist() == [0, 1, 0]
    assert need.loc[("oracle", "centroid"), ["no_equal_grip", "capped_passes"]].tolist() == [0, 1]
    assert need.loc[("slip", "heuristic"), "steepest_normal_z_median"] == pytest.approx(0.6)
    eps = epsilon_table(records()).set_index("planner")  # paper law: t0-t3, t6
    assert eps.loc["heuristic", ["n", "force_closure"]].tolist() == [2, 1]
    assert eps.loc["random", "force_closure"] == 0
    assert eps.loc["ferrari_canny", "epsilon_median"] == pytest.approx(0.05)
    assert eps.loc["heuristic", "force_closure_pct"] == 50.0
    assert not {"successes", "rate_why", "bootstrap_why", "bootstrap_low_pct"} & set(eps)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 4), st.integers(0, 6), st.integers(0, 3)), min_size=3,
                max_size=30))
def test_weighted_spearman_is_spearman_of_the_repeated_sample(rows):
    x, y, w = (np.array(c, dtype=float) for c in zip(*rows, strict=True))
    xs, ys = np.repeat(x, w.astype(int)), np.repeat(y, w.astype(int))
    if len(xs) < 2 or np.ptp(xs) == 0 or np.ptp(ys) == 0:
        return
    # scipy.stats.spearmanr on the explicitly repeated sample (ties get average ranks)
    assert weighted_spearman(x, y, w) == pytest.approx(stats.spearmanr(xs, ys).statistic, abs=1e-12)


def _trials(relation: float, n_trials: int = 30, seed: int = 1):
    rng = np.random.default_rng(seed)
    rows, tables = [], []
    for t in range(n_trials):
        h = rng.uniform(0, 1, 50)
        eps = np.maximum(0.0, relation * (0.5 - h) + 0.1 * rng.normal(size=50))
        fc = eps > 0
        rows.append({"trial_id": f"fc{t}", "status": "ok", "planner": "ferrari_canny", "grip_law": "paper",
                     "spearman_h_epsilon": stats.spearmanr(h, eps).statistic,
                     "spearman_h_epsilon_fc": stats.spearmanr(h[fc], eps[fc]).statistic})
        tables.append(pd.DataFrame({"trial_id": f"fc{t}", "h_total": h, "epsilon_fc": eps}))
    return pd.DataFrame(rows), pd.concat(tables, ignore_index=True)


def test_h_epsilon_correlation_per_trial_and_pooled():
    rows, candidates = _trials(relation=1.0)
    out = h_epsilon_correlation(rows, candidates, n_resamples=400).set_index("reading")
    per = out.loc["median per trial"]
    assert per["rho"] == pytest.approx(np.median(rows["spearman_h_epsilon"]))
    assert per["low"] <= per["rho"] <= per["high"] < 0 and per["n_trials"] == 30
    pooled = out.loc["pooled"]
    expected = stats.spearmanr(candidates["h_total"], candidates["epsilon_fc"]).statistic
    assert pooled["rho"] == pytest.approx(expected)
    assert pooled["n_pairs"] == 1500 and pooled["low"] <= pooled["rho"] <= pooled["high"] < 0
    assert "median per trial, force closure" in out.index
    # no relation: every interval contains zero
    unrelated = h_epsilon_correlation(*_trials(relation=0.0, seed=3), n_resamples=400)
    assert ((unrelated["low"] < 0) & (unrelated["high"] > 0)).all()


@pytest.mark.parametrize("candidates", [
    pd.DataFrame(), pd.DataFrame({"trial_id": ["other"], "h_total": [0.5], "epsilon_fc": [0.1]})])
def test_h_epsilon_correlation_without_candidates_gives_the_per_trial_rows_and_no_pooled_one(candidates):
    """A run that stored no candidate table reads an empty frame with no column (``Run.aux``); it raised
    KeyError 'trial_id', and the report handed it a frame it built with the three columns instead. The
    per-trial medians come from the records: numpy's median of the trials' rho, as with candidates."""
    rows, _ = _trials(relation=1.0, n_trials=5)
    out = h_epsilon_correlation(rows, candidates, n_resamples=200).set_index("reading")
    assert list(out.index) == ["median per trial", "median per trial, force closure"]
    assert out.loc["median per trial", "rho"] == pytest.approx(np.median(rows["spearman_h_epsilon"]))
    assert out.loc["median per trial", "n_trials"] == 5


def test_weighted_spearman_of_a_constant_sample_is_nan_without_a_warning():
    """As scipy's spearmanr (NaN for constant input), but no RuntimeWarning in a report run."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.isnan(weighted_spearman([1.0, 1.0, 1.0], [0.0, 1.0, 2.0], [1.0, 2.0, 1.0]))
    with pytest.warns(stats.ConstantInputWarning):
        assert np.isnan(stats.spearmanr([1.0, 1.0, 1.0, 1.0], [0.0, 1.0, 1.0, 2.0]).statistic)


def test_the_loop_at_n_max_share_counts_the_capped_trials():
    """The sensitivity and mesh-resolution tables' "still moving at N_max": 1 of 4 trials capped, 25 %
    (a missing flag is not set, records.flag); no trial, no share."""
    from graspcampaign.analysis.quasi_static import loop_at_n_max_pct

    assert loop_at_n_max_pct(pd.DataFrame({"loop_capped": [True, None, False, False]})) == 25.0
    assert math.isnan(loop_at_n_max_pct(pd.DataFrame({"loop_capped": pd.Series([], dtype=bool)})))
