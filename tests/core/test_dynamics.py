"""Tests of core.dynamics: hand geometry, fingertip contacts on a deforming mesh, the grasp loop.

Outside references: the closed-form 45/45/-90 directions (§5.2, §6.1), brute-force
``geometry.sphere_triangle_contacts`` over every face (the broad phase must be exact), Eq. 13 at
the 0.5 mm seed, Newton's third law (Phi^T transfers the full contact force), and the friction-cone
LP of core.statics on the settled contact set.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from graspcampaign.core import dynamics, geometry, msd, statics
from graspcampaign.core.contact import ContactParams
from graspcampaign.core.mesh import make_object

# A stiff fingertip for the loop tests: K = 5 N mm^-n (lambda1 = 15.8 with the Table 2
# materials), so that f_n reaches the weight of 0.1 kg within a fraction of a millimetre. A test
# fixture of the mechanics, not a paper value.
STIFF_TIP = ContactParams(lambda1=15.8, lambda2=0.88, n=0.487)


@pytest.fixture(scope="module")
def sphere():
    return make_object("sphere", 92)


def test_hand_contact_directions_default_is_45_45_minus_90():
    d = dynamics.hand_contact_directions()
    s = np.sqrt(0.5)
    np.testing.assert_allclose(d, [[s, 0, s], [-s, 0, s], [0, 0, -1]], atol=1e-12)
    tilted = dynamics.hand_contact_directions(elevation_deg=30.0, third_elevation_deg=-60.0)
    np.testing.assert_allclose(np.degrees(np.arcsin(tilted[:, 2])), [30.0, 30.0, -60.0])
    np.testing.assert_allclose(np.linalg.norm(tilted, axis=1), 1.0)


def test_planned_contacts_hit_the_sphere_surface_along_the_rays(sphere):
    directions = dynamics.hand_contact_directions()
    points, faces, normals = dynamics.planned_contacts(sphere, directions)
    radii = np.linalg.norm(points - sphere.centroid, axis=1)
    # A faceted sphere lies between its inscribed and circumscribed radii.
    assert np.all(radii <= 0.05 + 1e-12) and np.all(radii > 0.045)
    np.testing.assert_allclose(
        (points - sphere.centroid) / radii[:, None], directions, atol=1e-9
    )
    np.testing.assert_allclose(normals, np.asarray(sphere.face_normals)[faces])
    assert np.all(np.einsum("ij,ij->i", normals, directions) > np.cos(np.radians(20.0)))


@settings(max_examples=40, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.floats(-1.0, 1.0),
            st.floats(0.040, 0.056),
        ),
        min_size=3,
        max_size=3,
    )
)
def test_finger_contacts_broad_phase_is_exact(samples):
    mesh = make_object("sphere", 92)
    body = msd.msd_body_from_mesh(mesh, msd.MsdParams())
    centers = []
    for x, y, z, dist in samples:
        u = np.array([x, y, z]) + [1e-3, 0.0, 0.0]
        centers.append(dist * u / np.linalg.norm(u))
    centers = np.array(centers)
    approach = centers / np.linalg.norm(centers, axis=1)[:, None]
    got = dynamics.finger_contacts(mesh.vertices, body, centers, 0.005, approach)
    brute = geometry.sphere_triangle_contacts(centers, 0.005, np.asarray(mesh.triangles),
                                              backend="numpy")
    best = geometry.deepest_per_finger(brute)
    np.testing.assert_array_equal(got.active, best >= 0)
    for j in np.flatnonzero(best >= 0):
        assert got.depths[j] == pytest.approx(brute.depths[best[j]], abs=1e-15)
        assert got.faces[j] == brute.faces[best[j]]


def test_grasp_loop_with_compiled_contacts_matches_the_numpy_reference(sphere, monkeypatch):
    """300 steps of the Fig. 3 loop with the compiled contact query and with the numpy reference
    path (vertices[faces] through ``backend="numpy"``): the same contacts and trajectory. As in
    benchmarks/bench_msd.py, gravity is off and free fingers re-close fast, so contacts persist."""
    setup, initial = dynamics.prepare_grasp(sphere, 0.3, msd.MsdParams(mass=0.1, g=0.0), STIFF_TIP,
                                            dynamics.GraspParams(grip_speed=0.3))

    def run():
        gs = initial.copy()
        faces, forces = [], []
        for _ in range(300):
            out = dynamics.grasp_forces(setup, gs)
            faces.append(out.contacts.faces)
            forces.append(out.forces)
            dynamics.advance_grasp(setup, gs, out)
        return np.array(faces), np.array(forces), gs.state

    compiled = run()

    def numpy_reference(centers, radius, vertices, faces):
        return geometry.sphere_triangle_contacts(centers, radius, np.asarray(vertices)[faces],
                                                 backend="numpy")

    monkeypatch.setattr(dynamics.geometry, "sphere_mesh_contacts", numpy_reference)
    reference = run()
    assert (compiled[0] >= 0).mean() > 0.5  # most finger-steps are in contact
    np.testing.assert_array_equal(compiled[0], reference[0])
    np.testing.assert_allclose(compiled[1], reference[1], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(compiled[2], reference[2], rtol=1e-9, atol=1e-15)


def test_grasp_state_copy_shares_no_arrays(sphere):
    _, initial = dynamics.prepare_grasp(sphere, 0.3, msd.MsdParams(mass=0.1), STIFF_TIP)
    copy = initial.copy()
    for name in ("state", "grip", "grip_rate", "slip_coords"):
        getattr(copy, name)[...] = 7.0
        assert not np.any(getattr(initial, name) == 7.0), name
    assert copy.time == initial.time


def test_seeded_forces_follow_eq13_and_phi_transfer_conserves_them(sphere):
    setup, state = dynamics.prepare_grasp(sphere, 0.3, msd.MsdParams(mass=0.1), STIFF_TIP)
    out = dynamics.grasp_forces(setup, state)
    assert out.contacts.active.all()
    # At rest the rate term vanishes: f_n = K (delta_mm)^n with delta close to the 0.5 mm seed
    # (the faceted surface shifts the deepest face slightly).
    expected = STIFF_TIP.k_n_per_mm_n * (out.contacts.depths * 1e3) ** STIFF_TIP.n
    np.testing.assert_allclose(out.normal_forces, expected, rtol=1e-12)
    np.testing.assert_allclose(out.contacts.depths, 5e-4, atol=2e-4)
    np.testing.assert_allclose(out.tangential, 0.0, atol=1e-12)
    np.testing.assert_allclose(out.nodal_forces.sum(axis=0), out.forces.sum(axis=0), atol=1e-12)
    np.testing.assert_allclose(out.residual, out.forces.sum(axis=0) + [0, 0, -0.1 * 9.81])
    # Moment of the transferred forces about the origin equals that of the contact forces.
    nodes = msd.positions_from_state(state.state)
    np.testing.assert_allclose(
        np.cross(nodes, out.nodal_forces).sum(axis=0),
        np.cross(out.contacts.points, out.forces).sum(axis=0),
        atol=1e-12,
    )


def test_grasp_params_validation():
    with pytest.raises(ValueError, match="GraspParams.tau_f must be finite and > 0"):
        dynamics.GraspParams(tau_f=0.0)
    with pytest.raises(ValueError, match="mu must be finite and >= 0"):
        dynamics.prepare_grasp(make_object("sphere", 42), -0.1)


@pytest.mark.slow  # one simulated second of the dynamic grasp: `make test-full`
def test_settled_grasp_balances_the_weight_within_tau_f(sphere):
    # A stiffer shell (10 k) and the stiff fingertip: the loop mechanics in a regime where the
    # shell does not sag off the bottom fingertip (see test_paper_si_constants_do_not_hold_...).
    mass, mu = 0.1, 0.5
    params = msd.MsdParams(mass=mass, k=1.44e4)
    grasp = dynamics.GraspParams(t_max=1.0)
    result = dynamics.dynamic_grasp(sphere, mu, params, STIFF_TIP, grasp)
    assert result.status == "stable", result.status
    assert result.success
    weight = mass * params.g
    # Eq. 19 vertically: the per-finger forces carry the weight within tau_F.
    assert abs(result.contact_forces[:, 2].sum() - weight) < grasp.tau_f
    assert abs(result.residual_z[-1]) < grasp.tau_f
    np.testing.assert_allclose(result.wrench[2], result.residual_z[-1])
    assert np.all(result.normal_forces[-1] > 0.0)
    assert np.all(result.in_contact[-1])
    # The settled contact set is statically admissible (friction-cone LP, like for like).
    normals = -result.contact_forces / np.linalg.norm(result.contact_forces, axis=1)[:, None]
    lp = statics.friction_cone_feasibility(
        result.contact_points, normals, mu, mass, center=result.centroid[-1]
    )
    assert lp.status == "feasible"
    # Traces have one row per step.
    n = result.n_steps
    assert result.normal_forces.shape == (n, 3) and result.total_penetration.shape == (n,)
    assert result.delta_max < STIFF_TIP.fingertip_radius


def test_paper_si_constants_do_not_hold_a_heavy_sphere():
    # The paper's Table 3 contact law with the Table 2 materials gives K = 0.105 N mm^-n: carrying
    # 0.4 kg on the bottom fingertip would need delta ~ (3.9 / 0.105)^(1/0.487) mm ~ 1.7 m. The
    # surface shell sags around the fingertip and the grasp fails; the loop must say so.
    mesh = make_object("sphere", 92)
    result = dynamics.dynamic_grasp(mesh, 0.3, msd.MsdParams(mass=0.4), grasp=dynamics.GraspParams(t_max=0.5))
    assert not result.success
    assert result.status in {"dropped", "penetration_limit", "not_settled"}
    assert result.residual_z.min() < -0.5
