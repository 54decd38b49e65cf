"""Test 1 summaries the mutation run found unpinned: which normal fits Table 4 averages, and which
damage depths lie beyond the fingertip radius. Expected values come from pandas on the accepted rows."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from graspcampaign.analysis.calibration import damage_summary, table4

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
