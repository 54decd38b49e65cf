"""Tests of core.dynamics: the contact stage, the support, and one step of the dynamic grasp.

Outside references: Eq. 13 at the 0.5 mm seed, Newton's third law (Phi^T transfers the full
contact force), rigid-body mechanics (a held body keeps zero momentum; a free body falls by
g t^2 / 2, which RK4 integrates exactly), and the numpy reference path of the contact query.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from graspcampaign.core import dynamics, geometry, hand, msd
from graspcampaign.core.contact import ContactParams
from graspcampaign.core.mesh import make_object

# A stiff fingertip for the loop tests: K = 5 N mm^-n (lambda1 = 15.8 with the Table 2
# materials), so that f_n reaches the weight of 0.1 kg within a fraction of a millimetre. A test
# fixture of the mechanics, not a paper value.
STIFF_TIP = ContactParams(lambda1=15.8, lambda2=0.88, n=0.487)
G = 9.81


@pytest.fixture(scope="module")
def sphere():
    return make_object("sphere", 92)


def _seeded(setup, state, depth=5e-4):
    """The state with every finger advanced to ``depth`` past first touch, contacts re-evaluated."""
    moved = replace(state, grip=np.full(setup.n_fingers, depth))
    return replace(moved, contact=dynamics.grasp_forces(setup, moved))


def test_grasp_steps_with_compiled_contacts_match_the_numpy_reference(sphere, monkeypatch):
    """300 steps with the compiled contact query and with the numpy reference path (vertices[faces]
    through ``backend="numpy"``): the same contacts and trajectory. As in benchmarks/bench_msd.py,
    gravity is off, the body free, and the fingers close fast (0.3 m/s) while out of contact or
    while |R_z| >= tau_F (the grip law of §3), so contacts persist."""
    setup, opened = dynamics.prepare_grasp(sphere, 0.3, msd.MsdParams(mass=0.1, g=0.0), STIFF_TIP)

    def run():
        gs = _seeded(setup, opened)
        faces, forces = [], []
        for _ in range(300):
            faces.append(gs.contact.contacts.faces)
            forces.append(gs.contact.forces)
            out = gs.contact
            closing = ~out.contacts.active | (abs(out.residual[2]) >= setup.grasp.tau_f)
            gs = dynamics.grasp_step(setup, gs.commanded(np.where(closing, 0.3, 0.0), 1.0))
        return np.array(faces), np.array(forces), gs.state

    compiled = run()

    def numpy_reference(centers, radius, vertices, faces):
        return geometry.sphere_triangle_contacts(centers, radius, np.asarray(vertices)[faces],
                                                 backend="numpy")

    monkeypatch.setattr(hand.geometry, "sphere_mesh_contacts", numpy_reference)
    reference = run()
    assert (compiled[0] >= 0).mean() > 0.5  # most finger-steps are in contact
    np.testing.assert_array_equal(compiled[0], reference[0])
    np.testing.assert_allclose(compiled[1], reference[1], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(compiled[2], reference[2], rtol=1e-9, atol=1e-15)


def test_grasp_step_is_a_pure_function_of_setup_and_state(sphere):
    setup, opened = dynamics.prepare_grasp(sphere, 0.3, msd.MsdParams(mass=0.1), STIFF_TIP)
    gs = _seeded(setup, opened).commanded([0.01, 0.02, 0.0], 0.5)
    before = {name: np.copy(getattr(gs, name)) for name in ("state", "grip", "grip_rate",
                                                            "slip_coords")}
    nodal = gs.contact.nodal_forces.copy()
    new = dynamics.grasp_step(setup, gs)
    again = dynamics.grasp_step(setup, gs)
    for name, value in before.items():
        np.testing.assert_array_equal(getattr(gs, name), value, err_msg=name)
    np.testing.assert_array_equal(gs.contact.nodal_forces, nodal)
    np.testing.assert_array_equal(new.state, again.state)  # same input, same output
    assert new.time == pytest.approx(setup.dt)
    np.testing.assert_allclose(new.grip, gs.grip + setup.dt * np.array([0.01, 0.02, 0.0]))
    np.testing.assert_array_equal(new.grip_rate, gs.grip_rate)  # the command carries over
    assert new.load_fraction == 0.5
    assert new.stick is gs.contact.stick  # the evaluated stick state is committed


def test_seeded_forces_follow_eq13_and_phi_transfer_conserves_them(sphere):
    setup, opened = dynamics.prepare_grasp(sphere, 0.3, msd.MsdParams(mass=0.1), STIFF_TIP)
    assert not opened.contact.contacts.active.any()  # fingers start open (Fig. 11)
    np.testing.assert_allclose(
        dynamics.finger_centers(setup, opened.grip) - setup.targets,
        setup.approach * (STIFF_TIP.fingertip_radius + setup.grasp.open_gap),
    )
    state = _seeded(setup, opened)
    out = state.contact
    assert out.contacts.active.all()
    # At rest the rate term vanishes: f_n = K (delta_mm)^n with delta close to the 0.5 mm seed
    # (the faceted surface shifts the deepest face slightly).
    expected = STIFF_TIP.k_n_per_mm_n * (out.contacts.depths * 1e3) ** STIFF_TIP.n
    np.testing.assert_allclose(out.normal_forces, expected, rtol=1e-12)
    np.testing.assert_allclose(out.contacts.depths, 5e-4, atol=2e-4)
    np.testing.assert_allclose(out.tangential, 0.0, atol=1e-12)
    np.testing.assert_allclose(out.nodal_forces.sum(axis=0), out.forces.sum(axis=0), atol=1e-12)
    np.testing.assert_allclose(out.residual, out.forces.sum(axis=0) + [0, 0, -0.1 * G])
    # The held body at rest: the support takes whatever the fingers and gravity leave.
    np.testing.assert_allclose(out.support_force, -out.residual, atol=1e-12)
    # Moment of the transferred forces about the origin equals that of the contact forces.
    nodes = msd.positions_from_state(state.state)
    np.testing.assert_allclose(
        np.cross(nodes, out.nodal_forces).sum(axis=0),
        np.cross(out.contacts.points, out.forces).sum(axis=0),
        atol=1e-12,
    )


@settings(max_examples=50, deadline=None)
@given(arrays(np.float64, (12, 3), elements=st.floats(-1.0, 1.0)),
       arrays(np.float64, (12, 3), elements=st.floats(-10.0, 10.0)))
def test_rigid_body_part_removes_net_force_and_torque_and_is_a_projection(offsets, accel):
    # Points of a unit cube plus bounded offsets: never all collinear, so the inertia is regular.
    corners = np.array([[x, y, z] for x in (0, 2) for y in (0, 2) for z in (0, 2)], float)
    positions = np.vstack([corners, corners[:4] + [0.5, 0.5, 0.5]]) + 0.2 * offsets
    rigid = dynamics.rigid_body_part(positions, accel)
    rest = accel - rigid
    r = positions - positions.mean(axis=0)
    scale = 1.0 + np.abs(accel).sum()
    np.testing.assert_allclose(rest.sum(axis=0), 0.0, atol=1e-10 * scale)
    np.testing.assert_allclose(np.cross(r, rest).sum(axis=0), 0.0, atol=1e-9 * scale)
    # A rigid field is its own rigid part; the remainder has no rigid part.
    np.testing.assert_allclose(dynamics.rigid_body_part(positions, rigid), rigid, atol=1e-9 * scale)
    np.testing.assert_allclose(dynamics.rigid_body_part(positions, rest), 0.0, atol=1e-9 * scale)


def test_support_holds_the_body_and_releasing_it_gives_free_fall(sphere):
    """Open fingers touch nothing: held (w = 0) the centroid and the momentum stay at zero and the
    support carries m g; free (w = 1) the rest shape falls rigidly by g t^2 / 2 (no internal force
    at rest, nodal damping only on velocity: with b = 0 RK4 is exact for constant acceleration)."""
    mass = 0.1
    setup, state = dynamics.prepare_grasp(sphere, 0.3, msd.MsdParams(mass=mass, b=0.0), STIFF_TIP)
    np.testing.assert_allclose(state.contact.support_force, [0.0, 0.0, mass * G])
    held, free = state.commanded(np.zeros(3), 0.0), state.commanded(np.zeros(3), 1.0)
    for _ in range(50):
        held = dynamics.grasp_step(setup, held)
        free = dynamics.grasp_step(setup, free)
    t = 50 * setup.dt
    rest = setup.body.rest_positions
    np.testing.assert_allclose(msd.positions_from_state(held.state), rest, atol=1e-15)
    np.testing.assert_allclose(msd.velocities_from_state(held.state), 0.0, atol=1e-15)
    np.testing.assert_allclose(held.contact.support_force, [0.0, 0.0, mass * G], rtol=1e-12)
    drop = rest[:, 2] - msd.positions_from_state(free.state)[:, 2]
    np.testing.assert_allclose(drop, 0.5 * G * t * t, rtol=1e-9)
    np.testing.assert_allclose(free.contact.support_force, 0.0)


def test_prepare_grasp_takes_any_planned_contacts(sphere):
    # Three vertices and their vertex normals, as a quasi-static planner would give them.
    vertices = [0, 40, 80]
    points = sphere.vertices[vertices]
    normals = sphere.vertex_normals[vertices]
    setup, state = dynamics.prepare_grasp(sphere, 0.5, msd.MsdParams(mass=0.1), STIFF_TIP,
                                          points=points, normals=normals)
    np.testing.assert_allclose(setup.targets, points)
    np.testing.assert_allclose(setup.approach, normals / np.linalg.norm(normals, axis=1)[:, None])
    seeded = _seeded(setup, state)
    assert seeded.contact.contacts.active.all()
    with pytest.raises(ValueError, match="points and normals must be given together"):
        dynamics.prepare_grasp(sphere, 0.5, points=points)
    with pytest.raises(ValueError, match=r"must both have shape \(c, 3\), got \(3, 3\) and \(2, 3\)"):
        dynamics.prepare_grasp(sphere, 0.5, points=points, normals=normals[:2])


def test_grasp_params_validation():
    with pytest.raises(ValueError, match="GraspParams.tau_f must be finite and > 0"):
        dynamics.GraspParams(tau_f=0.0)
    with pytest.raises(ValueError, match="GraspParams.lift_time must be finite and > 0"):
        dynamics.GraspParams(lift_time=0.0)
    with pytest.raises(ValueError, match="GraspParams.open_gap must be finite and >= 0"):
        dynamics.GraspParams(open_gap=-1e-3)
    with pytest.raises(ValueError, match="mu must be finite and >= 0"):
        dynamics.prepare_grasp(make_object("sphere", 42), -0.1)
