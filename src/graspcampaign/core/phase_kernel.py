"""The phases of Fig. 11 driven in one compiled loop (the fast path of ``core.grasp_phases``).

:func:`core.grasp_phases.run_grasp_phases` drives any step through closure, lift-off and hold in
Python; with the compiled step its own per-step bookkeeping (reading the contacts, the phase
logic, recording, building the state objects) costs about as much as the step. A campaign that
grasps thousands of contact sets (``dynamic_check``) runs the same logic here, in one numba loop
around the kernel of :mod:`core.grasp_kernel`, and gets the same :class:`DynamicGraspResult`.

The Python driver stays the reference: tests require the same outcome, step count, phase times
and traces from both (``tests/core/test_phase_kernel.py``). Every rule of the phases (the seed
depth that ends the closure, the raised-cosine load ramp, the grip law of §3, the stops and the
settled window of Eq. 19) is the one documented in :mod:`core.grasp_phases`; a change there must
be made here too, and the equality tests say so if it is not.

Numba's cache (``cache=True``) is keyed on this file alone: it does not see a change of the
kernels the loop calls (:func:`core.grasp_kernel.step_kernel`, :mod:`core.msd_kernel`), so a
change there must come with an edit here (or a cleared ``__pycache__``), or the loop keeps the
old compiled step.

References
----------
Fig. 11 and §5.5, §3 (grip increment while equilibrium fails), §3.7 Eq. 19, §5.1 (seed).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from graspcampaign.core.contact import StickSlipState
from graspcampaign.core.dynamics import GraspForces, GraspSetup, GraspState, grasp_step
from graspcampaign.core.grasp_kernel import (
    ACTIVE,
    ANCHORS,
    DEPTHS,
    FORCES,
    GRIP,
    N_SCAL,
    N_VEC,
    NORMAL_FORCES,
    NORMALS,
    POINTS,
    REL_VEL,
    RESIDUAL,
    SLIDING,
    SLIP,
    SUPPORT,
    TANGENTIAL,
    WEIGHTS,
    packed_setup,
    step_kernel,
)
from graspcampaign.core.grasp_phases import (
    PHASES,
    STATUSES,
    DynamicGraspResult,
    PhaseTimes,
    grasp_result,
    run_grasp_phases,
)
from graspcampaign.core.hand import FingerContacts

__all__ = ["GRASP_RUNNERS", "run_grasp_phases_compiled"]

CLOSURE, LIFT, HOLD = 0, 1, 2  # indices into grasp_phases.PHASES
STABLE, NOT_SETTLED, PENETRATION_LIMIT, DROPPED, DIVERGED = 0, 1, 2, 3, 4  # STATUSES + diverged
# grasp constants vector
SEED, GRIP_SPEED, TAU_F, LIFT_TIME, SETTLE_SPEED, DROP, MAX_DEPTH, HALF_NODE_MASS = range(8)


@njit(cache=True, error_model="numpy")
def _phase_loop(x, time0, grip, slip, vec, scal, flags, hosts, sums, nodal, committed,
                committed_sliding, edges, rest_lengths, faces, constants, law, targets, approach,
                weight_z, dt, n_max, settle_steps, consts):
    """Run the phases from a prepared state; return the outcome, the traces and the last state."""
    n, n_fingers = x.shape[0], grip.shape[0]
    rows = n_max + 1
    times = np.empty(rows)
    phases = np.empty(rows, dtype=np.int8)
    loads = np.empty(rows)
    residuals = np.empty((rows, 3))
    supports = np.empty((rows, 3))
    normal_forces = np.empty((rows, n_fingers))
    tangentials = np.empty((rows, n_fingers, 3))
    slidings = np.empty((rows, n_fingers), dtype=np.bool_)
    depths = np.empty((rows, n_fingers))
    actives = np.empty((rows, n_fingers), dtype=np.bool_)
    grips = np.empty((rows, n_fingers))
    centroids = np.empty((rows, 3))
    kinetic = np.empty(rows)
    reached = np.zeros(n_fingers, dtype=np.bool_)
    touch = np.full(n_fingers, np.nan)
    since_touch = np.full(n_fingers, settle_steps)
    rate = np.zeros(n_fingers)
    marks = np.full(4, np.nan)  # lift_start, lift_end, hold_start, hold_end
    phase, status, quiet, n_steps, row = CLOSURE, NOT_SETTLED, 0, 0, 0
    t = time0
    z_lift = np.nan
    w_step = 0.0  # load fraction of the step that led to the current state
    while True:
        active, depth = flags[ACTIVE], scal[DEPTHS]
        means = np.zeros(7)  # as grasp_kernel.body_summary
        for i in range(n):
            for j in range(6):
                means[j] += x[i, j]
            for j in range(3, 6):
                means[6] += x[i, j] * x[i, j]
        for j in range(6):
            means[j] /= n
        for p in range(n_fingers):
            if active[p] and touch[p] != touch[p]:
                touch[p] = t
        if phase == CLOSURE:
            done = True
            for p in range(n_fingers):
                reached[p] = reached[p] or depth[p] >= consts[SEED]
                done = done and reached[p]
            if done:
                phase, marks[0], z_lift = LIFT, t, means[2]
        w = 0.0
        if phase != CLOSURE:
            tau = min(max((t - marks[0]) / consts[LIFT_TIME], 0.0), 1.0)
            w = 0.5 * (1.0 - math.cos(math.pi * tau))
            if phase == LIFT and t - marks[0] >= consts[LIFT_TIME]:
                phase, marks[1], w = HOLD, t, 1.0
        residual_z = sums[RESIDUAL, 2]
        times[row], phases[row], loads[row] = t, phase, w
        residuals[row], supports[row] = sums[RESIDUAL], sums[SUPPORT]
        normal_forces[row], tangentials[row] = scal[NORMAL_FORCES], vec[TANGENTIAL]
        slidings[row], depths[row], actives[row] = flags[SLIDING], depth, active
        grips[row], kinetic[row] = grip, consts[HALF_NODE_MASS] * means[6]
        centroids[row] = means[:3]
        row += 1

        deepest = depth[0]
        for p in range(1, n_fingers):
            deepest = max(deepest, depth[p])
        if deepest > consts[MAX_DEPTH]:
            status = PENETRATION_LIMIT
            break
        if phase != CLOSURE and z_lift - means[2] > consts[DROP]:
            status = DROPPED
            break
        if phase == HOLD:
            speed = math.sqrt(means[3] ** 2 + means[4] ** 2 + means[5] ** 2)
            longest_gap = 0
            for p in range(n_fingers):
                since_touch[p] = 0 if active[p] else since_touch[p] + 1
                longest_gap = max(longest_gap, since_touch[p])
            held = (abs(residual_z) < consts[TAU_F] and speed < consts[SETTLE_SPEED]
                    and longest_gap < settle_steps)
            quiet = quiet + 1 if held else 0
            if quiet == 1:
                marks[2] = t
            if quiet >= settle_steps:
                status, marks[3] = STABLE, t
                break
        if n_steps >= n_max:
            break

        squeezing = abs(w * residual_z) >= consts[TAU_F]
        for p in range(n_fingers):
            if phase == CLOSURE:
                rate[p] = 0.0 if reached[p] and active[p] else consts[GRIP_SPEED]
            else:
                rate[p] = consts[GRIP_SPEED] if (not active[p]) or squeezing else 0.0
        committed = vec[ANCHORS]
        committed_sliding = flags[SLIDING]
        finite, x, vec, scal, flags, hosts, sums, nodal = step_kernel(
            x, dt, edges, rest_lengths, faces, constants, nodal, 1.0 - w, grip, rate,
            vec[SLIP], active, vec[REL_VEL], committed, targets, approach, law, weight_z, w)
        if not finite:
            status = DIVERGED
            break
        grip = scal[GRIP]
        w_step = w
        t = t + dt
        n_steps += 1
    return (status, phase, n_steps, t, w_step, touch, marks, x, grip, rate, vec, scal, flags,
            hosts, sums, nodal, committed, committed_sliding, times[:row], phases[:row],
            loads[:row], residuals[:row], supports[:row], normal_forces[:row], tangentials[:row],
            slidings[:row], depths[:row], actives[:row], grips[:row], centroids[:row],
            kinetic[:row])


def _contact_arrays(out: GraspForces, slip_coords, grip):
    """Pack a GraspForces (e.g. the numpy evaluation of a prepared state) as the kernel's rows."""
    n_fingers = len(grip)
    hits = out.contacts
    vec = np.zeros((N_VEC, n_fingers, 3))
    for row, value in ((POINTS, hits.points), (NORMALS, hits.normals), (WEIGHTS, hits.weights),
                       (TANGENTIAL, out.tangential), (FORCES, out.forces),
                       (REL_VEL, out.relative_velocity), (ANCHORS, out.stick.anchors),
                       (SLIP, slip_coords)):
        vec[row] = value
    scal = np.zeros((N_SCAL, n_fingers))
    scal[DEPTHS], scal[NORMAL_FORCES], scal[GRIP] = hits.depths, out.normal_forces, grip
    flags = np.zeros((2, n_fingers), dtype=bool)
    flags[ACTIVE], flags[SLIDING] = hits.active, out.stick.sliding
    sums = np.stack([out.residual, out.support_force]).astype(float)
    return vec, scal, flags, np.asarray(hits.faces, dtype=np.int64), sums, \
        np.ascontiguousarray(out.nodal_forces, dtype=np.float64)


def run_grasp_phases_compiled(setup: GraspSetup, state: GraspState) -> DynamicGraspResult:
    """Drive a prepared grasp through closure, lift-off and hold in one compiled loop.

    Parameters
    ----------
    setup : GraspSetup
        Fixed model (:func:`core.dynamics.prepare_grasp`).
    state : GraspState
        Initial state: body at rest and held, fingers open (its command is not read: the phases
        set it).

    Returns
    -------
    result : DynamicGraspResult
        As ``run_grasp_phases(setup, state, step=grasp_kernel.compiled_grasp_step)``.

    Raises
    ------
    FloatingPointError
        If the state becomes non-finite (a step beyond the stability limit).
    """
    grasp, dt = setup.grasp, setup.dt
    packed = packed_setup(setup)
    n_max = int(np.ceil(grasp.t_max / dt))
    settle_steps = max(1, int(np.ceil(grasp.settle_time / dt)))
    consts = np.array([grasp.seed_depth, grasp.grip_speed, grasp.tau_f, grasp.lift_time,
                       grasp.settle_speed, grasp.drop_distance, setup.max_depth,
                       0.5 * setup.body.node_mass])
    grip = np.array(state.grip, dtype=np.float64)
    vec, scal, flags, hosts, sums, nodal = _contact_arrays(state.contact, state.slip_coords, grip)
    (status, phase, n_steps, t, w, touch, marks, x, grip, rate, vec, scal, flags, hosts, sums,
     nodal, committed, committed_sliding, *traces) = _phase_loop(
        np.ascontiguousarray(state.state.reshape(-1, 6)), float(state.time), grip,
        np.array(state.slip_coords, dtype=np.float64), vec, scal, flags, hosts, sums, nodal,
        np.array(state.stick.anchors, dtype=np.float64),
        np.array(state.stick.sliding, dtype=bool), packed.edges, packed.rest_lengths,
        packed.faces, packed.constants, packed.law, packed.targets, packed.approach,
        packed.weight_z, dt, n_max, settle_steps, consts)
    if status == DIVERGED:
        raise FloatingPointError(
            f"dynamic grasp diverged at t = {t:.4g} s (dt = {dt:.3g} s)")
    contact = GraspForces(
        contacts=FingerContacts(active=flags[ACTIVE], depths=scal[DEPTHS], faces=hosts,
                                points=vec[POINTS], normals=vec[NORMALS], weights=vec[WEIGHTS]),
        normal_forces=scal[NORMAL_FORCES], tangential=vec[TANGENTIAL], forces=vec[FORCES],
        residual=sums[RESIDUAL], support_force=sums[SUPPORT], nodal_forces=nodal,
        relative_velocity=vec[REL_VEL],
        stick=StickSlipState(anchors=vec[ANCHORS], sliding=flags[SLIDING]))
    final = GraspState(time=t, state=x.reshape(-1), grip=grip, grip_rate=rate, load_fraction=w,
                       stick=StickSlipState(anchors=committed, sliding=committed_sliding),
                       slip_coords=vec[SLIP], contact=contact)
    names = ("times", "phase", "load_fraction", "residual", "support_force", "normal_forces",
             "tangential", "sliding", "depths", "in_contact", "grip", "centroid",
             "kinetic_energy")
    arrays = dict(zip(names, traces, strict=True))
    arrays["phase"] = np.asarray(PHASES)[arrays["phase"]]
    if STATUSES[status] != "stable":
        marks[2] = np.nan
    times = PhaseTimes(closure_start=float(state.time), closure_end=float(marks[0]), touch=touch,
                       lift_start=float(marks[0]), lift_end=float(marks[1]),
                       hold_start=float(marks[2]), hold_end=float(marks[3]))
    return grasp_result(setup, final, arrays, STATUSES[status], PHASES[phase], times, int(n_steps))


def _run_numpy(setup: GraspSetup, state: GraspState) -> DynamicGraspResult:
    return run_grasp_phases(setup, state, grasp_step)


GRASP_RUNNERS = {"compiled": run_grasp_phases_compiled, "numpy": _run_numpy}
"""How a campaign runs a prepared grasp, by name: the compiled loop (default of the dynamic
studies) or the Python driver on the numpy reference step."""
