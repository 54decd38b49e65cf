"""Tests for analysis.quasi_static (the numbers behind the quasi-static report paragraphs)."""

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from graspcampaign.analysis.quasi_static import (
    epsilon_summary,
    gate_removed,
    h_epsilon_correlation,
    median_rho_by_planner,
    planner_grip_law_table,
    released_contact_share,
    single_fingertip_share,
    spearman_interval,
    what_this_shows,
)


def records():
    """Eight hand-written rows: two planners x (paper, slip), statuses and outcomes chosen."""
    return pd.DataFrame({
        "trial_id": [f"t{i}" for i in range(8)],
        "status": ["ok"] * 7 + ["error"],
        "planner": ["heuristic", "heuristic", "random", "random",
                    "heuristic", "random", "ferrari_canny", "random"],
        "grip_law": ["paper"] * 4 + ["slip", "slip", "paper", "paper"],
        "success": [True, False, True, False, True, False, False, True],
        "success_unbounded": [True, True, True, False, True, False, False, True],
        "success_no_torque": [True, False, True, True, True, False, False, True],
        "failure_check": ["none", "geometry", "none", "torque", "none", "residual", "residual",
                          "none"],
        "n_released": [1, 2, 0, 1, 0, 0, 1, 0],
        "n_upper": [1, 2, 0, 1, 0, 0, 1, 0],
        "n_loaded": [1, 1, 2, 2, 3, 3, 2, 3],
        "support_share_max": [1.0, 1.0, 0.97, 0.6, 0.34, 0.4, 0.7, 0.5],
        "rho": [0.1, 0.3, 0.5, 0.9, 0.0, 0.0, 0.2, 9.9],
        "epsilon_fc": [0.0, 0.02, 0.0, 0.0, 0.0, 0.0, 0.05, 1.0],
        "spearman_h_epsilon": [np.nan] * 6 + [-0.3, np.nan],
    })


def test_paragraph_numbers_count_the_paper_law_ok_rows():
    df = records()
    shows = what_this_shows(df)
    # paper-law ok rows: t0..t3 and t6 (t7 is an error row, t4/t5 are slip)
    assert (shows.released.k, shows.released.n) == (4, 5)
    assert released_contact_share(df).share == pytest.approx(0.8)
    assert shows.upper_released.k == 5
    assert median_rho_by_planner(df).to_dict() == pytest.approx(
        {"heuristic": 0.2, "random": 0.7, "ferrari_canny": 0.2})
    # passes t0 (one loaded contact, share 1) and t2 (share 0.97, two loaded)
    assert (shows.single_fingertip.k, shows.single_fingertip.n) == (2, 2)
    assert (shows.single_loaded.k, shows.single_loaded.n) == (1, 2)
    share, loaded = single_fingertip_share(df, threshold=0.99)
    assert (share.k, loaded.k) == (1, 1)
    assert (shows.gate_removed.k, shows.gate_removed.n) == (1, 3)


def test_tables_by_planner_and_grip_law():
    df = records()
    table = planner_grip_law_table(df)
    assert table.loc[("heuristic", "paper"), ["n", "success", "success_unbounded"]].tolist() == [2, 1, 2]
    assert table.loc[("random", "slip"), "fail_residual"] == 1
    removed = gate_removed(df, by=("planner",))
    assert removed.loc["heuristic", "removed"] == 1 and removed["removed"].sum() == 1
    eps = epsilon_summary(df)
    assert eps.loc["heuristic", "force_closure"] == 1 and eps.loc["random", "n"] == 2
    assert eps.loc["ferrari_canny", "epsilon_median"] == pytest.approx(0.05)


def test_spearman_interval_covers_the_population_value():
    # Bivariate normal with Pearson r has population Spearman rho_s = (6/pi) asin(r/2)
    # (Pearson 1907; Kruskal 1958) -- a closed form independent of the code under test.
    rng = np.random.default_rng(0)
    r, n, reps = 0.6, 60, 400
    rho_s = 6 / np.pi * np.arcsin(r / 2)
    cov = [[1, r], [r, 1]]
    hits = 0
    for _ in range(reps):
        x, y = rng.multivariate_normal([0, 0], cov, size=n).T
        res = spearman_interval(x, y)
        assert res.rho == pytest.approx(stats.spearmanr(x, y).statistic)
        hits += res.low <= rho_s <= res.high
    assert 0.91 <= hits / reps <= 0.98  # nominal 95 %, binomial sd ~1.1 %
    res = spearman_interval(np.arange(10), np.arange(10) ** 3)
    assert res.rho == pytest.approx(1.0) and res.n == 10
    assert np.isnan(spearman_interval([1, 2, 3], [3, 2, 1]).rho)  # n < 4: no interval


def test_h_epsilon_correlation_per_trial_and_pooled():
    rng = np.random.default_rng(1)
    rows, tables = [], []
    for t in range(12):
        h = rng.uniform(0, 1, 50)
        eps = np.maximum(0.0, 0.5 - h + 0.1 * rng.normal(size=50))  # agreement: rho < 0
        rho = stats.spearmanr(h, eps).statistic
        rows.append({"trial_id": f"fc{t}", "status": "ok", "planner": "ferrari_canny",
                     "grip_law": "paper", "spearman_h_epsilon": rho})
        tables.append(pd.DataFrame({"trial_id": f"fc{t}", "h_total": h, "epsilon_fc": eps}))
    out = h_epsilon_correlation(pd.DataFrame(rows), pd.concat(tables), n_resamples=500)
    per = out["per_trial"]
    assert per.rho == pytest.approx(np.median([r["spearman_h_epsilon"] for r in rows]))
    assert per.low <= per.rho <= per.high < 0 and per.n == 12
    pooled = out["pooled"]
    assert pooled.n == 600 and pooled.low <= pooled.rho <= pooled.high < 0
