"""Tests for the Ferrari-Canny L1 epsilon (core.ferrari_canny, kernels.epsilon_facets)."""

import functools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import linprog
from scipy.spatial import ConvexHull

from graspcampaign.core.ferrari_canny import epsilon_metric, epsilon_qhull, primitive_wrenches

ORIGIN = np.zeros(3)


def random_triples(seed, b=200, offset=0.0):
    rng = np.random.default_rng(seed)
    normals = rng.normal(size=(b, 3, 3))
    normals /= np.linalg.norm(normals, axis=2, keepdims=True)
    points = 0.05 * normals * rng.uniform(0.7, 1.3, (b, 3, 1)) + offset * rng.normal(size=(b, 3, 3))
    return points, normals, rng.uniform(0.05, 1.0, b)


@functools.cache
def _triples_and_hull_epsilon(seed, offset):
    """:func:`random_triples` and their qhull epsilon, computed once for both backends (qhull
    over 200 triples is most of the test's time); read-only, so no backend can alter them."""
    points, normals, mu = random_triples(seed, offset=offset)
    reference = epsilon_qhull(primitive_wrenches(points, normals, mu, ORIGIN, 0.06))
    for a in (points, normals, mu, reference):
        a.setflags(write=False)
    return points, normals, mu, reference


@pytest.mark.parametrize("backend", ["numba", "numpy"])
@pytest.mark.parametrize("seed, offset", [(0, 0.0), (1, 0.01), (2, 0.02)])
def test_epsilon_equals_convex_hull_on_random_triples(backend, seed, offset):
    # offset 0: radial normals (sphere-like, many pair-axis facets through the origin);
    # offset > 0: normals off the contact radius (torque from every normal force).
    points, normals, mu, reference = _triples_and_hull_epsilon(seed, offset)
    fast = epsilon_metric(points, normals, mu, ORIGIN, 0.06, backend=backend)
    closure = reference > 1e-9
    assert 0.2 < closure.mean() < 0.8  # both outcomes are exercised
    np.testing.assert_allclose(fast[closure], reference[closure], rtol=1e-9)
    np.testing.assert_allclose(fast[~closure], 0.0, atol=1e-12)


def equatorial_wrenches(mu, n_edges, radius=0.05, length=0.05):
    """Primitive wrenches of three contacts at 120 deg on a sphere's equator, built by hand.

    Contact j at ``p = R u_j`` (u_j horizontal) pushes along ``-u_j``; its tangents are the
    horizontal ``h_j = z x u_j`` and the vertical ``z``. The primitive force of edge k is
    ``f = -u_j + mu (cos t h_j + sin t z)`` (t = 2 pi k / q, starting on h_j as statics.
    tangent_bases does: t1 = z x n_out, t2 = n_out x t1 = z for n_out = u_j), and the torque
    about the centre is ``R u_j x f / L = (R / L) mu (cos t z - sin t h_j)`` because
    ``u x z = -h`` and ``u x h = z``.
    """
    rows = []
    t = 2 * np.pi * np.arange(n_edges) / n_edges
    z = np.array([0.0, 0.0, 1.0])
    for az in np.radians([0.0, 120.0, 240.0]):
        u = np.array([np.cos(az), np.sin(az), 0.0])
        h = np.cross(z, u)
        for c, s in zip(np.cos(t), np.sin(t), strict=True):
            force = -u + mu * (c * h + s * z)
            torque = (radius / length) * mu * (c * z - s * h)
            rows.append(np.concatenate([force, torque]))
    return np.array(rows)


@pytest.mark.parametrize("mu", [0.3, 0.5, 1.0])
def test_symmetric_equatorial_grasp_against_hand_built_hull(mu):
    # The wrench cloud is written out by hand (equatorial_wrenches), hulled by scipy, and the
    # distance to its nearest facet is compared with epsilon_metric from points and normals.
    cloud = equatorial_wrenches(mu, 8)
    hull = ConvexHull(cloud)
    expected = float(np.min(-hull.equations[:, -1]))
    az = np.radians([0.0, 120.0, 240.0])
    normals = np.stack([np.cos(az), np.sin(az), np.zeros(3)], axis=1)
    got = epsilon_metric(0.05 * normals, normals, mu, ORIGIN, 0.05)[0]
    assert expected > 0.0
    assert got == pytest.approx(expected, rel=1e-9)
    # A second implementation without qhull: the ray from the origin along d leaves the hull at
    # max{t : t d in conv(cloud)} (an LP); the inscribed radius is the minimum over d, reached
    # along the nearest facet's normal, so no ray is shorter and that ray has exactly epsilon.
    def ray(direction):
        n = len(cloud)
        cost = np.zeros(n + 1)
        cost[-1] = -1.0
        a_eq = np.hstack([cloud.T, -direction[:, None]])
        a_eq = np.vstack([a_eq, np.r_[np.ones(n), 0.0]])
        res = linprog(cost, A_eq=a_eq, b_eq=np.r_[np.zeros(6), 1.0],
                      bounds=[(0, None)] * (n + 1), method="highs")
        return res.x[-1]

    rng = np.random.default_rng(5)
    directions = rng.normal(size=(200, 6))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    assert min(ray(d) for d in directions) >= got - 1e-9
    nearest = hull.equations[np.argmin(-hull.equations[:, -1]), :6]
    assert ray(nearest) == pytest.approx(got, rel=1e-8)


def test_epsilon_is_zero_when_all_normals_point_the_same_way():
    # Three contacts on the top cap of a sphere, every finger pushing down: nothing pushes up.
    normals = np.array([[0.1, 0.0, 1.0], [-0.05, 0.08, 1.0], [-0.05, -0.08, 1.0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    for backend in ("numba", "numpy"):
        assert epsilon_metric(0.05 * normals, normals, 0.5, ORIGIN, 0.05, backend=backend)[0] == 0.0
    # the ConvexHull reference too: the origin outside the hull is 0, not a negative distance
    assert epsilon_qhull(primitive_wrenches(0.05 * normals, normals, 0.5, ORIGIN, 0.05))[0] == 0.0
    parallel = np.tile([[0.0, 0.0, 1.0]], (3, 1))  # identical normals: singular tangent map
    points = np.array([[0.01, 0.0, 0.05], [-0.01, 0.01, 0.05], [0.0, -0.01, 0.05]])
    assert epsilon_metric(points, parallel, 0.8, ORIGIN, 0.05)[0] == 0.0


def test_zero_friction_gives_zero_and_bad_input_is_named():
    points, normals, _ = random_triples(3, b=4)
    np.testing.assert_array_equal(epsilon_metric(points, normals, 0.0, ORIGIN, 0.05), 0.0)
    with pytest.raises(ValueError, match=r"n_edges must be an int >= 3, got 2"):
        epsilon_metric(points, normals, 0.3, ORIGIN, 0.05, n_edges=2)
    with pytest.raises(ValueError, match=r"torque_length must be > 0 m, got 0.0"):
        epsilon_metric(points, normals, 0.3, ORIGIN, 0.0)
    with pytest.raises(ValueError, match=r"backend must be 'numba' or 'numpy', got 'c'"):
        epsilon_metric(points, normals, 0.3, ORIGIN, 0.05, backend="c")


triple = st.lists(st.floats(-1.0, 1.0), min_size=9, max_size=9).filter(
    lambda v: np.all(np.linalg.norm(np.reshape(v, (3, 3)), axis=1) > 0.2))


@settings(max_examples=40, deadline=None)
@given(raw=triple, mu=st.floats(0.1, 1.0), order=st.permutations([0, 1, 2]),
       scale=st.floats(0.2, 5.0))
def test_epsilon_invariances(raw, mu, order, scale):
    normals = np.reshape(raw, (3, 3))
    normals = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    points = 0.05 * normals + 0.01 * np.roll(normals, 1, axis=0)
    base = epsilon_metric(points, normals, mu, ORIGIN, 0.06)[0]
    # contact order is a labelling, not geometry
    assert epsilon_metric(points[list(order)], normals[list(order)], mu, ORIGIN, 0.06)[0] == \
        pytest.approx(base, rel=1e-9, abs=1e-12)
    # scaling the grasp and the torque length together leaves every wrench unchanged
    assert epsilon_metric(scale * points, normals, mu, ORIGIN, 0.06 * scale)[0] == \
        pytest.approx(base, rel=1e-9, abs=1e-12)
    # more friction: every primitive force of mu lies in the polygon of a larger mu (n_hat is
    # the polygon's centre), so the hull grows and epsilon cannot fall
    assert epsilon_metric(points, normals, 1.5 * mu, ORIGIN, 0.06)[0] >= base - 1e-12
    # a 16-edge cone contains the 8-edge one (same first edge, every other vertex shared)
    assert epsilon_metric(points, normals, mu, ORIGIN, 0.06, n_edges=16)[0] >= base - 1e-12
