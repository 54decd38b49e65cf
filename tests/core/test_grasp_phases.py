"""Tests of core.grasp_phases: the dynamic grasp in the order of Fig. 11 and its Eq. 19 verdict.

Outside references: the closed-form static indentation of one fingertip carrying the weight,
``(m g / K)^(1/n)`` (values worked by hand below), Newton's laws on the held body, and the
friction-cone LP of core.statics on the settled contact set.
"""

from __future__ import annotations

import numpy as np
import pytest

from graspcampaign.core import dynamics, grasp_phases, msd, statics
from graspcampaign.core.contact import ContactParams, normal_force
from graspcampaign.core.mesh import make_object

G = 9.81
# The firm preset of conf/model/firm.yaml (docs/decisions.md): Shore 30A fingertip, Shore 50A
# object (Gent 1958), Hertz contact (lambda1 = 2/3, n = 3/2).
FIRM = ContactParams(lambda1=2.0 / 3.0, lambda2=0.88, n=1.5, e_finger=1.1424e6,
                     e_object=2.4558e6, nu_finger=0.5, nu_object=0.5)


@pytest.fixture(scope="module")
def firm_run(firm_grasp):
    """A small firm-preset grasp that holds: 144 nodes, 0.2 kg, mu = 0.3, default phases."""
    setup, _, result = firm_grasp
    return setup, result


def test_firm_preset_holds_with_valid_geometry_and_balances_the_weight(firm_run):
    setup, result = firm_run
    assert result.status == "stable", result.status
    assert result.success and result.success_unbounded and result.valid_geometry
    assert result.final_phase == "hold"
    assert result.delta_max <= FIRM.fingertip_radius
    # Eq. 19 vertically: the fingers carry the weight within tau_F, the support carries nothing.
    tau_f = setup.grasp.tau_f
    assert abs(result.contact_forces[:, 2].sum() - 0.2 * G) < tau_f
    assert abs(result.residual_z[-1]) < tau_f
    np.testing.assert_allclose(result.support_force[-1], 0.0, atol=1e-12)
    np.testing.assert_allclose(result.wrench[2], result.residual_z[-1])
    # The settled window is a hold: every finger touched within it, the centroid at rest.
    window = result.times >= result.phase_times.hold_start
    assert result.in_contact[window].any(axis=0).all()
    assert np.all(np.abs(result.residual_z[window]) < tau_f)
    # The settled contact set is statically admissible (friction-cone LP, like for like).
    normals = -result.contact_forces / np.linalg.norm(result.contact_forces, axis=1)[:, None]
    loaded = result.normal_forces[-1] > 0.0
    lp = statics.friction_cone_feasibility(result.contact_points[loaded], normals[loaded], 0.3,
                                           0.2, center=result.centroid[-1])
    assert lp.status == "feasible"


def test_phases_run_in_the_order_of_fig_11(firm_run):
    setup, result = firm_run
    times = result.phase_times
    order = {name: i for i, name in enumerate(grasp_phases.PHASES)}
    ranks = np.array([order[p] for p in result.phase])
    assert ranks[0] == 0 and ranks[-1] == 2 and np.all(np.diff(ranks) >= 0)
    # Contacts close before lift-off: every finger touched during the closure, and at the moment
    # the lift begins every finger is in contact at (at least) the seed depth.
    assert np.all(times.touch >= times.closure_start) and np.all(times.touch < times.closure_end)
    assert times.closure_end == times.lift_start < times.lift_end <= times.hold_start
    assert times.hold_start < times.hold_end == result.settled_at
    start = np.flatnonzero(result.times == times.lift_start)[0]
    assert result.in_contact[start].all()
    assert np.all(result.depths[:start + 1].max(axis=0) >= setup.grasp.seed_depth)
    # The load passes to the fingers only during the lift: 0 while closing, rising, 1 in the hold.
    w = result.load_fraction
    closing, lifting = result.phase == "closure", result.phase == "lift"
    assert np.all(w[closing] == 0.0) and np.all(w[result.phase == "hold"] == 1.0)
    assert np.all(np.diff(w[lifting]) >= 0.0) and w[lifting].max() < 1.0
    assert times.lift_end - times.lift_start == pytest.approx(setup.grasp.lift_time, abs=setup.dt)


def test_the_held_body_does_not_fall_during_closure(firm_run):
    setup, result = firm_run
    closing = result.phase == "closure"
    # Held: the centroid does not move although gravity and the fingers act on the body ...
    drift = np.abs(result.centroid[closing] - result.centroid[0]).max()
    assert drift < 1e-12
    # ... because the support takes the rest (Newton: support + fingers + weight = m a = 0).
    np.testing.assert_allclose(result.support_force[closing], -result.residual[closing],
                               atol=1e-9)
    assert result.support_force[closing, 2].min() > 0.5 * 0.2 * G  # it carries most of m g
    # Released for the same time, the same body falls g t^2 / 2 (the counterfactual).
    t = result.phase_times.closure_end
    mesh = make_object("sphere", 144)
    params = msd.msd_params_from_modulus(mesh, youngs_modulus=FIRM.e_object, mass=0.2)
    free_setup, free = dynamics.prepare_grasp(mesh, 0.3, params, FIRM,
                                              dynamics.GraspParams(open_gap=0.05))
    free = free.commanded(np.zeros(3), 1.0)
    for _ in range(int(round(t / free_setup.dt))):
        free = dynamics.grasp_step(free_setup, free)
    rest_z = free_setup.body.rest_positions[:, 2].mean()
    fall = rest_z - msd.positions_from_state(free.state)[:, 2].mean()
    # g t^2 / 2 = 34 mm in 83 ms; the absolute nodal damping b of the firm body (Rayleigh pair of
    # msd_params_from_modulus) acts like a drag and roughly halves it.
    assert fall > 0.25 * G * t * t * 0.5
    assert fall > 1e9 * drift


def test_paper_constants_cannot_hold_and_the_closed_form_says_why():
    # Table 3's law with Table 2's materials: K = 0.10534 N mm^-n, n = 0.487. One fingertip alone
    # carries 0.2 kg at (0.2 * 9.81 / 0.10534)^(1 / 0.487) mm = 18.625^2.0534 mm = 408 mm
    # (by hand: ln 18.625 = 2.9245, x 2.0534 = 6.0052, e^6.0052 = 405.5 mm with K = 0.10534).
    mesh = make_object("sphere", 92)
    contact = ContactParams.table3()
    params = msd.msd_params_from_modulus(mesh, youngs_modulus=contact.e_object, mass=0.2)
    result = grasp_phases.dynamic_grasp(mesh, 0.3, params, contact)
    assert result.delta_required == pytest.approx(0.4055, rel=2e-3)
    # Consequence of the closed form: Eq. 13 at rest at that depth gives exactly the weight.
    assert normal_force(result.delta_required, 0.0, contact.k_n_per_mm_n, contact.n,
                        contact.c_n_s_per_m) == pytest.approx(0.2 * G, rel=1e-12)
    assert result.status == "penetration_limit"
    assert result.final_phase in ("lift", "hold")  # it fails once the weight arrives
    assert not result.valid_geometry and not result.success and not result.success_unbounded
    assert result.delta_max > FIRM.fingertip_radius


def test_table4_gel_needs_39_mm_for_0_2_kg():
    # Table 4, gel: K = 0.346 N mm^-n, n = 0.473: (1.962 / 0.346)^(1 / 0.473) mm
    # = 5.6705^2.1142 mm; ln 5.6705 = 1.7352, x 2.1142 = 3.6686, e^3.6686 = 39.2 mm.
    from graspcampaign.core.contact import depth_for_force

    assert depth_for_force(0.2 * G, 0.346, 0.473) == pytest.approx(39.2e-3, rel=2e-3)


@pytest.mark.slow  # ~4000 RK4 steps (5-10 s); the fast suite checks the gate on records too
def test_validity_gate_removes_a_hold_deeper_than_the_fingertip_radius():
    """A 20 g gel sphere on the paper's contact law settles on the bottom fingertip ~5.2 mm deep:
    Eq. 19 is met, but the fingertip (r = 5 mm) would be buried past its radius. With the stop
    raised to 10 mm the run holds (``success_unbounded``) and the gate removes it (``success``);
    with the default stop (r) the same grasp ends ``penetration_limit``."""
    mesh = make_object("sphere", 42)
    contact = ContactParams.table3()
    params = msd.msd_params_from_modulus(mesh, youngs_modulus=contact.e_object, mass=0.02)
    deep = grasp_phases.dynamic_grasp(mesh, 0.5, params, contact,
                                      dynamics.GraspParams(max_depth=0.01))
    assert deep.status == "stable" and deep.success_unbounded
    assert deep.delta_max > contact.fingertip_radius
    assert not deep.valid_geometry and not deep.success
    stopped = grasp_phases.dynamic_grasp(mesh, 0.5, params, contact)
    assert stopped.status == "penetration_limit"
    assert not stopped.valid_geometry and not stopped.success
    assert stopped.n_steps < deep.n_steps


def test_load_fraction_is_a_smooth_ramp():
    w = grasp_phases.load_fraction(np.array([-1.0, 0.0, 0.05, 0.1, 0.2]), 0.1)
    np.testing.assert_allclose(w, [0.0, 0.0, 0.5, 1.0, 1.0], atol=1e-15)
