"""Tests 2-3 columns the mutation run found unpinned: which trials the validity gate alone fails
(``gate_removed``), the block-B payload as a share of the object's weight, and the sign of the
belief gap (none − paper). Expected values come from the trials counted by hand and pandas."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from test_hardware import _records

from graspcampaign.analysis import hardware


def test_gate_removed_is_a_success_only_without_the_validity_gate():
    rec = _records({"heuristic": (1, 3)})
    # trial 0 passes with the gate; 1 passes only without it; 2 fails both ways
    got = hardware.derive(rec.assign(success_unbounded=[True, True, False]))["gate_removed"]
    assert got.tolist() == [False, True, False]
    assert hardware.derive(rec)["gate_removed"].isna().all()  # a measured run knows no ungated success


def test_a_block_b_payload_is_a_share_of_the_objects_weight():
    """A 0.2 kg object weighs 0.2 · 9.81 N (SPEC §1): a pull of 0.981 N is 50 % of it."""
    rec = _records({"heuristic": (2, 2)}, block="B", disturbance_kind="down", mass_kg=0.2,
                   threshold_censored=False, threshold_pred_n=1.0, threshold_measured_nm=np.nan,
                   threshold_pred_nm=np.nan, first_finger_measured=0, first_finger_pred=1, peak_slip_mm=0.0)
    d = hardware.derive(rec.assign(threshold_measured_n=[0.981, 1.962]))
    assert d["payload_pct_w"].tolist() == pytest.approx([50.0, 100.0])


def test_the_belief_gap_is_exact_beliefs_minus_the_papers():
    """Under exact beliefs (none) 7 of 10 trials succeed, under the paper's 3: +40 pp."""
    paper = _records({"heuristic": (3, 10)})
    none = paper.assign(success=np.arange(10) < 7)
    long = pd.concat([paper.assign(belief_error="paper"), none.assign(belief_error="none")])
    row = hardware.belief_pairs(long).iloc[0]
    rate = long.groupby("belief_error")["success"].mean() * 100
    assert (row["success_paper_pct"], row["success_none_pct"]) == pytest.approx((rate["paper"], rate["none"]))
    assert row["difference_pp"] == pytest.approx(rate["none"] - rate["paper"]) == pytest.approx(40.0)
