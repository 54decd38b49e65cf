"""Tests for core.geometry: sphere-triangle contacts (§3.2-3.3), Eq. 11, 12, 17-18.

Outside references: ``trimesh.triangles.closest_point`` (Ericson's algorithm as implemented by
trimesh), ``trimesh.triangles.points_to_barycentric`` and ``trimesh.triangles.normals``; the disc
containment of case iv is re-derived with ``np.cross`` point-to-line distances. Invariants of
Phi^T are hypothesis property tests.
"""

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from graspcampaign.core.geometry import (
    CollisionCase,
    PenetrationSubcase,
    barycentric_weights,
    closest_point_barycentric,
    deepest_per_finger,
    face_frames,
    face_geometry,
    point_velocity,
    sphere_mesh_contacts,
    sphere_triangle_contacts,
    transfer_force,
)
from graspcampaign.core.mesh import make_object

N_PAIRS = 6000
SPACING = 1.0  # [m] pairs are laid out this far apart so only matching pairs can collide


def _random_pairs(rng, n):
    """Random triangles (5-50 mm) and sphere centres around them, mixing all four cases."""
    scale = rng.uniform(0.005, 0.05, size=(n, 1, 1))
    tri = rng.normal(size=(n, 3, 3)) * scale
    # A few distinct radii, so that pairs can be grouped per call (one radius per call).
    radius = rng.choice([0.002, 0.004, 0.005, 0.006, 0.008], size=n)
    normal, keep = trimesh.triangles.normals(tri)  # normals of the non-degenerate rows
    tri, radius = tri[keep], radius[keep]
    # Foot point anywhere around the triangle (barycentrics in [-0.6, 1.6]); for a third of the
    # pairs beyond a vertex, away from the centroid (mostly its corner region); then a height.
    w = rng.uniform(-0.6, 1.6, size=(len(tri), 3))
    w /= w.sum(axis=1, keepdims=True)
    foot = np.einsum("ki,kij->kj", w, tri)
    beyond = rng.random(len(tri)) < 1.0 / 3.0
    vertex = tri[np.arange(len(tri)), rng.integers(0, 3, size=len(tri))]
    outward = vertex - tri.mean(axis=1)
    outward -= np.einsum("ij,ij->i", outward, normal)[:, None] * normal
    step = rng.uniform(0.0, 1.0, size=(len(tri), 1)) * radius[:, None]
    foot = np.where(beyond[:, None],
                    vertex + step * outward / np.linalg.norm(outward, axis=1)[:, None], foot)
    height = rng.uniform(-1.0, 1.0, size=len(tri)) * radius
    centers = foot + height[:, None] * normal
    return tri, centers, radius


def _contacts_pairwise(tri, centers, radius, use_geometry, backend):
    """Run sphere_triangle_contacts on pairs laid out SPACING apart, one radius per pair."""
    rows = []
    for r in np.unique(radius):  # group by radius (the API takes one radius per call)
        idx = np.flatnonzero(radius == r)
        shift = np.zeros((len(idx), 3))
        shift[:, 0] = SPACING * np.arange(len(idx))
        t = tri[idx] + shift[:, None, :]
        c = centers[idx] + shift
        res = sphere_triangle_contacts(c, r, t, geometry=face_geometry(t) if use_geometry else None,
                                       backend=backend)
        assert (res.fingers == res.faces).all()  # only the matching pair can collide
        rows.append((idx[res.fingers], res, shift[res.fingers]))
    return rows


@pytest.fixture(scope="module")
def random_pairs():
    return _random_pairs(np.random.default_rng(20240611), N_PAIRS)


BACKENDS = ["numba", "numpy"]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("use_geometry", [True, False])
def test_contacts_match_trimesh_closest_point(random_pairs, use_geometry, backend):
    tri, centers, radius = random_pairs
    q_ref = trimesh.triangles.closest_point(tri, centers)
    dist_ref = np.linalg.norm(centers - q_ref, axis=1)
    normal_ref = trimesh.triangles.normals(tri)[0]
    bary_ref = trimesh.triangles.points_to_barycentric(tri, q_ref)

    found = np.zeros(len(tri), dtype=bool)
    n_cases = dict.fromkeys(CollisionCase, 0)
    for idx, res, shift in _contacts_pairwise(tri, centers, radius, use_geometry, backend):
        found[idx] = True
        r = radius[idx]
        assert np.allclose(res.points - shift, q_ref[idx], atol=1e-12)
        assert np.allclose(res.distances, dist_ref[idx], atol=1e-12)
        assert np.allclose(res.overlaps, r - dist_ref[idx], atol=1e-12)
        assert np.allclose(res.normals, normal_ref[idx], atol=1e-12)
        assert np.allclose(res.weights, bary_ref[idx], atol=1e-9)
        # Eq. 11 along the face normal, from the reference closest point.
        h = np.einsum("ij,ij->i", centers[idx] - q_ref[idx], normal_ref[idx])
        e_sq = np.maximum(dist_ref[idx] ** 2 - h**2, 0.0)
        assert np.allclose(res.heights, h, atol=1e-12)
        assert np.allclose(res.depths, np.sqrt(r**2 - e_sq) - h, atol=1e-12)

        # Subcase from the reference barycentrics: number of zero weights.
        zeros = (np.abs(bary_ref[idx]) < 1e-9).sum(axis=1)
        positive = np.where(np.abs(bary_ref[idx]) < 1e-9, np.inf, bary_ref[idx]).min(axis=1)
        clear = positive > 1e-6  # away from Voronoi-region boundaries
        expected_sub = np.choose(zeros, [PenetrationSubcase.INSIDE, PenetrationSubcase.EDGE,
                                         PenetrationSubcase.CORNER])
        assert np.array_equal(res.subcases[clear], expected_sub[clear])

        # Case iv: disc of Eq. 10 inside all three edge lines (np.cross distances).
        t = tri[idx]
        proj = centers[idx] - h[:, None] * normal_ref[idx]
        line_dist = np.stack([
            np.linalg.norm(np.cross(t[:, j - 2] - t[:, j - 1], proj - t[:, j - 1]), axis=1)
            / np.linalg.norm(t[:, j - 2] - t[:, j - 1], axis=1) for j in range(3)], axis=1)
        rho = np.sqrt(np.maximum(r**2 - h**2, 0.0))
        inside = expected_sub == PenetrationSubcase.INSIDE
        expected_case = np.where(
            expected_sub == PenetrationSubcase.CORNER, CollisionCase.CORNER,
            np.where(inside & (rho <= line_dist.min(axis=1)), CollisionCase.FULL,
                     CollisionCase.EDGE))
        clear &= np.abs(rho - line_dist.min(axis=1)) > 1e-9
        assert np.array_equal(res.cases[clear], expected_case[clear])
        for case in CollisionCase:
            n_cases[case] += int((res.cases == case).sum())

    # Exactly the pairs closer than r collide (away from touching contact).
    margin = np.abs(dist_ref - radius) > 1e-12
    assert np.array_equal(found[margin], (dist_ref < radius)[margin])
    n_cases[CollisionCase.NONE] = int((~found).sum())
    assert min(n_cases.values()) >= 300, n_cases  # every case of §3.2 is exercised


def test_ericson_closest_point_matches_trimesh(random_pairs):
    tri, centers, _ = random_pairs
    weights, subcases = closest_point_barycentric(centers, tri)
    q = np.einsum("ki,kij->kj", weights, tri)
    assert np.allclose(q, trimesh.triangles.closest_point(tri, centers), atol=1e-12)
    assert np.allclose(weights.sum(axis=1), 1.0) and (weights >= -1e-12).all()
    zeros = (weights == 0.0).sum(axis=1)
    assert np.array_equal(subcases, np.choose(zeros, [1, 2, 3]))


def test_face_frames_are_the_local_frames_of_section_3_2(random_pairs):
    tri, centers, radius = random_pairs
    tri, centers = tri[:200], centers[:200]
    dh = face_frames(tri)
    rot = dh[:, :3, :3]
    assert np.allclose(np.einsum("kij,klj->kil", rot, rot), np.eye(3), atol=1e-12)
    assert np.allclose(np.linalg.det(rot), 1.0)
    local = np.einsum("kij,kvj->kvi", rot, tri) + dh[:, None, :3, 3]
    assert np.allclose(local[:, :, 2], 0.0, atol=1e-15)  # face in z' = 0
    assert np.allclose(local[:, 1], 0.0, atol=1e-15)  # B at the origin
    assert (local[:, 0, 0] > 0).all() and np.allclose(local[:, 0, 1], 0.0, atol=1e-15)  # A on x'
    z0 = np.einsum("kij,kj->ki", rot, centers)[:, 2] + dh[:, 2, 3]
    h = np.einsum("ij,ij->i", centers - tri[:, 0], trimesh.triangles.normals(tri)[0])
    assert np.allclose(z0, h, atol=1e-15)


@pytest.fixture(scope="module")
def sphere_queries():
    m = make_object("sphere", 390)
    rng = np.random.default_rng(7)
    idx = rng.choice(len(m.vertices), 40, replace=False)
    offsets = rng.uniform(-0.004, 0.006, size=40)
    centers = m.vertices[idx] + (0.005 + offsets)[:, None] * m.vertex_normals[idx]
    centers = centers + rng.normal(scale=0.002, size=centers.shape)
    return m, centers


@pytest.mark.parametrize("backend", BACKENDS)
def test_broad_phases_agree_with_brute_force(sphere_queries, backend):
    m, centers = sphere_queries
    tri = m.triangles
    with_geo = sphere_triangle_contacts(centers, 0.005, tri, geometry=face_geometry(tri),
                                        backend=backend)
    soup = sphere_triangle_contacts(centers, 0.005, tri, backend=backend)
    # Brute force: every (finger, face) pair through the Ericson reference.
    p, f = np.meshgrid(np.arange(len(centers)), np.arange(len(tri)), indexing="ij")
    w, _ = closest_point_barycentric(centers[p.ravel()], tri[f.ravel()])
    q = np.einsum("ki,kij->kj", w, tri[f.ravel()])
    hit = np.linalg.norm(centers[p.ravel()] - q, axis=1) < 0.005
    for res in (with_geo, soup):
        assert np.array_equal(res.fingers, p.ravel()[hit])
        assert np.array_equal(res.faces, f.ravel()[hit])
    assert np.allclose(with_geo.depths, soup.depths) and np.allclose(with_geo.points, soup.points)
    assert len(with_geo) > 40


def test_compiled_and_numpy_paths_agree_pair_for_pair(random_pairs, sphere_queries):
    """The numba kernel against the numpy reference: same pairs, codes and values (to rounding),
    on the random pairs of every case and on a meshed sphere with an indexed-mesh query."""
    tri, centers, radius = random_pairs
    r = 0.005
    idx = np.flatnonzero(radius == r)
    shift = np.zeros((len(idx), 3))
    shift[:, 0] = SPACING * np.arange(len(idx))
    m, sphere_centers = sphere_queries
    cases = [
        (centers[idx] + shift, tri[idx] + shift[:, None, :]),
        (sphere_centers, m.triangles),
    ]
    for c, t in cases:
        ref = sphere_triangle_contacts(c, r, t, backend="numpy")
        for res in (sphere_triangle_contacts(c, r, t),
                    sphere_triangle_contacts(c, r, t, geometry=face_geometry(t))):
            assert len(res) == len(ref) > 40
            for name in ("fingers", "faces", "cases", "subcases"):
                assert np.array_equal(getattr(res, name), getattr(ref, name)), name
            for name in ("depths", "overlaps", "distances", "heights", "points", "finger_points",
                         "normals", "weights"):
                assert np.allclose(getattr(res, name), getattr(ref, name), rtol=1e-12,
                                   atol=1e-15), name
    mesh_res = sphere_mesh_contacts(sphere_centers, r, m.vertices, m.faces)
    ref = sphere_triangle_contacts(sphere_centers, r, m.triangles, backend="numpy")
    assert np.array_equal(mesh_res.faces, ref.faces) and np.allclose(mesh_res.points, ref.points)


def test_unknown_backend_is_refused(sphere_queries):
    m, centers = sphere_queries
    with pytest.raises(ValueError, match="backend must be 'numba' or 'numpy', got 'cuda'"):
        sphere_triangle_contacts(centers, 0.005, m.triangles, backend="cuda")


def test_eq11_reference_points(sphere_queries):
    m, centers = sphere_queries
    res = sphere_triangle_contacts(centers, 0.005, m.triangles)
    c = centers[res.fingers]
    assert (res.depths > 0).all() and (res.overlaps > 0).all()
    assert (res.depths >= res.overlaps - 1e-15).all()  # along the normal >= minimum translation
    assert np.allclose(np.linalg.norm(res.points - res.finger_points, axis=1), res.depths)
    assert np.allclose(np.linalg.norm(res.finger_points - c, axis=1), 0.005)  # on the sphere
    assert np.allclose(np.cross(res.points - res.finger_points, res.normals), 0.0, atol=1e-15)
    inside = res.subcases == PenetrationSubcase.INSIDE
    assert np.allclose(res.depths[inside], 0.005 - res.heights[inside])
    assert np.allclose(res.weights.sum(axis=1), 1.0)
    assert res.face_points is res.points


def test_deepest_per_finger(sphere_queries):
    m, centers = sphere_queries
    far = np.array([[1.0, 1.0, 1.0]])
    res = sphere_triangle_contacts(np.vstack([centers, far]), 0.005, m.triangles)
    idx = deepest_per_finger(res)
    assert idx.shape == (len(centers) + 1,) and idx[-1] == -1
    for finger in range(len(centers)):  # check against a per-finger max (test-side loop)
        mine = res.fingers == finger
        if mine.any():
            assert res.depths[idx[finger]] == res.depths[mine].max()
        else:
            assert idx[finger] == -1
    one = res.take(idx[idx >= 0])
    assert len(one) == (idx >= 0).sum() and np.array_equal(one.fingers, np.flatnonzero(idx >= 0))
    empty = sphere_triangle_contacts(far, 0.005, m.triangles)
    assert len(empty) == 0 and deepest_per_finger(empty).tolist() == [-1]


# ---------------------------------------------------------------------------------------------
# Eq. 12 and Eq. 17-18 (hypothesis)
# ---------------------------------------------------------------------------------------------
coords = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
triangles_st = arrays(np.float64, (3, 3), elements=coords).filter(
    lambda t: np.linalg.norm(np.cross(t[1] - t[0], t[2] - t[0])) > 1e-2)
simplex_st = arrays(np.float64, (3,), elements=st.floats(0.0, 1.0)).filter(
    lambda w: w.sum() > 1e-3).map(lambda w: w / w.sum())
vectors_st = arrays(np.float64, (3,), elements=st.floats(-10.0, 10.0))


@settings(max_examples=200, deadline=None)
@given(triangles_st, simplex_st)
def test_barycentric_weights_sum_to_one_and_reproduce_point(tri, w):
    point = w @ tri
    weights = barycentric_weights(point[None], tri[None])[0]
    assert weights.sum() == pytest.approx(1.0, abs=1e-12)
    assert np.allclose(weights, w, atol=1e-9)
    assert np.allclose(weights @ tri, point, atol=1e-12)
    ref = trimesh.triangles.points_to_barycentric(tri[None], point[None])[0]
    assert np.allclose(weights, ref, atol=1e-9)


@settings(max_examples=100, deadline=None)
@given(triangles_st, arrays(np.float64, (3, 3), elements=st.floats(-5.0, 5.0)))
def test_point_velocity_reproduces_vertex_velocities_at_vertices(tri, velocities):
    weights = barycentric_weights(tri, np.repeat(tri[None], 3, axis=0))
    assert np.allclose(weights, np.eye(3), atol=1e-12)
    v = point_velocity(weights, np.repeat(velocities[None], 3, axis=0))
    assert np.allclose(v, velocities, atol=1e-12)
    # Rigid translation: every point of the face moves with the common velocity.
    same = np.repeat(velocities[:1], 3, axis=0)[None]
    assert np.allclose(point_velocity(np.array([[0.2, 0.3, 0.5]]), same), velocities[0])


@settings(max_examples=200, deadline=None)
@given(triangles_st, simplex_st, vectors_st, vectors_st, arrays(np.float64, (3, 3),
                                                                elements=st.floats(-5.0, 5.0)))
def test_force_transfer_preserves_force_moment_and_power(tri, w, force, origin, velocities):
    point = w @ tri
    weights = barycentric_weights(point[None], tri[None])
    nodal = transfer_force(weights, force[None])[0]
    assert np.allclose(nodal.sum(axis=0), force, atol=1e-9)
    # Moment about the contact point is zero, as for the single contact force ...
    assert np.allclose(np.cross(tri - point, nodal).sum(axis=0), 0.0, atol=1e-9)
    # ... hence about any origin it equals the contact force's moment.
    assert np.allclose(np.cross(tri - origin, nodal).sum(axis=0), np.cross(point - origin, force),
                       atol=1e-8)
    # Virtual-work consistency of Phi^T: f . v_P = sum_i f_i . v_i.
    v_point = point_velocity(weights, velocities[None])[0]
    assert np.einsum("ij,ij->", nodal, velocities) == pytest.approx(force @ v_point, abs=1e-8)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("use_geometry", [True, False])
def test_degenerate_faces_never_collide(use_geometry, backend):
    tri = np.array([
        [[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.0, 0.01, 0.0]],  # regular face
        [[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.02, 0.0, 0.0]],  # collinear: zero area
        [[0.001, 0.001, 0.0]] * 3,  # a point
    ])
    # Projection (3, 3) mm, height 4.5 mm: disc radius sqrt(5^2 - 4.5^2) = 2.18 mm, clear of the
    # edge lines at 3, 3 and 2.83 mm -> case iv.
    centers = np.array([[0.003, 0.003, 0.0045]])
    geometry = face_geometry(tri) if use_geometry else None
    res = sphere_triangle_contacts(centers, 0.005, tri, geometry=geometry, backend=backend)
    assert res.faces.tolist() == [0]
    assert res.cases.tolist() == [CollisionCase.FULL]
    assert res.depths[0] == pytest.approx(0.0005)
