"""What each hardware planner can know (paper §8.1, §9.3; issue 13): materials and beliefs."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from graspcampaign.core import bench
from graspcampaign.core import disturbance as d
from graspcampaign.rig import belief as rb

# Table 4 of the paper, mu_s per family (gel, silicone soft, bio foam, silicone reference)
TABLE4_MU_S = {"gel": 0.772, "silicone_soft": 0.619, "bio_foam": 0.684, "silicone_ref": 0.509}


# ------------------------------------------------------------------ materials
def test_material_contact_params_reproduce_table4():
    for name, fam in bench.FAMILIES.items():
        m = rb.material_model(name)
        cp = m.contact_params()
        assert cp.k_n_per_mm_n == pytest.approx(fam.k_n_per_mm_n)  # Eq. 14 back to Table 4 K
        assert cp.c_n_s_per_m == pytest.approx(fam.c)
        assert m.cap_depth < m.damage_depth and m.cap_k_n_per_mm_n < m.k_n_per_mm_n


def test_material_contact_params_at_another_fingertip_radius():
    # K scales with sqrt(R) once (Eq. 14), in material_model; contact_params must not scale again
    fam = bench.FAMILIES["gel"]
    m = rb.material_model("gel", "natural", 8e-3)
    cp = m.contact_params(8e-3)
    assert m.k_n_per_mm_n == pytest.approx(fam.k_n_per_mm_n * math.sqrt(8.0 / 5.0))
    assert cp.k_n_per_mm_n == pytest.approx(m.k_n_per_mm_n)
    assert cp.lambda1 == pytest.approx(rb.material_model("gel").contact_params().lambda1)
    assert cp.c_n_s_per_m == pytest.approx(fam.c * 8.0 / 5.0)


def test_damage_depth_closed_form():
    # gel: stabilised softening 0.10 (d/2 mm)^2 reaches 1 - 0.85 at d = 2 mm sqrt(1.5)
    gel = bench.FAMILIES["gel"]
    assert rb.family_damage_depth(gel) == pytest.approx(2e-3 * math.sqrt(0.15 / 0.10))
    # reference silicone: permanent set 0.08 mm (d/2 mm)^1.5 reaches 0.5 mm first
    ref = bench.FAMILIES["silicone_ref"]
    assert rb.family_damage_depth(ref) == pytest.approx(2e-3 * (0.5 / 0.08) ** (2 / 3))


def test_coatings():
    low = rb.material_model("gel", "low")
    assert low.mu_s == rb.COATING_MU_S["low"]
    assert low.mu_k / low.mu_s == pytest.approx(bench.FAMILIES["gel"].mu_k / bench.FAMILIES["gel"].mu_s)
    with pytest.raises(ValueError, match="unknown friction level 'oily'"):
        rb.material_model("gel", "oily")


def test_coating_friction_is_keyed_by_the_vocabulary_names_and_ordered_physically():
    # the paper's coating names (the vocabulary's, which a paper block's keys are checked against);
    # a tacky rubber grips more than a talc skin, which grips more than a PTFE-like film (§9.2)
    from graspcampaign.analysis.vocabulary import COATINGS

    assert set(rb.COATING_MU_S) == set(COATINGS)
    assert rb.COATING_MU_S["high"] > rb.COATING_MU_S["medium"] > rb.COATING_MU_S["low"]


# ------------------------------------------------------------------ beliefs
def _contacts():
    """Three contacts on a 50 mm sphere: one upper, one lower, one equatorial."""
    tilt = np.radians([30.0, -20.0, 0.0])
    az = np.radians([0.0, 120.0, 240.0])
    normals = np.stack([np.cos(tilt) * np.cos(az), np.cos(tilt) * np.sin(az), np.sin(tilt)], 1)
    return 0.05 * normals, normals


def test_nominal_friction_is_the_campaign_mean_of_table4():
    assert rb.NOMINAL_MU_S == pytest.approx(np.mean(list(TABLE4_MU_S.values())))
    assert rb.NOMINAL_MU_S == pytest.approx(0.646, abs=5e-4)


def test_the_calibrated_planner_believes_its_material():
    points, normals = _contacts()
    for name, mu in TABLE4_MU_S.items():
        m = rb.material_model(name)
        b = rb.planner_belief("heuristic", points, normals, m)
        assert (b.model, b.belief_error, b.mu_s) == ("calibrated", "paper", mu)
        np.testing.assert_array_equal(b.normals, normals)  # its own mesh normals
        assert (b.k_n_per_mm_n, b.n) == (bench.FAMILIES[name].k_n_per_mm_n, bench.FAMILIES[name].n)
        # the cap keeps a finger within the damage depth and within its own 5 mm radius (§8.1)
        assert (b.cap_k_n_per_mm_n, b.cap_depth) == (m.cap_k_n_per_mm_n, min(m.cap_depth, 5e-3))
        assert (b.cap_depth < m.cap_depth) == (name == "silicone_ref")  # 5.8 mm characteristic
        # QLV creep of a standard linear solid after the 4.67 s lift and 3 s hold (Table 4 rho, tau)
        t = 50.0 / 30.0 + 3.0
        rho, tau = m.rho, m.tau
        assert b.creep(t) == pytest.approx(1 / rho - (1 / rho - 1) * math.exp(-rho * t / tau))
    coated = rb.planner_belief("heuristic", points, normals, rb.material_model("gel", "medium"))
    assert coated.mu_s == rb.COATING_MU_S["medium"]


@pytest.mark.parametrize("planner", ["no_pso", "centroid", "force_balance", "random"])
def test_uncalibrated_planners_believe_nominal_friction_and_the_hertzian_law(planner):
    points, normals = _contacts()
    for surface in ("natural", "low"):
        m = rb.material_model("gel", surface)
        b = rb.planner_belief(planner, points, normals, m)
        assert b.mu_s == rb.NOMINAL_MU_S  # no Test 1 record: the coating is invisible to it
        # SPEC §2.8 nominal law: n = 1.5, K = 2 lambda1 Psi sqrt(R) with lambda1 = 1 (Eq. 14)
        assert b.n == 1.5 and b.k_n_per_mm_n == b.cap_k_n_per_mm_n
        psi = 1.0 / ((1 - 0.5**2) / 89.3e3 + (1 - 0.45**2) / 140e3)  # Table 2 moduli [Pa]
        assert b.k_n_per_mm_n == pytest.approx(2 * psi / 1e6 * math.sqrt(5.0))
        assert b.cap_depth == min(m.cap_depth, 5e-3) and b.creep(100.0) == 1.0
    geometric = planner != "no_pso"
    assert (b.model == "nominal_geometry") == geometric
    if geometric:  # a planar grasp: every contact looks horizontal
        np.testing.assert_allclose(b.normals[:, 2], 0.0)
        assert b.g_geo() > d.geometric_efficiency(normals, rb.NOMINAL_MU_S)
    else:
        np.testing.assert_array_equal(b.normals, normals)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=9, max_size=9))
def test_planar_normals_keep_the_azimuth(values):
    normals = np.asarray(values).reshape(3, 3)
    points = 0.05 * normals + 0.001
    planar = rb.planar_normals(normals, points, np.zeros(3))
    np.testing.assert_allclose(np.linalg.norm(planar, axis=1), 1.0)
    np.testing.assert_allclose(planar[:, 2], 0.0)
    h = normals[:, :2]
    big = np.linalg.norm(h, axis=1) > 1e-6
    # same horizontal direction: zero cross product, positive dot product
    cross = h[big, 0] * planar[big, 1] - h[big, 1] * planar[big, 0]
    np.testing.assert_allclose(cross, 0.0, atol=1e-9)
    assert np.all(np.einsum("ij,ij->i", h[big], planar[big, :2]) > 0)


def test_a_vertical_normal_looks_radial_to_a_planar_planner():
    normals = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
    points = np.array([[0.0, 0.02, 0.05], [0.0, 0.0, -0.05], [0.05, 0.0, 0.0]])
    planar = rb.planar_normals(normals, points, np.zeros(3))
    np.testing.assert_allclose(planar, [[0, 1, 0], [1, 0, 0], [1, 0, 0]])


def test_actual_belief_and_unknown_planner():
    points, normals = _contacts()
    b = rb.actual_belief(points, normals, mu_s=0.7, k_n_per_mm_n=0.4, n=0.45, rho=0.7, tau=9.0,
                         damage_depth=3e-3)
    assert (b.model, b.belief_error, b.cap_depth, b.cap_k_n_per_mm_n) == ("actual", "none", 3e-3,
                                                                            0.4)
    assert b.g_geo() == d.geometric_efficiency(normals, 0.7)
    deep = rb.actual_belief(points, normals, mu_s=0.7, k_n_per_mm_n=0.4, n=0.45, rho=0.7, tau=9.0,
                            damage_depth=7e-3)
    assert deep.cap_depth == 5e-3  # never beyond the fingertip radius
    with pytest.raises(ValueError, match=r"^unknown hardware planner 'antipodal': use one of "
                                         r"heuristic, no_pso, centroid, force_balance, random$"):
        rb.planner_belief("antipodal", points, normals, rb.material_model("gel"))
