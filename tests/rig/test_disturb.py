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


def _held(row, budget_s=2.0, budget_k=1.5, base=1.2, mass=0.2):
    """Apply ``row`` to an equilateral grasp 50 mm about the centroid, noiseless readings."""
    from types import SimpleNamespace

    from graspcampaign.rig.virtual import RigParams

    angles = np.radians([0.0, 120.0, 240.0])
    normals = np.stack([np.cos(angles), np.sin(angles), np.zeros(3)], axis=1)
    return disturb.disturb(row, {}, SimpleNamespace(mu_s=0.6, k_t=1000.0), RigParams(noise_steps=0.0),
                           0.05 * normals, normals, np.ones(3), np.zeros(3), mass, budget_s,
                           budget_k, base, np.random.default_rng(0))


def test_a_lateral_ramp_slips_on_the_friction_circle_and_is_read_at_2_mm():
    """With 1.2 N of the 2.0 N static budget carrying the weight, the lateral pull the budget has
    left is sqrt(2.0^2 - 1.2^2) = 1.6 N (the friction circle). Past it the object slides under
    (2.0 - 1.5) N / 0.2 kg = 2.5 m/s^2 and reaches the 2 mm detection after sqrt(2 x 2 mm / 2.5)
    = 40 ms, by which a 5 N/s ramp adds 0.2 N: 1.80 N read (by hand)."""
    row = {"block": "A", "disturbance_kind": "lateral", "ramp_rate_n_per_s": 5.0, "ramp_cap_n": 15.0,
           "proof_force_n": 0.5}
    out = _held(row)["measures"]
    assert out["threshold_measured_n"] == pytest.approx(1.80, abs=1e-9)
    assert not out["threshold_censored"]


def test_a_torsion_ramp_below_its_cap_is_measured_not_censored():
    """The same 1.6 N at the contacts' 50 mm is 0.08 N m, far below the 1 N m cap (20 N at the
    contacts); a 0.1 N m/s ramp (2 N/s there) adds 2 N/s x 40 ms x 50 mm = 0.004 N m before the
    detection: 0.084 N m, read at the 0.005 N m resolution as 0.085 (by hand)."""
    row = {"block": "C", "disturbance_kind": "yaw", "torque_ramp_nm_per_s": 0.1, "torque_cap_nm": 1.0,
           "proof_torque_nm": 0.01}
    out = _held(row)["measures"]
    assert not out["threshold_censored"]
    assert out["threshold_measured_nm"] == pytest.approx(0.085, abs=1e-9)


def test_a_vertical_load_lasts_its_ramp_and_its_hold():
    """1 N ramped at 0.5 N/s, then held 3 s: 5 s under load (by hand)."""
    row = {"block": "B", "disturbance_kind": "down", "load_n": 1.0, "ramp_rate_n_per_s": 0.5, "hold_s": 3.0}
    assert _held(row, budget_s=5.0)["duration"] == pytest.approx(5.0)


def test_an_impulse_is_a_raised_cosine_pulse_of_its_width(monkeypatch):
    """§9.1 (D): impulsive raised-cosine pulses of 100 and 200 ms. The load sliding sees rises
    from 0 to its 3 N peak at half the 100 ms width and back to 0 at its end; its impulse is
    3 N x 0.1 s / 2 = 0.15 N s (the mean of a raised cosine is half its peak)."""
    seen = {}

    def record(times, lateral, *args):
        seen.update(times=times, lateral=lateral)
        return disturb.SlideResult(0.0, False, 0.0)

    monkeypatch.setattr(disturb, "slide", record)
    _held({"block": "D", "disturbance_kind": "lateral", "load_n": 3.0, "pulse_duration_ms": 100.0})
    t, f = seen["times"], seen["lateral"]
    assert f.max() == pytest.approx(3.0, rel=1e-3) and t[np.argmax(f)] == pytest.approx(0.05, abs=2e-3)
    assert f[np.searchsorted(t, 0.1) - 1] == pytest.approx(0.0, abs=0.01)
    assert np.trapezoid(f, t) == pytest.approx(0.15, rel=0.01)
