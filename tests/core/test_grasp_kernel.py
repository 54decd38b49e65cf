"""Tests of core.grasp_kernel: the compiled dynamic-grasp step against the numpy reference step.

Outside references: the numpy step of core.dynamics (itself checked against Eq. 13, Newton's
laws and rigid-body mechanics in test_dynamics.py), Newton's third law for the Phi^T transfer,
and numpy for the node summary.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from graspcampaign.core import dynamics, grasp_kernel, grasp_phases, msd
from graspcampaign.core.contact import ContactParams
from graspcampaign.core.mesh import make_object

# The stiff test fingertip of test_dynamics.py (K = 5 N mm^-n): contacts carry 0.1 kg within a
# fraction of a millimetre. A fixture of the mechanics, not a paper value.
STIFF = dict(lambda1=15.8, lambda2=0.88, n=0.487)


@pytest.fixture(scope="module")
def sphere():
    return make_object("sphere", 92)


def _seeded(setup, state, depth=5e-4):
    moved = replace(state, grip=np.full(setup.n_fingers, depth))
    return replace(moved, contact=dynamics.grasp_forces(setup, moved))


def _run(step, setup, gs, load_fraction, n_steps=300):
    """The grip law of §3 (every finger closes while |R_z| >= tau_F, a finger out of contact
    closes until it touches), at 0.3 m/s so that contacts persist; per-step records."""
    rows = {"faces": [], "forces": [], "normal": [], "sliding": [], "nodal": [], "support": []}
    for _ in range(n_steps):
        out = gs.contact
        rows["faces"].append(out.contacts.faces)
        rows["forces"].append(out.forces)
        rows["normal"].append(out.normal_forces)
        rows["sliding"].append(out.stick.sliding & out.contacts.active)
        rows["nodal"].append(out.nodal_forces)
        rows["support"].append(out.support_force)
        closing = ~out.contacts.active | (abs(out.residual[2]) >= setup.grasp.tau_f)
        gs = step(setup, gs.commanded(np.where(closing, 0.3, 0.0), load_fraction))
    return {k: np.array(v) for k, v in rows.items()}, gs


@pytest.mark.parametrize("law, mu, g, load_fraction, bulk", [
    ("linear", 0.3, 0.0, 1.0, 0.0),
    ("linear", 0.05, 9.81, 0.5, 0.0),
    ("linear", 0.3, 9.81, 0.0, 0.47e6),
    ("hunt_crossley", 0.1, 9.81, 1.0, 0.0),
    ("hunt_crossley", 0.3, 9.81, 0.0, 0.0),
], ids=["linear-free-no-gravity", "linear-lifting-sliding", "linear-held-volume",
        "hc-free", "hc-held"])
def test_compiled_step_follows_the_numpy_step_for_300_steps(sphere, law, mu, g, load_fraction,
                                                             bulk):
    """Same host faces and slip states at every step, forces and final state to rounding.

    The schedule is the §3 grip law, which does not amplify rounding (about 1e-14 m after 300
    steps); a schedule where only out-of-contact fingers close amplifies it to ~1e-7 m
    (docs/decisions.md, compiled dynamic step)."""
    contact = ContactParams(**STIFF, damping_law=law)
    setup, opened = dynamics.prepare_grasp(sphere, mu, msd.MsdParams(mass=0.1, g=g,
                                                                     bulk_modulus=bulk), contact)
    start = _seeded(setup, opened)
    reference, ref_end = _run(dynamics.grasp_step, setup, start, load_fraction)
    compiled, end = _run(grasp_kernel.compiled_grasp_step, setup, start, load_fraction)
    assert (reference["faces"] >= 0).mean() > 0.4  # contacts persist
    assert reference["sliding"].any() and (~reference["sliding"]).any()  # both friction regimes
    np.testing.assert_array_equal(compiled["faces"], reference["faces"])
    np.testing.assert_array_equal(compiled["sliding"], reference["sliding"])
    # Positions agree to ~1e-12 m at worst (a slip transition amplifies the last bits); through
    # the contact stiffness n K delta^(n-1) (1e4-1e5 N/m near the onset of Eq. 13 with n < 1)
    # that is ~1e-8 N, against forces of 1-10 N.
    for key in ("forces", "normal", "nodal", "support"):
        np.testing.assert_allclose(compiled[key], reference[key], rtol=1e-7, atol=1e-8,
                                   err_msg=key)
    np.testing.assert_allclose(end.state, ref_end.state, rtol=0, atol=1e-10)
    np.testing.assert_allclose(end.grip, ref_end.grip, rtol=0, atol=1e-15)
    np.testing.assert_allclose(end.slip_coords, ref_end.slip_coords, rtol=0, atol=1e-12)
    np.testing.assert_allclose(end.stick.anchors, ref_end.stick.anchors, rtol=0, atol=1e-12)
    assert end.time == ref_end.time


def test_compiled_step_keeps_the_step_contract(sphere):
    setup, opened = dynamics.prepare_grasp(sphere, 0.3, msd.MsdParams(mass=0.1),
                                           ContactParams(**STIFF))
    gs = _seeded(setup, opened).commanded([0.01, 0.02, 0.0], 0.5)
    before = {name: np.copy(getattr(gs, name)) for name in ("state", "grip", "grip_rate",
                                                            "slip_coords")}
    new = grasp_kernel.compiled_grasp_step(setup, gs)
    again = grasp_kernel.compiled_grasp_step(setup, gs)
    for name, value in before.items():
        np.testing.assert_array_equal(getattr(gs, name), value, err_msg=name)
    np.testing.assert_array_equal(new.state, again.state)
    assert isinstance(new, dynamics.GraspState)
    assert isinstance(new.contact, dynamics.GraspForces)
    assert new.time == pytest.approx(setup.dt) and new.load_fraction == 0.5
    np.testing.assert_array_equal(new.grip_rate, gs.grip_rate)
    assert new.stick is gs.contact.stick  # the evaluated stick state is committed
    out = new.contact
    assert out.contacts.active.dtype == bool and out.contacts.faces.dtype == np.int64
    # Newton's third law through Phi^T: the nodes receive the full contact forces and their moment
    nodes = msd.positions_from_state(new.state)
    np.testing.assert_allclose(out.nodal_forces.sum(axis=0), out.forces.sum(axis=0), atol=1e-12)
    np.testing.assert_allclose(np.cross(nodes, out.nodal_forces).sum(axis=0),
                               np.cross(out.contacts.points, out.forces).sum(axis=0), atol=1e-12)


def test_contact_stage_matches_grasp_forces_with_an_open_finger(sphere):
    setup, opened = dynamics.prepare_grasp(sphere, 0.2, msd.MsdParams(mass=0.1),
                                           ContactParams(**STIFF, damping_law="hunt_crossley"))
    rng = np.random.default_rng(2)
    moved = replace(opened, grip=np.array([8e-4, 3e-4, -5e-4]),  # third finger still open
                    grip_rate=np.array([0.01, 0.0, 0.02]),
                    state=opened.state + 2e-5 * rng.normal(size=opened.state.shape),
                    slip_coords=1e-5 * rng.normal(size=(3, 3)))
    reference = dynamics.grasp_forces(setup, moved)
    packed = grasp_kernel.packed_setup(setup)
    vec, scal, flags, hosts, sums, nodal = grasp_kernel.contact_stage(
        moved.state.reshape(-1, 6), packed.edges, packed.faces, packed.targets, packed.approach,
        moved.grip, moved.grip_rate, moved.slip_coords, moved.stick.anchors, packed.law,
        packed.weight_z, setup.msd_params.b, moved.load_fraction)
    hits = reference.contacts
    np.testing.assert_array_equal(flags[grasp_kernel.ACTIVE], [True, True, False])
    np.testing.assert_array_equal(flags[grasp_kernel.ACTIVE], hits.active)
    np.testing.assert_array_equal(hosts, hits.faces)
    for row, field in ((grasp_kernel.POINTS, hits.points), (grasp_kernel.NORMALS, hits.normals),
                       (grasp_kernel.WEIGHTS, hits.weights), (grasp_kernel.FORCES, reference.forces),
                       (grasp_kernel.TANGENTIAL, reference.tangential),
                       (grasp_kernel.REL_VEL, reference.relative_velocity),
                       (grasp_kernel.ANCHORS, reference.stick.anchors)):
        np.testing.assert_allclose(vec[row], field, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(scal[grasp_kernel.DEPTHS], hits.depths, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(scal[grasp_kernel.NORMAL_FORCES], reference.normal_forces,
                               rtol=1e-12)
    np.testing.assert_array_equal(flags[grasp_kernel.SLIDING], reference.stick.sliding)
    np.testing.assert_allclose(sums[grasp_kernel.RESIDUAL], reference.residual, rtol=1e-12)
    np.testing.assert_allclose(sums[grasp_kernel.SUPPORT], reference.support_force, rtol=1e-12)
    np.testing.assert_allclose(nodal, reference.nodal_forces, rtol=1e-12, atol=1e-15)


def test_phases_on_the_compiled_step_reproduce_the_numpy_run(firm_grasp):
    """The whole Fig. 11 sequence (closure, lift-off, hold) of a small firm grasp that holds:
    same outcome, phase times, step count and contact history as the numpy run. Over its ~4600
    steps stick-slip makes the trajectory sensitive to the last bits: the compiled run stays
    within the spread that a 1e-15 m perturbation of the initial state produces on itself."""
    setup, state, reference = firm_grasp
    compiled = grasp_phases.run_grasp_phases(setup, state, step=grasp_kernel.compiled_grasp_step)
    assert reference.status == compiled.status == "stable"
    assert compiled.success == reference.success
    assert compiled.n_steps == reference.n_steps
    for name in ("closure_end", "lift_start", "lift_end", "hold_start", "hold_end"):
        assert getattr(compiled.phase_times, name) == getattr(reference.phase_times, name), name
    np.testing.assert_array_equal(compiled.phase, reference.phase)
    np.testing.assert_array_equal(compiled.in_contact, reference.in_contact)
    jitter = 1e-15 * np.random.default_rng(0).normal(size=state.state.shape)
    perturbed = replace(state, state=state.state + jitter)
    perturbed = replace(perturbed, contact=dynamics.grasp_forces(setup, perturbed))
    spread = grasp_phases.run_grasp_phases(setup, perturbed, step=grasp_kernel.compiled_grasp_step)
    steps = min(spread.n_steps, compiled.n_steps) + 1
    envelope = np.abs(spread.normal_forces[:steps] - compiled.normal_forces[:steps]).max()
    assert envelope > 0.0
    assert np.abs(compiled.normal_forces - reference.normal_forces).max() <= 5.0 * envelope
    first = slice(0, 300)  # the first 300 steps agree to rounding
    np.testing.assert_allclose(compiled.normal_forces[first], reference.normal_forces[first],
                               rtol=1e-9, atol=1e-12)


def test_compiled_step_reports_divergence_like_the_numpy_step(sphere):
    params = msd.MsdParams(mass=0.1)
    grasp = dynamics.GraspParams(dt=1e-2)  # far beyond the RK4 limit (~2e-4 s)
    setup, state = dynamics.prepare_grasp(sphere, 0.3, params, ContactParams(**STIFF), grasp)
    message = r"dynamic grasp diverged at t = [0-9.e-]+ s \(dt = 0.01 s\)"
    for step in (dynamics.grasp_step, grasp_kernel.compiled_grasp_step):
        gs = _seeded(setup, state, depth=2e-3).commanded(np.zeros(3), 1.0)
        with pytest.raises(FloatingPointError, match=message), np.errstate(all="ignore"):
            for _ in range(200):
                gs = step(setup, gs)


def test_body_summary_matches_numpy(sphere):
    rng = np.random.default_rng(1)
    state = rng.normal(size=6 * 92)
    nodes = state.reshape(-1, 6)
    summary = grasp_kernel.body_summary(state)
    np.testing.assert_allclose(summary[:6], nodes.mean(axis=0), rtol=1e-13, atol=1e-15)
    assert summary[6] == pytest.approx(np.sum(nodes[:, 3:] ** 2), rel=1e-13)
