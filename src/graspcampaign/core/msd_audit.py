"""Energies of the MSD body, the energy audit and the step-size convergence study.

References
----------
Eq. 1-5 (§2.1-2.2); §12 (missing step-size convergence study and energy audit).
Hairer, E., Norsett, S. P. & Wanner, G. (1993), Solving Ordinary Differential Equations I,
§II.1 (classical RK4).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from graspcampaign.core.msd_body import MsdBody, MsdParams
from graspcampaign.core.msd_forces import edge_terms, msd_rhs, volume_energy
from graspcampaign.core.msd_integrate import IntegrationResult, integrate_rk4, rk4_step
from graspcampaign.core.msd_state import (
    check_state,
    positions_from_state,
    velocities_from_state,
)

__all__ = [
    "EnergyAuditResult",
    "StepConvergenceResult",
    "dissipation_power",
    "elastic_energy",
    "energy_audit",
    "gravitational_energy",
    "kinetic_energy",
    "step_convergence",
]


# ----------------------------------------------------------------------------------------------
# Energies
# ----------------------------------------------------------------------------------------------


def kinetic_energy(body: MsdBody, state) -> np.ndarray:
    """Return the kinetic energy ``1/2 m_i sum |v_i|^2`` [J] of a (6 n,) or (s, 6 n) state."""
    velocities = velocities_from_state(state)
    return 0.5 * body.node_mass * np.sum(velocities * velocities, axis=(-2, -1))


def elastic_energy(body: MsdBody, params: MsdParams, state) -> np.ndarray:
    """Return the spring energy ``1/2 k sum (|x_ij| - l0)^2`` [J] of a (6 n,) or (s, 6 n) state."""
    positions = positions_from_state(state)
    d = positions[..., body.edges[:, 0], :] - positions[..., body.edges[:, 1], :]
    stretch = np.linalg.norm(d, axis=-1) - body.rest_lengths
    return 0.5 * params.k * np.sum(stretch * stretch, axis=-1)


def gravitational_energy(body: MsdBody, params: MsdParams, state) -> np.ndarray:
    """Return ``m_i g sum z_i`` [J] (zero at z = 0) of a (6 n,) or (s, 6 n) state."""
    positions = positions_from_state(state)
    return body.node_mass * params.g * np.sum(positions[..., 2], axis=-1)


def dissipation_power(body: MsdBody, params: MsdParams, state) -> float:
    """Return the power dissipated by the nodal and edge dampers ``b sum|v|^2 + c sum l_dot^2`` [W]."""
    state = np.asarray(state, dtype=np.float64).ravel()
    _, _, stretch_rate = edge_terms(body, state)
    velocities = velocities_from_state(state)
    return float(params.b * np.sum(velocities * velocities) + params.c * np.sum(stretch_rate**2))


@dataclass(frozen=True)
class EnergyAuditResult:
    """Energy balance of an RK4 run (no contact).

    Attributes
    ----------
    times : (s,) float
        [s].
    kinetic, elastic, gravitational : (s,) float
        Energies [J]; ``elastic`` includes the volume term when ``bulk_modulus > 0``.
    mechanical : (s,) float
        Their sum [J].
    dissipated : (s,) float
        Energy removed by the dampers since t0, integrated with the same RK4 [J].
    external_work : (s,) float
        Work done by the constant external nodal forces since t0 [J].
    balance_error : (s,) float
        ``mechanical - mechanical[0] + dissipated - external_work`` [J]; zero for the exact flow.
    max_relative_error : float
        ``max |balance_error| / max(scale)`` with scale the largest of the energy magnitudes [-].
    n_increases : int
        Steps at which ``mechanical`` grew by more than round-off although no external power
        entered (only meaningful with ``f_ext = None``).
    """

    times: np.ndarray
    kinetic: np.ndarray
    elastic: np.ndarray
    gravitational: np.ndarray
    mechanical: np.ndarray
    dissipated: np.ndarray
    external_work: np.ndarray
    balance_error: np.ndarray
    max_relative_error: float
    n_increases: int


def energy_audit(
    body: MsdBody,
    params: MsdParams,
    state0,
    dt: float,
    n_steps: int,
    f_ext=None,
    record_every: int = 1,
    stepper: Callable | None = None,
) -> EnergyAuditResult:
    """Run an integrator without contact and close the energy balance step by step.

    Parameters
    ----------
    body, params
        The MSD body.
    state0 : (6 n,) float
        Initial state.
    dt : float
        Step [s].
    n_steps : int
        Number of steps.
    f_ext : (n, 3) float, optional
        Constant external nodal forces [N].
    record_every : int
        Record stride.
    stepper : callable, optional
        ``stepper(state, dt) -> (new_state, dissipated, work)``: one step of another integrator
        with the energy its dampers removed and the external work done over the step [J] (e.g.
        ``core.implicit.ImplicitIntegrator.audit_stepper(f_ext)``, which holds its own
        ``f_ext``). Default: classical RK4 with ``f_ext``.

    Returns
    -------
    result : EnergyAuditResult

    Notes
    -----
    With RK4 the dissipated energy ``D`` and the external work ``W`` are appended to the state as
    two extra ODE components (``D_dot`` = damper power, ``W_dot = f_ext . v``) and integrated by
    the same RK4, so the balance error measures only the integrator's truncation error (O(dt^4)
    globally), not a quadrature error. A ``stepper`` reports ``D`` and ``W`` as its own method
    integrates them (the implicit midpoint rule: ``dt P`` at the midpoint state). This is the
    energy audit the paper lists as missing (§12).
    """
    state0 = check_state(state0, body.n_nodes)
    n6 = 6 * body.n_nodes
    if stepper is not None and f_ext is not None:
        raise ValueError("energy_audit: give f_ext to the stepper, not to energy_audit")
    stepper = stepper or _rk4_audit_stepper(body, params, f_ext)
    run = _run_audit_stepper(stepper, state0, dt, n_steps, record_every)
    states = run.states[:, :n6]
    kinetic = kinetic_energy(body, states)
    elastic = elastic_energy(body, params, states) + volume_energy(body, params, states)
    gravitational = gravitational_energy(body, params, states)
    mechanical = kinetic + elastic + gravitational
    dissipated = run.states[:, n6]
    external_work = run.states[:, n6 + 1]
    balance = mechanical - mechanical[0] + dissipated - external_work
    scale = max(
        float(np.max(np.abs(kinetic))),
        float(np.max(np.abs(elastic))),
        float(np.max(np.abs(mechanical - mechanical[0]))),
        float(np.max(np.abs(dissipated))),
        np.finfo(float).tiny,
    )
    roundoff = 64.0 * np.finfo(float).eps * (np.abs(mechanical[:-1]) + scale)
    increases = int(np.sum(np.diff(mechanical) > roundoff))
    return EnergyAuditResult(
        times=run.times,
        kinetic=kinetic,
        elastic=elastic,
        gravitational=gravitational,
        mechanical=mechanical,
        dissipated=dissipated,
        external_work=external_work,
        balance_error=balance,
        max_relative_error=float(np.max(np.abs(balance)) / scale),
        n_increases=increases,
    )


def _rk4_audit_stepper(body: MsdBody, params: MsdParams, f_ext) -> Callable:
    """Return the RK4 audit step: the state with ``D`` and ``W`` as two extra ODE components."""
    n6 = 6 * body.n_nodes
    f_ext_arr = None if f_ext is None else np.asarray(f_ext, dtype=np.float64)

    def augmented(t, y):
        x = y[:n6]
        dx = msd_rhs(t, x, body, params, f_ext_arr)
        velocities = x.reshape(-1, 6)[:, 3:]
        work = 0.0 if f_ext_arr is None else float(np.sum(f_ext_arr * velocities))
        return np.concatenate([dx, [dissipation_power(body, params, x), work]])

    def step(state, dt):
        y = rk4_step(augmented, 0.0, np.concatenate([state, [0.0, 0.0]]), dt)
        return y[:n6], float(y[n6]), float(y[n6 + 1])

    return step


def _run_audit_stepper(stepper: Callable, state0, dt: float, n_steps: int,
                       record_every: int) -> IntegrationResult:
    """Run ``stepper`` and record ``[state, D, W]`` (accumulated) like :func:`integrate_rk4`."""
    if not dt > 0.0:
        raise ValueError(f"dt must be > 0, got {dt!r}")
    if n_steps < 0 or record_every < 1:
        raise ValueError(f"need n_steps >= 0 and record_every >= 1, got {n_steps}, {record_every}")
    recorded = list(range(0, n_steps + 1, record_every))
    if recorded[-1] != n_steps:
        recorded.append(n_steps)
    states = np.empty((len(recorded), state0.size + 2))
    states[0] = np.concatenate([state0, [0.0, 0.0]])
    state, dissipated, work = np.array(state0, dtype=np.float64), 0.0, 0.0
    slot = 1
    for step in range(1, n_steps + 1):
        state, d_inc, w_inc = stepper(state, dt)
        dissipated += d_inc
        work += w_inc
        if slot < len(recorded) and recorded[slot] == step:
            states[slot, :-2] = state
            states[slot, -2:] = (dissipated, work)
            slot += 1
    return IntegrationResult(times=dt * np.asarray(recorded, dtype=float), states=states)


# ----------------------------------------------------------------------------------------------
# Step-size convergence study
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class StepConvergenceResult:
    """Global error of a fixed-step integrator (RK4 by default) against a tight reference.

    Attributes
    ----------
    dts : (q,) float
        Step sizes, decreasing [s].
    errors : (q,) float
        Max-norm position error at ``t_end`` against the reference [m].
    orders : (q - 1,) float
        Observed orders ``log(e_i / e_{i+1}) / log(dt_i / dt_{i+1})`` [-] (4 for RK4, 2 for the
        implicit midpoint rule).
    t_end : float
        Comparison time [s].
    reference : str
        How the reference solution was obtained.
    """

    dts: np.ndarray
    errors: np.ndarray
    orders: np.ndarray
    t_end: float
    reference: str


def step_convergence(
    body: MsdBody,
    params: MsdParams,
    state0,
    t_end: float,
    dts,
    f_ext=None,
    rtol: float = 1e-11,
    atol: float = 1e-14,
    stepper: Callable | None = None,
) -> StepConvergenceResult:
    """Measure the global error of a fixed-step integrator as the step shrinks (§12).

    Parameters
    ----------
    body, params
        The MSD body (no contact).
    state0 : (6 n,) float
        Initial state.
    t_end : float
        Comparison time [s]; every ``dt`` must divide it (checked to 1e-9 relative).
    dts : (q,) float
        Steps to test [s].
    f_ext : (n, 3) float, optional
        Constant nodal forces [N].
    rtol, atol : float
        Tolerances of the ``scipy.integrate.solve_ivp`` DOP853 reference.
    stepper : callable, optional
        ``stepper(state, dt) -> (new_state, ...)``: one step of the integrator under study, with
        the same ``f_ext`` (e.g. ``core.implicit.ImplicitIntegrator.audit_stepper(f_ext)``).
        Default: classical RK4.

    Returns
    -------
    result : StepConvergenceResult
    """
    from scipy.integrate import solve_ivp

    state0 = check_state(state0, body.n_nodes)
    dts = np.sort(np.asarray(dts, dtype=float))[::-1]

    def rhs(t, x):
        return msd_rhs(t, x, body, params, f_ext)

    reference = solve_ivp(rhs, (0.0, t_end), state0, method="DOP853", rtol=rtol, atol=atol)
    if not reference.success:
        raise RuntimeError(f"reference solve_ivp failed: {reference.message}")
    ref_positions = positions_from_state(reference.y[:, -1])
    errors = []
    for dt in dts:
        n_steps = int(round(t_end / dt))
        if abs(n_steps * dt - t_end) > 1e-9 * t_end:
            raise ValueError(f"dt = {dt} does not divide t_end = {t_end}")
        if stepper is None:
            final = integrate_rk4(rhs, 0.0, state0, t_end / n_steps, n_steps, n_steps).states[-1]
        else:
            final = state0
            for _ in range(n_steps):
                final = stepper(final, t_end / n_steps)[0]
        errors.append(float(np.max(np.abs(positions_from_state(final) - ref_positions))))
    errors = np.asarray(errors)
    orders = np.log(errors[:-1] / errors[1:]) / np.log(dts[:-1] / dts[1:])
    return StepConvergenceResult(
        dts=dts,
        errors=errors,
        orders=orders,
        t_end=float(t_end),
        reference=f"scipy.integrate.solve_ivp DOP853 rtol={rtol:g} atol={atol:g}",
    )
