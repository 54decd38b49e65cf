"""Test 1 virtual bench: probe motion profile, the probe-specimen contact model and cyclic softening.

The contact force is Eq. 13 with a toe region, quasi-linear viscoelastic relaxation and
adhesion; its hot loops are compiled in :mod:`graspcampaign.core.bench_kernels` (tests hold
each kernel to the numpy path here). Units are SI; the power term of Eq. 13 takes the
indentation in millimetres (§3.5, §7.2).

References
----------
Paper Eq. 13 (normal law), Eq. 14 (K from the effective modulus), §7.1-7.4.
Fung, Y. C. (1981). *Biomechanics*, ch. 7 -- quasi-linear viscoelasticity (QLV).
Mullins, L. (1969). Softening of rubber by deformation. *Rubber Chem. Technol.* 42, 339.
"""

from __future__ import annotations

import math

import numpy as np

from graspcampaign.core import bench_kernels
from graspcampaign.core.bench_specimen import (
    CYCLES_TO_STABILISE,
    CYCLIC_REFERENCE_DEPTH,
    FINGERTIP_RADIUS,
    SET_EXPONENT,
    SOFTENING_EXPONENT,
    SpecimenParams,
)
from graspcampaign.core.contact import normal_force

__all__ = [
    "APPROACH_GAP",
    "RETRACT_DWELL",
    "axis_motion",
    "contact_force",
    "curvature_scale",
    "cyclic_state",
    "inverse_toe_depth",
    "qlv_force",
    "trapezoid_duration",
    "trapezoid_move",
]


# --------------------------------------------------------------------------- motion


def _trapezoid_timing(d: float, v_max: float, a_max: float) -> tuple[float, float, float]:
    """Peak speed, ramp time and duration of a trapezoidal move of length ``d > 0``
    (triangular when ``d a_max < v_max^2``) [m/s, s, s]."""
    if d * a_max >= v_max**2:
        v, ta = v_max, v_max / a_max
        return v, ta, 2 * ta + (d - v_max**2 / a_max) / v_max
    v = math.sqrt(a_max * d)
    ta = v / a_max
    return v, ta, 2 * ta


def trapezoid_duration(distance: float, v_max: float, a_max: float) -> float:
    """Duration T [s] of :func:`trapezoid_move` over signed ``distance`` [m] (0 for no travel),
    without evaluating the motion."""
    d = abs(distance)
    return 0.0 if d == 0.0 else _trapezoid_timing(d, v_max, a_max)[2]


def trapezoid_move(times: np.ndarray, distance: float, v_max: float, a_max: float
                   ) -> tuple[np.ndarray, np.ndarray, float]:
    """Evaluate a finite-acceleration trapezoidal move (triangular when too short).

    Parameters
    ----------
    times : (s,) float
        Times since the start of the move [s]; values outside ``[0, T]`` clamp.
    distance : float
        Signed travel [m].
    v_max, a_max : float
        Speed and acceleration limits [m/s, m/s^2] (§7.1: <= 50 mm/s, 300 mm/s^2).

    Returns
    -------
    positions : (s,) float
        Travel since the start [m].
    velocities : (s,) float
        Signed speed [m/s].
    duration : float
        Move duration T [s].
    """
    d = abs(distance)
    sign = 1.0 if distance >= 0 else -1.0
    if d == 0.0:
        z = np.zeros_like(times, dtype=float)
        return z, z.copy(), 0.0
    v, ta, duration = _trapezoid_timing(d, v_max, a_max)
    t = np.clip(times, 0.0, duration)
    pos = np.where(t < ta, 0.5 * a_max * t**2,
                   np.where(t <= duration - ta, 0.5 * a_max * ta**2 + v * (t - ta),
                            d - 0.5 * a_max * (duration - t) ** 2))
    vel = np.where(t < ta, a_max * t,
                   np.where(t <= duration - ta, v, a_max * (duration - t)))
    vel = np.where((times < 0) | (times > duration), 0.0, vel)
    return sign * pos, sign * vel, duration


def axis_motion(times: np.ndarray, start: float, moves: list[tuple[float, float, float, float]]
                ) -> tuple[np.ndarray, np.ndarray]:
    """Position and velocity of one axis driven by sequential moves (t0, target, v, a):
    :func:`trapezoid_move` after move, by the compiled
    :func:`graspcampaign.core.bench_kernels.axis_profile`."""
    return bench_kernels.axis_profile(np.ascontiguousarray(times, dtype=float), float(start),
                                      np.array(moves, dtype=float).reshape(-1, 4))


# ------------------------------------------------------------------------ contact model

APPROACH_GAP = 0.1e-3
"""Probe start height above the touched-off surface [m] (decision)."""
RETRACT_DWELL = 0.2
"""Dwell after retraction so the pull-off and zero line are recorded [s]."""


def _toe_depth(depths: np.ndarray, toe: float) -> np.ndarray:
    """Effective indentation with a compliant onset toe.

    ``delta_eff = delta - toe (1 - exp(-delta/toe))``: quadratic onset
    ``delta^2 / (2 toe)`` for ``delta << toe`` and a constant shift ``toe`` beyond it,
    i.e. the shifted law ``K (delta - delta_0)^n`` of §7.2 with ``delta_0 = toe``.
    """
    d = np.maximum(depths, 0.0)
    if toe <= 0.0:
        return d
    return d - toe * -np.expm1(-d / toe)


def qlv_force(elastic: np.ndarray, dt: float, rho: float, tau: float) -> np.ndarray:
    """Quasi-linear viscoelastic force for an elastic force history (Fung 1981).

    ``F(t) = int G(t - s) dF_e(s)`` with ``G(t) = rho + (1 - rho) exp(-t / tau)``, the
    reduced relaxation function whose step response is the §7.4 law
    ``F_0 (rho + (1 - rho) exp(-t / tau))``; exact recursion for piecewise-constant
    increments evaluated at mid-step.
    """
    inc = np.diff(elastic, prepend=0.0)
    decay = math.exp(-dt / tau)
    h = bench_kernels.first_order_filter(inc, (1.0 - rho) * math.exp(-0.5 * dt / tau), decay)
    return rho * elastic + h


def contact_force(depths: np.ndarray, rates: np.ndarray, dt: float, spec: SpecimenParams,
                  k_scale: float = 1.0, adhesion: bool = True, backend: str = "numba"
                  ) -> np.ndarray:
    """Normal force of the virtual fingertip-specimen pair for a depth history.

    Eq. 13's power term on the toe-smoothed depth passes through the QLV kernel (the slow
    dissipation that §7.2 says dominates the loop), the linear-rate term ``C delta_dot``
    is added while in contact, the ``max(0, .)`` clamp applies, and on the unloading branch
    a small adhesive neck pulls the probe until it snaps ``3 toe`` past the surface.

    ``backend="numba"`` runs :func:`graspcampaign.core.bench_kernels.press_force`, the same
    operations in one compiled pass; ``"numpy"`` (below) is the reference it is held to.
    """
    k = spec.k_n_per_mm_n * k_scale
    if backend == "numba":
        return bench_kernels.press_force(
            np.ascontiguousarray(depths, dtype=float), np.ascontiguousarray(rates, dtype=float),
            k, spec.n, spec.c, spec.toe, spec.rho,
            (1.0 - spec.rho) * math.exp(-0.5 * dt / spec.tau), math.exp(-dt / spec.tau),
            spec.adhesion if adhesion else 0.0, 3.0 * max(spec.toe, 1e-6))
    if backend != "numpy":
        raise ValueError(f"backend must be 'numba' or 'numpy', got {backend!r}")
    eff = _toe_depth(depths, spec.toe)
    elastic = normal_force(eff, np.zeros_like(eff), k, spec.n, 0.0)
    relaxed = qlv_force(elastic, dt, spec.rho, spec.tau)
    in_contact = depths > 0.0
    force = np.maximum(relaxed + np.where(in_contact, spec.c * rates, 0.0), 0.0)
    force = np.where(in_contact | (relaxed > 0), force, 0.0)
    if adhesion and spec.adhesion > 0.0 and depths.size:
        unload = int(np.argmax(depths)) + 1  # the unloading branch: after the peak
        tail = depths[unload:]
        neck = 3.0 * max(spec.toe, 1e-6)
        weight = np.where(tail >= 0.0, np.exp(-np.maximum(tail, 0.0) / neck),
                          np.clip(1.0 + tail / neck, 0.0, 1.0))
        # the neck exists only after contact was made and until it snaps once
        snapped = np.cumsum(tail <= -neck) > 0
        force[unload:] = force[unload:] - spec.adhesion * weight * ~snapped
    return force


def inverse_toe_depth(eff: np.ndarray, toe: float) -> np.ndarray:
    """Inverse of :func:`_toe_depth` by Newton iteration (monotone, converges in a few)."""
    d = eff + toe
    for _ in range(8):
        g = d - toe * -np.expm1(-d / toe) - eff
        step = d - g / (1.0 - np.exp(-d / toe))
        if np.array_equal(step, d):  # a fixed point: the remaining iterations change nothing
            break
        d = step
    return np.maximum(d, 0.0)


def curvature_scale(surface_radius: float) -> float:
    """Stiffness factor of a curved specimen: Eq. 14's sqrt(R) with R_eff = R Rs/(R + Rs)."""
    if not math.isfinite(surface_radius):
        return 1.0
    r_eff = FINGERTIP_RADIUS * surface_radius / (FINGERTIP_RADIUS + surface_radius)
    return math.sqrt(r_eff / FINGERTIP_RADIUS)


# --------------------------------------------------------------------------- cycling


def cyclic_state(spec: SpecimenParams, depths: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mullins-type softening and permanent set over a fatigue run.

    The stabilised state for the deepest indentation reached so far is
    ``s_inf = softening_ref (d / d_ref)^2`` and ``p_inf = set_ref (d / d_ref)^1.5``; each
    cycle relaxes the state towards it with an e-folding of 25 cycles (98 % after 100
    cycles, §7.4). Cycle 1 is the undamaged reference (``s = p = 0``).

    Parameters
    ----------
    spec : SpecimenParams
    depths : (c,) float
        Indentation of every cycle in order [m].

    Returns
    -------
    softening : (c,) float
        ``1 - K_c / K_1`` of every cycle.
    permanent_set : (c,) float
        Permanent set before every cycle [m].

    References
    ----------
    Mullins (1969); paper §7.4.
    """
    d_max = np.maximum.accumulate(np.asarray(depths, dtype=float))
    s_inf = spec.softening_ref * (d_max / CYCLIC_REFERENCE_DEPTH) ** SOFTENING_EXPONENT
    p_inf = spec.set_ref * (d_max / CYCLIC_REFERENCE_DEPTH) ** SET_EXPONENT
    a = math.exp(-1.0 / CYCLES_TO_STABILISE)
    s = np.zeros_like(s_inf)
    p = np.zeros_like(p_inf)
    for i in range(1, s.size):
        # the cycle before i loaded to d_max[i-1]; its damage shows from cycle i on
        s[i] = s_inf[i - 1] + (s[i - 1] - s_inf[i - 1]) * a
        p[i] = p_inf[i - 1] + (p[i - 1] - p_inf[i - 1]) * a
    return s, p
