"""Tests for core.metric: H(G) (Eq. 6-9), §5.2 closed forms, §8.1 hardware form.

References are closed forms on an ideal sphere of radius R (inscribed-angle theorem, chord
lengths 2 R sin(central/2)) and the paper's stated values for S1.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from graspcampaign.core.feature import sharp_features
from graspcampaign.core.mesh import make_object
from graspcampaign.core.metric import (
    HARDWARE_WEIGHTS,
    HeuristicContext,
    HeuristicWeights,
    default_d_opt,
    heuristic_context,
    heuristic_terms,
)

R = 0.050


def _ideal_sphere_context(points):
    """Context for contacts exactly on the sphere of radius R (normals radial, d_opt = R sqrt 3)."""
    points = np.asarray(points, dtype=float)
    n = len(points)
    return HeuristicContext(
        vertices=points, normals=points / np.linalg.norm(points, axis=1)[:, None],
        centroid=np.zeros(3), d_max=R, d_opt=np.sqrt(3.0) * R,
        sharp_vertex=np.zeros(n, bool), near_sharp_edge=np.zeros(n, bool),
        pc_magnitude=np.zeros(n), pe_magnitude=np.zeros(n))


def _on_circle_xz(angles_deg):
    a = np.radians(angles_deg)
    return R * np.column_stack([np.cos(a), np.zeros_like(a), np.sin(a)])


def test_equatorial_120_degrees_is_ideal():
    a = np.radians([0.0, 120.0, 240.0])
    points = R * np.column_stack([np.cos(a), np.sin(a), np.zeros(3)])
    t = heuristic_terms(_ideal_sphere_context(points), np.array([[0, 1, 2]]))
    assert t.s1[0] == pytest.approx(0.0, abs=1e-12)
    assert t.s3[0] == pytest.approx(0.0, abs=1e-12)
    assert t.s2[0] == pytest.approx(0.0, abs=1e-12)  # equilateral with side d_opt = R sqrt 3
    assert t.total()[0] == pytest.approx(0.0, abs=1e-12)
    assert t.score_hardware()[0] == pytest.approx(1.0)  # sum of the hardware weights


def test_equatorial_120_degrees_on_the_mesh():
    m = make_object("sphere", 1750)
    ctx = heuristic_context(m, sharp_features(m))
    a = np.radians([0.0, 120.0, 240.0])
    targets = R * np.column_stack([np.cos(a), np.sin(a), np.zeros(3)])
    idx = np.linalg.norm(m.vertices[None] - targets[:, None], axis=2).argmin(axis=1)
    t = heuristic_terms(ctx, idx[None])
    assert t.s1[0] < 0.03 and t.s3[0] < 0.03 and t.s2[0] < 0.03
    assert t.n_c[0] == 0 and t.n_e[0] == 0


def test_section_5_2_reachable_optimum():
    # Two contacts at 45 deg on either side of the vertical, the third at -90 deg, all in a plane
    # through the centre. Force directions 90/135/135 deg apart -> S1 = (30+15+15)/240 = 0.25.
    t = heuristic_terms(_ideal_sphere_context(_on_circle_xz([45.0, 135.0, -90.0])),
                        np.array([[0, 1, 2]]))
    assert t.s1[0] == pytest.approx(0.25, abs=1e-12)  # paper §5.2: 0.25
    # Inscribed-angle theorem: central angles 90/135/135 deg -> interior 67.5/67.5/45 deg.
    angle_part = (7.5 + 7.5 + 15.0) / 60.0 / 3.0
    sides = 2 * R * np.sin(np.radians([45.0, 67.5, 67.5]))
    side_part = np.mean(np.abs(sides - np.sqrt(3) * R) / (np.sqrt(3) * R))
    assert t.s2_angle[0] == pytest.approx(angle_part)
    assert t.s2_side[0] == pytest.approx(side_part)
    assert t.s2[0] == pytest.approx(0.5 * (angle_part + side_part))  # 0.1362 (paper 0.25)
    assert t.s3[0] == pytest.approx((2 * np.sin(np.radians(45.0)) - 1.0) / 3.0)  # 0.1381 (0.33)
    assert t.total()[0] == pytest.approx(0.25 + t.s2[0] + t.s3[0])  # 0.5243 (paper 0.833)
    # §5.2 weight sets: uniform scaling scales H.
    for factor in (0.5, 2.0):
        assert t.total(HeuristicWeights().scaled(factor))[0] == pytest.approx(
            factor * t.total()[0])


def test_default_d_opt_is_inscribed_equilateral_side():
    # Equatorial section of the sphere: circle of radius R -> side R sqrt 3.
    assert default_d_opt(make_object("sphere", 1750)) == pytest.approx(np.sqrt(3) * R, rel=0.01)
    # Ellipsoid: section ellipse 60 x 45 mm, area-equivalent radius sqrt(a b).
    assert default_d_opt(make_object("ellipsoid", 1750)) == pytest.approx(
        np.sqrt(3) * np.sqrt(0.060 * 0.045), rel=0.01)
    # Rounded cube: rounded square, area (2a)^2 - (4 - pi) r^2.
    area = 0.080**2 - (4 - np.pi) * 0.012**2
    assert default_d_opt(make_object("rounded_cube", 1750)) == pytest.approx(
        np.sqrt(3) * np.sqrt(area / np.pi), rel=0.01)
    # Handle: the section is the half annulus between R - r and R + r plus the two cap lines.
    handle_area = 0.5 * np.pi * ((0.036 + 0.012) ** 2 - (0.036 - 0.012) ** 2)
    assert default_d_opt(make_object("handle", 1750)) == pytest.approx(
        np.sqrt(3) * np.sqrt(handle_area / np.pi), rel=0.02)


def test_penalty_counts_and_magnitudes_on_sharp_shapes():
    m = make_object("rounded_cube", 390)
    f = sharp_features(m)
    ctx = heuristic_context(m, f)
    rng = np.random.default_rng(1)
    triples = rng.integers(0, len(m.vertices), size=(5000, 3))
    t = heuristic_terms(ctx, triples)
    assert np.array_equal(t.n_c, f.sharp_vertices[triples].sum(axis=1))
    assert np.array_equal(t.n_e, f.vertex_near_sharp_edge[triples].sum(axis=1))
    assert (t.n_c > 0).any() and (t.n_e > 0).any()
    # Continuous magnitudes are non-zero exactly where the counts are, and never exceed them.
    assert np.array_equal(t.pc_mag > 0, t.n_c > 0) and (t.pc_mag <= t.n_c).all()
    assert np.array_equal(t.pe_mag > 0, t.n_e > 0) and (t.pe_mag <= t.n_e).all()
    assert np.allclose(t.total(), t.s1 + t.s2 + t.s3 + t.n_c + t.n_e)
    w = HARDWARE_WEIGHTS
    assert np.allclose(t.score_hardware(), 0.45 * (1 - t.s1) + 0.30 * (1 - t.s2)
                       + 0.25 * (1 - t.s3) - t.pc_mag - t.pe_mag)
    assert (w.w1, w.w2, w.w3) == (0.45, 0.30, 0.25)
    # Ranges of the bounded terms.
    assert (t.s2 >= 0).all() and (t.s2 <= 1).all() and (t.s3 >= 0).all() and (t.s3 <= 1).all()
    assert (t.s1 >= 0).all() and (t.s1 <= 1.5).all()

    sphere = make_object("sphere", 390)
    ts = heuristic_terms(heuristic_context(sphere, sharp_features(sphere)), triples % 390)
    assert not ts.n_c.any() and not ts.n_e.any() and not ts.pc_mag.any() and not ts.pe_mag.any()


def test_degenerate_triples_and_input_errors():
    m = make_object("sphere", 144)
    ctx = heuristic_context(m, sharp_features(m))
    t = heuristic_terms(ctx, np.array([[3, 3, 7], [5, 5, 5]]))
    assert np.isfinite(t.total()).all()
    assert np.allclose(t.s2_angle, 1.0)
    with pytest.raises(ValueError, match=r"triples must have shape \(m, 3\), got \(4,\)"):
        heuristic_terms(ctx, np.arange(4))
    with pytest.raises(ValueError, match="d_opt must be positive, got -1.0"):
        heuristic_context(m, sharp_features(m), d_opt=-1.0)
    assert heuristic_context(m, sharp_features(m), d_opt=0.07).d_opt == 0.07


@pytest.fixture(scope="module")
def cube_terms():
    m = make_object("rounded_cube", 390)
    ctx = heuristic_context(m, sharp_features(m))
    rng = np.random.default_rng(2)
    return heuristic_terms(ctx, rng.integers(0, len(m.vertices), size=(2000, 3)))


positive = st.floats(0.01, 10.0)


@settings(max_examples=150, deadline=None)
@given(w=st.tuples(positive, positive, positive, positive, positive),
       factor=st.floats(1e-3, 1e3), start=st.integers(0, 1900), size=st.integers(2, 100))
def test_uniform_weight_scaling_leaves_argmin_unchanged(cube_terms, w, factor, start, size):
    weights = HeuristicWeights(*w)
    h = cube_terms.total(weights)[start:start + size]
    h_scaled = cube_terms.total(weights.scaled(factor))[start:start + size]
    best, best_scaled = int(np.argmin(h)), int(np.argmin(h_scaled))
    # Same candidate, unless two candidates tie to rounding (then they are equally good).
    assert best == best_scaled or h[best_scaled] == pytest.approx(h[best], rel=1e-12)
    assert np.allclose(h_scaled, factor * h, rtol=1e-12)
