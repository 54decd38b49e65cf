"""Test 3 disturbances on the virtual rig: Coulomb sliding on the shared budget (§9.1)."""

from __future__ import annotations

import numpy as np
import pytest

from graspcampaign.rig import disturb


def test_sliding_integration_matches_constant_acceleration():
    # demand exceeds the static budget only while the lateral pulse acts; with B_k > demand the
    # object re-sticks; travel during the pulse is 1/2 a t^2 plus the stopping distance.
    m, bs, bk = 0.2, 2.0, 1.5
    t = np.arange(0.0, 0.1, 1e-4)
    lateral = np.where(t < 0.05, 2.5, 0.0)
    res = disturb.slide(t, lateral, np.zeros_like(t), bs, bk, m, 1.0, 0.0)
    a = (2.5 - bk) / m
    speed = a * 0.05
    expected = 0.5 * a * 0.05**2 + speed**2 / (2 * bk / m)
    assert res.travel == pytest.approx(expected, rel=0.02)
    assert not res.dropped
    lost = disturb.slide(t, np.zeros_like(t), np.full_like(t, 2.5), bs, bk, m, 0.01, 2.5)
    assert lost.dropped
