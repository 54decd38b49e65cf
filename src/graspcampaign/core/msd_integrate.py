"""Classical RK4 for the MSD body and its stable step limits.

References
----------
Hairer, E., Norsett, S. P. & Wanner, G. (1993), Solving Ordinary Differential Equations I,
§II.1 (classical RK4) and §IV.2 (stability function and region of RK4).
Anderson, W. N. & Morley, T. D. (1985), "Eigenvalues of the Laplacian of a graph", Linear and
Multilinear Algebra 18:141-145 (lambda_max(L) <= max over edges of d_i + d_j).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from graspcampaign.core.msd_body import MsdBody, MsdParams
from graspcampaign.core.msd_forces import volume_gradient

__all__ = [
    "RK4_IMAGINARY_AXIS_LIMIT",
    "IntegrationResult",
    "body_step_limit",
    "integrate_rk4",
    "rk4_step",
    "stable_step_limit",
]


RK4_IMAGINARY_AXIS_LIMIT = 2.0 * np.sqrt(2.0)
"""|R(i y)| <= 1 for |y| <= 2 sqrt(2) (Hairer et al. 1993, §IV.2): undamped oscillators."""


# ----------------------------------------------------------------------------------------------
# Integrator
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class IntegrationResult:
    """Fixed-step trajectory.

    Attributes
    ----------
    times : (s,) float
        Sample times [s].
    states : (s, 6 n) float
        States at those times.
    """

    times: np.ndarray
    states: np.ndarray


def rk4_step(f: Callable, t: float, state: np.ndarray, dt: float) -> np.ndarray:
    """Advance ``dX/dt = f(t, X)`` by one classical fourth-order Runge-Kutta step.

    Parameters
    ----------
    f : callable
        ``f(t, X) -> dX`` with X of any shape.
    t : float
        Current time [s].
    state : ndarray
        Current state X.
    dt : float
        Step [s].

    Returns
    -------
    new_state : ndarray
        X(t + dt) to O(dt^5) locally.

    References
    ----------
    Hairer, Norsett & Wanner (1993), §II.1, Table 1.2 (Kutta 1901).
    """
    half = 0.5 * dt
    k1 = f(t, state)
    k2 = f(t + half, state + half * k1)
    k3 = f(t + half, state + half * k2)
    k4 = f(t + dt, state + dt * k3)
    return state + (dt / 6.0) * (k1 + 2.0 * (k2 + k3) + k4)


def integrate_rk4(
    f: Callable,
    t0: float,
    state0,
    dt: float,
    n_steps: int,
    record_every: int = 1,
) -> IntegrationResult:
    """Integrate with fixed-step RK4 and record every ``record_every``-th state.

    Parameters
    ----------
    f : callable
        ``f(t, X) -> dX``.
    t0 : float
        Initial time [s].
    state0 : (d,) float
        Initial state.
    dt : float
        Step [s], > 0.
    n_steps : int
        Number of steps, >= 0.
    record_every : int
        Record stride; the final state is always recorded.

    Returns
    -------
    result : IntegrationResult
        ``times`` and ``states`` including the initial and the final state.
    """
    if not dt > 0.0:
        raise ValueError(f"dt must be > 0, got {dt!r}")
    if n_steps < 0 or record_every < 1:
        raise ValueError(f"need n_steps >= 0 and record_every >= 1, got {n_steps}, {record_every}")
    state = np.array(state0, dtype=np.float64)
    recorded = list(range(0, n_steps + 1, record_every))
    if recorded[-1] != n_steps:
        recorded.append(n_steps)
    states = np.empty((len(recorded), state.size))
    states[0] = state
    slot = 1
    for step in range(1, n_steps + 1):
        state = rk4_step(f, t0 + (step - 1) * dt, state, dt)
        if slot < len(recorded) and recorded[slot] == step:
            states[slot] = state
            slot += 1
    return IntegrationResult(times=t0 + dt * np.asarray(recorded, dtype=float), states=states)


@lru_cache(maxsize=1)
def _rk4_boundary_table() -> tuple[np.ndarray, np.ndarray]:
    """Return (angles, radii): first exit radius of the RK4 stability region along each ray.

    Angles in [pi/2, pi] (closed left half-plane, upper half; the region is symmetric). Along a
    ray ``z = rho e^{i theta}``, ``|R(z)|^2 - 1`` is a degree-8 polynomial in rho with
    coefficients ``sum_{j+k=m} cos((j-k) theta) / (j! k!)``; the exit radius is its first positive
    real root where it turns positive.
    """
    angles = np.linspace(0.5 * np.pi, np.pi, 721)
    inv_fact = 1.0 / np.array([1.0, 1.0, 2.0, 6.0, 24.0])
    j, k = np.meshgrid(np.arange(5), np.arange(5), indexing="ij")
    radii = np.empty_like(angles)
    for a, theta in enumerate(angles):  # 721 small polynomials, once per process
        terms = inv_fact[j] * inv_fact[k] * np.cos((j - k) * theta)
        coeffs = np.bincount((j + k).ravel(), weights=terms.ravel(), minlength=9)
        coeffs[0] -= 1.0  # |R|^2 - 1; rho = 0 is a root: divide it out
        poly = coeffs[1:][::-1]  # highest degree first for np.roots
        roots = np.roots(poly)
        real = np.sort(roots.real[(np.abs(roots.imag) < 1e-7) & (roots.real > 1e-9)])
        exit_radius = np.inf
        for root in real:
            if np.polyval(coeffs[::-1], root * (1.0 + 1e-6)) > 0.0:
                exit_radius = root
                break
        radii[a] = exit_radius
    return angles, radii


def stable_step_limit(
    k: float,
    node_mass: float,
    max_degree: int,
    c: float = 0.0,
    b: float = 0.0,
    k_extra: float = 0.0,
    c_extra: float = 0.0,
) -> float:
    """Return the largest RK4 step that keeps every linearised mode of the shell stable.

    Parameters
    ----------
    k : float
        Edge stiffness [N/m].
    node_mass : float
        Mass per node [kg].
    max_degree : int
        Largest node degree of the edge graph.
    c, b : float
        Edge damper and absolute nodal damper [N*s/m].
    k_extra, c_extra : float
        Extra per-node stiffness / damping (floor penalty, contact) [N/m], [N*s/m].

    Returns
    -------
    dt_max : float
        Step limit [s]. Undamped: ``2 sqrt(2) / w_max`` (RK4 on the imaginary axis).

    Notes
    -----
    Linearised at rest, the stiffness is ``K = sum_e k (D^T D)_e kron u_e u_e^T`` and
    ``x^T K x <= k x^T (L kron I3) x``, so ``lambda_max(K) <= k lambda_max(L) <= 2 k d_max``
    (Anderson & Morley 1985), hence ``w_max^2 <= (2 k d_max + k_extra) / m_i`` (= 4 k / m for a
    chain, d = 2). On the 356-node sphere the bound (4.2e3 rad/s) is 1.47x the true w_max.
    The edge damper has the same projectors, so the damping rates are bounded by
    ``nu_max = (b + 2 c d_max + c_extra) / m_i``. Every mode then solves
    ``s^2 + nu s + w^2 = 0`` with ``0 <= w <= w_max``, ``b/m_i <= nu <= nu_max``; the returned
    step is the minimum over a grid of such (w, nu) of the exit radius of the RK4 region along
    ``arg(s)`` divided by ``|s|`` (2 sqrt 2 on the imaginary axis, 2.785 on the real axis,
    2.6155 at its narrowest, arg s = 122.7 deg). Geometric (pre-stress) stiffness of strained
    edges is neglected: valid for small strains. Contact stiffness of Eq. 13 with n < 1 is
    unbounded as delta -> 0; the contact forces are held per step (see ``core.dynamics``).

    References
    ----------
    Hairer & Wanner (1996), Solving ODEs II, §IV.2 (stability region of RK4);
    Anderson & Morley (1985).
    """
    if node_mass <= 0.0 or k < 0.0 or max_degree < 0:
        raise ValueError("need node_mass > 0, k >= 0, max_degree >= 0")
    return _shell_step_limit(2.0 * max_degree, k, c, b, node_mass, k_extra, c_extra)


def body_step_limit(body: MsdBody, params: MsdParams, k_extra: float = 0.0, c_extra: float = 0.0) -> float:
    """Return the RK4 step limit of :func:`stable_step_limit` with the body's exact lambda_max(K).

    Parameters
    ----------
    body : MsdBody
    params : MsdParams
    k_extra, c_extra : float
        Extra per-node stiffness / damping (floor penalty, contact) [N/m], [N*s/m].

    Returns
    -------
    dt_max : float
        Step limit [s] of the linearisation at rest; uses ``body.unit_stiffness_max`` (sparse
        eigensolver) instead of the ``2 d_max`` bound, which is 2.2x loose on the 356-node sphere.
        With ``bulk_modulus > 0`` the eigenvalue of the rank-one volume stiffness is added to
        ``k_extra`` (a bound: ``lambda_max(A + B) <= lambda_max(A) + lambda_max(B)``).
    """
    if params.bulk_modulus > 0.0 and body.faces is not None:
        # Rank-one volume stiffness (K_b / V0) g g^T: its eigenvalue is (K_b / V0) |dV/dx|^2.
        grads, _ = volume_gradient(body, body.rest_positions)
        k_extra = k_extra + params.bulk_modulus / body.rest_volume * float(np.sum(grads * grads))
    return _shell_step_limit(
        body.unit_stiffness_max, params.k, params.c, params.b, body.node_mass, k_extra, c_extra
    )


def _shell_step_limit(
    kappa: float, k: float, c: float, b: float, m: float, k_extra: float, c_extra: float
) -> float:
    """Return the RK4 step limit of modes bounded by ``lambda_max(K) <= k kappa`` (Notes of
    :func:`stable_step_limit`): ``w_max^2 = (k kappa + k_extra) / m``, damping rates in
    ``[b / m, (b + c kappa + c_extra) / m]``."""
    return _rk4_step_limit(np.sqrt((k * kappa + k_extra) / m), b / m, (b + c * kappa + c_extra) / m)


def _rk4_step_limit(w_max: float, nu_lo: float, nu_hi: float) -> float:
    """Return min over modes s^2 + nu s + w^2 = 0 (w <= w_max, nu in [nu_lo, nu_hi]) of h*(s)."""
    if w_max == 0.0 and nu_hi == 0.0:
        return float("inf")
    if nu_hi == 0.0:
        return float(RK4_IMAGINARY_AXIS_LIMIT / w_max)
    angles, exit_radius = _rk4_boundary_table()
    w = np.linspace(0.0, w_max, 257)[:, None]
    nu = np.linspace(nu_lo, nu_hi, 65)[None, :]
    disc = (nu / 2.0) ** 2 - w**2
    sq = np.sqrt(np.abs(disc))
    # Fastest root: complex pair -nu/2 +- i sq, or the real root -nu/2 - sq.
    re = np.where(disc < 0.0, -nu / 2.0, -nu / 2.0 - sq)
    im = np.where(disc < 0.0, sq, 0.0)
    modulus = np.hypot(re, im)
    angle = np.arctan2(im, re)
    valid = modulus > 0.0
    radius = np.interp(angle[valid], angles, exit_radius)
    # Guard against interpolation between table nodes with the neighbouring minimum.
    step = angles[1] - angles[0]
    radius = np.minimum(radius, np.interp(angle[valid] + step, angles, exit_radius))
    radius = np.minimum(radius, np.interp(angle[valid] - step, angles, exit_radius))
    return float(np.min(radius / modulus[valid]))
