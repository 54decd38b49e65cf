"""Test 1 contact-calibration bench: virtual waveforms and per-event fits (paper §7).

Two halves in numpy/scipy, their hot loops compiled in :mod:`graspcampaign.core.bench_kernels`
(tests hold each kernel to the numpy/scipy path it replaces):

* **Virtual bench** -- :func:`simulate_event` turns one commanded contact event
  (:class:`EventCommand`) and one specimen's true constants (:class:`SpecimenParams`)
  into a sampled waveform (:class:`Waveform`), drawing every random number from the
  ``numpy.random.Generator`` it is given.
* **Per-event fits** -- :func:`fit_normal` (Eq. 13: ``K``, ``n``, ``C``, RMSE in % of
  peak), :func:`fit_shifted` (``K (delta - delta_0)^m``), :func:`fit_relaxation`
  (``F(t) = F_0 (rho + (1 - rho) exp(-t / tau))``), :func:`fit_sliding` (``mu_s``,
  ``mu_k``, ``k_t``), :func:`fit_oblique` (peak components and measured slip),
  :func:`cyclic_state` / :func:`damage_depth` (Mullins-type softening, permanent set and
  the damage-depth threshold); :class:`TraceSet` (Eq. 13 error over many traces and parameter
  sets, the §7.5 PSO cost).

Units are SI inside this module (m, s, N, N/m, N s/m). The one exception is fixed by the
paper (§3.5, §7.2): the power term of Eq. 13 takes the indentation in millimetres and
``K`` in N mm^-n; that conversion happens only inside
:func:`graspcampaign.core.contact.normal_force`, in the analytic Jacobian of
:func:`fit_normal` and in the compiled kernels that mirror them (tests hold them together).

Shape letters: ``s`` samples of one waveform, ``c`` cycles of one fatigue run.

References
----------
Paper Eq. 13 (normal law), Eq. 14 (K from the effective modulus), Eq. 15-16 (stick-slip),
§7.1-7.4 and Table 4 (bench, families, constants).
Fung, Y. C. (1981). *Biomechanics*, ch. 7 -- quasi-linear viscoelasticity (QLV).
Mullins, L. (1969). Softening of rubber by deformation. *Rubber Chem. Technol.* 42, 339.
Baumberger, T. & Caroli, C. (2006). Solid friction from stick-slip down to pinning and
aging. *Adv. Phys.* 55, 279 -- spring-block stick-slip, symmetric force drop, aging.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import least_squares

from graspcampaign.core import bench_kernels, fit_kernel
from graspcampaign.core.contact import depth_for_force, normal_force
from graspcampaign.core.contact import effective_modulus as _psi
from graspcampaign.core.fit_kernel import MODEL_NORMAL, MODEL_RELAXATION, MODEL_SHIFTED

log = logging.getLogger(__name__)

__all__ = [
    "FINGERTIP_RADIUS",
    "FINGERTIP_MODULUS",
    "FINGERTIP_POISSON",
    "SPECIMEN_POISSON",
    "FAMILIES",
    "ENVIRONMENT_FRICTION",
    "FamilyParams",
    "SpecimenParams",
    "SensorParams",
    "EventCommand",
    "Waveform",
    "NormalFitResult",
    "ShiftedFitResult",
    "RelaxationFitResult",
    "SlidingFitResult",
    "ObliqueFitResult",
    "DamageDepthResult",
    "TraceSet",
    "environment_friction_factors",
    "draw_specimen",
    "trapezoid_move",
    "cyclic_state",
    "simulate_event",
    "fit_normal",
    "loading_window",
    "fit_shifted",
    "fit_relaxation",
    "fit_sliding",
    "fit_oblique",
    "slip_margin",
    "damage_depth",
    "true_damage_depth",
    "with_environment",
    "SpreadParams",
    "specimen_effective_modulus",
]

FINGERTIP_RADIUS = 5e-3
"""Fingertip radius R [m] (§7.1, Table 2)."""
FINGERTIP_MODULUS = 89.3e3
"""Fingertip Young's modulus E_1 [Pa] (§7.1 "about 89 kPa", Table 2: 0.0893 MPa)."""
FINGERTIP_POISSON = 0.5
"""Fingertip Poisson's ratio nu_1 (§7.1, Table 2)."""
SPECIMEN_POISSON = 0.45
"""Specimen Poisson's ratio nu_2 (Table 2, object)."""
REFERENCE_DEPTH_MM = 0.5
"""Reference indentation of f_0.5 = K (0.5 mm)^n [mm] (Table 4; K is in N mm^-n)."""


def _f05(k_n_per_mm_n: float, n: float) -> float:
    """Return Table 4's force at the reference indentation, ``K (0.5 mm)^n`` [N]."""
    return k_n_per_mm_n * REFERENCE_DEPTH_MM**n


@dataclass(frozen=True)
class FamilyParams:
    """Constants of one material family (Table 4 plus documented virtual-bench choices).

    Attributes
    ----------
    name, label : str
        Key (``"gel"``) and Table 4 label.
    modulus_mean, modulus_sd : float
        Young's modulus across the 12 specimens, mean and SD [Pa] (Table 4).
    n : float
        Contact exponent of Eq. 13 (Table 4).
    k_n_per_mm_n : float
        Contact stiffness K [N mm^-n] (Table 4).
    c : float
        Contact damping C [N s/m] (Table 4).
    mu_s, mu_k : float
        Static and kinetic friction coefficients, mean over environments (Table 4).
    k_t : float
        Tangential stick stiffness [N/m] (Table 4, 1.97-4.96 N/mm).
    rho, tau : float
        Relaxation ratio and time constant [s] (Table 4).
    softening_ref : float
        Stabilised ``1 - K/K_1`` after cycling at ``CYCLIC_REFERENCE_DEPTH`` (decision; §7.4
        says silicones "essentially unchanged", gel and foam "mild" and above 0.85).
    set_ref : float
        Stabilised permanent set at the same depth [m] (decision within §7.4's 0.08-0.36 mm).
    adhesion : float
        Tensile pull-off force at separation [N] (decision; §7.1 "small", tacky specimens).
    """

    name: str
    label: str
    modulus_mean: float
    modulus_sd: float
    n: float
    k_n_per_mm_n: float
    c: float
    mu_s: float
    mu_k: float
    k_t: float
    rho: float
    tau: float
    softening_ref: float
    set_ref: float
    adhesion: float

    @property
    def f05(self) -> float:
        """Force at the 0.5 mm reference indentation, K 0.5^n [N] (Table 4)."""
        return _f05(self.k_n_per_mm_n, self.n)


FAMILIES: dict[str, FamilyParams] = {
    f.name: f
    for f in (
        FamilyParams("gel", "Gel, soft (hydrogel)", 40.1e3, 6.2e3, 0.473, 0.346, 0.055,
                     0.772, 0.544, 1.97e3, 0.64, 7.1, 0.10, 0.36e-3, 0.015),
        FamilyParams("silicone_soft", "Silicone, soft", 74.6e3, 10.6e3, 0.462, 0.507, 0.062,
                     0.619, 0.440, 3.33e3, 0.80, 11.7, 0.02, 0.10e-3, 0.008),
        FamilyParams("bio_foam", "Bio fruit-like foam", 114.4e3, 28.1e3, 0.483, 0.582, 0.062,
                     0.684, 0.506, 4.42e3, 0.65, 8.3, 0.08, 0.25e-3, 0.006),
        FamilyParams("silicone_ref", "Silicone, reference", 145.5e3, 8.0e3, 0.432, 0.693,
                     0.060, 0.509, 0.364, 4.96e3, 0.88, 15.4, 0.01, 0.08e-3, 0.003),
    )
}
"""The four Table 4 families, keyed by short name, in Table 4 order."""

ENVIRONMENT_FRICTION = {"cool_dry": 0.59, "warm_humid": 0.70}
"""Campaign-mean mu_s in the two extreme environment groups (§7.3)."""

CYCLIC_REFERENCE_DEPTH = 2.0e-3
"""Depth at which ``softening_ref`` and ``set_ref`` are stated [m] (decision)."""
SOFTENING_EXPONENT = 2.0
"""Stabilised softening grows as (depth / reference depth)^2 (decision)."""
SET_EXPONENT = 1.5
"""Stabilised permanent set grows as (depth / reference depth)^1.5 (decision)."""
CYCLES_TO_STABILISE = 25.0
"""e-folding cycle count of Mullins-type softening: 98 % of the asymptote by cycle 100 (§7.4)."""
STICK_SLIP_SPEED = 1.0e-3
"""Speed scale of re-stick aging [m/s]: sawtooth amplitude ~ exp(-v / v_c), < 1 mN above ~5 mm/s,
so the contact slides steadily above ~3 mm/s (§7.3)."""


def specimen_effective_modulus(modulus: float) -> float:
    """Return Eq. 14's effective modulus Psi [Pa] of the bench fingertip on a specimen.

    Parameters
    ----------
    modulus : float
        Specimen Young's modulus E_2 [Pa].

    Returns
    -------
    psi : float
        Via :func:`graspcampaign.core.contact.effective_modulus` with the §7.1 fingertip.
    """
    return float(_psi(FINGERTIP_MODULUS, FINGERTIP_POISSON, modulus, SPECIMEN_POISSON))


def environment_friction_factors(families: dict[str, FamilyParams] | None = None
                                 ) -> dict[str, float]:
    """Return the multiplicative friction factor of each environment group.

    §7.3 reports the campaign mean of mu_s rising from 0.59 (cool/dry) to 0.70
    (warm/humid); Table 4 gives each family's mean over all environments. We scale every
    family's mu_s and mu_k by ``f_env = mu_env / mean_f(mu_s,f)`` for the two extremes and
    set normal-lab so that the three factors average to one, which keeps each family's
    environment mean equal to its Table 4 value.

    Returns
    -------
    factors : dict
        ``{"cool_dry": 0.913, "normal_lab": 1.003, "warm_humid": 1.084}`` for Table 4.
    """
    fams = FAMILIES if families is None else families
    mean_mu_s = float(np.mean([f.mu_s for f in fams.values()]))
    cool = ENVIRONMENT_FRICTION["cool_dry"] / mean_mu_s
    warm = ENVIRONMENT_FRICTION["warm_humid"] / mean_mu_s
    return {"cool_dry": cool, "normal_lab": 3.0 - cool - warm, "warm_humid": warm}


@dataclass(frozen=True)
class SpecimenParams:
    """True constants of one specimen in one environment group (virtual bench).

    Attributes
    ----------
    family, environment : str
    specimen : int
        Specimen number within its family, 1-12.
    modulus : float
        Drawn Young's modulus [Pa].
    k_n_per_mm_n, n, c : float
        Eq. 13 constants of the fingertip-specimen pair [N mm^-n, -, N s/m].
    mu_s, mu_k : float
        Friction coefficients in this environment.
    k_t : float
        Tangential stick stiffness [N/m].
    rho, tau : float
        QLV relaxation ratio and time constant [s].
    toe : float
        Length scale of the compliant onset toe [m].
    adhesion : float
        Pull-off force at separation [N].
    softening_ref, set_ref : float
        Stabilised ``1 - K/K_1`` and permanent set [m] at ``CYCLIC_REFERENCE_DEPTH``.
    """

    family: str
    specimen: int
    environment: str
    modulus: float
    k_n_per_mm_n: float
    n: float
    c: float
    mu_s: float
    mu_k: float
    k_t: float
    rho: float
    tau: float
    toe: float
    adhesion: float
    softening_ref: float
    set_ref: float

    @property
    def f05(self) -> float:
        """Force at 0.5 mm, K 0.5^n [N]."""
        return _f05(self.k_n_per_mm_n, self.n)


@dataclass(frozen=True)
class SpreadParams:
    """Specimen-to-specimen spread of the virtual bench (all decisions, docs/decisions.md).

    Relative spreads are lognormal sigmas; absolute ones are normal SDs.
    """

    n_sd: float = 0.03
    c_rel: float = 0.10
    mu_rel: float = 0.04
    mu_ratio_rel: float = 0.02
    k_t_rel: float = 0.10
    rho_sd: float = 0.02
    tau_rel: float = 0.08
    toe_mean: float = 5e-6
    toe_rel: float = 0.3
    cyclic_rel: float = 0.15


def draw_specimen(family: FamilyParams, specimen: int, environment: str,
                  rng: np.random.Generator, spread: SpreadParams | None = None
                  ) -> SpecimenParams:
    """Draw one specimen's true constants around its family's Table 4 values.

    The modulus is drawn from N(mean, SD) of Table 4 (truncated at 30 % of the mean); the
    force at 0.5 mm scales with the effective modulus Psi of Eq. 14 relative to the family
    mean, ``f05 = f05_family * Psi(E) / Psi(E_mean)``, and ``K = f05 / 0.5^n`` with the
    specimen's own exponent, so K keeps its n-dependent unit consistent. Friction is scaled
    by the environment factor of :func:`environment_friction_factors`.

    Parameters
    ----------
    family : FamilyParams
    specimen : int
        Specimen number (recorded only).
    environment : str
        ``"cool_dry"``, ``"normal_lab"`` or ``"warm_humid"``.
    rng : numpy.random.Generator
        Must depend on (study seed, family, specimen) only -- not on the environment -- so
        that the same physical specimen is drawn in every environment group.
    spread : SpreadParams, optional

    Returns
    -------
    SpecimenParams
    """
    sp = SpreadParams() if spread is None else spread
    factors = environment_friction_factors()
    if environment not in factors:
        raise ValueError(f"unknown environment {environment!r}; expected one of "
                         f"{sorted(factors)}")
    z = rng.standard_normal(10)
    modulus = max(family.modulus_mean + family.modulus_sd * z[0], 0.3 * family.modulus_mean)
    n = family.n + sp.n_sd * z[1]
    f05 = family.f05 * specimen_effective_modulus(modulus) / specimen_effective_modulus(
        family.modulus_mean)
    k = f05 / REFERENCE_DEPTH_MM**n
    mu_s = family.mu_s * math.exp(sp.mu_rel * z[2]) * factors[environment]
    mu_k = mu_s * (family.mu_k / family.mu_s) * math.exp(sp.mu_ratio_rel * z[3])
    cyc = math.exp(sp.cyclic_rel * z[9])
    return SpecimenParams(
        family=family.name, specimen=int(specimen), environment=environment,
        modulus=modulus, k_n_per_mm_n=k, n=n,
        c=family.c * math.exp(sp.c_rel * z[4]),
        mu_s=mu_s, mu_k=min(mu_k, 0.98 * mu_s),
        k_t=family.k_t * math.exp(sp.k_t_rel * z[5]),
        rho=float(np.clip(family.rho + sp.rho_sd * z[6], 0.05, 0.99)),
        tau=family.tau * math.exp(sp.tau_rel * z[7]),
        toe=sp.toe_mean * math.exp(sp.toe_rel * z[8]),
        adhesion=family.adhesion,
        softening_ref=family.softening_ref * cyc,
        set_ref=family.set_ref * cyc,
    )


@dataclass(frozen=True)
class SensorParams:
    """Bench sensors (§7.1, Fig. 22) and the virtual bench's noise and fault rates.

    Attributes
    ----------
    force_resolution : float
        Load-cell resolution, 1 mN (§7.1) [N].
    displacement_resolution : float
        Actuator/encoder resolution, 1 um (§7.1) [m].
    force_noise : float
        Bridge-amplifier noise SD before quantisation [N] (decision: 1.5 LSB).
    displacement_noise : float
        Encoder noise SD before quantisation [m] (decision).
    touch_off_sd : float
        Error of the surface position found at touch-off [m] (decision).
    angle_sd : float
        Tilt-stage angle error SD [rad] (decision: 0.2 deg).
    abort_rate : float
        Probability that one attempt aborts: 61 / 19,229 (§7.1).
    anomaly_rate : float
        Probability that the rig log records a minor anomaly (decision).
    """

    force_resolution: float = 1e-3
    displacement_resolution: float = 1e-6
    force_noise: float = 1.5e-3
    displacement_noise: float = 0.3e-6
    touch_off_sd: float = 2e-6
    angle_sd: float = math.radians(0.2)
    abort_rate: float = 61.0 / 19229.0
    anomaly_rate: float = 0.02


@dataclass(frozen=True)
class EventCommand:
    """One commanded bench event in SI units.

    Attributes
    ----------
    block : str
        ``"normal"``, ``"relaxation"``, ``"sliding"``, ``"oblique"`` or ``"cyclic"``.
    depth : float
        Target indentation along the surface normal [m] (NaN for sliding).
    speed : float
        Traverse speed [m/s]: approach speed, or the tangential speed for sliding.
    accel : float
        Trapezoidal-profile acceleration [m/s^2] (300 mm/s^2, §7.1).
    daq_hz : float
        Data-acquisition rate [Hz] (50-500 Hz, §7.1).
    hold : float
        Dwell at peak (normal, oblique, cyclic) or relaxation hold [s].
    normal_load : float
        Target normal force of a sliding event [N].
    stroke : float
        Tangential stroke of a sliding event [m].
    angle : float
        Press angle from the surface normal [rad] (oblique).
    surface_radius : float
        Specimen surface radius of curvature [m]; ``inf`` for flat.
    softening : float
        ``1 - K/K_1`` of this fatigue cycle (cyclic only).
    permanent_set : float
        Permanent set of this fatigue cycle [m] (cyclic only).
    """

    block: str
    depth: float = math.nan
    speed: float = 1e-3
    accel: float = 0.3
    daq_hz: float = 100.0
    hold: float = 0.2
    normal_load: float = math.nan
    stroke: float = math.nan
    angle: float = 0.0
    surface_radius: float = math.inf
    softening: float = 0.0
    permanent_set: float = 0.0


@dataclass(frozen=True)
class Waveform:
    """One recorded event, SI units; all arrays have shape (s,).

    Attributes
    ----------
    time : (s,) float
        Time from the start of the record [s].
    displacement : (s,) float
        Probe travel along its axis from the touched-off surface, positive into the
        specimen [m].
    normal_force : (s,) float
        Contact normal force, compressive positive [N].
    tangential_force : (s,) float
        Contact tangential force [N].
    tangential_displacement : (s,) float
        In-plane (X) stage travel, or measured tangential slip for oblique presses [m].
    aborted : bool
        True when the attempt was aborted (the record is truncated).
    anomaly : str
        Minor anomaly written to the rig log (``""`` when none).
    """

    time: np.ndarray
    displacement: np.ndarray
    normal_force: np.ndarray
    tangential_force: np.ndarray
    tangential_displacement: np.ndarray
    aborted: bool = False
    anomaly: str = ""


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


def _axis(times: np.ndarray, start: float, moves: list[tuple[float, float, float, float]]
          ) -> tuple[np.ndarray, np.ndarray]:
    """Position and velocity of one axis driven by sequential moves (t0, target, v, a):
    :func:`trapezoid_move` after move, by the compiled
    :func:`graspcampaign.core.bench_kernels.axis_profile`."""
    return bench_kernels.axis_profile(np.ascontiguousarray(times, dtype=float), float(start),
                                      np.array(moves, dtype=float).reshape(-1, 4))


def _move_time(distance: float, v: float, a: float) -> float:
    """Duration of a trapezoidal move [s] (:func:`trapezoid_move`'s ``duration``)."""
    return _trapezoid_timing(abs(distance), v, a)[2] if distance != 0 else 0.0


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


def _qlv(elastic: np.ndarray, dt: float, rho: float, tau: float) -> np.ndarray:
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


def _contact_force(depths: np.ndarray, rates: np.ndarray, dt: float, spec: SpecimenParams,
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
    relaxed = _qlv(elastic, dt, spec.rho, spec.tau)
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


def _untoe(eff: np.ndarray, toe: float) -> np.ndarray:
    """Inverse of :func:`_toe_depth` by Newton iteration (monotone, converges in a few)."""
    d = eff + toe
    for _ in range(8):
        g = d - toe * -np.expm1(-d / toe) - eff
        step = d - g / (1.0 - np.exp(-d / toe))
        if np.array_equal(step, d):  # a fixed point: the remaining iterations change nothing
            break
        d = step
    return np.maximum(d, 0.0)


def _curvature_scale(surface_radius: float) -> float:
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


# ------------------------------------------------------------------------ simulation


def _press(cmd: EventCommand, dt: float, depth_along_axis: float,
           hold: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Approach, press to ``depth_along_axis``, hold, retract; return t, x, v, t_unload."""
    start = -APPROACH_GAP
    t_move = _move_time(depth_along_axis - start, cmd.speed, cmd.accel)  # in and out alike
    t_unload = t_move + hold
    total = t_unload + t_move + RETRACT_DWELL
    times = np.arange(0.0, total, dt)
    x, v = _axis(times, start, [(0.0, depth_along_axis, cmd.speed, cmd.accel),
                                (t_unload, start, cmd.speed, cmd.accel)])
    return times, x, v, t_unload


def _simulate_press(cmd: EventCommand, spec: SpecimenParams, rng: np.random.Generator,
                    sensor: SensorParams) -> dict[str, np.ndarray]:
    dt = 1.0 / cmd.daq_hz
    surface = sensor.touch_off_sd * rng.standard_normal() + cmd.permanent_set
    k_scale = (1.0 - cmd.softening) * _curvature_scale(cmd.surface_radius)
    if cmd.block == "oblique":
        theta = cmd.angle + sensor.angle_sd * rng.standard_normal()
        axial = cmd.depth / math.cos(cmd.angle)
        t, x, v, _ = _press(cmd, dt, axial, cmd.hold)
        depth = x * math.cos(theta) - surface
        fn = _contact_force(depth, v * math.cos(theta), dt, spec, k_scale)
        ft = np.maximum(fn, 0.0) * math.tan(theta)
        # Coulomb test (Eq. 15-16): the applied tangential load tan(theta) f_n sticks while
        # it is within mu_s f_n; past breakaway the tangential share of the probe travel
        # becomes slip.
        if math.tan(theta) > spec.mu_s:
            contact = np.flatnonzero(fn > 0.0)
            u_b = x[contact[0]] if contact.size else np.inf
            slip = np.maximum(x - u_b, 0.0) * math.sin(theta)
            slip = np.maximum.accumulate(slip)
        else:
            slip = ft / spec.k_t
        return {"time": t, "x": x, "fn": fn, "ft": ft, "xt": slip}
    t, x, v, _ = _press(cmd, dt, cmd.depth + cmd.permanent_set, cmd.hold)
    fn = _contact_force(x - surface, v, dt, spec, k_scale)
    return {"time": t, "x": x, "fn": fn, "ft": np.zeros_like(fn), "xt": np.zeros_like(fn)}


PRELOAD_DWELL = 0.5
"""Dwell at the sliding normal load before the tangential stroke [s] (decision)."""
NORMAL_APPROACH_SPEED = 2e-3
"""Normal approach speed of sliding events [m/s] (decision)."""


def _simulate_sliding(cmd: EventCommand, spec: SpecimenParams, rng: np.random.Generator,
                      sensor: SensorParams) -> dict[str, np.ndarray]:
    dt = 1.0 / cmd.daq_hz
    surface = sensor.touch_off_sd * rng.standard_normal()
    target = cmd.normal_load
    depth0 = float(_untoe(depth_for_force(target, spec.k_n_per_mm_n, spec.n), spec.toe))
    start = -APPROACH_GAP
    t_in = _move_time(depth0 - start, NORMAL_APPROACH_SPEED, cmd.accel)  # retraction alike
    t_slide = t_in + PRELOAD_DWELL
    t_stroke = _move_time(cmd.stroke, cmd.speed, cmd.accel)
    t_out = t_slide + t_stroke + 0.2
    total = t_out + t_in + RETRACT_DWELL
    times = np.arange(0.0, total, dt)
    z, vz = _axis(times, start, [(0.0, depth0 + surface, NORMAL_APPROACH_SPEED, cmd.accel),
                                 (t_out, start, NORMAL_APPROACH_SPEED, cmd.accel)])
    fn = _contact_force(z - surface, vz, dt, spec)
    # force control at the target between the end of approach and retraction; the depth
    # creeps so that the relaxing material keeps carrying the load (first-order QLV creep)
    held = (times >= t_in) & (times < t_out)
    th = times[held] - t_in
    g = spec.rho + (1.0 - spec.rho) * np.exp(-th / spec.tau)
    z_held = _untoe(depth_for_force(target / g, spec.k_n_per_mm_n, spec.n), spec.toe) + surface
    z = z.copy()
    z[held] = z_held
    fn[held] = target
    xs, vs = _axis(times, 0.0, [(t_slide, cmd.stroke, cmd.speed, cmd.accel)])
    ft = np.zeros_like(times)
    sl = times >= t_slide
    # breakaway: elastic stick from rest up to mu_s f_n, then the spring-block sawtooth
    # symmetric about mu_k f_n (an undamped slip overshoots as far below mu_k f_n as the
    # release was above it) with an aging re-stick threshold that fades with speed
    # (Baumberger & Caroli 2006)
    f_s, f_k = spec.mu_s * target, spec.mu_k * target
    x_rel = xs[sl]
    # pre-sliding from rest follows Mindlin's partial-slip curve (Johnson 1985, §7.2):
    # initial slope k_t, full slip at x* = 1.5 f_s / k_t
    x_star = 1.5 * f_s / spec.k_t
    ft_sl = f_s * (1.0 - np.clip(1.0 - x_rel / x_star, 0.0, 1.0) ** 1.5)
    broke = np.flatnonzero(x_rel >= x_star)
    if broke.size:
        b = int(broke[0])
        speed = np.abs(vs[sl][b:])
        amp = np.maximum(2.0 * (spec.mu_s - spec.mu_k) * target
                         * np.exp(-speed / STICK_SLIP_SPEED), 1e-9)
        travel = x_rel[b:] - x_rel[b]
        rise = (2.0 * f_k - f_s) + spec.k_t * travel  # first reload after breakaway
        seg = rise.copy()
        reached = np.flatnonzero(rise >= f_k + 0.5 * amp)
        if reached.size:
            r = int(reached[0])
            # later cycles: rise at k_t from f_k - amp/2 to f_k + amp/2, then slip back
            dphase = spec.k_t * np.diff(travel[r:], prepend=travel[r]) / amp[r:]
            frac = np.mod(np.cumsum(dphase), 1.0)
            seg[r:] = f_k + amp[r:] * (frac - 0.5)
        ft_sl[b:] = seg
    ft[sl] = ft_sl
    ft[times >= t_out] = 0.0
    return {"time": times, "x": z, "fn": fn, "ft": ft, "xt": xs}


def _inject_anomaly(kind: str, out: dict[str, np.ndarray], rng: np.random.Generator) -> None:
    fn = out["fn"]
    if kind == "force_spike":
        i = int(rng.integers(fn.size))
        fn[i:i + 3] += rng.uniform(0.02, 0.08)
    elif kind == "baseline_drift":
        fn += rng.uniform(0.005, 0.02) * np.linspace(0.0, 1.0, fn.size)


ANOMALY_KINDS = ("force_spike", "baseline_drift", "environment_excursion")
"""Minor anomalies the virtual rig log records; the last one leaves the trace unchanged."""


def simulate_event(cmd: EventCommand, spec: SpecimenParams, rng: np.random.Generator,
                   sensor: SensorParams | None = None) -> Waveform:
    """Synthesise the recorded waveform of one commanded bench event.

    Parameters
    ----------
    cmd : EventCommand
        The commanded event (SI units).
    spec : SpecimenParams
        True constants of the specimen in the event's environment.
    rng : numpy.random.Generator
        Derived from (study seed, event id, attempt) by the caller, so the waveform does
        not depend on execution order.
    sensor : SensorParams, optional

    Returns
    -------
    Waveform
        Quantised, noisy channels; truncated and flagged when the attempt aborts.

    Notes
    -----
    The model is documented block by block in ``docs/decisions.md`` (Test 1 bench
    protocol): Eq. 13 with a compliant onset toe and QLV relaxation for every press, a
    force-controlled preload and a spring-block stick-slip for sliding, a Coulomb
    friction-cone press for oblique contact, and Mullins-type state for cycling.
    """
    sensor = SensorParams() if sensor is None else sensor
    u_abort, u_anom = rng.random(2)
    if cmd.block == "sliding":
        out = _simulate_sliding(cmd, spec, rng, sensor)
    elif cmd.block in ("normal", "relaxation", "oblique", "cyclic"):
        out = _simulate_press(cmd, spec, rng, sensor)
    else:
        raise ValueError(f"unknown block {cmd.block!r}")
    anomaly = ""
    if u_anom < sensor.anomaly_rate:
        anomaly = ANOMALY_KINDS[int(rng.integers(len(ANOMALY_KINDS)))]
        _inject_anomaly(anomaly, out, rng)
    s = out["time"].size
    fn, ft, x, xt = (
        bench_kernels.noisy_quantised(np.ascontiguousarray(out[key], dtype=float),
                                      rng.standard_normal(s), sd, step)
        for key, sd, step in (("fn", sensor.force_noise, sensor.force_resolution),
                              ("ft", sensor.force_noise, sensor.force_resolution),
                              ("x", sensor.displacement_noise, sensor.displacement_resolution),
                              ("xt", sensor.displacement_noise,
                               sensor.displacement_resolution)))
    aborted = bool(u_abort < sensor.abort_rate)
    if aborted:
        keep = max(2, int(rng.uniform(0.1, 0.9) * s))
        return Waveform(out["time"][:keep], x[:keep], fn[:keep], ft[:keep], xt[:keep],
                        aborted=True, anomaly="interlock_abort")
    return Waveform(out["time"], x, fn, ft, xt, aborted=False, anomaly=anomaly)


# ------------------------------------------------------------------------------ fits

RMSE_REVIEW_THRESHOLD_PCT = 5.0
"""Normal-fit RMSE (% of peak) above which a fit is flagged for review (§7.2; decision)."""
MIN_FIT_FORCE = 2e-3
"""Smallest force entering the normal fit window [N] (two load-cell LSBs)."""


@dataclass(frozen=True)
class NormalFitResult:
    """Eq. 13 fit of one loading branch.

    Attributes
    ----------
    k_n_per_mm_n, n, c : float
        Fitted K [N mm^-n], exponent, damping C [N s/m].
    c_se : float
        Asymptotic standard error of C [N s/m]: at bench speeds ``|C delta_dot|`` is below
        the 1 mN resolution and C is rarely identified within one event (see Notes of
        :func:`fit_normal`).
    f05 : float
        K 0.5^n [N].
    rmse_pct : float
        Force RMSE over the fit window in % of the event's peak force.
    peak_force : float
        Peak measured normal force [N].
    max_depth : float
        Peak indentation [m].
    loading_work, unloading_work : float
        Work on the loading and unloading branches, compressive part [J].
    n_points : int
        Samples in the fit window.
    success : bool
        False when the window was too short or the solver failed (fields are NaN).
    """

    k_n_per_mm_n: float
    n: float
    c: float
    c_se: float
    f05: float
    rmse_pct: float
    peak_force: float
    max_depth: float
    loading_work: float
    unloading_work: float
    n_points: int
    success: bool


def _nan_normal(peak: float = math.nan, npts: int = 0) -> NormalFitResult:
    nan = math.nan
    return NormalFitResult(nan, nan, nan, nan, nan, nan, peak, nan, nan, nan, npts, False)


def loading_window(displacement: np.ndarray, normal_force_: np.ndarray, onset: float = 0.0
                   ) -> np.ndarray:
    """Return the mask of the samples Eq. 13 is fitted to (and judged on).

    Parameters
    ----------
    displacement, normal_force_ : (s,) float
        Probe travel [m] and measured normal force [N].
    onset : float, optional
        Displacement of the contact surface [m]; ``delta = displacement - onset``.

    Returns
    -------
    window : (s,) bool
        Loading branch (up to the first sample of peak travel) with ``delta > 0`` and
        ``f > MIN_FIT_FORCE`` (see :func:`fit_normal`).
    """
    x = np.asarray(displacement, dtype=float)
    window = np.zeros(x.size, dtype=bool)
    window[: int(np.argmax(x)) + 1] = True
    return window & (x - onset > 0.0) & (np.asarray(normal_force_, dtype=float) > MIN_FIT_FORCE)


@dataclass(frozen=True)
class TraceSet:
    """Points of several normal-indentation traces, concatenated, checked once (§7.5).

    Attributes
    ----------
    depths, rates, forces : (m,) float
        Penetration [m], penetration rate [m/s] and measured force [N] of every point, trace
        after trace (e.g. each trace's :func:`loading_window`).
    offsets : (t + 1,) int
        Trace ``j`` holds points ``offsets[j]:offsets[j + 1]``; every trace is non-empty.
    peaks : (t,) float
        Peak force of each trace [N].
    """

    depths: np.ndarray
    rates: np.ndarray
    forces: np.ndarray
    offsets: np.ndarray
    peaks: np.ndarray

    def __post_init__(self) -> None:
        for name in ("depths", "rates", "forces", "peaks"):
            object.__setattr__(self, name, np.ascontiguousarray(getattr(self, name),
                                                                dtype=np.float64))
        offsets = np.ascontiguousarray(self.offsets, dtype=np.int64)
        object.__setattr__(self, "offsets", offsets)
        m = self.depths.size
        if (offsets.size != self.peaks.size + 1 or offsets[0] != 0 or offsets[-1] != m
                or np.any(np.diff(offsets) <= 0)):
            raise ValueError(f"offsets must rise strictly from 0 to {m} (one non-empty trace "
                             f"per peak), got {offsets.tolist()!r}")
        if self.rates.size != m or self.forces.size != m:
            raise ValueError(f"depths, rates and forces must have one value per point, got "
                             f"{m}, {self.rates.size} and {self.forces.size}")

    @classmethod
    def from_traces(cls, traces: list[tuple[np.ndarray, np.ndarray, np.ndarray, float]]
                    ) -> TraceSet:
        """Concatenate ``(depths, rates, forces, peak)`` tuples, one per trace."""
        return cls(np.concatenate([t[0] for t in traces]),
                   np.concatenate([t[1] for t in traces]),
                   np.concatenate([t[2] for t in traces]),
                   np.concatenate([[0], np.cumsum([t[0].size for t in traces])]),
                   np.array([t[3] for t in traces], dtype=float))

    def rmse_pct(self, k: np.ndarray, n: np.ndarray, c: np.ndarray, backend: str = "numba"
                 ) -> np.ndarray:
        """Return the Eq. 13 force RMSE of every trace for every parameter set [% of peak].

        Parameters
        ----------
        k, n, c : (p,) float
            Stiffness K [N mm^-n], exponent n [-] and damping C [N s/m] of each set.
        backend : {"numba", "numpy"}
            ``"numba"`` (default): the fused kernel
            :func:`graspcampaign.core.bench_kernels.trace_rmse_pct`; ``"numpy"``: the
            reference, :func:`graspcampaign.core.contact.normal_force` on the ``(p, m)`` grid
            and a matrix product over trace membership. Both agree to rounding (tests).

        Returns
        -------
        rmse_pct : (p, t) float
            ``100 sqrt(mean_j (f_pred - f)^2) / peak_j``, ``f_pred`` from Eq. 13.

        References
        ----------
        Paper Eq. 13, §7.5.
        """
        k, n, c = (np.ascontiguousarray(v, dtype=np.float64).reshape(-1) for v in (k, n, c))
        if backend == "numba":
            return bench_kernels.trace_rmse_pct(k, n, c, self.depths, self.rates, self.forces,
                                                self.offsets, self.peaks)
        if backend != "numpy":
            raise ValueError(f"backend must be 'numba' or 'numpy', got {backend!r}")
        sizes = np.diff(self.offsets)
        member = np.zeros((self.depths.size, sizes.size))
        member[np.arange(self.depths.size), np.repeat(np.arange(sizes.size), sizes)] = (
            1.0 / np.repeat(sizes, sizes))
        pred = normal_force(self.depths[None, :], self.rates[None, :], k[:, None], n[:, None],
                            c[:, None])
        return np.sqrt(((pred - self.forces[None, :]) ** 2) @ member) / self.peaks * 100.0

    def mean_rmse_pct(self, k: np.ndarray, n: np.ndarray, c: np.ndarray,
                      backend: str = "numba") -> np.ndarray:
        """Return :meth:`rmse_pct` averaged over the traces, shape (p,) [% of peak].

        The numba path averages inside the kernel
        (:func:`graspcampaign.core.bench_kernels.trace_rmse_mean_pct`): this is the §7.5 PSO
        cost, called ~10^5 times per material, where numpy's per-call overhead would cost as
        much as the kernel.
        """
        if backend == "numba":
            k, n, c = (np.ascontiguousarray(v, dtype=np.float64).reshape(-1)
                       for v in (k, n, c))
            return bench_kernels.trace_rmse_mean_pct(k, n, c, self.depths, self.rates,
                                                     self.forces, self.offsets, self.peaks)
        return self.rmse_pct(k, n, c, backend=backend).mean(axis=1)


def _branch_work(x: np.ndarray, f: np.ndarray) -> float:
    fc = np.maximum(f, 0.0)
    return float(abs(np.sum(0.5 * (fc[1:] + fc[:-1]) * np.diff(x))))


FIT_BACKENDS = ("numba", "scipy")
"""Solvers of the per-event fits: the compiled Levenberg-Marquardt run to a stationary point
(:func:`graspcampaign.core.fit_kernel.lm_fit`, default) or ``scipy.optimize.least_squares``
with its default tolerances (the reference, and the fallback of the compiled path)."""


_FREE = np.full(3, -np.inf), np.full(3, np.inf)
# typical magnitudes of the parameters (the absolute part of the compiled solver's step test):
# (K [N mm^-n], n, C [N s/m]) as the reference's x_scale; (K, m, x0 [mm]); (A [N], B [N], tau [s])
_TYPICAL_NORMAL = np.array([0.1, 0.1, 0.05])
_TYPICAL_SHIFTED = np.array([0.1, 0.1, 0.01])
_TYPICAL_RELAXATION = np.array([1e-3, 1e-3, 1e-2])


def _least_squares(resid, jac, x0: np.ndarray, model: int, data: tuple[np.ndarray, ...],
                   bounds: tuple[np.ndarray, np.ndarray], typical: np.ndarray, backend: str,
                   check=None, **scipy_options) -> tuple[np.ndarray, np.ndarray, bool]:
    """Minimise ``|resid(p)|^2`` from ``x0``; return the solution, its residuals, success.

    ``backend="numba"`` runs :func:`graspcampaign.core.fit_kernel.lm_fit` on the model
    ``model`` with ``data = (a, b, y)`` (contiguous float arrays); when it does not reach a
    stationary point strictly inside ``bounds`` ((3,) float arrays, +-inf where free), or
    ``check(p)`` is False (a condition under which the compiled model is not the reference
    residual), the fit falls back to ``backend="scipy"``:
    ``scipy.optimize.least_squares(resid, x0, jac=jac, bounds=bounds, **scipy_options)``.
    """
    if backend == "numba":
        p, _, status, _ = fit_kernel.lm_fit(model, x0, *data, *bounds, typical)
        if (status == fit_kernel.LM_CONVERGED and np.all(np.isfinite(p))
                and (check is None or check(p))):
            return p, resid(p), True
        log.debug("compiled fit (model %d) ended with status %d; using scipy", model, status)
    if bounds is _FREE:
        sol = least_squares(resid, x0, jac=jac, **scipy_options)
    else:
        sol = least_squares(resid, x0, jac=jac, bounds=bounds, **scipy_options)
    return sol.x, sol.fun, bool(sol.success)


def _check_backend(backend: str) -> None:
    if backend not in FIT_BACKENDS:
        raise ValueError(f"backend must be 'numba' or 'scipy', got {backend!r}")


def fit_normal(time: np.ndarray, displacement: np.ndarray, normal_force_: np.ndarray,
               onset: float = 0.0, backend: str = "numba") -> NormalFitResult:
    """Fit Eq. 13, ``f = K delta_mm^n + C delta_dot``, to the compressive loading branch.

    The window runs from contact to the peak indentation and keeps samples with
    ``delta > 0`` and ``f > 2 mN``: the tensile pull-off at separation lies outside the
    ``max(0, .)`` law (§7.2 (ii)) and the unloading branch carries the slow viscoelastic
    loop, which §7.2 attributes to relaxation rather than to ``C``. The start comes from a
    log-log regression; Levenberg-Marquardt with the analytic Jacobian refines ``(K, n, C)``.

    Parameters
    ----------
    time : (s,) float
        Sample times [s].
    displacement : (s,) float
        Probe travel from the touched-off surface [m].
    normal_force_ : (s,) float
        Measured normal force [N].
    onset : float, optional
        Displacement of the contact surface [m]; ``delta = displacement - onset``.
    backend : {"numba", "scipy"}, optional
        Solver (:data:`FIT_BACKENDS`): the compiled Levenberg-Marquardt run to a stationary
        point (default), or the reference ``scipy.optimize.least_squares`` (MINPACK's
        Levenberg-Marquardt), which is also the fallback when the compiled path does not
        converge or Eq. 13's ``max(0, .)`` clamp is active at its solution.

    Returns
    -------
    NormalFitResult

    Notes
    -----
    At constant approach speed ``C delta_dot`` is a constant offset, so within one event C is
    told apart from ``K delta^n`` only by the acceleration ramps; with ``|C delta_dot| <=
    0.6 mN`` at 10 mm/s against a 1 mN load cell, per-event C mostly absorbs offset-like model
    error (onset toe, touch-off) and is reported with its standard error ``c_se``.

    References
    ----------
    Paper Eq. 13, §7.2; More (1978) Levenberg-Marquardt, via scipy.optimize.least_squares.
    """
    _check_backend(backend)
    x = np.asarray(displacement, dtype=float)
    f = np.asarray(normal_force_, dtype=float)
    t = np.asarray(time, dtype=float)
    if x.size < 8:
        return _nan_normal(float(np.max(f)) if f.size else math.nan, 0)
    ipk = int(np.argmax(x))
    peak = float(np.max(f))
    depth = x - onset
    rate = bench_kernels.gradient(x, t)  # numpy.gradient, bit for bit
    win = loading_window(x, f, onset)
    w_load = _branch_work(x[: ipk + 1], f[: ipk + 1])
    w_unload = _branch_work(x[ipk:], f[ipk:])
    if np.count_nonzero(win) < 6 or peak <= 0.0:
        return _nan_normal(peak, int(np.count_nonzero(win)))
    d_mm = depth[win] * 1e3
    r = rate[win]
    y = f[win]
    # start: log-log regression on the upper part (away from the onset toe)
    upper = y > 0.2 * y.max()
    if np.count_nonzero(upper) < 3:
        upper = np.ones_like(y, dtype=bool)
    slope, icpt = np.polyfit(np.log(d_mm[upper]), np.log(y[upper]), 1)
    x0 = np.array([math.exp(icpt), float(np.clip(slope, 0.05, 3.0)), 0.0])
    log_d = np.log(d_mm)

    def resid(p: np.ndarray) -> np.ndarray:
        return normal_force(depth[win], r, p[0], p[1], p[2]) - y

    def jac(p: np.ndarray) -> np.ndarray:
        pw = np.exp(p[1] * log_d)
        return np.column_stack([pw, p[0] * pw * log_d, r])

    d_win = depth[win]

    def unclamped(p: np.ndarray) -> bool:  # the compiled model omits Eq. 13's max(0, .)
        return bool(np.all(p[0] * np.power(d_win * 1e3, p[1]) + p[2] * r > 0.0))

    try:
        p_fit, fun, success = _least_squares(
            resid, jac, x0, MODEL_NORMAL, (d_mm, r, y), _FREE, _TYPICAL_NORMAL, backend,
            check=unclamped, method="lm", x_scale=[0.1, 0.1, 0.05], max_nfev=200)
    except (ValueError, np.linalg.LinAlgError) as exc:  # pragma: no cover - defensive
        log.debug("normal fit failed: %s", exc)
        return _nan_normal(peak, int(d_mm.size))
    k, n, c = (float(v) for v in p_fit)
    ok = success and k > 0 and 0 < n < 5
    rmse = float(np.sqrt(np.mean(fun**2)) / peak * 100.0)
    dof = max(d_mm.size - 3, 1)
    try:
        j = jac(p_fit)
        cov = np.linalg.inv(j.T @ j) * (float(fun @ fun) / dof)
        c_se = float(np.sqrt(max(cov[2, 2], 0.0)))
    except np.linalg.LinAlgError:
        c_se = math.inf
    return NormalFitResult(k, n, c, c_se, _f05(k, n), rmse, peak, float(depth[ipk]), w_load,
                           w_unload, int(d_mm.size), ok)


@dataclass(frozen=True)
class ShiftedFitResult:
    """Shifted-law fit ``f = K (delta_mm - delta_0,mm)^m`` (the §7.2 refinement).

    Attributes
    ----------
    k_n_per_mm_m, m : float
        Stiffness [N mm^-m] and exponent.
    delta0 : float
        Onset offset [m] (in displacement coordinates: the apparent contact surface).
    rmse_pct : float
        RMSE in % of peak force.
    success : bool
    """

    k_n_per_mm_m: float
    m: float
    delta0: float
    rmse_pct: float
    success: bool


def fit_shifted(time: np.ndarray, displacement: np.ndarray, normal_force_: np.ndarray,
                backend: str = "numba") -> ShiftedFitResult:
    """Fit ``K (x - x_0)^m`` to the loading branch, with the onset ``x_0`` free.

    Samples below 10 % of the peak force are left out so the onset toe does not drive the
    fit; ``x_0`` then extrapolates the contact surface of the power-law part, which is
    also how :func:`fit_normal` is given its ``onset`` for fatigue cycles.

    Parameters
    ----------
    time : (s,) float
    displacement : (s,) float
        [m].
    normal_force_ : (s,) float
        [N].
    backend : {"numba", "scipy"}, optional
        Solver (:data:`FIT_BACKENDS`): the compiled Levenberg-Marquardt run to a stationary
        point (default), or the reference ``scipy.optimize.least_squares`` (trust-region
        reflective within the bounds below), which is also the fallback when the compiled
        path meets a bound.

    Returns
    -------
    ShiftedFitResult

    References
    ----------
    Paper §7.2 ("a shifted law K(delta - delta_0)^m ... a candidate refinement").
    """
    del time
    _check_backend(backend)
    x = np.asarray(displacement, dtype=float)
    f = np.asarray(normal_force_, dtype=float)
    nan = ShiftedFitResult(math.nan, math.nan, math.nan, math.nan, False)
    if x.size < 8:
        return nan
    ipk = int(np.argmax(x))
    peak = float(np.max(f))
    xs, fs = x[: ipk + 1], f[: ipk + 1]
    win = fs > 0.1 * peak
    if np.count_nonzero(win) < 6 or peak <= 0:
        return nan
    xm, y = xs[win] * 1e3, fs[win]
    first = xm.min()
    x0 = np.array([y.max() / max(xm.max() - first + 0.05, 0.05) ** 0.5, 0.5, first - 0.05])

    def resid(p: np.ndarray) -> np.ndarray:
        d = np.maximum(xm - p[2], 1e-9)
        return p[0] * d ** p[1] - y

    def jac(p: np.ndarray) -> np.ndarray:
        d = np.maximum(xm - p[2], 1e-9)
        pw = d ** p[1]
        return np.column_stack([pw, p[0] * pw * np.log(d), -p[0] * p[1] * pw / d])

    try:
        p_fit, fun, success = _least_squares(
            resid, jac, x0, MODEL_SHIFTED, (xm, xm, y),
            (np.array([1e-6, 0.05, -1.0]), np.array([100.0, 3.0, first - 1e-6])),
            _TYPICAL_SHIFTED, backend, method="trf", max_nfev=200)
    except (ValueError, np.linalg.LinAlgError) as exc:  # pragma: no cover - defensive
        log.debug("shifted fit failed: %s", exc)
        return nan
    k, m, d0 = (float(v) for v in p_fit)
    rmse = float(np.sqrt(np.mean(fun**2)) / peak * 100.0)
    return ShiftedFitResult(k, m, d0 * 1e-3, rmse, success)


RELAXATION_FIT_POINTS = 600
"""Largest number of (block-averaged) hold samples passed to the relaxation solver."""


@dataclass(frozen=True)
class RelaxationFitResult:
    """Hold-relaxation fit ``F(t) = F_0 (rho + (1 - rho) exp(-t / tau))`` (§7.4).

    Attributes
    ----------
    f0 : float
        Force at the start of the hold [N].
    rho, tau : float
        Steady ratio and time constant [s].
    rmse_pct : float
        RMSE in % of ``f0``.
    hold : float
        Duration of the detected hold [s].
    success : bool
    """

    f0: float
    rho: float
    tau: float
    rmse_pct: float
    hold: float
    success: bool


def _plateau(x: np.ndarray, tolerance: float) -> np.ndarray:
    """Indices of the hold at peak travel: the span from the first to the last sample within
    ``tolerance`` of the plateau level (median of the samples within 5 um of the maximum, so
    one quantisation outlier neither sets the level nor splits the hold)."""
    top = x[x >= x.max() - 5e-6]
    level = float(np.median(top))
    idx = np.flatnonzero(x >= level - tolerance)
    return np.arange(idx[0], idx[-1] + 1) if idx.size else idx


def fit_relaxation(time: np.ndarray, displacement: np.ndarray, normal_force_: np.ndarray,
                   tolerance: float = 3e-6, backend: str = "numba") -> RelaxationFitResult:
    """Fit the §7.4 relaxation law to the hold at peak indentation.

    The hold is the span of samples whose displacement lies within ``tolerance`` of the
    peak plateau. ``F = A + B exp(-(t - t_0)/tau)`` is fitted by least squares within
    ``A, B >= 0``, ``0.01 s <= tau <= 10 x hold`` from a start read off the trace;
    ``F_0 = A + B`` and ``rho = A / F_0``.

    Parameters
    ----------
    time, displacement, normal_force_ : (s,) float
        [s], [m], [N].
    tolerance : float, optional
        Hold detection band [m].
    backend : {"numba", "scipy"}, optional
        Solver (:data:`FIT_BACKENDS`): the compiled Levenberg-Marquardt run to a stationary
        point strictly inside the bounds (default), or the reference
        ``scipy.optimize.least_squares`` (trust-region reflective), which is also the
        fallback when the compiled path meets a bound.

    Returns
    -------
    RelaxationFitResult
    """
    _check_backend(backend)
    t = np.asarray(time, dtype=float)
    x = np.asarray(displacement, dtype=float)
    f = np.asarray(normal_force_, dtype=float)
    nan = RelaxationFitResult(math.nan, math.nan, math.nan, math.nan, math.nan, False)
    if x.size < 10:
        return nan
    run = _plateau(x, tolerance)
    if run.size < 10:
        return nan
    th = t[run] - t[run[0]]
    y = f[run]
    hold = float(th[-1])
    # block means of at most RELAXATION_FIT_POINTS: the law is smooth on the scale of tau
    # (>= 5 s) and averaging keeps the information while bounding the solver's cost
    m = -(-th.size // RELAXATION_FIT_POINTS)
    if m > 1:
        nb = th.size // m
        th = th[: nb * m].reshape(nb, m).mean(axis=1)
        y = y[: nb * m].reshape(nb, m).mean(axis=1)
    tail = y[-max(3, y.size // 20):].mean()
    head = y[: 3].mean()
    if head <= 0 or th.size < 5:
        return nan
    target = tail + (head - tail) / math.e
    below = np.flatnonzero(y <= target)
    tau0 = float(th[below[0]]) if below.size and th[below[0]] > 0 else hold / 4.0
    p0 = np.array([max(tail, 1e-6), max(head - tail, 1e-6),
                   float(np.clip(tau0, 2e-2, 5.0 * max(hold, 1.0)))])

    def resid(p: np.ndarray) -> np.ndarray:
        return p[0] + p[1] * np.exp(-th / p[2]) - y

    def jac(p: np.ndarray) -> np.ndarray:
        e = np.exp(-th / p[2])
        return np.column_stack([np.ones_like(th), e, p[1] * e * th / p[2] ** 2])

    try:
        # bounded: a drifting baseline must not send tau to infinity with a negative amplitude
        p_fit, fun, success = _least_squares(
            resid, jac, p0, MODEL_RELAXATION, (th, th, y),
            (np.array([0.0, 0.0, 1e-2]), np.array([np.inf, np.inf, 10.0 * max(hold, 1.0)])),
            _TYPICAL_RELAXATION, backend, method="trf", max_nfev=200)
    except (ValueError, np.linalg.LinAlgError) as exc:  # pragma: no cover - defensive
        log.debug("relaxation fit failed: %s", exc)
        return nan
    a, b, tau = (float(v) for v in p_fit)
    f0 = a + b
    ok = success and f0 > 0 and tau > 0
    rmse = float(np.sqrt(np.mean(fun**2)) / f0 * 100.0) if f0 > 0 else math.nan
    return RelaxationFitResult(f0, a / f0 if f0 > 0 else math.nan, tau, rmse, hold, ok)


@dataclass(frozen=True)
class SlidingFitResult:
    """Friction constants of one sliding event (§7.3).

    Attributes
    ----------
    mu_s : float
        Breakaway peak ``max f_t / f_n`` before the first slip.
    mu_k : float
        Mean ``f_t / f_n`` over the kinetic window (40-90 % of the stroke).
    k_t : float
        Initial tangential slope ``d f_t / d x`` at the start of the stroke: linear coefficient
        of a quadratic through the samples below half the breakaway force [N/m].
    normal_force : float
        Mean normal force over the stroke [N].
    stick_slip_amplitude : float
        SD of ``f_t / f_n`` in the kinetic window (sawtooth strength).
    success : bool
    """

    mu_s: float
    mu_k: float
    k_t: float
    normal_force: float
    stick_slip_amplitude: float
    success: bool


KINETIC_WINDOW = (0.4, 0.9)
"""Fraction of the stroke over which mu_k is averaged: after the breakaway transient and
before the deceleration (v^2 / 2a <= 0.17 mm of the 3 mm stroke at 10 mm/s)."""


def fit_sliding(time: np.ndarray, normal_force_: np.ndarray, tangential_force: np.ndarray,
                tangential_displacement: np.ndarray) -> SlidingFitResult:
    """Extract mu_s, mu_k and k_t from a tangential slide under constant normal load.

    Parameters
    ----------
    time : (s,) float
        [s].
    normal_force_, tangential_force : (s,) float
        [N].
    tangential_displacement : (s,) float
        In-plane stage travel [m].

    Returns
    -------
    SlidingFitResult

    References
    ----------
    Paper Eq. 15-16, §7.3.
    """
    del time
    fn = np.asarray(normal_force_, dtype=float)
    ft = np.asarray(tangential_force, dtype=float)
    xs = np.asarray(tangential_displacement, dtype=float)
    nan = SlidingFitResult(math.nan, math.nan, math.nan, math.nan, math.nan, False)
    stroke = xs.max() - xs.min() if xs.size else 0.0
    if xs.size < 10 or stroke <= 0:
        return nan
    start = xs.min()
    rel = xs - start
    moving = np.flatnonzero(rel > 2e-6)
    full = np.flatnonzero(rel >= stroke - 2e-6)
    if moving.size < 10 or not full.size:
        return nan
    seg = np.arange(max(int(moving[0]) - 1, 0), int(full[0]) + 1)
    fn_seg = fn[seg]
    fnm = float(np.mean(fn_seg))
    if fnm <= 0 or seg.size < 10:
        return nan
    pos = rel[seg] / stroke
    fts = ft[seg]
    # breakaway: the static peak precedes the kinetic window; later re-stick peaks stay below
    # it because the aged re-stick threshold never exceeds mu_s (Eq. 15-16)
    pre = np.flatnonzero(pos < KINETIC_WINDOW[0])
    if pre.size < 3:
        return nan
    ib = int(pre[np.argmax(fts[pre])])
    f_break = float(fts[ib])
    mu_s = f_break / float(np.mean(fn_seg[pre]))
    kin = (pos >= KINETIC_WINDOW[0]) & (pos <= KINETIC_WINDOW[1])
    ratio = fts[kin] / np.maximum(fn_seg[kin], 1e-6)
    mu_k = float(np.mean(ratio))
    amp = float(np.std(ratio))
    # initial slope: quadratic through the pre-sliding samples below half the breakaway force
    # (the curvature term absorbs the softening towards full slip)
    sel = np.arange(ib + 1)
    band = fts[sel] <= 0.5 * f_break
    if np.count_nonzero(band) >= 4:
        k_t = float(np.polyfit(rel[seg][sel][band], fts[sel][band], 2)[1])
    elif np.count_nonzero(band) >= 2:
        k_t = float(np.polyfit(rel[seg][sel][band], fts[sel][band], 1)[0])
    else:
        k_t = math.nan
    return SlidingFitResult(mu_s, mu_k, k_t, fnm, amp, bool(np.isfinite(k_t)))


SLIP_DETECTION = 0.25e-3
"""Tangential slip above which an oblique press counts as measured slip [m] (decision: about
twice the largest elastic stick deflection mu_s f_n / k_t of the oblique block, ~0.13 mm)."""


@dataclass(frozen=True)
class ObliqueFitResult:
    """Peak load components and measured state of one oblique press (§7.3).

    Attributes
    ----------
    normal_force, tangential_force : float
        Mean components over the dwell at peak [N].
    slip : float
        Largest tangential slip during the press [m].
    slipped : bool
        Measured state: ``slip > SLIP_DETECTION`` (0.25 mm).
    success : bool
    """

    normal_force: float
    tangential_force: float
    slip: float
    slipped: bool
    success: bool


def fit_oblique(time: np.ndarray, displacement: np.ndarray, normal_force_: np.ndarray,
                tangential_force: np.ndarray, tangential_displacement: np.ndarray,
                tolerance: float = 3e-6) -> ObliqueFitResult:
    """Read the peak load components and the tangential slip of an oblique press.

    Parameters
    ----------
    time, displacement, normal_force_, tangential_force, tangential_displacement : (s,) float
        [s], [m], [N], [N], [m].
    tolerance : float, optional
        Band defining the dwell at peak travel [m].

    Returns
    -------
    ObliqueFitResult
    """
    del time
    x = np.asarray(displacement, dtype=float)
    if x.size < 5:
        return ObliqueFitResult(math.nan, math.nan, math.nan, False, False)
    dwell = _plateau(x, tolerance)
    fn = float(np.mean(np.asarray(normal_force_)[dwell]))
    ft = float(np.mean(np.asarray(tangential_force)[dwell]))
    xt = np.asarray(tangential_displacement, dtype=float)
    slip = float(np.max(np.abs(xt - xt[0])))
    return ObliqueFitResult(fn, ft, slip, slip > SLIP_DETECTION, fn > 0)


def slip_margin(mu_s: float | np.ndarray, normal_force_: float | np.ndarray,
                tangential_force: float | np.ndarray) -> float | np.ndarray:
    """Return the friction-cone slip margin ``mu_s f_n - |f_t|`` [N] (§7.3, Eq. 15-16)."""
    return np.asarray(mu_s) * np.asarray(normal_force_) - np.abs(tangential_force)


@dataclass(frozen=True)
class DamageDepthResult:
    """Damage-depth threshold of one specimen (§7.4).

    Attributes
    ----------
    depth : float
        Smallest indentation at which either criterion is reached [m] (``inf`` if the
        fitted trends never reach it).
    depth_softening : float
        Indentation at which the stabilised K/K_1 falls to the stiffness target [m].
    depth_set : float
        Indentation at which the stabilised permanent set reaches the limit [m].
    criterion : str
        ``"softening"`` or ``"set"``: whichever is reached first.
    extrapolated : bool
        True when the threshold lies beyond the deepest tested level.
    """

    depth: float
    depth_softening: float
    depth_set: float
    criterion: str
    extrapolated: bool


def _power_crossing(depths: np.ndarray, values: np.ndarray, limit: float) -> float:
    ok = (values > 0) & np.isfinite(values)
    if np.count_nonzero(ok) < 2:
        return math.inf
    d, v = depths[ok], values[ok]
    if np.unique(d).size < 2:
        return math.inf
    q, a = np.polyfit(np.log(d), np.log(v), 1)
    if q <= 0:
        return math.inf
    return float(math.exp((math.log(limit) - a) / q))


def damage_depth(depths: np.ndarray, stiffness_ratios: np.ndarray, permanent_sets: np.ndarray,
                 stiffness_target: float = 0.85, set_limit: float = 0.5e-3
                 ) -> DamageDepthResult:
    """Return the indentation beyond which a specimen fails the durability criteria.

    Each tested level contributes its *stabilised* stiffness ratio ``K/K_1`` and permanent
    set; power laws ``1 - K/K_1 = a d^q`` and ``set = b d^r`` are fitted through the levels
    (log-log least squares) and solved for ``1 - K/K_1 = 1 - target`` and
    ``set = set_limit``.

    Parameters
    ----------
    depths : (l,) float
        Indentation of each tested level [m].
    stiffness_ratios : (l,) float
        Stabilised ``K/K_1`` at each level.
    permanent_sets : (l,) float
        Stabilised permanent set at each level [m].
    stiffness_target : float, optional
        Durability target of K/K_1, 0.85 (§7.4).
    set_limit : float, optional
        Permanent-set durability limit [m] (decision: 0.5 mm = 10 % of R).

    Returns
    -------
    DamageDepthResult
    """
    d = np.asarray(depths, dtype=float)
    soft = 1.0 - np.asarray(stiffness_ratios, dtype=float)
    sets = np.asarray(permanent_sets, dtype=float)
    ds = _power_crossing(d, soft, 1.0 - stiffness_target)
    dp = _power_crossing(d, sets, set_limit)
    depth = min(ds, dp)
    crit = "softening" if ds <= dp else "set"
    return DamageDepthResult(depth, ds, dp, crit, bool(depth > d.max()))


def true_damage_depth(spec: SpecimenParams | FamilyParams, stiffness_target: float = 0.85,
                      set_limit: float = 0.5e-3) -> DamageDepthResult:
    """Return the damage-depth threshold implied by a specimen's (or family's) cyclic constants.

    Closed form of :func:`damage_depth` for the stabilised laws of :func:`cyclic_state`:
    ``softening_ref (d/d_ref)^2 = 1 - target`` and ``set_ref (d/d_ref)^1.5 = set_limit``.
    """
    ds = (CYCLIC_REFERENCE_DEPTH * ((1.0 - stiffness_target) / spec.softening_ref)
          ** (1.0 / SOFTENING_EXPONENT)) if spec.softening_ref > 0 else math.inf
    dp = (CYCLIC_REFERENCE_DEPTH * (set_limit / spec.set_ref) ** (1.0 / SET_EXPONENT)
          if spec.set_ref > 0 else math.inf)
    depth = min(ds, dp)
    return DamageDepthResult(depth, ds, dp, "softening" if ds <= dp else "set",
                             depth > CYCLIC_REFERENCE_DEPTH)


def with_environment(spec: SpecimenParams, environment: str) -> SpecimenParams:
    """Return ``spec`` moved to another environment group (friction rescaled)."""
    f = environment_friction_factors()
    scale = f[environment] / f[spec.environment]
    return replace(spec, environment=environment, mu_s=spec.mu_s * scale,
                   mu_k=spec.mu_k * scale)
