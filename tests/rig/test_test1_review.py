"""§7.2 (iii): every fit of the normal law -- a normal-block event's and a fatigue cycle's -- is
flagged for review when its force RMSE exceeds the threshold, and accepted otherwise."""

from __future__ import annotations

import numpy as np
import pytest

from graspcampaign.rig.test1_fits import META_COLUMNS, REVIEW_RMSE_PCT, fit_row

TIME = np.linspace(0.0, 2.0, 401)
TRAVEL_MM = 3.0 * np.sin(np.pi * TIME / 2.0)  # 3 mm in and back out
POWER_LAW_N = 0.3 * TRAVEL_MM**1.2  # Eq. 13 at rest: K delta^n, exactly


def _fit(block: str, force: np.ndarray) -> dict:
    row = dict.fromkeys(META_COLUMNS, 0) | {"block": block, "event_id": "e1"}
    arrays = {"time_s": TIME, "displacement_mm": TRAVEL_MM, "normal_force_n": force,
              "tangential_force_n": np.zeros_like(TIME), "tangential_displacement_mm": np.zeros_like(TIME)}
    return fit_row(row, arrays, 1, "")


@pytest.mark.parametrize("block", ["normal", "cyclic"])
def test_a_fit_of_the_normal_law_is_reviewed_by_its_rmse(block):
    exact = _fit(block, POWER_LAW_N)
    assert exact["fit_ok"] and exact["rmse_pct"] < REVIEW_RMSE_PCT
    assert (exact["accepted"], exact["review_reason"]) == (True, "")
    # a ±25 % ripple on the power law: no (K, n, C) follows it within the threshold
    rippled = _fit(block, POWER_LAW_N * (1.0 + 0.25 * np.sin(12.0 * np.pi * TIME)))
    assert rippled["fit_ok"] and rippled["rmse_pct"] > REVIEW_RMSE_PCT
    assert (rippled["accepted"], rippled["review_reason"]) == (False, "rmse")
