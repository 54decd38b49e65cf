"""Tests of core.phase_kernel: the compiled phase loop against the Python phase driver.

Outside reference: the Python driver of core.grasp_phases (itself tested against Newton's laws,
the closed-form required indentation and the friction-cone LP in test_grasp_phases.py) running
the same compiled step; both must give the same result bit for bit, since they run the same
kernel under the same rules.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from graspcampaign.core import dynamics, grasp_kernel, grasp_phases, msd, phase_kernel
from graspcampaign.core.contact import ContactParams
from graspcampaign.core.mesh import make_object


def _assert_same(python, compiled):
    for field in dataclasses.fields(grasp_phases.DynamicGraspResult):
        a, b = getattr(python, field.name), getattr(compiled, field.name)
        if field.name == "phase_times":
            for name in ("closure_start", "closure_end", "lift_start", "lift_end", "hold_start",
                         "hold_end"):
                np.testing.assert_equal(getattr(b, name), getattr(a, name), err_msg=name)
            np.testing.assert_array_equal(b.touch, a.touch)
        elif isinstance(a, np.ndarray):
            np.testing.assert_array_equal(b, a, err_msg=field.name)
        else:
            np.testing.assert_equal(b, a, err_msg=field.name)


def test_compiled_loop_reproduces_the_python_driver_on_a_holding_grasp(firm_setup):
    setup, state = firm_setup  # the grasp only: this test never reads the numpy reference run
    python = grasp_phases.run_grasp_phases(setup, state, step=grasp_kernel.compiled_grasp_step)
    compiled = phase_kernel.run_grasp_phases_compiled(setup, state)
    assert compiled.status == "stable" and compiled.success
    _assert_same(python, compiled)


@pytest.mark.parametrize("mass, mu, expected", [(0.2, 0.3, "penetration_limit"),
                                                (0.4, 0.0, "dropped")])
def test_compiled_loop_reproduces_failing_grasps(mass, mu, expected):
    """The paper's constants (Table 3, Table 2): the bottom finger cannot carry the weight; and a
    frictionless horizontal squeeze of the firm body: it slides out."""
    mesh = make_object("sphere", 92)
    if expected == "dropped":
        contact = ContactParams(lambda1=2.0 / 3.0, lambda2=0.88, n=1.5, e_finger=1.1424e6,
                                e_object=2.4558e6, nu_finger=0.5, nu_object=0.5)
        angles = np.radians([0.0, 120.0, 240.0])
        directions = np.stack([np.cos(angles), np.sin(angles), np.zeros(3)], axis=1)
    else:
        contact, directions = ContactParams.table3(), None
    params = msd.msd_params_from_modulus(mesh, youngs_modulus=contact.e_object, mass=mass)
    setup, state = dynamics.prepare_grasp(mesh, mu, params, contact, directions=directions)
    python = grasp_phases.run_grasp_phases(setup, state, step=grasp_kernel.compiled_grasp_step)
    compiled = phase_kernel.run_grasp_phases_compiled(setup, state)
    assert compiled.status == expected
    _assert_same(python, compiled)


def test_compiled_loop_stops_at_t_max_like_the_driver():
    mesh = make_object("sphere", 92)
    contact = ContactParams.table3()
    params = msd.msd_params_from_modulus(mesh, youngs_modulus=contact.e_object, mass=0.2)
    setup, state = dynamics.prepare_grasp(mesh, 0.3, params, contact,
                                          dynamics.GraspParams(t_max=0.03))
    python = grasp_phases.run_grasp_phases(setup, state, step=grasp_kernel.compiled_grasp_step)
    compiled = phase_kernel.run_grasp_phases_compiled(setup, state)
    assert compiled.status == "not_settled" and compiled.final_phase == "closure"
    assert compiled.n_steps == int(np.ceil(0.03 / setup.dt))
    _assert_same(python, compiled)


def test_runners_by_name():
    assert set(phase_kernel.GRASP_RUNNERS) == {"compiled", "numpy"}
    mesh = make_object("sphere", 92)
    contact = ContactParams.table3()
    params = msd.msd_params_from_modulus(mesh, youngs_modulus=contact.e_object, mass=0.2)
    setup, state = dynamics.prepare_grasp(mesh, 0.3, params, contact,
                                          dynamics.GraspParams(t_max=0.02))
    reference = grasp_phases.run_grasp_phases(setup, state)
    numpy_run = phase_kernel.GRASP_RUNNERS["numpy"](setup, state)
    np.testing.assert_array_equal(numpy_run.positions, reference.positions)
    compiled = phase_kernel.GRASP_RUNNERS["compiled"](setup, state)
    np.testing.assert_allclose(compiled.positions, reference.positions, rtol=0, atol=1e-12)


def test_compiled_loop_reports_divergence():
    mesh = make_object("sphere", 92)
    contact = ContactParams.table3()
    setup, state = dynamics.prepare_grasp(mesh, 0.3, msd.MsdParams(mass=0.2), contact,
                                          dynamics.GraspParams(dt=1e-2, max_depth=1e3))
    # a jittered shell at ~10x the RK4 limit: its mesh modes grow without bound (no stop on the
    # penetration of the flying nodes, so the state reaches inf)
    jitter = 1e-6 * np.random.default_rng(0).normal(size=state.state.shape)
    state = dataclasses.replace(state, state=state.state + jitter)
    with pytest.raises(FloatingPointError, match=r"dynamic grasp diverged at t = [0-9.e-]+ s "
                                                 r"\(dt = 0.01 s\)"), np.errstate(all="ignore"):
        phase_kernel.run_grasp_phases_compiled(setup, state)
