"""Disturbance statics and grip sizing (paper §8.1, §9.1) against closed forms and scipy."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, reject, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from graspcampaign.core import disturbance as d
from graspcampaign.core.statics import GRAVITY, friction_cone_feasibility, required_friction


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


def test_geometric_efficiency_of_balanced_and_degenerate_sets():
    assert d.geometric_efficiency(_cone(0.0), 0.6) == pytest.approx(1.0)
    assert d.geometric_efficiency(_cone(0.0, phase=0.4), 0.1) == pytest.approx(1.0)
    # all three fingers pushing the same way cannot be shared with positive forces
    same_side = np.array([[1.0, 0, 0], [1.0, 0, 0], [1.0, 0, 0]])
    assert d.geometric_efficiency(same_side, 0.6) == 0.0
    assert d.geometric_efficiency(_cone(0.3), 0.0) == 0.0  # no friction, no friction budget
    batch = np.stack([_cone(0.0), _cone(0.5), _cone(-0.5)])
    np.testing.assert_allclose(d.geometric_efficiency(batch, 0.6),
                               [d.geometric_efficiency(b, 0.6) for b in batch])


def test_geometric_efficiency_counts_the_sign_of_nz():
    # An upper contact (n_z > 0) pushes the object down, a lower one holds it up: for the same
    # tilt the lower cone is never worse, and the upper cone's G falls as it steepens, reaching 0
    # once tan(tilt) >= kappa mu (its push outweighs its friction reach).
    mu = 0.4  # kappa mu = 0.96: the upper cone fails at 43.8 deg
    tilts = np.radians([5.0, 15.0, 30.0, 40.0])
    upper = [d.geometric_efficiency(_cone(t), mu) for t in tilts]
    lower = [d.geometric_efficiency(_cone(-t), mu) for t in tilts]
    assert all(a > b for a, b in zip(upper[:-1], upper[1:], strict=True))  # strictly falling
    assert all(lo >= up for lo, up in zip(lower, upper, strict=True))
    assert lower == [1.0] * 4  # a cradle is capped at the paper's range (0, 1]
    assert d.geometric_efficiency(_cone(np.arctan(d.KAPPA * mu) + 1e-3), mu) == 0.0
    # the sign-blind reading (friction reach alone) would rank the two cones equal
    assert upper[2] < np.cos(tilts[2]) - 0.2


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=9, max_size=9), st.floats(0.0, 3.0))
def test_geometric_efficiency_in_unit_interval(values, mu):
    normals = np.asarray(values).reshape(3, 3)
    assume(np.all(np.linalg.norm(normals, axis=1) >= 1e-3))
    g = d.geometric_efficiency(normals, mu)
    assert 0.0 <= g <= 1.0


# ------------------------------------------------------------------ SF and the friction-cone LP
# Relation 1 (module docstring of core.disturbance): static equilibrium inside the cones
# |f_t| <= kappa mu f_n with normal forces f needs V(f) >= W'. Checked against the LP of
# core.statics (scipy HiGHS), which nothing in core.disturbance uses.
KMU = st.floats(0.05, 3.0)


def _unit(v):
    v = np.asarray(v, dtype=float).reshape(3, 3)
    return v / np.linalg.norm(v, axis=1, keepdims=True)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=9, max_size=9), KMU, st.floats(0.05, 1.0))
def test_lp_equilibrium_never_exceeds_the_vertical_capacity(values, mu_eff, mass):
    raw = np.asarray(values).reshape(3, 3)
    assume(np.all(np.linalg.norm(raw, axis=1) >= 1e-2))
    normals = _unit(raw)
    points = 0.05 * normals  # contacts on a 50 mm sphere, outward radial normals
    try:
        lp = friction_cone_feasibility(points, normals, mu_eff, mass)
    except RuntimeError as exc:  # the reference cannot answer: HiGHS reports a solve error (not
        # infeasibility) on some near-degenerate sets, e.g. normals (0, 1.2e-7, 1) and (0, 0, 1),
        # or (0, -6e-8, -1) with (0, -1, 0) and (1, 1, 0)/sqrt 2 -- a core.statics matter
        assert "friction-cone LP failed" in str(exc)
        reject()
    if lp.feasible:  # inner-cone solution: |f_t| <= mu_eff cos(pi/q) f_n <= mu_eff f_n
        capacity = d.vertical_capacity(normals, lp.normal_forces, mu_eff)
        # HiGHS meets every row to its primal feasibility tolerance (1e-7 by default), so the
        # bound holds to ~1e-7 times the forces involved
        assert capacity >= mass * GRAVITY - 1e-6 * (mass * GRAVITY + lp.normal_forces.sum())


def test_the_lp_check_is_not_vacuous():
    # the property above must see feasible sets: ~1/3 of random radial contact sets are
    rng = np.random.default_rng(7)
    feasible = 0
    for _ in range(120):
        normals = _unit(rng.normal(size=9))
        lp = friction_cone_feasibility(0.05 * normals, normals, 1.5, 0.2)
        if lp.feasible:
            feasible += 1
            assert d.vertical_capacity(normals, lp.normal_forces, 1.5) >= \
                0.2 * GRAVITY - 1e-6 * (0.2 * GRAVITY + lp.normal_forces.sum())
    assert feasible >= 20


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-0.4, 1.3), min_size=3, max_size=3),
       st.lists(st.floats(-0.7, 0.7), min_size=3, max_size=3), st.floats(0.05, 1.5),
       st.floats(0.1, 5.0))
def test_safety_factor_is_the_vertical_capacity_at_the_shared_grip(tilts, turns, mu, grip):
    # contacts near a 120-deg pattern, each with its own tilt: mostly 0 < G < 1
    az = np.radians([0.0, 120.0, 240.0]) + np.asarray(turns)
    t = np.asarray(tilts)
    normals = np.stack([np.cos(t) * np.cos(az), np.cos(t) * np.sin(az), np.sin(t)], axis=1)
    g = d.geometric_efficiency(normals, mu)
    assume(0.0 < g < 1.0)  # below the cap and above the clip
    shares, ok = d.load_shared_forces(np.full(3, grip), normals)
    assert ok
    sf = d.safety_factor(mu, grip, g, 0.3, a_lift=0.0)
    assert sf == pytest.approx(d.vertical_capacity(normals, shares, d.KAPPA * mu) / (0.3 * GRAVITY))


@pytest.mark.parametrize(("tilt_deg", "mu"), [(0.0, 0.35), (10.0, 0.35), (25.0, 0.35),
                                               (0.0, 1.0), (25.0, 1.0), (40.0, 0.6),
                                               (55.0, 1.0), (65.0, 1.0)])
def test_sf_one_is_the_lp_minimum_grip_on_symmetric_sets(tilt_deg, mu):
    # Relation 2: on a 120-deg-symmetric set the grip at which SF = 1 is the LP's smallest
    # per-finger normal force; the exact cone lies between the LP's inscribed cones at
    # kappa mu (forces at least exact) and kappa mu / cos(pi/q) (forces at most exact).
    tilt = np.radians(tilt_deg)
    normals = _cone(tilt, phase=0.3)
    points = 0.05 * normals
    mass, q = 0.25, 32  # every case keeps tan(tilt) below kappa mu cos(pi/q), off the boundary
    g = d.geometric_efficiency(normals, mu)
    grip = d.grip_for_safety_factor(1.0, mu, g, mass, a_lift=0.0)
    inner = friction_cone_feasibility(points, normals, d.KAPPA * mu, mass, n_facets=q)
    outer = friction_cone_feasibility(points, normals, d.KAPPA * mu / np.cos(np.pi / q), mass,
                                      n_facets=q)
    assert inner.feasible and outer.feasible
    assert outer.normal_forces.sum() / 3 <= grip * (1 + 1e-7)
    assert grip <= inner.normal_forces.sum() / 3 * (1 + 1e-7)


@pytest.mark.parametrize("tilt_deg", [10.0, 25.0, 40.0])
def test_a_lower_cone_is_credited_conservatively(tilt_deg):
    # capped at G = 1, the SF of a cradle asks for more grip than the LP needs
    normals = _cone(-np.radians(tilt_deg))
    lp = friction_cone_feasibility(0.05 * normals, normals, d.KAPPA * 0.5, 0.25)
    grip = d.grip_for_safety_factor(1.0, 0.5, d.geometric_efficiency(normals, 0.5), 0.25,
                                    a_lift=0.0)
    assert lp.feasible and grip >= lp.normal_forces.sum() / 3


@pytest.mark.parametrize("tilt_deg", [10.0, 30.0, 50.0])
def test_sf_can_reach_one_exactly_when_the_lp_is_feasible_on_symmetric_sets(tilt_deg):
    # required_friction returns the inner-cone bisection value mu_r, the exact value lying in
    # [cos(pi/q) mu_r, mu_r]: G > 0 (some grip reaches SF = 1) just above mu_r, G = 0 below.
    normals = _cone(np.radians(tilt_deg))
    q, tol = 32, 1e-6
    mu_r = required_friction(0.05 * normals, normals, 0.25, n_facets=q, tol=tol)
    assert d.geometric_efficiency(normals, mu_r / d.KAPPA) > 0.0
    assert d.geometric_efficiency(normals, np.cos(np.pi / q) * (mu_r - 2 * tol) / d.KAPPA) == 0.0


def test_sf_and_lp_disagree_on_general_sets():
    # Relation 3, both directions. (a) SF ignores torque: three balanced horizontal normals
    # acting at one point beside the centre of mass reach any SF, yet no force set through
    # one point balances the weight's moment.
    normals = _cone(0.0)
    points = np.tile([0.05, 0.0, 0.0], (3, 1))
    assert d.safety_factor(0.6, 5.0, d.geometric_efficiency(normals, 0.6), 0.2) > 1.0
    assert friction_cone_feasibility(points, normals, 10.0, 0.2).status == "infeasible"
    # (b) equal commands cannot unload a harmful contact: one finger under the centre of mass
    # and two steep upper fingers. The LP holds the object on the lower finger alone (even
    # without friction); equal grips push down harder than the friction holds up: G = 0.
    up = np.radians(60.0)
    normals = np.array([[0.0, 0.0, -1.0], [np.cos(up), 0.0, np.sin(up)],
                        [-np.cos(up), 0.0, np.sin(up)]])
    assert friction_cone_feasibility(0.05 * normals, normals, 0.0, 0.2).feasible
    assert d.geometric_efficiency(normals, 0.3 / d.KAPPA) == 0.0


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


@settings(max_examples=80, deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=9, max_size=9), st.integers(0, 3),
       st.lists(st.floats(0.1, 5.0), min_size=3, max_size=3))
def test_load_sharing_is_the_least_squares_projection(values, degenerate, commanded):
    # Reference: c - A^T pinv(A A^T) A c with numpy's SVD pseudo-inverse, A the horizontal force
    # directions; degenerate cases: collinear, vertical and parallel normals (rank 1 and 0).
    normals = np.asarray(values).reshape(3, 3)
    if degenerate == 1:
        normals[:, :2] = normals[0, :2] * np.array([[1.0], [-2.0], [0.5]])
    elif degenerate == 2:
        normals[:, :2] = 0.0
        normals[:, 2] = 1.0
    assume(np.all(np.linalg.norm(normals, axis=1) >= 1e-3))
    unit = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    a = -unit[:, :2].T
    c = np.asarray(commanded)
    gram = a @ a.T
    # below 1e-12 horizontal components numpy's pinv divides by a subnormal (inf); such a normal
    # is vertical (the next test)
    assume(np.trace(gram) == 0.0 or np.trace(gram) > 1e-20)
    expected = c - a.T @ (np.linalg.pinv(gram) @ (a @ c))
    got, _ = d.load_shared_forces(c, normals)
    # both lose ~eps * cond digits on a nearly rank-one Gram matrix (two nearly vertical normals)
    sv = np.linalg.svd(gram, compute_uv=False)
    cond = sv[0] / sv[1] if sv[1] > 1e-15 * sv[0] else 1.0
    np.testing.assert_allclose(got, expected, atol=(1e-9 + 1e-14 * cond) * np.abs(c).max())


@pytest.mark.filterwarnings("error::RuntimeWarning")  # it divided a subnormal zero matrix by its det 0
def test_a_normal_vertical_to_round_off_carries_no_horizontal_force():
    # hypothesis found (0, 7.9e-159, 1): numpy's pinv of its 6e-317 Gram matrix overflows to inf;
    # vertical normals balance horizontally already, so the commands stand unchanged
    normals = np.array([[0.0, 7.852299121474925e-159, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    got, feasible = d.load_shared_forces([1.0, 2.0, 3.0], normals)
    np.testing.assert_array_equal(got, [1.0, 2.0, 3.0])
    assert feasible
    # a horizontal part of 1e-6 is a direction: finger 1 alone pushes along it, so it lets go
    tilted = normals + [[1e-6, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    got, feasible = d.load_shared_forces([1.0, 2.0, 3.0], tilted)
    np.testing.assert_allclose(got, [0.0, 2.0, 3.0], atol=1e-12)
    assert not feasible
