"""Test 3 disturbances on the virtual rig: one friction budget, ramps, pulses and sinusoids.

A held grasp (:func:`graspcampaign.rig.virtual.virtual_trial`) holds a static friction budget
``B_s`` and a kinetic one ``B_k``; the vertical demand on friction is the weight less the normal
forces' own support. :func:`disturb` applies the row's disturbance to that budget (§9.1): lateral
and torsion ramps are pulled until slip (detected at 2 mm, released after a latency), vertical
loads are ramped to their level, impulses and sinusoids are integrated in time by :func:`slide`
(2-D Coulomb sliding of the object relative to the hand). Readings are quantised at the sensors'
resolutions (:func:`quantise`).

References
----------
Paper §9.1-9.4; Eq. 15-16 (Coulomb stick-slip); Johnson (1985) §7.2 (Mindlin partial slip).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from graspcampaign.core import disturbance as dist
from graspcampaign.core import slip as slip_statics

if TYPE_CHECKING:  # annotations only: virtual imports this module
    from graspcampaign.rig.specimen import Specimen
    from graspcampaign.rig.virtual import RigParams

__all__ = ["SlideResult", "disturb", "empty_measures", "quantise", "ramp_to_slip", "slide"]


def num(row: dict, key: str, default: float = math.nan) -> float:
    """Return ``row[key]`` as a float, ``default`` when missing or not a number."""
    try:
        return float(row.get(key, default))
    except (TypeError, ValueError):
        return default


def empty_measures() -> dict[str, Any]:
    """Return the Test 3 measured columns of a trial that measured no threshold."""
    return {"threshold_measured_n": math.nan, "threshold_measured_nm": math.nan,
            "threshold_censored": False, "first_finger_measured": 0,
            "rotation_at_limit_deg": math.nan}


@dataclass(frozen=True)
class SlideResult:
    travel: float  # peak displacement [m]
    dropped: bool
    onset_time: float  # first time the budget was exceeded [s], nan if never


def slide(times: np.ndarray, lateral: np.ndarray, vertical: np.ndarray, budget_s: float,
           budget_k: float, mass: float, drop_travel: float, settle_demand: float) -> SlideResult:
    """Integrate 2-D Coulomb sliding of the object relative to the hand (semi-implicit Euler).

    ``lateral`` and ``vertical`` (down positive) are the demand on the friction budget [N];
    sticking while the demand lies inside ``budget_s``, sliding against ``budget_k``. After the
    last sample, a still-sliding object re-sticks if ``budget_k`` exceeds ``settle_demand``
    (stopping distance v^2 / 2a added), otherwise it is lost.
    """
    x = np.zeros(2)
    v = np.zeros(2)
    peak = 0.0
    onset = math.nan
    sliding = False
    dt = times[1] - times[0] if len(times) > 1 else 1e-3
    for i in range(len(times)):
        demand = np.array([lateral[i], vertical[i]])
        size = math.hypot(*demand)
        if not sliding:
            if size <= budget_s:
                continue
            sliding = True
            if math.isnan(onset):
                onset = float(times[i])
        speed = math.hypot(*v)
        direction = v / speed if speed > 1e-12 else demand / max(size, 1e-300)
        a = (demand - budget_k * direction) / mass
        v_new = v + a * dt
        if speed > 1e-12 and float(np.dot(v_new, v)) <= 0.0 and size <= budget_s:
            v[:] = 0.0
            sliding = False
            continue
        v = v_new
        x = x + v * dt
        peak = max(peak, math.hypot(*x))
        if x[1] > drop_travel:
            return SlideResult(peak, True, onset)
    if sliding:
        speed = math.hypot(*v)
        if budget_k <= settle_demand:
            return SlideResult(max(peak, drop_travel), True, onset)
        peak += speed * speed * mass / (2.0 * (budget_k - settle_demand))
    return SlideResult(peak, peak > drop_travel, onset)


def ramp_to_slip(rate: float, cap: float, threshold: float, budget_s: float, budget_k: float,
                  base: float, mass: float, p: RigParams) -> tuple[float, float, bool, float]:
    """Quasi-static ramp until slip, detection at 2 mm, release after the latency.

    Returns ``(measured_threshold, slip_travel, dropped, duration)``; a threshold above the cap
    returns ``(cap, 0, False, cap / rate)`` (censored by the caller).
    """
    if threshold > cap:
        return cap, 0.0, False, cap / rate
    excess = max(budget_s - budget_k, 1e-9)
    accel = excess / mass  # the demand stays at the budget while the ramp continues
    t_detect = math.sqrt(2.0 * p.detection_slip / accel)
    measured = threshold + rate * t_detect
    t_total = t_detect + p.release_latency
    speed = accel * t_total
    travel = 0.5 * accel * t_total**2
    if budget_k <= base:  # the kinetic budget cannot even carry the weight: lost after release
        return measured, max(travel, p.drop_travel), True, threshold / rate + t_total
    travel += speed * speed * mass / (2.0 * (budget_k - base))
    return measured, travel, travel > p.drop_travel, threshold / rate + t_total


def quantise(value: float, step: float, rng: np.random.Generator, steps: float,
              floor: float | None = None) -> float:
    noisy = value + steps * step * rng.standard_normal()
    if floor is not None:
        noisy = max(noisy, floor)
    return float(np.round(noisy / step) * step)



def disturb(row, predictions, spec: Specimen, p: RigParams, points, normals, forces, centroid,
             mass, budget_s, budget_k, base, rng) -> dict[str, Any]:
    """Apply the row's Test 3 disturbance to a held grasp; return measures and events."""
    block = str(row["block"])
    kind = str(row["disturbance_kind"])
    direction = num(row, "direction_deg", 0.0)
    measures = empty_measures()
    travel, dropped, threshold_ok, duration = 0.0, False, True, 0.0
    first = slip_statics.first_slip_finger(points, normals, forces, centroid, mass, spec.mu_s, kind,
                                   direction, p.kappa)
    base_pos = max(base, 0.0)
    budget_s = max(budget_s, 1e-12)  # guards the ratios below; a zero budget never holds
    lateral_limit = math.sqrt(max(budget_s**2 - base_pos**2, 0.0))
    if block == "A":
        rate, cap = num(row, "ramp_rate_n_per_s"), num(row, "ramp_cap_n", 15.0)
        measured, travel, dropped, duration = ramp_to_slip(rate, cap, lateral_limit, budget_s,
                                                            budget_k, base, mass, p)
        censored = lateral_limit > cap
        measured = quantise(measured, p.load_cell_resolution, rng, p.noise_steps, 0.0)
        measures.update(threshold_measured_n=measured, threshold_censored=censored,
                        first_finger_measured=0 if censored else first)
        threshold_ok = measured >= num(row, "proof_force_n")
    elif block == "C":
        r_eff = max(dist.effective_radius(points, centroid), 1e-6)
        rate, cap = num(row, "torque_ramp_nm_per_s"), num(row, "torque_cap_nm", 1.0)
        measured, travel, dropped, duration = ramp_to_slip(
            rate / r_eff, cap / r_eff, lateral_limit, budget_s, budget_k, base, mass, p)
        censored = lateral_limit > cap / r_eff
        torque = quantise(measured * r_eff, p.torque_resolution, rng, p.noise_steps, 0.0)
        pad = float(slip_statics.microslip(1.0, budget_s / 3.0, spec.k_t))
        rotation = math.degrees((pad + (0.0 if censored else p.detection_slip)) / r_eff)
        measures.update(threshold_measured_nm=torque, threshold_censored=censored,
                        first_finger_measured=0 if censored else first,
                        rotation_at_limit_deg=round(rotation + 0.1 * rng.standard_normal(), 2))
        threshold_ok = torque >= num(row, "proof_torque_nm")
    elif block == "B":
        load = num(row, "load_n")
        rate = num(row, "ramp_rate_n_per_s", 0.5)
        sign = 1.0 if kind == "down" else -1.0
        demand = base + sign * load
        duration = load / rate + num(row, "hold_s", 3.0)
        if abs(demand) <= budget_s:
            travel = float(slip_statics.microslip(abs(demand) / budget_s, budget_s / 3.0, spec.k_t))
            measures.update(threshold_measured_n=quantise(load, p.load_cell_resolution, rng,
                                                           p.noise_steps, 0.0),
                            threshold_censored=True, first_finger_measured=0)
        else:
            onset = budget_s - base if kind == "down" else budget_s + base
            measured, travel, dropped, _ = ramp_to_slip(rate, load, onset, budget_s, budget_k,
                                                         base, mass, p)
            measures.update(threshold_measured_n=quantise(measured, p.load_cell_resolution, rng,
                                                           p.noise_steps, 0.0),
                            threshold_censored=False, first_finger_measured=first)
    elif block in ("D", "E"):
        if block == "D":
            width = num(row, "pulse_duration_ms") * 1e-3
            duration = num(row, "duration_s", width + p.observe)
            times = np.arange(0.0, width + p.observe, p.dt)
            lateral = np.where(times <= width,
                               0.5 * num(row, "load_n") * (1.0 - np.cos(2 * np.pi * times / width)),
                               0.0)
        else:
            duration = num(row, "duration_s", 5.0)
            times = np.arange(0.0, duration, p.dt)
            lateral = num(row, "amplitude_n") * np.sin(2 * np.pi * num(row, "frequency_hz") * times)
        peak = float(np.abs(lateral).max())
        if peak <= lateral_limit:
            travel = float(slip_statics.microslip(math.hypot(peak, base_pos) / budget_s, budget_s / 3.0,
                                          spec.k_t))
        else:
            res = slide(times, lateral, np.full_like(times, base), budget_s, budget_k, mass,
                         p.drop_travel, base)
            travel, dropped = res.travel, res.dropped
            measures.update(first_finger_measured=first)
    # Threshold blocks are graded at their proof load: the slip of the threshold search beyond it
    # is a measurement, not a failure.
    graded = travel if block not in ("A", "C") or not threshold_ok else 0.0
    return {"measures": measures, "travel": travel, "graded_travel": graded, "dropped": dropped,
            "threshold_ok": threshold_ok, "duration": duration}
