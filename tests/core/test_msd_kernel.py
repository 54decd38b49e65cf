"""Tests of core.msd_kernel: the compiled MSD forces, support and RK4 stages.

Outside references: scipy.integrate.solve_ivp (DOP853) for the order of the compiled RK4, the
energy balance (kinetic + elastic + gravitational + dissipated = external work) for the audit, and
the numpy reference path of core.msd / core.dynamics, to which the kernels are held to rounding.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from graspcampaign.core import dynamics, msd, msd_kernel


@pytest.fixture(scope="module")
def small_mesh():
    # 42 nodes, r = 50 mm: trimesh.creation.icosphere(subdivisions=1, radius=0.05)
    return trimesh.creation.icosphere(subdivisions=1, radius=0.05)


def _kernel_args(body, params):
    faces = np.zeros((0, 3), dtype=np.int64) if body.faces is None else body.faces
    return (np.ascontiguousarray(body.edges), body.rest_lengths, np.ascontiguousarray(faces),
            msd_kernel.body_constants(body, params))


def _perturbed(mesh, seed, scale=1.0):
    rng = np.random.default_rng(seed)
    n = len(mesh.vertices)
    return msd.state_from_positions(mesh.vertices * scale + 1e-3 * rng.normal(size=(n, 3)),
                                    0.05 * rng.normal(size=(n, 3)))


@pytest.mark.parametrize("params", [
    msd.MsdParams(),
    msd.MsdParams(b=0.0, c=0.0, g=0.0),
    msd.MsdParams(bulk_modulus=0.47e6),
], ids=["default", "undamped", "volume"])
def test_derivative_matches_msd_rhs(small_mesh, params):
    body = msd.msd_body_from_mesh(small_mesh, params)
    state = _perturbed(small_mesh, 3, scale=0.98)
    f_ext = np.random.default_rng(4).normal(size=(42, 3))
    out = np.empty((42, 6))
    msd_kernel.msd_derivative(state.reshape(-1, 6), *_kernel_args(body, params), f_ext, out,
                              np.empty((5, body.n_edges)), np.empty((42, 3)))
    reference = msd.msd_rhs(0.0, state, body, params, f_ext).reshape(-1, 6)
    scale = np.abs(reference[:, 3:]).max()
    np.testing.assert_array_equal(out[:, :3], reference[:, :3])
    np.testing.assert_allclose(out[:, 3:], reference[:, 3:], rtol=0, atol=1e-13 * scale)


@settings(max_examples=50, deadline=None)
@given(arrays(np.float64, (12, 3), elements=st.floats(-1.0, 1.0)),
       arrays(np.float64, (12, 3), elements=st.floats(-10.0, 10.0)),
       st.floats(0.0, 1.0))
def test_rigid_part_removal_matches_the_reference(offsets, accel, share):
    corners = np.array([[x, y, z] for x in (0, 2) for y in (0, 2) for z in (0, 2)], float)
    positions = np.vstack([corners, corners[:4] + [0.5, 0.5, 0.5]]) + 0.2 * offsets
    x = msd.state_from_positions(positions).reshape(-1, 6)
    rates = np.zeros((12, 6))
    rates[:, 3:] = accel
    msd_kernel.remove_rigid_part(x, rates, share)
    expected = accel - share * dynamics.rigid_body_part(positions, accel)
    np.testing.assert_allclose(rates[:, 3:], expected, rtol=0, atol=1e-10 * (1 + np.abs(accel).max()))


@pytest.mark.parametrize("share", [0.0, 0.6, 1.0])
def test_rk4_body_step_follows_the_numpy_step_for_200_steps(small_mesh, share):
    params = msd.MsdParams()
    body = msd.msd_body_from_mesh(small_mesh, params)
    f_ext = np.zeros((42, 3))
    f_ext[:3] = [[0.0, 0.0, 0.3], [0.1, 0.0, 0.0], [0.0, -0.2, 0.0]]
    dt = 0.5 * msd.body_step_limit(body, params)

    def rhs(t, x):
        dx = msd.msd_rhs(t, x, body, params, f_ext)
        if share > 0.0:
            rates = dx.reshape(-1, 6)
            rates[:, 3:] -= share * dynamics.rigid_body_part(x.reshape(-1, 6)[:, :3], rates[:, 3:])
        return dx

    state = compiled = _perturbed(small_mesh, 9)
    for _ in range(200):
        state = msd.rk4_step(rhs, 0.0, state, dt)
        compiled = msd_kernel.rk4_body_step(compiled.reshape(-1, 6), dt, *_kernel_args(body, params),
                                            f_ext, share).reshape(-1)
    moved = np.abs(state - _perturbed(small_mesh, 9)).reshape(-1, 6)[:, :3].max()
    assert moved > 1e-4  # the body really moved (m)
    # to rounding: 200 steps of different summation orders at the nodes
    got, want = compiled.reshape(-1, 6), state.reshape(-1, 6)
    np.testing.assert_allclose(got[:, :3], want[:, :3], rtol=0, atol=1e-14)  # m
    np.testing.assert_allclose(got[:, 3:], want[:, 3:], rtol=0,
                               atol=1e-12 * np.abs(want[:, 3:]).max())  # m/s


def test_compiled_rk4_is_fourth_order_against_dop853(small_mesh):
    params = msd.MsdParams()
    body = msd.msd_body_from_mesh(small_mesh, params)
    state0 = _perturbed(small_mesh, 5)
    limit = msd.body_step_limit(body, params)
    t_end = 0.02
    n0 = int(np.ceil(t_end / (0.2 * limit)))
    dts = [t_end / n0, t_end / (2 * n0), t_end / (4 * n0)]
    compiled = msd.step_convergence(body, params, state0, t_end, dts,
                                    stepper=msd_kernel.audit_stepper(body, params))
    reference = msd.step_convergence(body, params, state0, t_end, dts)
    np.testing.assert_allclose(compiled.orders, 4.0, atol=0.2)
    np.testing.assert_allclose(compiled.errors, reference.errors, rtol=1e-6)


@pytest.mark.parametrize("case", ["damped", "external_work", "volume"])
def test_compiled_energy_audit_closes_like_the_numpy_audit(small_mesh, case):
    f_ext = None
    if case == "damped":
        params = msd.MsdParams()
    elif case == "external_work":
        params = msd.MsdParams(b=0.0, c=0.0)
        f_ext = np.zeros((42, 3))
        f_ext[:3] = [[0.1, 0.0, 0.2], [0.0, -0.1, 0.0], [0.0, 0.0, 0.3]]
    else:
        params = msd.MsdParams(bulk_modulus=0.47e6, b=0.0, c=0.0)
    body = msd.msd_body_from_mesh(small_mesh, params)
    state0 = _perturbed(small_mesh, 8, scale=0.98)
    dt = 0.05 * msd.body_step_limit(body, params)
    stepper = msd_kernel.audit_stepper(body, params, f_ext)
    coarse = msd.energy_audit(body, params, state0, dt, 800, record_every=10, stepper=stepper)
    fine = msd.energy_audit(body, params, state0, dt / 2, 1600, record_every=20,
                            stepper=msd_kernel.audit_stepper(body, params, f_ext))
    reference = msd.energy_audit(body, params, state0, dt, 800, f_ext=f_ext, record_every=10)
    # the balance closes, and its error is RK4's truncation (fourth order: 2^4 = 16 per halving)
    assert fine.max_relative_error < 1e-5
    assert coarse.max_relative_error / fine.max_relative_error > 12.0
    np.testing.assert_allclose(coarse.max_relative_error, reference.max_relative_error, rtol=1e-5)
    np.testing.assert_allclose(coarse.dissipated, reference.dissipated, rtol=1e-9, atol=1e-18)
    np.testing.assert_allclose(coarse.external_work, reference.external_work, rtol=1e-9,
                               atol=1e-18)
    if case == "damped":
        assert coarse.n_increases == 0 and coarse.dissipated[-1] > 0.0
    if case == "external_work":
        assert abs(fine.external_work[-1]) > 1e-3 * np.abs(fine.kinetic).max()
