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


def test_the_loop_area_is_the_area_the_force_displacement_path_encloses():
    """A damped press (force above the power law going in, below it coming out; 0.3 N of preload
    keeps it compressive throughout) encloses a hysteresis loop: its area by the shoelace formula
    on the closed (mm, N) path, in mJ, is the loop area the fit records."""
    rate = np.gradient(TRAVEL_MM, TIME)  # at most 3 pi / 2 = 4.7 mm/s: 0.05 rate >= -0.24 N
    force = 0.3 + POWER_LAW_N + 0.05 * rate
    out = _fit("normal", force)
    shoelace = 0.5 * abs(np.dot(TRAVEL_MM, np.roll(force, -1)) - np.dot(force, np.roll(TRAVEL_MM, -1)))
    assert out["loop_area_mj"] == pytest.approx(shoelace, rel=1e-9)
    assert out["loading_work_mj"] > out["unloading_work_mj"] > 0


def test_an_event_of_a_file_without_attempts_is_its_first_attempt():
    """A rig file with no ``attempt`` column holds first attempts: attempt 1 (the virtual bench
    numbers its attempts from 1, ``range(1, MAX_ATTEMPTS + 1)``), not 0."""
    import pandas as pd

    from graspcampaign.rig.test1_fits import fit_waveforms

    waveforms = pd.DataFrame({"event_id": "e1", "time_s": TIME, "displacement_mm": TRAVEL_MM,
                              "normal_force_n": POWER_LAW_N, "tangential_force_n": 0.0,
                              "tangential_displacement_mm": 0.0})
    schedule = pd.DataFrame([dict.fromkeys(META_COLUMNS, 0) | {"block": "normal", "event_id": "e1"}])
    fits = fit_waveforms(waveforms, schedule)
    assert fits["attempt"].tolist() == [1] and fits["source"].tolist() == ["measured"]
