"""Mutation round 8: edges of the quasi-static mechanism counts, the H(G)-epsilon correlation, the
vocabulary and Cohen's kappa that no test pinned, each against counts by hand or scipy
(docs/decisions.md, mutation round 8)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from graspcampaign.analysis import quasi_static as qs
from graspcampaign.analysis.dynamic_check import cohens_kappa
from graspcampaign.analysis.vocabulary import OTHER_COLOURS, colour, things


def passes(**columns) -> pd.DataFrame:
    n = len(next(iter(columns.values())))
    base = {"status": "ok", "planner": "heuristic", "grip_law": "paper", "success": [True] * n,
            "n_released": [0] * n, "n_upper": [2] * n, "rho": [1.0] * n, "mass_kg": [1.0] * n,
            "support_share_max": [0.5] * n, "n_loaded": [3] * n}
    return pd.DataFrame({**base, **columns})


def test_a_pass_with_exactly_the_threshold_share_rests_on_one_fingertip():
    """One contact giving >= 95 % of the support: 0.95 counts, the float just below it does not."""
    rows = passes(support_share_max=[0.95, np.nextafter(0.95, 0.0), 1.0])
    assert qs.mechanism(rows, tau_f_n=100.0)["single_fingertip"].tolist() == [2]


def test_a_required_friction_force_equal_to_the_budget_is_not_passable():
    """rho m g < tau_f_n, strictly: with m = 1 kg and tau = g N (9.81), rho 1 needs exactly the
    budget and is not passable; rho 0.5 and 0.999 are, rho 2 is not."""
    rows = passes(rho=[1.0, 0.5, 0.999, 2.0])
    assert qs.mechanism(rows, tau_f_n=qs.GRAVITY)["rho_passable"].tolist() == [2]


def fc_trials(per_trial: list[float]) -> pd.DataFrame:
    return pd.DataFrame({"status": "ok", "planner": "ferrari_canny", "grip_law": "paper",
                         "trial_id": [f"t{i}" for i in range(len(per_trial))],
                         "spearman_h_epsilon": per_trial, "spearman_h_epsilon_fc": np.nan})


def test_two_trials_have_a_median_per_trial_and_a_pooled_rho():
    """Two trials are enough for both readings: the median of their rhos (numpy: their mean) and
    the pooled rho of their six candidates (scipy's spearmanr, every candidate once)."""
    candidates = pd.DataFrame({"trial_id": ["t0"] * 3 + ["t1"] * 3, "h_total": [1, 2, 3, 4, 5, 6.5],
                               "epsilon_fc": [0.3, 0.1, 0.2, 0.05, 0.0, 0.01]})
    out = qs.h_epsilon_correlation(fc_trials([0.2, 0.6]), candidates, n_resamples=200).set_index("reading")
    assert out.loc["median per trial", "rho"] == pytest.approx(np.median([0.2, 0.6]))
    assert out.loc["median per trial", "n_trials"] == 2
    expected = stats.spearmanr(candidates["h_total"], candidates["epsilon_fc"]).statistic
    assert out.loc["pooled", "rho"] == pytest.approx(expected)
    assert out.loc["pooled", ["n_trials", "n_pairs"]].tolist() == [2, 6]


def test_each_unknown_value_gets_its_own_colour_until_the_cycle_repeats():
    """Values no vocabulary knows take OTHER_COLOURS in turn: as many distinct colours as it has,
    then the first again."""
    drawn = [colour("no_such_column", f"v{i}", i) for i in range(len(OTHER_COLOURS) + 1)]
    assert len(set(drawn[:-1])) == len(OTHER_COLOURS) and drawn[-1] == drawn[0]


def test_a_bare_count_column_names_itself():
    """``n`` alone is a count, not a quantity in newtons with no name: its things are "n"."""
    assert things("n") == "n"
    assert things("lat_threshold_n") == "lat_threshold"


def test_a_table_with_a_negative_count_is_refused():
    said = r"table must be a \(2, 2\) array of counts, got \[\[5, -1\], \[2, 3\]\]"
    with pytest.raises(ValueError, match=said):
        cohens_kappa([[5, -1], [2, 3]])
