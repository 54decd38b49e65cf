"""Tests of core.jacobian: force Jacobians of the MSD body and of the floor.

Outside reference: central finite differences of core.msd's own force functions, and
scipy.optimize.approx_fprime for one column.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from scipy.optimize import approx_fprime

from graspcampaign.core import jacobian, msd, msd_body


@pytest.fixture(scope="module")
def small_mesh():
    # 42 nodes, r = 50 mm: trimesh.creation.icosphere(subdivisions=1, radius=0.05)
    return trimesh.creation.icosphere(subdivisions=1, radius=0.05)


def _body_force(body, params, state):
    """Total body force m_i (a + g e_z) from msd_rhs (gravity removed: it has no Jacobian)."""
    accel = msd.msd_rhs(0.0, state, body, params).reshape(-1, 6)[:, 3:]
    return (body.node_mass * (accel + [0.0, 0.0, params.g])).ravel()


def _central_difference(fn, state, slot_offset, h=1e-7):
    n3 = state.size // 2
    out = np.zeros((n3, n3))
    for k in range(n3):
        node, axis = divmod(k, 3)
        plus, minus = state.copy(), state.copy()
        plus[6 * node + slot_offset + axis] += h
        minus[6 * node + slot_offset + axis] -= h
        out[:, k] = (fn(plus) - fn(minus)) / (2 * h)
    return out


@pytest.mark.parametrize("bulk_modulus", [0.0, 0.47e6])
def test_body_jacobian_matches_finite_differences(small_mesh, bulk_modulus):
    params = msd.MsdParams(bulk_modulus=bulk_modulus)
    body = msd.msd_body_from_mesh(small_mesh, params)
    rng = np.random.default_rng(0)
    # Stretched (2 %), jittered and moving: the geometric terms of rotating, stretched edges count.
    state = msd.state_from_positions(small_mesh.vertices * 1.02 + 2e-3 * rng.normal(size=(42, 3)),
                                     0.1 * rng.normal(size=(42, 3)))
    jac = jacobian.body_jacobian(body, params, state)

    def force(s):
        return _body_force(body, params, s)

    d_x = _central_difference(force, state, 0)
    d_v = _central_difference(force, state, 3)
    assert np.max(np.abs(jac.dense_d_position() - d_x)) < 1e-6 * np.max(np.abs(d_x))
    assert np.max(np.abs(jac.d_velocity.toarray() - d_v)) < 1e-6 * np.max(np.abs(d_v))
    assert (jac.rank_one_vector is None) == (bulk_modulus == 0.0)
    # One column again with scipy's forward differences (a second, independent estimator).
    column = approx_fprime(state[0:1], lambda x: force(np.r_[x, state[1:]])[5], 1e-8)
    assert column[0] == pytest.approx(jac.dense_d_position()[5, 0], rel=1e-4)


def test_rest_jacobian_is_the_rest_stiffness_and_symmetric(small_mesh):
    params = msd.MsdParams()
    body = msd.msd_body_from_mesh(small_mesh, params)
    jac = jacobian.body_jacobian(body, params, msd.state_from_positions(small_mesh.vertices))
    # At rest (no stretch, no motion) dF/dx = -K of msd's own rest stiffness, symmetric.
    np.testing.assert_allclose(jac.d_position.toarray(),
                               -msd_body.rest_stiffness_matrix(body, params.k).toarray(), atol=1e-9)
    d_v = jac.d_velocity.toarray()
    np.testing.assert_allclose(d_v, d_v.T, atol=1e-12)
    assert np.all(np.linalg.eigvalsh(d_v) <= 1e-12)  # dampers only remove energy


def test_floor_jacobian_matches_finite_differences_in_stick_and_slip():
    floor = msd.FloorParams(height=0.0, mu=0.5)
    # node 0 above the floor, 1 sticking, 2 sliding (far from its anchor), 3 leaving fast (clamped)
    positions = [[0.0, 0.0, 1e-3], [1e-6, 0.0, -1e-4], [2e-3, 1e-3, -2e-4], [0.0, 0.0, -1e-5]]
    velocities = [[0.0, 0.0, 0.0], [1e-3, -2e-3, -1e-3], [0.01, 0.0, 0.0], [0.0, 0.0, 1.0]]
    state = msd.state_from_positions(positions, velocities)
    anchors = np.zeros((4, 2))
    d_pos, d_vel = jacobian.floor_jacobian(state, floor, anchors)

    def force(s):
        return msd.floor_forces(s, floor, anchors).ravel()

    for blocks, offset in ((d_pos, 0), (d_vel, 3)):
        numeric = _central_difference(force, state, offset, h=1e-9)
        dense = np.zeros((12, 12))
        for node in range(4):
            dense[3 * node:3 * node + 3, 3 * node:3 * node + 3] = blocks[node]
        np.testing.assert_allclose(dense, numeric, rtol=1e-5, atol=1e-6 * np.abs(numeric).max())
    assert np.all(d_pos[[0, 3]] == 0.0)
    assert d_pos[1, 0, 0] == -floor.tangential_stiffness  # sticking: the stick spring
    assert abs(d_pos[2, 0, 0]) < floor.tangential_stiffness  # sliding: capped at mu f_n
