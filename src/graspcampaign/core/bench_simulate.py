"""Test 1 virtual bench: commanded events, sensors, and :func:`simulate_event` (virtual waveforms).

:func:`simulate_event` turns one commanded contact event (:class:`EventCommand`) and one
specimen's true constants (:class:`~graspcampaign.core.bench_specimen.SpecimenParams`) into a
sampled waveform (:class:`Waveform`), drawing every random number from the
``numpy.random.Generator`` it is given. Virtual-rig data only.

Shape letters: ``s`` samples of one waveform.

References
----------
Paper Eq. 13 (normal law), Eq. 15-16 (stick-slip), §7.1-7.4 (bench).
Baumberger, T. & Caroli, C. (2006). Solid friction from stick-slip down to pinning and
aging. *Adv. Phys.* 55, 279 -- spring-block stick-slip, symmetric force drop, aging.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from graspcampaign.core import bench_kernels
from graspcampaign.core.bench_contact import (
    APPROACH_GAP,
    RETRACT_DWELL,
    axis_motion,
    contact_force,
    curvature_scale,
    inverse_toe_depth,
    trapezoid_duration,
)
from graspcampaign.core.bench_specimen import STICK_SLIP_SPEED, SpecimenParams
from graspcampaign.core.contact import depth_for_force

__all__ = [
    "ANOMALY_KINDS",
    "NORMAL_APPROACH_SPEED",
    "PRELOAD_DWELL",
    "EventCommand",
    "SensorParams",
    "Waveform",
    "press_profile",
    "simulate_event",
]


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


# ------------------------------------------------------------------------ simulation


def press_profile(cmd: EventCommand, dt: float, depth_along_axis: float,
                  hold: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Approach, press to ``depth_along_axis``, hold, retract; return t, x, v, t_unload."""
    start = -APPROACH_GAP
    t_move = trapezoid_duration(depth_along_axis - start, cmd.speed, cmd.accel)  # in and out alike
    t_unload = t_move + hold
    total = t_unload + t_move + RETRACT_DWELL
    times = np.arange(0.0, total, dt)
    x, v = axis_motion(times, start, [(0.0, depth_along_axis, cmd.speed, cmd.accel),
                                      (t_unload, start, cmd.speed, cmd.accel)])
    return times, x, v, t_unload


def _simulate_press(cmd: EventCommand, spec: SpecimenParams, rng: np.random.Generator,
                    sensor: SensorParams) -> dict[str, np.ndarray]:
    dt = 1.0 / cmd.daq_hz
    surface = sensor.touch_off_sd * rng.standard_normal() + cmd.permanent_set
    k_scale = (1.0 - cmd.softening) * curvature_scale(cmd.surface_radius)
    if cmd.block == "oblique":
        theta = cmd.angle + sensor.angle_sd * rng.standard_normal()
        axial = cmd.depth / math.cos(cmd.angle)
        t, x, v, _ = press_profile(cmd, dt, axial, cmd.hold)
        depth = x * math.cos(theta) - surface
        fn = contact_force(depth, v * math.cos(theta), dt, spec, k_scale)
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
    t, x, v, _ = press_profile(cmd, dt, cmd.depth + cmd.permanent_set, cmd.hold)
    fn = contact_force(x - surface, v, dt, spec, k_scale)
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
    depth0 = float(inverse_toe_depth(depth_for_force(target, spec.k_n_per_mm_n, spec.n), spec.toe))
    start = -APPROACH_GAP
    t_in = trapezoid_duration(depth0 - start, NORMAL_APPROACH_SPEED, cmd.accel)  # retraction alike
    t_slide = t_in + PRELOAD_DWELL
    t_stroke = trapezoid_duration(cmd.stroke, cmd.speed, cmd.accel)
    t_out = t_slide + t_stroke + 0.2
    total = t_out + t_in + RETRACT_DWELL
    times = np.arange(0.0, total, dt)
    z, vz = axis_motion(times, start, [(0.0, depth0 + surface, NORMAL_APPROACH_SPEED, cmd.accel),
                                       (t_out, start, NORMAL_APPROACH_SPEED, cmd.accel)])
    fn = contact_force(z - surface, vz, dt, spec)
    # force control at the target between the end of approach and retraction; the depth
    # creeps so that the relaxing material keeps carrying the load (first-order QLV creep)
    held = (times >= t_in) & (times < t_out)
    th = times[held] - t_in
    g = spec.rho + (1.0 - spec.rho) * np.exp(-th / spec.tau)
    z_held = inverse_toe_depth(depth_for_force(target / g, spec.k_n_per_mm_n, spec.n), spec.toe) + surface
    z = z.copy()
    z[held] = z_held
    fn[held] = target
    xs, vs = axis_motion(times, 0.0, [(t_slide, cmd.stroke, cmd.speed, cmd.accel)])
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
