"""Test 1 summaries the mutation run found unpinned: which normal fits Table 4 averages, and which
damage depths lie beyond the fingertip radius (round 2); the oblique calibration, the fatigue
baseline and E's SD (round 6). Expected values come from pandas on the accepted rows or by hand."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from graspcampaign.analysis.calibration import cyclic_summary, damage_summary, oblique_summary, table4

KEY = {"material": "gel", "specimen": 1, "environment": "normal_lab"}


def test_table4_averages_the_accepted_normal_fits_only():
    """A fit flagged for review (§7.2 (iii): RMSE above the threshold) stays in the fits but not in
    Table 4's means nor in its count of accepted fits."""
    fits = pd.DataFrame({**KEY, "block": "normal", "fit_ok": True, "accepted": [True, True, False],
                         "n_exp": [0.4, 0.6, 3.0], "k_n_per_mm_n": [0.2, 0.4, 9.0],
                         "f05_n": [0.1, 0.3, 5.0], "c_n_s_per_m": 0.05,
                         **dict.fromkeys(["mu_s", "mu_k", "k_t_n_per_mm", "rho", "tau_s"], np.nan)})
    row = table4(fits).iloc[0]
    accepted = fits[fits["accepted"]]
    assert row["n_accepted_fits"] == 2
    for column in ("n_exp", "k_n_per_mm_n", "f05_n"):
        assert row[column] == pytest.approx(accepted[column].mean())


def test_a_damage_depth_equal_to_the_fingertip_radius_is_not_beyond_it():
    """Only a depth *deeper* than the radius r is no contact (as the validity gate: depth = r, a
    fingertip centred on the surface, is still one)."""
    depths = pd.DataFrame({**KEY, "specimen": [1, 2, 3], "damage_depth_mm": [4.99, 5.0, 5.01],
                           "criterion": "set", "extrapolated": False})
    assert damage_summary(depths, None, 5.0)["beyond_radius"].tolist() == [1]


def test_an_oblique_event_reads_its_specimens_median_breakaway():
    """mu_s calibrated is the median of the specimen's slides in that environment (0.6 of 0.5, 0.6,
    0.9; their mean is 0.667): a 32 deg push (tan 32 deg = 0.625) is predicted to slip, and the
    margin is 0.6 x 1.0 N - 0.62 N = -0.02 N by hand."""
    fits = pd.DataFrame({**KEY, "block": ["sliding"] * 3 + ["oblique"], "mu_s": [0.5, 0.9, 0.6, np.nan],
                         "angle_deg": [np.nan] * 3 + [32.0], "peak_normal_force_n": [np.nan] * 3 + [1.0],
                         "peak_tangential_force_n": [np.nan] * 3 + [0.62],
                         "slipped_measured": [False] * 3 + [True]})
    row = oblique_summary(fits).iloc[0]
    assert row["mu_s_calibrated"] == pytest.approx(0.6)
    assert row["margin_n"] == pytest.approx(-0.02)
    assert row["predicted_slip"] and row["classification_matches_margin"]
    assert row["classification_matches_measured"]


def test_fatigue_cycles_are_read_against_cycle_one_whatever_the_row_order():
    """Rows stored as cycles 3, 1, 2: K/K1 and the permanent set are taken against cycle 1
    (f0.5 1.0 N, onset 0.1 mm): 1.0, 0.9, 0.8 and 0, 0.1, 0.2 mm in cycle order."""
    fits = pd.DataFrame({**KEY, "block": "cyclic", "cycle_index": [3, 1, 2],
                         "f05_n": [0.8, 1.0, 0.9], "onset_mm": [0.3, 0.1, 0.2]})
    out = cyclic_summary(fits)
    assert out["cycle_index"].tolist() == [1, 2, 3]
    np.testing.assert_allclose(out["k_ratio"], [1.0, 0.9, 0.8])
    np.testing.assert_allclose(out["permanent_set_mm"], [0.0, 0.1, 0.2], atol=1e-15)


def test_table4_modulus_sd_over_specimens_and_a_zero_damping_not_negative():
    """E's SD is the sample SD over specimens (100, 120, 140 kPa: 20 kPa by hand, n - 1 = 2), each
    specimen once however many truths rows it has; a damping C of exactly 0 is not negative."""
    fits = pd.DataFrame({**KEY, "block": "normal", "fit_ok": True, "accepted": True, "n_exp": 0.5,
                         "k_n_per_mm_n": 0.3, "f05_n": 0.2, "c_n_s_per_m": [-0.01, 0.0, 0.05],
                         **dict.fromkeys(["mu_s", "mu_k", "k_t_n_per_mm", "rho", "tau_s"], np.nan)})
    truths = pd.DataFrame({**KEY, "specimen": [1, 1, 2, 3], "modulus_kpa": [100.0, 100.0, 120.0, 140.0]})
    row = table4(fits, truths).iloc[0]
    assert row["modulus_kpa"] == pytest.approx(120.0) and row["modulus_sd_kpa"] == pytest.approx(20.0)
    assert row["c_negative"] == 1
