"""Test 1 contact-calibration bench (paper §7): the damage-depth threshold, and the bench's public face.

The bench is split by concept; this module holds the damage-depth threshold (§7.4) and
re-exports every public name of the others, so ``from graspcampaign.core import bench`` and
``bench.X`` keep working. Hot loops are compiled in :mod:`graspcampaign.core.bench_kernels` and
:mod:`graspcampaign.core.fit_kernel` (tests hold each kernel to the numpy/scipy path it replaces).

* :mod:`~graspcampaign.core.bench_specimen`: fingertip constants, Table 4 families, drawn
  specimens, environment groups;
* :mod:`~graspcampaign.core.bench_contact`: probe motion, the contact model, cyclic softening
  (:func:`cyclic_state`);
* :mod:`~graspcampaign.core.bench_simulate`: **virtual bench** -- :func:`simulate_event` turns one
  commanded contact event (:class:`EventCommand`) and one specimen's true constants
  (:class:`SpecimenParams`) into a sampled waveform (:class:`Waveform`);
* **per-event fits** -- :mod:`~graspcampaign.core.bench_fit_normal` (:func:`fit_normal`,
  :func:`fit_shifted`, :class:`TraceSet`, the §7.5 PSO cost),
  :mod:`~graspcampaign.core.bench_fit_relaxation` (:func:`fit_relaxation`),
  :mod:`~graspcampaign.core.bench_fit_friction` (:func:`fit_sliding`, :func:`fit_oblique`),
  with the solvers of :mod:`~graspcampaign.core.bench_fit_backend`.

Units are SI (m, s, N, N/m, N s/m); ``K`` is in N mm^-n (§3.5, §7.2).

Shape letters: ``c`` cycles of one fatigue run.

References
----------
Paper §7.4 (damage depth), §7.1-7.4 and Table 4 (bench, families, constants).
Mullins, L. (1969). Softening of rubber by deformation. *Rubber Chem. Technol.* 42, 339.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from graspcampaign.core import fit_kernel  # noqa: F401  (re-exported: tests patch bench.fit_kernel)
from graspcampaign.core.bench_contact import (
    APPROACH_GAP,
    RETRACT_DWELL,
    cyclic_state,
    trapezoid_duration,
    trapezoid_move,
)
from graspcampaign.core.bench_fit_backend import (
    FIT_BACKENDS,
)
from graspcampaign.core.bench_fit_friction import (
    KINETIC_WINDOW,
    SLIP_DETECTION,
    ObliqueFitResult,
    SlidingFitResult,
    fit_oblique,
    fit_sliding,
    slip_margin,
)
from graspcampaign.core.bench_fit_normal import (
    MIN_FIT_FORCE,
    RMSE_REVIEW_THRESHOLD_PCT,
    NormalFitResult,
    ShiftedFitResult,
    TraceSet,
    fit_normal,
    fit_shifted,
    loading_window,
)
from graspcampaign.core.bench_fit_relaxation import (
    MIN_FIT_SAMPLES,
    RELAXATION_FIT_POINTS,
    RelaxationFitResult,
    fit_relaxation,
)
from graspcampaign.core.bench_simulate import (
    ANOMALY_KINDS,
    NORMAL_APPROACH_SPEED,
    PRELOAD_DWELL,
    EventCommand,
    SensorParams,
    Waveform,
    simulate_event,
)
from graspcampaign.core.bench_specimen import (
    CYCLES_TO_STABILISE,
    CYCLIC_REFERENCE_DEPTH,
    ENVIRONMENT_FRICTION,
    FAMILIES,
    FINGERTIP_MODULUS,
    FINGERTIP_POISSON,
    FINGERTIP_RADIUS,
    REFERENCE_DEPTH_MM,
    SET_EXPONENT,
    SOFTENING_EXPONENT,
    SPECIMEN_POISSON,
    STICK_SLIP_SPEED,
    FamilyParams,
    SpecimenParams,
    SpreadParams,
    draw_specimen,
    environment_friction_factors,
    specimen_effective_modulus,
    with_environment,
)

log = logging.getLogger(__name__)

__all__ = [
    # damage-depth threshold (this module)
    "DamageDepthResult",
    "damage_depth",
    "true_damage_depth",
    # re-exported: they live in graspcampaign.core.bench_specimen
    "FINGERTIP_RADIUS",
    "FINGERTIP_MODULUS",
    "FINGERTIP_POISSON",
    "SPECIMEN_POISSON",
    "FAMILIES",
    "ENVIRONMENT_FRICTION",
    "FamilyParams",
    "SpecimenParams",
    "environment_friction_factors",
    "draw_specimen",
    "with_environment",
    "SpreadParams",
    "specimen_effective_modulus",
    "CYCLES_TO_STABILISE",
    "CYCLIC_REFERENCE_DEPTH",
    "REFERENCE_DEPTH_MM",
    "SET_EXPONENT",
    "SOFTENING_EXPONENT",
    "STICK_SLIP_SPEED",
    # re-exported: they live in graspcampaign.core.bench_contact
    "trapezoid_move",
    "trapezoid_duration",
    "cyclic_state",
    "APPROACH_GAP",
    "RETRACT_DWELL",
    # re-exported: they live in graspcampaign.core.bench_simulate
    "SensorParams",
    "EventCommand",
    "Waveform",
    "simulate_event",
    "ANOMALY_KINDS",
    "NORMAL_APPROACH_SPEED",
    "PRELOAD_DWELL",
    # re-exported: they live in graspcampaign.core.bench_fit_backend
    "FIT_BACKENDS",
    # re-exported: they live in graspcampaign.core.bench_fit_normal
    "NormalFitResult",
    "ShiftedFitResult",
    "TraceSet",
    "fit_normal",
    "loading_window",
    "fit_shifted",
    "MIN_FIT_FORCE",
    "RMSE_REVIEW_THRESHOLD_PCT",
    # re-exported: they live in graspcampaign.core.bench_fit_relaxation
    "RelaxationFitResult",
    "fit_relaxation",
    "MIN_FIT_SAMPLES",
    "RELAXATION_FIT_POINTS",
    # re-exported: they live in graspcampaign.core.bench_fit_friction
    "SlidingFitResult",
    "ObliqueFitResult",
    "fit_sliding",
    "fit_oblique",
    "slip_margin",
    "KINETIC_WINDOW",
    "SLIP_DETECTION",
]


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


