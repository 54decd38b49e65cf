"""The virtual world's truth: specimens per object, the day's ambient friction (§7.3)."""

from __future__ import annotations

import pytest

from graspcampaign.rig import specimen as sp


def test_specimens_are_per_object_and_environment_scales_friction():
    a = sp.specimen_truth(0, "sphere-03", "silicone_soft", 3, "natural", "normal_lab")
    b = sp.specimen_truth(0, "sphere-03", "silicone_soft", 3, "natural", "warm_humid")
    c = sp.specimen_truth(0, "pear-03", "silicone_soft", 3, "natural", "normal_lab")
    assert a.k_n_per_mm_n == b.k_n_per_mm_n and b.mu_s > a.mu_s
    assert c.k_n_per_mm_n != a.k_n_per_mm_n
    low = sp.specimen_truth(0, "sphere-03", "silicone_soft", 3, "low", "normal_lab")
    assert low.mu_s < 0.3 and low.mu_k / low.mu_s == pytest.approx(a.mu_k / a.mu_s)
    assert sp.day_environment(0, "test2_grasp", 4) in sp.ENVIRONMENT_PROBABILITIES
