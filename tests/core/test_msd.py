"""Tests of core.msd: MSD shell, RK4, stability limit, energy audit, gravity settling.

Outside references: the closed-form damped two-body oscillator, scipy.integrate.solve_ivp (DOP853),
numpy.linalg.eigvalsh of a stiffness matrix assembled here with an explicit loop, and the RK4
stability polynomial.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import trimesh
from scipy.integrate import solve_ivp

from graspcampaign.core import msd


def _dense_rest_stiffness(positions, edges, k):
    """Assemble K = sum_e k (e_i - e_j)(e_i - e_j)^T kron u u^T with a plain loop (reference)."""
    n = positions.shape[0]
    stiffness = np.zeros((3 * n, 3 * n))
    for i, j in edges:
        u = positions[i] - positions[j]
        u /= np.linalg.norm(u)
        block = k * np.outer(u, u)
        for a, b, sign in ((i, i, 1), (j, j, 1), (i, j, -1), (j, i, -1)):
            stiffness[3 * a : 3 * a + 3, 3 * b : 3 * b + 3] += sign * block
    return stiffness


@pytest.fixture(scope="module")
def small_mesh():
    # 42 nodes, r = 50 mm: trimesh.creation.icosphere(subdivisions=1, radius=0.05)
    return trimesh.creation.icosphere(subdivisions=1, radius=0.05)


@pytest.fixture(scope="module")
def small_body(small_mesh):
    return msd.msd_body_from_mesh(small_mesh, msd.MsdParams())


# ---------------------------------------------------------------------------- layout and body


def test_state_layout_interleaves_position_and_velocity_per_node():
    positions = np.arange(12.0).reshape(4, 3)
    velocities = -np.arange(12.0).reshape(4, 3)
    state = msd.state_from_positions(positions, velocities)
    assert state.shape == (24,)
    np.testing.assert_array_equal(state[6:12], [3, 4, 5, -3, -4, -5])
    np.testing.assert_array_equal(msd.positions_from_state(state), positions)
    np.testing.assert_array_equal(msd.velocities_from_state(state), velocities)
    batch = np.stack([state, 2 * state])
    assert msd.positions_from_state(batch).shape == (2, 4, 3)


def test_check_state_rejects_wrong_shape_and_nan():
    with pytest.raises(ValueError, match=r"shape \(12,\) for n = 2, got \(6,\)"):
        msd.check_state(np.zeros(6), 2)
    bad = np.zeros(12)
    bad[3] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        msd.check_state(bad, 2)


def test_body_from_arrays_validates_and_merges_duplicate_edges():
    positions = np.eye(3)
    body = msd.msd_body_from_arrays(positions, [[0, 1], [1, 0], [1, 2]], mass=0.3)
    assert body.n_edges == 2
    assert body.node_mass == pytest.approx(0.1)
    np.testing.assert_allclose(body.rest_lengths, np.sqrt(2.0))
    with pytest.raises(ValueError, match="self-loops"):
        msd.msd_body_from_arrays(positions, [[0, 0]], mass=1.0)
    with pytest.raises(ValueError, match=r"edge indices must lie in \[0, 3\)"):
        msd.msd_body_from_arrays(positions, [[0, 3]], mass=1.0)
    with pytest.raises(ValueError, match=r"positions must have shape \(n, 3\)"):
        msd.msd_body_from_arrays(np.zeros((3, 2)), [[0, 1]], mass=1.0)
    with pytest.raises(ValueError, match="MsdParams.k must be finite and > 0"):
        msd.MsdParams(k=0.0)


def test_body_from_mesh_uses_unique_mesh_edges(small_mesh, small_body):
    assert small_body.n_nodes == len(small_mesh.vertices)
    assert small_body.n_edges == len(small_mesh.edges_unique)
    np.testing.assert_allclose(np.sort(small_body.rest_lengths), np.sort(small_mesh.edges_unique_length))
    assert small_body.mass == pytest.approx(0.4)


def test_rest_state_is_force_free_and_internal_forces_match_edge_loop(small_mesh, small_body):
    params = msd.MsdParams()
    rest = msd.state_from_positions(small_mesh.vertices)
    np.testing.assert_allclose(msd.internal_forces(small_body, params, rest), 0.0, atol=1e-12)
    rng = np.random.default_rng(3)
    state = msd.state_from_positions(
        small_mesh.vertices + 1e-3 * rng.normal(size=(42, 3)), 1e-2 * rng.normal(size=(42, 3))
    )
    x, v = msd.positions_from_state(state), msd.velocities_from_state(state)
    expected = np.zeros((42, 3))
    for (i, j), l0 in zip(small_body.edges, small_body.rest_lengths, strict=True):
        d = x[i] - x[j]
        length = np.linalg.norm(d)
        u = d / length
        f = (params.k * (length - l0) + params.c * np.dot(v[i] - v[j], u)) * u
        expected[i] -= f
        expected[j] += f
    np.testing.assert_allclose(msd.internal_forces(small_body, params, state), expected, atol=1e-12)
    dstate = msd.msd_rhs(0.0, state, small_body, params).reshape(-1, 6)
    np.testing.assert_allclose(dstate[:, :3], v)
    accel = (expected - params.b * v) / small_body.node_mass + [0.0, 0.0, -params.g]
    np.testing.assert_allclose(dstate[:, 3:], accel, rtol=1e-12, atol=1e-9)


# ---------------------------------------------------------------------------- RK4 accuracy


def _two_node_closed_form(t, rest_length, amplitude, k, c, b, node_mass):
    """Damped relative oscillation r(t) of two nodes on one edge; centre of mass at rest.

    m r'' = -(b + 2c) r' - 2k (r - l0)  ->  u = r - l0 = A e^{-gt} (cos wd t + g/wd sin wd t).
    """
    gamma = (b + 2.0 * c) / (2.0 * node_mass)
    omega_d = np.sqrt(2.0 * k / node_mass - gamma**2)
    u = amplitude * np.exp(-gamma * t) * (np.cos(omega_d * t) + gamma / omega_d * np.sin(omega_d * t))
    return rest_length + u


def test_rk4_is_fourth_order_on_a_damped_two_node_spring():
    rest_length, amplitude = 0.01, 2e-3
    params = msd.MsdParams(mass=0.02, k=100.0, c=0.05, b=0.02, g=0.0)
    body = msd.msd_body_from_arrays([[0.0, 0, 0], [rest_length, 0, 0]], [[0, 1]], params.mass)
    state0 = msd.state_from_positions([[0.0, 0, 0], [rest_length + amplitude, 0, 0]])
    t_end = 0.1
    exact = _two_node_closed_form(
        t_end, rest_length, amplitude, params.k, params.c, params.b, body.node_mass
    )
    centre = 0.5 * (rest_length + amplitude)
    errors = []
    for n_steps in (50, 100, 200, 400):
        run = msd.integrate_rk4(
            lambda t, x: msd.msd_rhs(t, x, body, params), 0.0, state0, t_end / n_steps, n_steps,
            record_every=n_steps,
        )
        x = msd.positions_from_state(run.states[-1])
        expected = np.array([[centre - exact / 2, 0, 0], [centre + exact / 2, 0, 0]])
        errors.append(np.max(np.abs(x - expected)))
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    # Halving dt divides the global error by 2^4 = 16.
    assert np.all((ratios > 14.0) & (ratios < 18.0)), ratios
    assert errors[-1] < 1e-9


def test_rk4_agrees_with_solve_ivp_dop853_on_a_small_mesh(small_mesh, small_body):
    params = msd.MsdParams()
    rng = np.random.default_rng(11)
    state0 = msd.state_from_positions(
        small_mesh.vertices + 5e-4 * rng.normal(size=(42, 3)), 0.05 * rng.normal(size=(42, 3))
    )
    f_ext = np.zeros((42, 3))
    f_ext[0] = [0.0, 0.0, 0.5]
    t_end = 0.05
    dt = 0.1 * msd.body_step_limit(small_body, params)
    n_steps = int(np.ceil(t_end / dt))
    run = msd.integrate_rk4(
        lambda t, x: msd.msd_rhs(t, x, small_body, params, f_ext), 0.0, state0, t_end / n_steps,
        n_steps, record_every=n_steps,
    )
    reference = solve_ivp(
        lambda t, x: msd.msd_rhs(t, x, small_body, params, f_ext), (0.0, t_end), state0,
        method="DOP853", rtol=1e-10, atol=1e-13,
    )
    assert reference.success
    diff = np.abs(run.states[-1] - reference.y[:, -1]).reshape(-1, 6)
    print(diff[:, :3].max(), diff[:, 3:].max())
    assert diff[:, :3].max() < 5e-9  # m, against displacements of a few mm
    assert diff[:, 3:].max() < 5e-7  # m/s, against velocities of ~0.1 m/s


def test_step_convergence_study_reports_order_four(small_mesh, small_body):
    params = msd.MsdParams()
    rng = np.random.default_rng(5)
    state0 = msd.state_from_positions(small_mesh.vertices + 1e-3 * rng.normal(size=(42, 3)))
    limit = msd.body_step_limit(small_body, params)
    t_end = 0.02
    n0 = int(np.ceil(t_end / (0.2 * limit)))
    result = msd.step_convergence(
        small_body, params, state0, t_end, [t_end / n0, t_end / (2 * n0), t_end / (4 * n0)]
    )
    assert np.all(np.diff(result.errors) < 0.0)
    np.testing.assert_allclose(result.orders, 4.0, atol=0.2)
    assert "DOP853" in result.reference


# ---------------------------------------------------------------------------- energy


def test_energy_never_grows_with_damping_and_no_contact(small_mesh, small_body):
    params = msd.MsdParams()
    rng = np.random.default_rng(7)
    state0 = msd.state_from_positions(
        small_mesh.vertices * 1.05 + 1e-3 * rng.normal(size=(42, 3)), 0.1 * rng.normal(size=(42, 3))
    )
    limit = msd.body_step_limit(small_body, params)
    audit = msd.energy_audit(small_body, params, state0, 0.5 * limit, 300)
    assert audit.n_increases == 0
    assert np.all(np.diff(audit.mechanical) <= 1e-14 * np.abs(audit.mechanical[:-1]).max())
    assert audit.dissipated[-1] > 0.5 * (audit.mechanical[0] - audit.mechanical[-1])
    assert audit.max_relative_error < 1e-3
    # The balance error is RK4 truncation: at least fourth order once w_max dt is small.
    coarse = msd.energy_audit(small_body, params, state0, 0.1 * limit, 1500, record_every=5)
    fine = msd.energy_audit(small_body, params, state0, 0.05 * limit, 3000, record_every=10)
    assert coarse.n_increases == fine.n_increases == 0
    assert coarse.max_relative_error / fine.max_relative_error > 12.0  # 2^4 = 16 asymptotically
    assert fine.max_relative_error < 1e-6


def test_energy_audit_closes_without_damping_and_with_external_work(small_mesh, small_body):
    params = msd.MsdParams(b=0.0, c=0.0)
    rng = np.random.default_rng(8)
    state0 = msd.state_from_positions(small_mesh.vertices + 1e-3 * rng.normal(size=(42, 3)))
    f_ext = np.zeros((42, 3))
    f_ext[:3] = [[0.1, 0.0, 0.2], [0.0, -0.1, 0.0], [0.0, 0.0, 0.3]]
    # At w_max dt ~ 1 RK4's own numerical damping of the undamped mesh modes
    # (|R(i w dt)|^2 = 1 - (w dt)^6 / 72 + ...) dominates the balance error; it falls as dt^5.
    limit = msd.body_step_limit(small_body, params)
    coarse = msd.energy_audit(small_body, params, state0, 0.05 * limit, 800, f_ext=f_ext)
    fine = msd.energy_audit(small_body, params, state0, 0.025 * limit, 1600, f_ext=f_ext)
    assert np.all(fine.dissipated == 0.0)
    assert np.abs(fine.external_work[-1]) > 1e-3 * np.abs(fine.kinetic).max()
    assert coarse.max_relative_error / fine.max_relative_error > 16.0
    assert fine.max_relative_error < 1e-5


# ---------------------------------------------------------------------------- stability limit


def test_stable_step_limit_closed_forms():
    # Undamped: 2 sqrt(2) / w_max with w_max^2 = 2 k d_max / m (= 4 k / m for a chain).
    assert msd.stable_step_limit(100.0, 0.01, 2) == pytest.approx(2 * np.sqrt(2) / np.sqrt(400 / 0.01))
    # Pure nodal damping, no spring: real root -b/m, RK4 real-axis limit 2.785.
    assert msd.stable_step_limit(0.0, 0.01, 2, b=1.0) == pytest.approx(2.7853 / 100.0, rel=1e-3)
    # Damping shrinks the limit below the imaginary-axis value, never below 2.6155/|s|.
    undamped = msd.stable_step_limit(1.4e3, 1e-3, 6)
    damped = msd.stable_step_limit(1.4e3, 1e-3, 6, c=0.1, b=0.01)
    assert 2.6 / 2.83 * undamped < damped < undamped


def test_stable_step_limit_bounds_the_true_spectrum_and_is_sharp(small_mesh, small_body):
    params = msd.MsdParams(b=0.0, c=0.0, g=0.0)
    stiffness = _dense_rest_stiffness(small_mesh.vertices, small_body.edges, params.k)
    omega_true = np.sqrt(np.linalg.eigvalsh(stiffness)[-1] / small_body.node_mass)
    bound = msd.stable_step_limit(params.k, small_body.node_mass, small_body.max_degree)
    exact = msd.body_step_limit(small_body, params)
    assert exact == pytest.approx(2 * np.sqrt(2) / omega_true, rel=1e-6)
    assert bound <= exact
    rng = np.random.default_rng(1)
    state0 = msd.state_from_positions(small_mesh.vertices + 1e-6 * rng.normal(size=(42, 3)))

    def energy_growth(dt, n_steps=3000):
        with np.errstate(all="ignore"):  # the unstable run overflows on purpose
            return _energy_growth(dt, n_steps)

    def _energy_growth(dt, n_steps):
        run = msd.integrate_rk4(
            lambda t, x: msd.msd_rhs(t, x, small_body, params), 0.0, state0, dt, n_steps,
            record_every=n_steps,
        )
        energy = msd.kinetic_energy(small_body, run.states) + msd.elastic_energy(
            small_body, params, run.states
        )
        return energy[-1] / energy[0]

    assert energy_growth(0.99 * exact) <= 1.0 + 1e-9
    assert not energy_growth(1.05 * exact) <= 1e3  # grows without bound (or overflows to nan)


def test_msd_params_from_modulus_hits_the_target_damping_ratios():
    mesh = trimesh.creation.icosphere(subdivisions=2, radius=0.05)  # 162 nodes
    params = msd.msd_params_from_modulus(mesh, youngs_modulus=0.14e6, mass=0.4)
    assert params.k == pytest.approx(0.14e6 * mesh.edges_unique_length.mean())
    node_mass = 0.4 / len(mesh.vertices)
    stiffness = _dense_rest_stiffness(mesh.vertices, mesh.edges_unique, params.k)
    omega = np.sqrt(np.clip(np.linalg.eigvalsh(stiffness) / node_mass, 0.0, None))[6:]
    zeta = params.b / (2 * node_mass * omega) + params.c * omega / (2 * params.k)
    assert zeta[0] == pytest.approx(0.1, rel=1e-6)
    assert zeta[-1] == pytest.approx(1.0, rel=1e-6)
    assert np.all(zeta >= 0.1 - 1e-9)


def test_msd_params_from_modulus_drops_nodal_damping_on_a_coarse_mesh(small_mesh, caplog):
    params = msd.msd_params_from_modulus(small_mesh)
    assert params.b == 0.0
    assert params.c > 0.0
    assert "b set to 0" in caplog.text


# ---------------------------------------------------------------------------- floor and settling


def test_floor_forces_push_up_only_and_cap_friction():
    floor = msd.FloorParams(height=0.0, mu=0.5)
    state = msd.state_from_positions(
        [[0.0, 0, 1e-3], [0.0, 0, -1e-4], [0.0, 0, -1e-4]], [[0, 0, 0], [0, 0, 0], [0, 0, 1.0]]
    )
    anchors = np.array([[0.0, 0.0], [-1.0, 0.0], [0.0, 0.0]])
    forces = msd.floor_forces(state, floor, anchors)
    np.testing.assert_allclose(forces[0], 0.0)
    assert forces[1, 2] == pytest.approx(floor.stiffness * 1e-4)
    # Stretched far from its anchor: friction saturates at mu f_n along -stretch.
    np.testing.assert_allclose(forces[1, :2], [-0.5 * forces[1, 2], 0.0])
    # Leaving the floor fast: the damper would pull, the clamp keeps f_n = 0 (no adhesion).
    np.testing.assert_allclose(forces[2], 0.0)
    moved = msd.floor_anchors_update(state, floor, anchors)
    assert np.linalg.norm(moved[1] - [0.0, 0.0]) == pytest.approx(0.5 * forces[1, 2] / floor.stiffness)


def test_settle_on_floor_reaches_rest_and_floor_carries_the_weight():
    # 162 nodes: trimesh.creation.icosphere(subdivisions=2, radius=0.05)
    mesh = trimesh.creation.icosphere(subdivisions=2, radius=0.05)
    params = msd.MsdParams()
    body = msd.msd_body_from_mesh(mesh, params)
    result = msd.settle_on_floor(body, params, t_max=3.0)
    assert result.settled
    assert 0.5 < result.squash_ratio < 1.0
    assert result.kinetic_energy.max() > 1e3 * result.kinetic_energy[-1]
    assert result.max_floor_penetration < 1e-4
    floor = msd.FloorParams(height=mesh.vertices[:, 2].min())
    support = msd.floor_forces(msd.state_from_positions(result.positions), floor)[:, 2].sum()
    assert support == pytest.approx(params.mass * params.g, rel=1e-2)
    assert dataclasses.is_dataclass(result)


# ---------------------------------------------------------------------------- optional volume term


def test_enclosed_volume_matches_trimesh_and_volume_forces_are_its_gradient(small_mesh):
    params = msd.MsdParams(bulk_modulus=0.47e6)
    body = msd.msd_body_from_mesh(small_mesh, params)
    assert body.rest_volume == pytest.approx(small_mesh.volume, rel=1e-12)  # trimesh reference
    rng = np.random.default_rng(2)
    x = small_mesh.vertices + 2e-3 * rng.normal(size=(42, 3))
    assert msd.enclosed_volume(body, x) == pytest.approx(
        trimesh.Trimesh(x, small_mesh.faces, process=False).volume, rel=1e-12
    )
    forces = msd.volume_forces(body, params, x)
    h = 1e-7
    for node in (0, 17, 41):
        for axis in range(3):
            plus, minus = x.copy(), x.copy()
            plus[node, axis] += h
            minus[node, axis] -= h
            numeric = -(
                msd.volume_energy(body, params, msd.state_from_positions(plus))
                - msd.volume_energy(body, params, msd.state_from_positions(minus))
            ) / (2 * h)
            assert forces[node, axis] == pytest.approx(numeric, rel=1e-5, abs=1e-9)


def test_energy_audit_closes_with_the_volume_term(small_mesh):
    params = msd.MsdParams(bulk_modulus=0.47e6, b=0.0, c=0.0)
    body = msd.msd_body_from_mesh(small_mesh, params)
    rng = np.random.default_rng(4)
    state0 = msd.state_from_positions(small_mesh.vertices * 0.98 + 5e-4 * rng.normal(size=(42, 3)))
    dt = 0.025 * msd.body_step_limit(body, params)
    audit = msd.energy_audit(body, params, state0, dt, 1600, record_every=10)
    assert msd.volume_energy(body, params, state0) > 0.1 * audit.elastic[0]
    assert audit.max_relative_error < 1e-5
