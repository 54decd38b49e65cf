"""Tests for core.feature: angular defects, dihedral deviations, sharp features (§3.1, §11).

References: trimesh (face angles, face normals and adjacency, computed here independently of the
module's calls), the discrete Gauss-Bonnet theorem (defects of a closed genus-0 surface sum to
4*pi), and the closed-form cube and icosahedron.
"""

import warnings

import numpy as np
import pytest
import trimesh

from graspcampaign.core.feature import (
    CoarseMeshWarning,
    FeatureThresholds,
    distance_to_sharp_edges,
    is_coarse,
    near_sharp_edge,
    sharp_features,
    smooth_mean_defect,
)
from graspcampaign.core.mesh import make_object

STUDY_NODES = [144, 356, 390, 1750]


@pytest.mark.parametrize("shape", ["sphere", "rounded_cube", "handle", "pear"])
def test_defects_and_dihedrals_match_trimesh(shape):
    m = make_object(shape, 390)
    f = sharp_features(m)
    # Defect from per-face corner angles (trimesh.Trimesh.face_angles), summed per vertex.
    angle_sum = np.bincount(m.faces.ravel(), weights=m.face_angles.ravel(),
                            minlength=len(m.vertices))
    assert np.allclose(f.vertex_defects, 2 * np.pi - angle_sum, atol=1e-12)
    assert np.allclose(f.vertex_defects, trimesh.curvature.vertex_defects(m))
    # Discrete Gauss-Bonnet: sum of defects = 2*pi*chi = 4*pi for a genus-0 surface.
    assert f.vertex_defects.sum() == pytest.approx(4 * np.pi, abs=1e-9)
    # Dihedral deviation = angle between the two face normals of each adjacent pair.
    n = m.face_normals[m.face_adjacency]
    cosines = np.clip(np.einsum("ij,ij->i", n[:, 0], n[:, 1]), -1, 1)
    assert np.allclose(f.edge_deviation_rad, np.arccos(cosines), atol=1e-7)
    assert np.array_equal(f.adjacency_edges, m.face_adjacency_edges)


def test_closed_form_cube_and_icosahedron():
    cube = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    with pytest.warns(CoarseMeshWarning, match="only 8 vertices"):
        f = sharp_features(cube)
    assert np.allclose(f.vertex_defects, np.pi / 2)  # three right angles meet at each corner
    assert f.sharp_vertices.all()
    assert f.n_sharp_edges == 12  # the cube's edges; face diagonals are flat
    assert np.allclose(np.sort(f.edge_deviation_rad)[-12:], np.pi / 2)

    ico = trimesh.creation.icosahedron()
    with pytest.warns(CoarseMeshWarning):
        g = sharp_features(ico)
    assert np.allclose(g.vertex_defects, 2 * np.pi - 5 * np.pi / 3)
    dihedral = np.arccos(-np.sqrt(5) / 3)  # 138.19 deg
    assert np.allclose(g.edge_deviation_rad, np.pi - dihedral)
    with pytest.warns(CoarseMeshWarning):
        h = sharp_features(ico, FeatureThresholds(edge_dihedral_deg=45.0))
    assert h.n_sharp_edges == 0  # 41.8 deg < 45 deg


@pytest.mark.parametrize("n_nodes", STUDY_NODES)
def test_sphere_has_no_sharp_features(n_nodes):
    f = sharp_features(make_object("sphere", n_nodes))
    assert f.n_sharp_vertices == 0
    assert f.n_sharp_edges == 0
    assert not f.vertex_near_sharp_edge.any()
    assert np.isinf(f.vertex_sharp_edge_distance).all()
    # §3.1: defects ~ 4*pi/N and dihedral deviations below 30 deg.
    assert np.allclose(f.vertex_defects, smooth_mean_defect(n_nodes), rtol=0.15)
    assert np.degrees(f.edge_deviation_rad.max()) < 20.0


@pytest.mark.parametrize("n_nodes", [144, 356, 390, 1000])
def test_rounded_cube_corners_are_sharp(n_nodes):
    m = make_object("rounded_cube", n_nodes)
    f = sharp_features(m)
    octant = (m.vertices > 0).astype(int) @ [1, 2, 4]
    for corner in range(8):
        assert f.sharp_vertices[octant == corner].any()
    if n_nodes >= 356:
        # Sharp vertices only in the corner regions (all three coordinates on the fillet).
        corner_region = (np.abs(m.vertices) > 0.040 - 0.012 - 0.004).all(axis=1)
        assert not (f.sharp_vertices & ~corner_region).any()


def test_handle_rim_edges_are_sharp():
    m = make_object("handle", 390)
    f = sharp_features(m)
    # Both flat caps lie in the plane y = y_min (the half torus ends at sweep 0 and 180 deg);
    # their vertices are the rim loops plus one fan centre per cap at (+-36 mm, y_min, 0).
    on_cap_plane = np.isclose(m.vertices[:, 1], m.vertices[:, 1].min(), atol=1e-9)
    cap_centre = np.isclose(np.abs(m.vertices[:, 0]), 0.036) & np.isclose(m.vertices[:, 2], 0.0)
    rim = on_cap_plane & ~cap_centre
    assert f.n_sharp_edges > 0
    assert rim[f.sharp_edges].all()  # every sharp edge is a rim edge
    assert f.n_sharp_edges == int(rim.sum())  # and every rim edge is sharp (two closed loops)
    rim_edge = rim[f.adjacency_edges].all(axis=1)
    assert np.degrees(f.edge_deviation_rad[rim_edge].min()) > 80.0  # flat cap meets the tube
    assert f.vertex_near_sharp_edge[rim].all()
    # The smooth tube away from the rims carries no sharp edge.
    not_rim_edge = ~rim[f.adjacency_edges].any(axis=1)
    assert np.degrees(f.edge_deviation_rad[not_rim_edge].max()) < 30.0
    # Inner (concave, saddle) side: negative defects, never sharp.
    radial = np.linalg.norm(m.vertices[:, :2] - m.vertices[on_cap_plane, :2].mean(axis=0), axis=1)
    inner = (radial < 0.036 - 0.006) & ~on_cap_plane
    assert inner.any() and (f.vertex_defects[inner] < 0).all()


@pytest.mark.filterwarnings("ignore::graspcampaign.core.feature.CoarseMeshWarning")
def test_distance_to_sharp_edges_closed_form_cube():
    cube = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    points = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.5, 0.9, 0.9], [1.0, 1.0, 0.3]])
    expected = [np.sqrt(2.0), np.sqrt(2.0), np.hypot(0.1, 0.1), 0.0]
    assert np.allclose(distance_to_sharp_edges(points, cube), expected)
    f = sharp_features(cube)
    assert np.allclose(distance_to_sharp_edges(points, f), expected)
    assert f.vertex_near_sharp_edge.all()  # every cube vertex lies on three sharp edges
    near = near_sharp_edge(points, np.full(4, 0.4), f)  # band 0.5 * 0.4 = 0.2
    assert near.tolist() == [False, False, True, True]


def test_distance_matches_dense_sampling_of_segments():
    m = make_object("handle", 390)
    f = sharp_features(m)
    rng = np.random.default_rng(3)
    points = m.vertices[rng.choice(len(m.vertices), 60, replace=False)] + rng.normal(
        scale=0.005, size=(60, 3))
    s = np.linspace(0.0, 1.0, 401)
    a, b = f.sharp_edge_segments[:, 0], f.sharp_edge_segments[:, 1]
    samples = (a[:, None] + s[None, :, None] * (b - a)[:, None]).reshape(-1, 3)
    dense = np.linalg.norm(points[:, None] - samples[None], axis=2).min(axis=1)
    exact = distance_to_sharp_edges(points, f)
    assert (exact <= dense + 1e-12).all()
    step = np.linalg.norm(b - a, axis=1).max() / 400
    assert (dense - exact <= step).all()


def test_coarse_mesh_warning_and_resolution_aware_option(caplog):
    coarse = make_object("sphere", 50)
    with pytest.warns(CoarseMeshWarning, match="only 50 vertices.*resolution_aware=True") as caught:
        fixed = sharp_features(coarse)
    assert len(caught) == 1 and not caplog.records  # said once: a warning, not also a log record
    assert is_coarse(50) and not is_coarse(50, FeatureThresholds(resolution_aware=True))
    assert not is_coarse(144)
    assert fixed.n_sharp_vertices == 50  # 4*pi/50 = 0.25 rad > 0.2 rad: every vertex trips
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        aware = sharp_features(coarse, FeatureThresholds(resolution_aware=True))
        assert aware.n_sharp_vertices == 0 and aware.n_sharp_edges == 0
        # Real corners stay sharp under the resolution-aware rule.
        cube = sharp_features(make_object("rounded_cube", 144),
                              FeatureThresholds(resolution_aware=True))
        assert cube.n_sharp_vertices >= 8
        # At the studied resolutions the paper's fixed thresholds apply unchanged.
        assert FeatureThresholds(resolution_aware=True).effective(390) == pytest.approx(
            (0.2, np.radians(30.0)))
        sharp_features(make_object("sphere", 144))  # no warning at the coarsest study mesh


def test_a_face_centre_of_a_subdivided_cube_is_not_near_its_edges():
    """A unit cube subdivided once: 8 corners and 12 edge midpoints lie on its sharp edges, the 6
    face centres 0.5 from them (by hand); each vertex's mean edge length is the mean over its
    trimesh neighbours (about 0.66 at a face centre), so 0.5 is beyond half of it: not near."""
    cube = trimesh.creation.box(extents=[1.0, 1.0, 1.0]).subdivide()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoarseMeshWarning)
        f = sharp_features(cube)
    mean = [np.mean(np.linalg.norm(cube.vertices[n] - v, axis=1))
            for v, n in zip(cube.vertices, cube.vertex_neighbors, strict=True)]
    np.testing.assert_allclose(f.vertex_mean_edge_length, mean, rtol=1e-12)
    centre = np.isclose(np.abs(cube.vertices), 0.5).sum(axis=1) == 1  # one coordinate on a face
    assert centre.sum() == 6
    np.testing.assert_allclose(f.vertex_sharp_edge_distance[centre], 0.5, rtol=1e-12)
    assert not f.vertex_near_sharp_edge[centre].any() and f.vertex_near_sharp_edge[~centre].all()
