"""Disturbance statics and grip sizing (paper §8.1, §9.1) against closed forms and scipy."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from graspcampaign.core import disturbance as d
from graspcampaign.core.statics import GRAVITY


def _cone(tilt_rad: float, phase: float = 0.0) -> np.ndarray:
    """Three outward normals at 120 deg azimuth, all tilted by the same angle from horizontal."""
    az = phase + np.radians([0.0, 120.0, 240.0])
    return np.stack([np.cos(tilt_rad) * np.cos(az), np.cos(tilt_rad) * np.sin(az),
                     np.full(3, np.sin(tilt_rad))], axis=1)


def test_safety_factor_closed_form_and_inverse():
    # SF = 3 mu F G kappa / (W (1 + a/g)), worked by hand: 3*0.6*1.2*0.9*2.4/(0.3*9.81*1.0306)
    sf = d.safety_factor(0.6, 1.2, 0.9, 0.3, a_lift=0.3)
    assert sf == pytest.approx(3 * 0.6 * 1.2 * 0.9 * 2.4 / (0.3 * 9.81 * (1 + 0.3 / 9.81)))
    grip = d.grip_for_safety_factor(sf, 0.6, 0.9, 0.3, a_lift=0.3)
    assert grip == pytest.approx(1.2)
    assert np.isinf(d.grip_for_safety_factor(1.5, 0.6, 0.0, 0.3))


def test_geometric_efficiency_definition():
    assert d.geometric_efficiency(_cone(0.0)) == pytest.approx(1.0)
    # a balanced cone tilted by theta: each contact's friction reaches up by cos(theta)
    for tilt in (0.2, 0.7, 1.2):
        assert d.geometric_efficiency(_cone(tilt)) == pytest.approx(np.cos(tilt))
    assert d.geometric_efficiency(_cone(np.pi / 2 - 1e-9)) == pytest.approx(0.0, abs=1e-6)
    same_side = np.array([[1.0, 0, 0], [1.0, 0, 0], [1.0, 0, 0]])
    assert d.geometric_efficiency(same_side) == pytest.approx(0.0)
    # batched
    batch = np.stack([_cone(0.0), _cone(0.5)])
    np.testing.assert_allclose(d.geometric_efficiency(batch), [1.0, np.cos(0.5)])


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=9, max_size=9))
def test_geometric_efficiency_in_unit_interval(values):
    normals = np.asarray(values).reshape(3, 3)
    assume(np.all(np.linalg.norm(normals, axis=1) >= 1e-3))
    g = d.geometric_efficiency(normals)
    assert 0.0 <= g <= 1.0 + 1e-12


def test_disturbance_limits_closed_forms():
    sf, w, r = 1.5, 2.943, 0.04
    lim = d.disturbance_limits(sf, w, r)
    assert lim.lateral_force == pytest.approx(w * np.sqrt(sf**2 - 1))
    assert lim.down_force == pytest.approx(w * (sf - 1))
    assert lim.yaw_torque == pytest.approx(w * np.sqrt(sf**2 - 1) * r)
    assert d.disturbance_limits(0.9, w, r) == d.DisturbanceLimits(0.0, 0.0, 0.0)


def test_retention_margin():
    w, r = 2.0, 0.05
    lat = d.disturbance_limits(1.5, w, r).lateral_force
    assert d.retention_margin(1.5, w, r, "lateral", 1.0) == pytest.approx(lat)
    assert d.retention_margin(1.5, w, r, "down", 0.5) == pytest.approx(w * 0.5 / 0.5)
    assert d.retention_margin(1.5, w, r, "up", 1.0) == pytest.approx(1.5 * 2.0 / 1.0)
    assert d.retention_margin(1.5, w, r, "none", 0.0) == 1.5
    with pytest.raises(ValueError, match="kind must be one of"):
        d.retention_margin(1.5, w, r, "sideways", 1.0)


def test_creep_compliance_inverts_the_relaxation_function():
    # For a standard linear solid, the relaxation function G(t) = rho + (1 - rho) exp(-t/tau)
    # and the creep function J satisfy J(t) G(0) + int_0^t G(t - s) J'(s) ds = 1 (Findley 1976).
    rho, tau = 0.64, 7.1
    relax = lambda t: rho + (1 - rho) * np.exp(-t / tau)  # noqa: E731
    dj = lambda s: (1 / rho - 1) * (rho / tau) * np.exp(-rho * s / tau)  # noqa: E731
    for t in (0.5, 3.0, 20.0):
        integral = quad(lambda s, t=t: relax(t - s) * dj(s), 0.0, t)[0]
        total = d.creep_compliance(0.0, rho, tau) * relax(t) + integral
        assert total == pytest.approx(1.0, rel=1e-9)
    assert d.creep_compliance(0.0, rho, tau) == pytest.approx(1.0)
    assert d.creep_compliance(1e6, rho, tau) == pytest.approx(1 / rho)


def test_indentation_and_force_are_inverse():
    k, n = 0.346, 0.473
    depth = d.indentation_from_force(0.4, k, n, creep=1.1)
    assert depth == pytest.approx((0.4 * 1.1 / k) ** (1 / n) * 1e-3)
    assert d.force_at_indentation(depth, k, n, creep=1.1) == pytest.approx(0.4)


def test_size_grip_uncapped_and_capped():
    free = d.size_grip(mu_s=0.7, g_geo=1.0, mass=0.1, k_n_per_mm_n=0.7, n=0.45, cap_depth=6e-3)
    assert not free.capped
    assert free.sf_predicted == pytest.approx(d.SF_TARGET)
    capped = d.size_grip(mu_s=0.5, g_geo=0.6, mass=0.6, k_n_per_mm_n=0.35, n=0.47,
                         cap_depth=2e-3, creep=1.2, max_share=1.3)
    assert capped.capped
    assert capped.grip_force == pytest.approx(0.35 * 2.0**0.47 / 1.2 / 1.3)
    assert capped.depth == pytest.approx(2e-3)
    assert capped.sf_predicted < d.SF_TARGET
    with pytest.raises(ValueError, match="max_share must be positive"):
        d.size_grip(mu_s=0.5, g_geo=0.6, mass=0.6, k_n_per_mm_n=0.35, n=0.47, cap_depth=2e-3,
                    max_share=0.0)


def test_load_sharing():
    forces, ok = d.load_shared_forces([1.0, 1.0, 1.0], _cone(0.3))
    np.testing.assert_allclose(forces, 1.0)
    assert ok
    # two fingers on one side, one opposite: the lone finger takes the horizontal sum
    normals = np.array([[np.cos(0.3), np.sin(0.3), 0], [np.cos(-0.3), np.sin(-0.3), 0],
                        [-1.0, 0.0, 0.0]])
    forces, ok = d.load_shared_forces([1.0, 1.0, 1.0], normals)
    assert ok
    net = (-(normals[:, :2]) * forces[:, None]).sum(axis=0)
    np.testing.assert_allclose(net, 0.0, atol=1e-12)
    _, ok = d.load_shared_forces([1.0, 1.0, 1.0], np.array([[1.0, 0, 0], [1.0, 0.1, 0],
                                                             [1.0, -0.1, 0]]))
    assert not ok


def test_tangential_forces_symmetric_grasp_carry_a_third_each():
    normals = _cone(0.0)
    points = 0.05 * normals
    ft = d.contact_tangential_forces(points, normals, [1, 1, 1], np.zeros(3),
                                     [0, 0, -3.0], np.zeros(3))
    np.testing.assert_allclose(ft, [[0, 0, 1.0]] * 3, atol=1e-12)


def test_tangential_forces_balance_any_grasp():
    rng = np.random.default_rng(3)
    for _ in range(20):
        normals = rng.normal(size=(3, 3))
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        points = 0.04 * normals + 0.005 * rng.normal(size=(3, 3))
        fn = rng.uniform(0.5, 2.0, 3)
        force, moment = rng.normal(size=3), 0.01 * rng.normal(size=3)
        ft = d.contact_tangential_forces(points, normals, fn, np.zeros(3), force, moment)
        np.testing.assert_allclose(np.einsum("ij,ij->i", ft, normals), 0.0, atol=1e-10)
        total = ft - fn[:, None] * normals
        np.testing.assert_allclose(total.sum(axis=0) + force, 0.0, atol=1e-9)
        np.testing.assert_allclose(np.cross(points, total).sum(axis=0) + moment, 0.0, atol=1e-9)


def test_lateral_slip_scale_symmetric_closed_form():
    # Equatorial contacts, weight W, capacity c per contact, pull along finger 1's normal: only
    # fingers 2, 3 can resist it, each with a horizontal tangent at 30 deg to the pull, so
    # slip at F = sqrt(3) sqrt(c^2 - (W/3)^2).
    normals = _cone(0.0)
    points = 0.05 * normals
    w, c = 3.0, 1.68
    scales = d.slip_load_factors(points, normals, [1, 1, 1], np.zeros(3), np.full(3, c),
                                 [0, 0, -w], np.zeros(3), [1.0, 0, 0], np.zeros(3))
    assert np.isinf(scales[0])
    np.testing.assert_allclose(scales[1:], np.sqrt(3) * np.sqrt(c**2 - (w / 3) ** 2))
    assert d.first_slip_finger(points, normals, [1, 1, 1], np.zeros(3), w / GRAVITY, c / 2.4,
                               "lateral", 0.0) in (2, 3)


def test_first_slip_finger_follows_the_weakest_contact():
    normals = _cone(0.0)
    points = 0.05 * normals
    assert d.first_slip_finger(points, normals, [0.5, 1.0, 1.0], np.zeros(3), 0.2, 0.6,
                               "none") == 1
    assert d.first_slip_finger(points, normals, [1.0, 1.0, 0.5], np.zeros(3), 0.2, 0.6,
                               "down") == 3


def test_microslip_limits():
    q, k = 1.2, 2.0e3
    assert d.microslip(0.0, q, k) == 0.0
    assert d.microslip(1e-6, q, k) == pytest.approx(1e-6 * q / k, rel=1e-5)
    assert d.microslip(1.0, q, k) == pytest.approx(1.5 * q / k)
    assert d.microslip(2.0, q, k) == pytest.approx(1.5 * q / k)
