"""Tests for the contact law (Eq. 13-16)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.differentiate import derivative

from graspcampaign.core.contact import (
    BENCH_RESTITUTION,
    GRASP_APPROACH_SPEED,
    NOMINAL_CONTACT,
    TABLE3_CONTACT,
    ContactParams,
    StickSlipParams,
    StickSlipState,
    contact_damping_c,
    depth_for_force,
    normal_force,
    normal_stiffness,
    tangential_force,
)


def test_damping_matches_spec_check_value():
    # SPEC §1: lambda2 = 0.88, R = 5 mm -> C = 4 pi 0.005 0.88 = 0.0553 N s/m
    # (Table 4 measures 0.055-0.062).
    params = ContactParams(lambda1=1.0, lambda2=0.88, n=1.0, fingertip_radius=5e-3)
    assert params.c_n_s_per_m == pytest.approx(0.0553, abs=5e-5)
    assert contact_damping_c(0.88, 5e-3) == pytest.approx(0.05529203, rel=1e-7)


def test_stiffness_uses_mpa_and_mm():
    # Psi from Table 2: python -c "print(1/((1-0.5**2)/0.0893e6 + (1-0.45**2)/0.14e6))"
    # -> 70946.7176077189 Pa; K = 2 * 1 * 0.0709467 MPa * sqrt(5 mm).
    assert NOMINAL_CONTACT.psi == pytest.approx(70946.7176077189, rel=1e-12)
    assert NOMINAL_CONTACT.k_n_per_mm_n == pytest.approx(2 * 0.0709467176077189 * np.sqrt(5.0))
    assert TABLE3_CONTACT.k_n_per_mm_n == pytest.approx(0.332 * NOMINAL_CONTACT.k_n_per_mm_n)
    assert (NOMINAL_CONTACT.n, NOMINAL_CONTACT.lambda1, NOMINAL_CONTACT.lambda2) == (1.5, 1.0, 1.0)
    assert (TABLE3_CONTACT.lambda1, TABLE3_CONTACT.lambda2, TABLE3_CONTACT.n) == (
        0.332,
        0.880,
        0.487,
    )


def test_contact_params_validate():
    with pytest.raises(ValueError, match=r"ContactParams.n must be finite and > 0"):
        ContactParams(lambda1=1.0, lambda2=1.0, n=0.0)
    with pytest.raises(ValueError, match=r"nu_object must lie in \[0, 0.5\]"):
        ContactParams(lambda1=1.0, lambda2=1.0, n=1.0, nu_object=0.7)


def test_normal_force_power_term_in_millimetres():
    # 1 mm with K = 2 N/mm^1.5 -> 2 N; 2 mm -> 2 * 2^1.5 N (hand computation of Eq. 13).
    forces = normal_force(np.array([1e-3, 2e-3]), 0.0, 2.0, 1.5, 0.0)
    np.testing.assert_allclose(forces, [2.0, 2.0 * 2.0**1.5])


def test_normal_force_damper_in_metres_per_second_and_clamp():
    # K delta^n + C delta_dot with delta_dot in m/s: 2 + 0.05 * 0.1 = 2.005 N.
    assert normal_force(1e-3, 0.1, 2.0, 1.5, 0.05) == pytest.approx(2.005)
    # A fast separation would pull: the max(0, .) clamp removes it.
    assert normal_force(1e-3, -100.0, 2.0, 1.5, 0.05) == 0.0
    # Open contacts carry nothing, whatever their rate.
    np.testing.assert_array_equal(normal_force([0.0, -1e-3], [1.0, 1.0], 2.0, 1.5, 0.05), 0.0)


@settings(max_examples=40, deadline=None)
@given(
    depth=st.floats(1e-5, 5e-2),
    k=st.floats(0.01, 5.0),
    n=st.floats(0.1, 2.0),
)
def test_normal_stiffness_is_derivative_per_metre(depth, k, n):
    def elastic(d):
        return normal_force(d, 0.0, k, n, 0.0)

    reference = derivative(elastic, depth, initial_step=depth / 10)
    assert normal_stiffness(depth, k, n) == pytest.approx(reference.df, rel=1e-6)


def test_normal_stiffness_at_zero_depth_is_one_sided():
    np.testing.assert_array_equal(
        normal_stiffness(0.0, 2.0, np.array([0.5, 1.0, 1.5])), [np.inf, 2000.0, 0.0]
    )


FRICTION = StickSlipParams(mu_s=0.5, mu_k=0.4, k_t=100.0, c_t=0.0)
UP = np.array([[0.0, 0.0, 1.0]])


def test_stick_below_the_cone_is_elastic():
    state = StickSlipState.initial(np.zeros((1, 3)))
    # Displacement 1 mm along x plus a normal component the tangent plane must ignore.
    point = np.array([[1e-3, 0.0, 5e-3]])
    forces, new = tangential_force(state, FRICTION, point, np.array([1.0]), np.zeros((1, 3)), UP)
    np.testing.assert_allclose(forces, [[-0.1, 0.0, 0.0]])  # -k_t xi, |0.1| <= 0.5 * 1
    assert not new.sliding[0]
    np.testing.assert_array_equal(new.anchors, state.anchors)


def test_slip_opposes_velocity_at_kinetic_level_and_saturates_anchor():
    state = StickSlipState.initial(np.zeros((1, 3)))
    point = np.array([[0.0, 1e-2, 0.0]])  # k_t xi = 1 N > mu_s f_n = 0.5 N
    velocity = np.array([[0.0, 0.2, 0.0]])
    forces, new = tangential_force(state, FRICTION, point, np.array([1.0]), velocity, UP)
    np.testing.assert_allclose(forces, [[0.0, -0.4, 0.0]])  # -mu_k f_n V_t/|V_t| (Eq. 15)
    assert new.sliding[0]
    # The state is pure: the input anchors are untouched.
    np.testing.assert_array_equal(state.anchors, 0.0)
    # Anchor dragged so the elastic force equals the sliding force; at rest it now sticks there.
    again, after = tangential_force(new, FRICTION, point, np.array([1.0]), np.zeros((1, 3)), UP)
    np.testing.assert_allclose(again, forces, atol=1e-12)
    assert not after.sliding[0]


def test_unloaded_contact_carries_no_friction():
    state = StickSlipState(anchors=np.zeros((2, 3)), sliding=np.zeros(2, dtype=bool))
    points = np.array([[1e-3, 0, 0], [0, 0, 0]], dtype=float)
    forces, new = tangential_force(
        state, FRICTION, points, np.zeros(2), np.zeros((2, 3)), np.repeat(UP, 2, axis=0)
    )
    np.testing.assert_array_equal(forces, 0.0)
    np.testing.assert_allclose(new.anchors, points)


def test_stick_slip_validation():
    with pytest.raises(ValueError, match=r"k_t must be > 0"):
        StickSlipParams(mu_s=0.5, mu_k=0.5, k_t=0.0)
    with pytest.raises(ValueError, match=r"shape \(c, 3\), got \(3,\)"):
        StickSlipState.initial(np.zeros(3))


@settings(max_examples=30, deadline=None)
@given(force=st.floats(1e-3, 100.0), k=st.floats(0.01, 5.0), n=st.floats(0.1, 2.0))
def test_depth_for_force_inverts_the_elastic_term(force, k, n):
    depth = depth_for_force(force, k, n)
    assert normal_force(depth, 0.0, k, n, 0.0) == pytest.approx(force, rel=1e-9)


# ---------------------------------------------------------------- original Hunt-Crossley damping


@pytest.mark.parametrize("rate", [0.002, 0.02, 1.0])
def test_hunt_crossley_has_no_force_step_at_contact_onset_and_linear_has(rate):
    params = ContactParams.table3()
    k, n, c = params.k_n_per_mm_n, params.n, params.c_n_s_per_m
    depths = np.array([1e-6, 1e-10, 1e-14, 1e-20])  # m, approaching contact onset
    original = normal_force(depths, rate, k, n, c, "hunt_crossley", params.alpha_hc_s_per_m)
    linear = normal_force(depths, rate, k, n, c)
    # original: f = K delta^n (1 + 1.5 alpha delta_dot) -> 0 with delta (like delta^n, n = 0.487),
    # for any closing rate
    assert np.all(np.diff(original) < 0.0) and original[-1] < 1e-4 * c * rate
    np.testing.assert_allclose(original[1:] / original[:-1], (depths[1:] / depths[:-1]) ** n)
    # paper's form (Sec. 3.5 / 5.1): a finite step C delta_dot survives as delta -> 0+
    np.testing.assert_allclose(linear[-1], c * rate, rtol=1e-3)
    assert normal_force(0.0, rate, k, n, c) == 0.0  # open contact: no force at all


@given(depth=st.floats(1e-6, 5e-3), k=st.floats(0.05, 5.0), n=st.floats(0.3, 1.6),
       alpha=st.floats(0.0, 50.0))
def test_both_damping_laws_agree_in_statics(depth, k, n, alpha):
    linear = normal_force(depth, 0.0, k, n, 0.06)
    original = normal_force(depth, 0.0, k, n, 0.06, "hunt_crossley", alpha)
    assert original == pytest.approx(linear, rel=1e-12)
    assert linear == pytest.approx(k * (depth * 1e3) ** n, rel=1e-12)  # K delta_mm^n


def test_default_alpha_reproduces_the_bench_restitution_at_the_closing_speed():
    # A 10 g mass hits the Table 3 contact at v_i = 20 mm/s; with alpha = (1 - e)/v_i the rebound
    # speed ratio must come back near e = 0.882 (the relation is first order in 1 - e).
    from scipy.integrate import solve_ivp

    params = ContactParams.table3(damping_law="hunt_crossley")
    mass, v_in = 0.01, GRASP_APPROACH_SPEED

    def rhs(t, y):
        f = normal_force(max(y[0], 0.0), y[1], params.k_n_per_mm_n, params.n, 0.0,
                         "hunt_crossley", params.alpha_hc_s_per_m)
        return [y[1], -f / mass]

    def separation(t, y):
        return y[0]

    separation.terminal, separation.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 1.0), [1e-12, v_in], events=separation, rtol=1e-10, atol=1e-15,
                    max_step=1e-4)
    e = -sol.y_events[0][0][1] / v_in
    assert e == pytest.approx(BENCH_RESTITUTION, abs=0.015)
    assert params.alpha_hc_s_per_m == pytest.approx((1 - 0.882) / 0.02)


def test_damping_law_validation():
    with pytest.raises(ValueError, match="^ContactParams.damping_law must be one of linear, "
                                         "hunt_crossley, got 'quadratic'$"):
        ContactParams.table3(damping_law="quadratic")
    with pytest.raises(ValueError, match="^damping_law must be one of linear, hunt_crossley, "
                                         "got 'x'$"):
        normal_force(1e-3, 0.0, 1.0, 0.5, 0.05, "x")
