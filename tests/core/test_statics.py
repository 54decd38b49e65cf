"""Tests of core.statics: wrench residual, friction-cone LP feasibility, horizontal audit.

Outside references: closed-form statics (a pinch needs mu f_n >= m g / 2 per finger; a block on an
incline needs mu >= tan(theta)), and the §12 horizontal audit of the paper (>= 1.6 at mu = 0.1).
"""

from __future__ import annotations

import numpy as np
import pytest

from graspcampaign.core import statics, statics_audit

G = 9.81
RADIUS = 0.05
# The paper's dynamic optimum (§5.2, Fig. 8, §6.1): two contacts 45 deg above the equator,
# diametrically opposite in azimuth, the third at the bottom pole.
DIRECTIONS_45_45_M90 = np.array(
    [[np.cos(np.pi / 4), 0.0, np.sin(np.pi / 4)], [-np.cos(np.pi / 4), 0.0, np.sin(np.pi / 4)], [0, 0, -1.0]]
)


def test_wrench_residual_is_force_plus_weight_and_torque_about_the_centre():
    center = np.array([0.0, 0.0, 0.01])
    np.testing.assert_allclose(
        statics.wrench_residual([[0.0, 0.0, 0.01]], [[0.0, 0.0, 0.2 * G]], 0.2, center), 0.0,
        atol=1e-12,
    )
    residual = statics.wrench_residual([[0.1, 0.0, 0.01]], [[0.0, 0.0, 1.0]], 0.0, center)
    # r x f = (0.1, 0, 0) x (0, 0, 1) = (0, -0.1, 0)
    np.testing.assert_allclose(residual, [0, 0, 1.0, 0, -0.1, 0], atol=1e-12)


def test_check_contacts_rejects_bad_shapes():
    with pytest.raises(ValueError, match=r"points must have shape \(c, 3\), got \(3,\)"):
        statics.check_contacts(np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match="normals must be non-zero"):
        statics.check_contacts(np.zeros((1, 3)), np.zeros((1, 3)))


@pytest.mark.parametrize("mu", [0.1, 0.3, 0.5])
@pytest.mark.parametrize("mass", [0.2, 0.4, 0.6])
def test_45_45_m90_set_is_statically_feasible_at_all_nine_combinations(mu, mass):
    points, normals = statics.sphere_contacts_from_directions(DIRECTIONS_45_45_M90, RADIUS)
    result = statics.friction_cone_feasibility(points, normals, mu, mass)
    assert result.status == "feasible"
    np.testing.assert_allclose(result.residual, 0.0, atol=1e-9)
    assert np.all(result.normal_forces >= -1e-12)
    assert np.all(result.tangential_forces <= mu * result.normal_forces + 1e-9)


def test_45_45_m90_set_stays_feasible_as_mu_goes_to_zero():
    # §6.1: "on this contact set the normal directions alone can carry the weight".
    points, normals = statics.sphere_contacts_from_directions(DIRECTIONS_45_45_M90, RADIUS)
    result = statics.friction_cone_feasibility(points, normals, 0.0, 0.6)
    assert result.status == "feasible"
    # Minimum-grip solution: the bottom finger carries the weight alone.
    np.testing.assert_allclose(result.normal_forces, [0.0, 0.0, 0.6 * G], atol=1e-9)
    assert statics.required_friction(points, normals, 0.6) == 0.0
    # With every finger pushing at least 1 N the top pair adds sqrt(2) N downward: bottom = mg + sqrt 2.
    squeezed = statics.friction_cone_feasibility(points, normals, 0.0, 0.6, min_normal_force=1.0)
    np.testing.assert_allclose(squeezed.normal_forces, [1.0, 1.0, 0.6 * G + np.sqrt(2.0)], atol=1e-9)


def test_equatorial_pinch_needs_friction_and_squeezes_mg_over_two_mu():
    points, normals = statics.sphere_contacts_from_directions([[1.0, 0, 0], [-1.0, 0, 0]], RADIUS)
    assert statics.friction_cone_feasibility(points, normals, 0.0, 0.4).status == "infeasible"
    mu = 0.2
    result = statics.friction_cone_feasibility(points, normals, mu, 0.4, n_facets=16)
    assert result.status == "feasible"
    # Vertical friction lies on a facet normal of the inscribed 16-gon: rho = cos(pi/16).
    expected = 0.4 * G / (2 * mu * np.cos(np.pi / 16))
    np.testing.assert_allclose(result.normal_forces, expected, rtol=1e-7)


def test_block_on_an_incline_brackets_mu_equal_tan_theta():
    theta = np.radians(20.0)
    n_out = np.array([np.sin(theta), 0.0, -np.cos(theta)])  # tilted bottom face
    tangent = np.array([np.cos(theta), 0.0, np.sin(theta)])
    side = np.array([0.0, 1.0, 0.0])
    base = -0.03 * n_out
    points = np.array(
        [base + 0.02 * tangent, base - 0.01 * tangent + 0.02 * side, base - 0.01 * tangent - 0.02 * side]
    )
    normals = np.tile(n_out, (3, 1))
    tan = np.tan(theta)
    assert statics.friction_cone_feasibility(points, normals, 0.95 * tan, 0.3).status == "infeasible"
    assert statics.friction_cone_feasibility(points, normals, 1.01 * tan, 0.3).status == "undetermined"
    assert statics.friction_cone_feasibility(points, normals, 1.05 * tan, 0.3).status == "feasible"
    required = statics.required_friction(points, normals, 0.3)
    assert tan <= required <= tan / np.cos(np.pi / 16) + 1e-6


def test_min_horizontal_residual_reproduces_the_papers_audit_of_fig13():
    # §12: with relative magnitudes 0.4 / 4.9 / 11.9 on the 45/45/-90 set no cone-admissible
    # friction closes the horizontal balance; minimum ~1.6 at mu = 0.1. Closed form: the normals
    # leave 4.9 cos45 - 0.4 cos45 = 3.18 along x; friction can remove at most
    # 0.1 (0.4 cos45 + 4.9 cos45 + 11.9) = 1.565, leaving 1.617.
    normals = DIRECTIONS_45_45_M90
    residual = statics_audit.min_horizontal_residual(normals, [0.4, 4.9, 11.9], mu=0.1)
    expected = 4.5 * np.cos(np.pi / 4) - 0.1 * (5.3 * np.cos(np.pi / 4) + 11.9)
    assert residual == pytest.approx(expected, rel=5e-3)
    assert residual == pytest.approx(1.6, abs=0.05)
    held = statics_audit.min_horizontal_residual(normals, [0.4, 4.9, 11.9], mu=0.5)
    assert held == pytest.approx(0.0, abs=1e-9)


def _tilt(vector, axis, angle_deg):
    """Rotate ``vector`` about the unit ``axis`` by ``angle_deg`` (Rodrigues)."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    a = np.radians(angle_deg)
    v = np.asarray(vector, float)
    return v * np.cos(a) + np.cross(k, v) * np.sin(a) + k * np.dot(k, v) * (1.0 - np.cos(a))


@pytest.mark.parametrize("mass", [0.2, 0.4, 0.6])
def test_ideal_sphere_normals_are_feasible_at_mu_zero(mass):
    points, normals = statics.sphere_contacts_from_directions(DIRECTIONS_45_45_M90, RADIUS)
    diagnosis = statics_audit.frictionless_diagnosis(points, normals, mass)
    assert diagnosis.status == "feasible" and diagnosis.reason == "feasible"
    np.testing.assert_allclose(diagnosis.off_radial_deg, 0.0, atol=1e-6)
    assert diagnosis.torque_residual == pytest.approx(0.0, abs=1e-12)


def test_a_normal_off_radial_in_the_plane_of_the_fingers_breaks_only_the_torque_balance():
    # Bottom normal tilted 3 deg about y: the three normals still span the xz plane with positive
    # combinations (force balance holds), but the bottom line of action misses the centre by
    # R sin 3 deg, so its force has a moment (0, R f3 sin 3 deg, 0) that nothing cancels.
    points, normals = statics.sphere_contacts_from_directions(DIRECTIONS_45_45_M90, RADIUS)
    normals[2] = _tilt(normals[2], [0.0, 1.0, 0.0], 3.0)
    diagnosis = statics_audit.frictionless_diagnosis(points, normals, 0.4)
    assert diagnosis.status == "infeasible"
    assert diagnosis.force_only_status == "feasible" and diagnosis.reason == "torque_balance"
    np.testing.assert_allclose(diagnosis.off_radial_deg, [0.0, 0.0, 3.0], atol=1e-9)
    assert diagnosis.torque_residual > 0.0
    # Friction heals it: the same set is feasible at mu = 0.1 (tan 3 deg = 0.052 < 0.1).
    assert statics.friction_cone_feasibility(points, normals, 0.1, 0.4).status == "feasible"


def test_normals_all_leaning_to_one_side_break_the_force_balance():
    # Every normal tilted 2 deg toward -y (about n x (-y)): the pushes -f n all have a +y
    # component, so no non-negative forces cancel in y, torque or not.
    points, normals = statics.sphere_contacts_from_directions(DIRECTIONS_45_45_M90, RADIUS)
    normals = np.array([_tilt(n, np.cross(n, [0.0, -1.0, 0.0]), 2.0) for n in normals])
    assert np.all(normals[:, 1] < 0.0)
    diagnosis = statics_audit.frictionless_diagnosis(points, normals, 0.4)
    assert diagnosis.reason == "force_balance" and diagnosis.force_only_status == "infeasible"
    assert diagnosis.torque_residual is None
    np.testing.assert_allclose(diagnosis.off_radial_deg, 2.0, atol=1e-9)


def test_the_356_node_sphere_fails_at_mu_zero_in_the_force_balance():
    """The like-for-like contact set of friction_mass: facet normals 2.5-4.8 deg off radial, all
    leaning to -y, so the mu = 0 infeasibility is a force (not torque) imbalance."""
    from graspcampaign.core.hand import hand_contact_directions, planned_contacts
    from graspcampaign.core.mesh import make_object

    mesh = make_object("sphere", 356)
    points, _, normals = planned_contacts(mesh, hand_contact_directions())
    diagnosis = statics_audit.frictionless_diagnosis(points, normals, 0.4, mesh.centroid)
    assert np.all((diagnosis.off_radial_deg > 2.4) & (diagnosis.off_radial_deg < 4.8))
    assert np.all(normals[:, 1] < 0.0)
    assert diagnosis.reason == "force_balance"
