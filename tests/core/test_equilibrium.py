"""Tests for the quasi-static evaluator (Algorithms 1-2, §6.1)."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from graspcampaign.core.contact import NOMINAL_CONTACT, TABLE3_CONTACT
from graspcampaign.core.equilibrium import (
    FAILURE_CHECKS,
    EvaluatorParams,
    evaluate_grasps,
    static_checks,
)

RADIUS = 0.05
ORIGIN = np.zeros(3)


def ring(latitude_deg, azimuth0_deg=0.0, radius=RADIUS):
    """Three contacts on a sphere at one latitude, 120 deg apart: points and outward normals."""
    lat = np.radians(latitude_deg)
    az = np.radians(azimuth0_deg + np.array([0.0, 120.0, 240.0]))
    normals = np.stack([np.cos(lat) * np.cos(az), np.cos(lat) * np.sin(az), np.full(3, np.sin(lat))], axis=1)
    return radius * normals, normals


@pytest.mark.parametrize("contact", [NOMINAL_CONTACT, TABLE3_CONTACT], ids=["n1.5", "n0.487"])
@pytest.mark.parametrize("latitude", [-20.0, -45.0, -70.0])
def test_symmetric_sphere_grasp_balances_vertically(contact, latitude):
    points, normals = ring(latitude)
    mass, mu = 0.4, 0.3
    result = evaluate_grasps(points, normals, ORIGIN, mass, mu, contact.k_n_per_mm_n, contact.n)
    assert abs(result.residual_z[0]) < 1e-6
    # Closed form: 3 f sin|lat| = m g and f = K delta_mm^n (Eq. 13).
    force = mass * 9.81 / (3 * np.sin(np.radians(-latitude)))
    np.testing.assert_allclose(result.normal_forces[0], force, rtol=1e-9)
    depth_mm = (force / contact.k_n_per_mm_n) ** (1 / contact.n)
    np.testing.assert_allclose(result.depths[0] * 1e3, depth_mm, rtol=1e-8)
    # The three checks pass; the verdict also needs every contact within the 5 mm fingertip
    # radius (the nominal law at -20 deg needs 5.25 mm: a pass of the checks, gated away).
    assert result.success_unbounded[0]
    assert result.valid_geometry[0] == (depth_mm <= 5.0)
    assert result.success[0] == (depth_mm <= 5.0)
    expected_label = "none" if depth_mm <= 5.0 else "geometry"
    assert FAILURE_CHECKS[result.failure_check[0]] == expected_label
    assert result.delta_max_mm[0] == pytest.approx(depth_mm, rel=1e-8)
    # Radial normals through the centre: no torque; normals already carry the weight: eta ~ 0.
    assert result.torque_norm[0] < 1e-9
    assert abs(result.eta[0]) < 1e-9
    assert result.slip_margin[0] == pytest.approx(mu * force, rel=1e-6)
    assert 0 < result.iterations[0] <= 100


def test_gradient_is_per_metre_newton_step():
    # For the linear law (n = 1) alpha = 2 is the exact Newton step on R_z: one iteration
    # closes the residual. Mixing mm and m in line 7 would overshoot by 1000x instead.
    points, normals = ring(-30.0)
    params = EvaluatorParams(alpha=2.0, n_max=1, eps=1e-12)
    result = evaluate_grasps(points, normals, ORIGIN, 0.3, 0.5, 0.5, 1.0, params)
    assert abs(result.residual_z[0]) < 1e-9


@pytest.mark.parametrize("mu", [0.1, 0.3, 0.5])
def test_horizontal_normals_leave_depth_at_seed(mu):
    # §6.5: centroid-equilateral placement, every n_z = 0 -> g = 0 -> delta never moves, and the
    # run fails the residual (first) and the slip check at every mu.
    points, normals = ring(0.0, azimuth0_deg=17.0)
    params = EvaluatorParams()
    result = evaluate_grasps(
        points,
        normals,
        ORIGIN,
        0.2,
        mu,
        TABLE3_CONTACT.k_n_per_mm_n,
        TABLE3_CONTACT.n,
        record_trace=True,
    )
    np.testing.assert_array_equal(result.depths, params.seed_depth)
    np.testing.assert_array_equal(result.trace.depths, params.seed_depth)
    assert result.iterations[0] == 0
    assert result.failure_labels()[0] == "residual"
    assert not result.slip_ok[0] and result.eta[0] > mu
    assert result.residual_norm[0] == pytest.approx(0.2 * 9.81, rel=1e-9)


@settings(max_examples=60, deadline=None)
@given(
    normals_raw=st.lists(st.floats(-1.0, 1.0), min_size=9, max_size=9),
    depths_mm=st.lists(st.floats(0.01, 50.0), min_size=3, max_size=3),
    mass=st.floats(0.05, 1.0),
)
def test_uniform_utilisation_closes_vertical_balance(normals_raw, depths_mm, mass):
    normals = np.reshape(normals_raw, (3, 3))
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.where(lengths > 1e-3, normals / np.maximum(lengths, 1e-3), [1.0, 0.0, 0.0])
    if np.all(np.abs(normals[:, 2]) > 1 - 1e-6):
        normals[0] = [1.0, 0.0, 0.0]  # at least one non-vertical contact (§6.1)
    points = 0.05 * normals
    depths = np.asarray(depths_mm)[None] * 1e-3
    result = static_checks(points, normals, ORIGIN, mass, 0.3, depths, 0.3, 1.5)
    assert abs(result.post_friction_residual_z[0]) < 1e-9 * max(1.0, np.abs(result.residual_z[0]))
    # eta from the vertical balance with t_hat the unit projection of +z on each tangent plane.
    tangents = np.array([0.0, 0.0, 1.0]) - normals[:, 2:3] * normals
    t_z = np.linalg.norm(tangents, axis=1)
    t_z[np.abs(normals[:, 2]) >= 1 - EvaluatorParams().normal_z_tol] = 0.0  # float-noise guard
    expected = -result.residual_z[0] / np.sum(result.normal_forces[0] * t_z)
    assert result.eta[0] == pytest.approx(expected, rel=1e-9)


def test_vertical_contact_is_excluded_from_slip_margin():
    # A contact at the bottom pole pushes straight up: no tangent plane direction (§6.1).
    normals = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])
    points = RADIUS * normals
    depths = np.array([[1e-3, 2e-3, 2e-3]])
    result = static_checks(points, normals, ORIGIN, 0.2, 0.5, depths, 0.3, 1.5)
    forces = result.normal_forces[0]
    eta = (0.2 * 9.81 - forces[0]) / (forces[1] + forces[2])
    assert result.eta[0] == pytest.approx(eta)
    assert result.slip_margin[0] == pytest.approx(min(forces[1:]) * (0.5 - abs(eta)))
    assert result.slip_margin_ratio[0] == pytest.approx(1 - abs(eta) / 0.5)


def test_all_vertical_normals_give_empty_slip_minimum():
    normals = np.array([[0.0, 0.0, -1.0]] * 3)
    result = static_checks(RADIUS * normals, normals, ORIGIN, 0.1, 0.5, [[1e-3] * 3], 0.3, 1.5)
    assert np.isnan(result.eta[0]) and result.slip_margin[0] == np.inf and result.slip_ok[0]


def test_frictionless_contacts_are_judged_without_numpy_warnings():
    # mu = 0 (allowed: core.plausible): 1 - |eta|/mu takes its limits, -inf for any tangential
    # demand (friction is needed and there is none); an unloaded row keeps the empty minimum
    points, normals = ring(-30.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = static_checks(np.stack([points] * 2), np.stack([normals] * 2), ORIGIN, 0.3, 0.0,
                               [[1e-3] * 3, [0.0] * 3], 0.3, 1.5)
    assert result.eta[0] != 0.0 and result.slip_margin_ratio[0] == -np.inf
    assert not result.slip_ok[0]
    assert np.isnan(result.eta[1]) and result.slip_margin_ratio[1] == np.inf


def test_torque_about_centroid():
    # Normals not through the centroid: tau = sum r x f n_hat, compared with a hand cross product.
    points = np.array([[0.05, 0.0, 0.0], [-0.05, 0.01, 0.0], [0.0, 0.0, -0.05]])
    normals = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
    depths = np.array([[1e-3, 2e-3, 1e-3]])
    result = static_checks(points, normals, ORIGIN, 0.1, 0.5, depths, 0.3, 1.5)
    f = result.normal_forces[0]
    tau = sum(np.cross(points[k], -normals[k] * f[k]) for k in range(3))
    assert result.torque_norm[0] == pytest.approx(np.linalg.norm(tau))
    assert result.torque_norm[0] > 0


def test_failure_check_order_and_labels():
    points, normals = ring(-45.0)
    # Shift the centroid sideways: radial forces (net m g up) now carry a torque about it.
    result = evaluate_grasps(points, normals, [0.01, 0.0, 0.0], 0.3, 0.5, 0.3, 1.5)
    assert result.torque_norm[0] == pytest.approx(0.01 * 0.3 * 9.81, rel=1e-6)
    assert result.residual_ok[0] and not result.torque_ok[0]
    assert result.failure_labels().tolist() == ["torque"]


def test_batch_equals_one_by_one_with_per_candidate_parameters():
    rng = np.random.default_rng(3)
    normals = rng.normal(size=(6, 3, 3))
    normals /= np.linalg.norm(normals, axis=2, keepdims=True)
    points = RADIUS * normals
    k = rng.uniform(0.05, 0.5, 6)
    n = rng.uniform(0.2, 1.6, 6)
    mass = rng.uniform(0.1, 0.6, 6)
    batch = evaluate_grasps(points, normals, ORIGIN, mass, 0.3, k, n, record_trace=True)
    for b in range(6):
        single = evaluate_grasps(points[b], normals[b], ORIGIN, mass[b], 0.3, k[b], n[b])
        np.testing.assert_array_equal(single.depths[0], batch.depths[b])
        assert single.failure_check[0] == batch.failure_check[b]
        assert single.iterations[0] == batch.iterations[b]
    assert np.all(np.isfinite(batch.depths)) and np.all(batch.depths >= 0)
    assert batch.trace.residual_norm.shape == (6, 100)
    assert batch.trace.normal_forces.shape == (6, 100, 3)


def test_released_contact_with_sublinear_law_does_not_freeze_the_loop():
    # A top contact pushes down; the first step releases it (delta = 0). With n < 1 its literal
    # gradient is infinite; it must stay released while the two lower contacts carry the weight.
    lat = np.radians([45.0, -45.0, -45.0])
    az = np.radians([0.0, 180.0, 180.0]) + np.array([0.0, 0.3, -0.3])
    normals = np.stack([np.cos(lat) * np.cos(az), np.cos(lat) * np.sin(az), np.sin(lat)], axis=1)
    result = evaluate_grasps(
        RADIUS * normals, normals, ORIGIN, 0.2, 0.5, TABLE3_CONTACT.k_n_per_mm_n, TABLE3_CONTACT.n
    )
    assert result.depths[0, 0] == 0.0 and result.normal_forces[0, 0] == 0.0
    assert abs(result.residual_z[0]) < 1e-6
    assert np.all(np.isfinite(result.depths))


def test_trace_starts_at_seed_residual():
    points, normals = ring(-30.0)
    result = evaluate_grasps(points, normals, ORIGIN, 0.4, 0.3, 0.3, 1.5, record_trace=True)
    seed_force = 0.3 * 0.5**1.5
    expected = 3 * seed_force * np.sin(np.radians(30.0)) - 0.4 * 9.81
    assert result.trace.residual_z[0, 0] == pytest.approx(expected)
    assert result.trace.normal_forces[0, 0, 0] == pytest.approx(seed_force)
    assert abs(result.trace.residual_z[0, -1]) < 1e-6


def test_input_validation():
    points, normals = ring(-30.0)
    with pytest.raises(ValueError, match=r"points must have shape \(b, 3, 3\), got \(3,\)"):
        evaluate_grasps(points[0], normals, ORIGIN, 0.4, 0.3, 0.3, 1.5)
    with pytest.raises(ValueError, match=r"normals must be unit vectors"):
        evaluate_grasps(points, 2 * normals, ORIGIN, 0.4, 0.3, 0.3, 1.5)
    with pytest.raises(ValueError, match=r"mass must be a scalar or have shape \(1,\)"):
        evaluate_grasps(points, normals, ORIGIN, [0.4, 0.2], 0.3, 0.3, 1.5)
    with pytest.raises(ValueError, match=r"alpha must be finite and > 0"):
        EvaluatorParams(alpha=0.0)
    # The fixed-grip checks share the evaluator's validation of the contact law.
    with pytest.raises(ValueError, match=r"k_n_per_mm_n and n must be finite and > 0"):
        static_checks(points, normals, ORIGIN, 0.4, 0.3, [[1e-3] * 3], 0.0, 1.5)


def test_residual_check_reading_vertical_versus_norm():
    # Two upward contacts tilted unequally: Algorithm 2 closes R_z but leaves a horizontal
    # residual, which fails |R| < tau_F (SPEC §2.7) and passes |R_z| < tau_F (§6.2 prose).
    lat = np.radians([-60.0, -20.0, 45.0])
    az = np.radians([0.0, 150.0, 260.0])
    normals = np.stack([np.cos(lat) * np.cos(az), np.cos(lat) * np.sin(az), np.sin(lat)], axis=1)
    args = (RADIUS * normals, normals, ORIGIN, 0.3, 0.5, 0.3, 1.5)
    norm = evaluate_grasps(*args)
    vertical = evaluate_grasps(*args, EvaluatorParams(residual_check="vertical"))
    assert abs(norm.residual_z[0]) < 1e-6 and norm.residual_norm[0] > 0.5
    assert norm.failure_labels()[0] == "residual" and vertical.residual_ok[0]
    np.testing.assert_array_equal(norm.depths, vertical.depths)
    with pytest.raises(ValueError, match=r"residual_check must be 'norm' or 'vertical'"):
        EvaluatorParams(residual_check="z")
