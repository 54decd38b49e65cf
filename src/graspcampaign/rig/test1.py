"""Test 1 bench-calibration protocol (paper §7): schedule, virtual bench, ingest, fits, PSO.

Public entry points (all return pandas DataFrames with a unit in every dimensional column):

* :func:`test1_schedule` -- the commanded-event sheet, one row per planned event (19,168 for
  the full protocol), with held-out splits, actuator profile, DAQ rate and a randomised run
  order blocked by day and session.
* :func:`specimen_truths` -- the virtual bench's true constants per specimen and environment.
* :func:`run_virtual_bench` -- attempts log, per-event fits and (optionally) waveforms for a
  schedule; every produced row carries ``source = "virtual"``.
* :func:`validate_waveforms` / :func:`read_waveforms` -- ingest checks raising
  :class:`IngestError`; :func:`fit_waveforms` -- the same per-event fits from a table.
* :func:`oblique_summary`, :func:`cyclic_summary`, :func:`damage_depths`, :func:`table4` --
  cross-event summaries; :func:`pso_reidentify`, :func:`table5` -- §7.5.

Waveform table columns: ``event_id, time_s, displacement_mm, normal_force_n,
tangential_force_n, tangential_displacement_mm`` plus optional metadata (``attempt``,
``anomaly``, ``source``).
"""

from __future__ import annotations

import hashlib
import logging
import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
import pandas as pd

from graspcampaign.analysis.calibration import MATERIALS, cyclic_summary, oblique_summary, table4, table5
from graspcampaign.core import bench
from graspcampaign.core.bench import FAMILIES, EventCommand, SensorParams, SpreadParams
from graspcampaign.core.contact import contact_damping_c, contact_stiffness_k
from graspcampaign.rig.ingest import (
    SOURCES,
    IngestError,
    _fail,
    _table_and_label,
    header_problems,
    read_table,
)
from graspcampaign.rig.test1_summary import (
    SOURCE,
    WAVEFORM_COLUMNS,
    channels,
    damage_depths,
    normal_traces,
    pso_transfer_errors,
)
from graspcampaign.rig.test1_summary import transfer_errors as _transfer_errors

log = logging.getLogger(__name__)

__all__ = [
    "BLOCKS",
    "ENVIRONMENTS",
    "MATERIALS",
    "PUBLISHED",
    "SPLITS",
    "WAVEFORM_COLUMNS",
    "IngestError",
    "Test1Protocol",
    "VirtualBenchResult",
    "cyclic_summary",
    "damage_depths",
    "event_id_for",
    "fit_waveforms",
    "oblique_summary",
    "pso_reidentify",
    "pso_transfer_errors",
    "read_waveforms",
    "run_events",
    "run_virtual_bench",
    "specimen_truths",
    "split_event_ids",
    "table4",
    "table5",
    "test1_schedule",
    "transfer_errors",
    "validate_waveforms",
]

ENVIRONMENTS = ("cool_dry", "normal_lab", "warm_humid")
"""Environment groups of §7.1."""
BLOCKS = ("normal", "relaxation", "sliding", "oblique", "cyclic")
"""The five test blocks of §7.1."""
SPLITS = ("train", "unseen_specimen", "unseen_speed", "unseen_load", "flat_to_curved",
          "extended_relaxation")
"""Training split and the held-out splits of §7.6."""

PUBLISHED = {
    "events_commanded": 19229,
    "events_completed": 19168,
    "events_aborted": 61,
    "normal_fits": 5040,
    "normal_fits_accepted": 4888,
    "oblique_events": 1728,
    "cycle_measurements": 1600,
    "pso_runs_logged": 124,
    "pso_runs_converged": 120,
}
"""Counts the paper reports for Test 1 (§7.1-7.5)."""



@dataclass(frozen=True)
class Test1Protocol:
    """Factors of the Test 1 matrix (§7.1-7.6); defaults reproduce the published counts.

    Per specimen and environment group (4 x 12 x 3 = 144 cells): 35 normal indentations
    (5 speeds x 7 depths), 30 hold relaxations (3 depths x 2 ramp speeds x 4 repeats at
    60 s, plus 3 depths x 2 repeats at the extended hold), 45 slides (5 speeds x 3 loads x
    3 repeats) and 12 oblique presses (4 angles x 2 flat + 1 curved): 122 x 144 = 17,568.
    Cyclic fatigue (normal-lab only, the 10 training specimens of each family): 200 cycles
    as a two-level depth staircase, every 5th cycle measured, 40 x 40 = 1,600. Total 19,168
    planned events, i.e. the 19,168 completed events of §7.1; 5,040 = 144 x 35 normal fits
    and 1,728 = 144 x 12 oblique events as published.
    """

    n_specimens: int = 12
    held_out_specimens: tuple[int, ...] = (11, 12)
    accel_mm_per_s2: float = 300.0
    max_speed_mm_per_s: float = 50.0
    normal_speeds_mm_per_s: tuple[float, ...] = (0.5, 1.0, 2.0, 5.0, 10.0)
    normal_depths_mm: tuple[float, ...] = (0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75)
    normal_dwell_s: float = 0.2
    relaxation_depths_mm: tuple[float, ...] = (0.5, 1.0, 1.5)
    relaxation_speeds_mm_per_s: tuple[float, ...] = (2.0, 10.0)
    relaxation_repeats: int = 4
    relaxation_hold_s: float = 60.0
    extended_hold_s: float = 180.0
    extended_speed_mm_per_s: float = 10.0
    extended_repeats: int = 2
    relaxation_daq_hz: float = 50.0
    sliding_speeds_mm_per_s: tuple[float, ...] = (0.5, 1.0, 2.0, 5.0, 10.0)
    sliding_load_depths_mm: tuple[float, ...] = (0.5, 1.0, 1.5)
    sliding_repeats: int = 3
    sliding_stroke_mm: float = 3.0
    oblique_angles_deg: tuple[float, ...] = (0.0, 15.0, 30.0, 45.0)
    oblique_depth_mm: float = 1.5
    oblique_speed_mm_per_s: float = 1.0
    oblique_dwell_s: float = 0.5
    oblique_flat_repeats: int = 2
    oblique_curved_repeats: int = 1
    curved_radius_mm: float = 25.0
    cyclic_levels: tuple[tuple[float, int], ...] = ((1.0, 100), (2.0, 100))
    cyclic_measure_every: int = 5
    cyclic_speed_mm_per_s: float = 2.0
    cyclic_environment: str = "normal_lab"
    unseen_speed_mm_per_s: float = 5.0
    unseen_load_level: int = 2
    min_loading_samples: int = 100
    max_slide_step_um: float = 2.0

    def cyclic_depths_mm(self) -> np.ndarray:
        """Indentation of every cycle of the fatigue run, shape (c,) [mm]."""
        return np.concatenate([np.full(n, d) for d, n in self.cyclic_levels])

    def measured_cycles(self) -> np.ndarray:
        """1-based indices of the measured cycles: every ``cyclic_measure_every``-th of each
        level, starting with the level's first cycle."""
        out, first = [], 1
        for _, n in self.cyclic_levels:
            out.extend(range(first, first + n, self.cyclic_measure_every))
            first += n
        return np.asarray(out)


DAQ_RATES_HZ = (50.0, 100.0, 200.0, 250.0, 500.0)
"""Selectable DAQ rates within the 50-500 Hz of §7.1."""


def _daq_for_press(distance_mm: float, speed_mm_per_s: float, p: Test1Protocol) -> float:
    t_load = bench.trapezoid_move(np.zeros(1), distance_mm * 1e-3, speed_mm_per_s * 1e-3,
                                  p.accel_mm_per_s2 * 1e-3)[2]
    for rate in DAQ_RATES_HZ:
        if rate * t_load >= p.min_loading_samples:
            return rate
    return DAQ_RATES_HZ[-1]


def _daq_for_slide(speed_mm_per_s: float, p: Test1Protocol) -> float:
    for rate in DAQ_RATES_HZ:
        if speed_mm_per_s * 1e3 / rate <= p.max_slide_step_um:
            return rate
    return DAQ_RATES_HZ[-1]


def _hash_int(text: str, nbytes: int = 8) -> int:
    return int.from_bytes(hashlib.blake2b(text.encode(), digest_size=nbytes).digest(), "big")


def event_id_for(material: str, specimen: int, environment: str, block: str,
                 condition: str, repeat: int) -> str:
    """Return the stable, content-derived id of one planned event.

    ``"t1-" + blake2b(material|specimen|environment|block|condition|repeat)[:12 hex]``; the
    id depends on what the event is, never on the seed or on its position in the sheet.
    """
    key = f"{material}|{specimen}|{environment}|{block}|{condition}|{repeat}"
    return "t1-" + hashlib.blake2b(key.encode(), digest_size=6).hexdigest()


def _rng(seed: int, *key: str) -> np.random.Generator:
    words = [_hash_int(k, 4) for k in key]
    return np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=tuple(words)))


def event_rng(seed: int, event_id: str, attempt: int) -> np.random.Generator:
    """Generator of one attempt: ``SeedSequence(seed, spawn_key=(h(event_id), attempt))``."""
    return np.random.default_rng(np.random.SeedSequence(
        int(seed), spawn_key=(_hash_int(event_id, 4), _hash_int("attempt", 4), int(attempt))))


# ---------------------------------------------------------------------------- schedule


def _base_row(material: str, specimen: int, environment: str, block: str, p: Test1Protocol
              ) -> dict:
    return {
        "material": material, "specimen": specimen,
        "specimen_id": f"{material}-S{specimen:02d}", "environment": environment,
        "block": block, "surface": "flat", "surface_radius_mm": math.nan, "angle_deg": 0.0,
        "speed_mm_per_s": math.nan, "depth_mm": math.nan, "normal_load_n": math.nan,
        "load_level": -1, "hold_s": math.nan, "stroke_mm": math.nan, "cycle_index": 0,
        "repeat": 0, "profile": "trapezoidal", "accel_mm_per_s2": p.accel_mm_per_s2,
        "max_speed_mm_per_s": p.max_speed_mm_per_s,
    }


def _cell_events(material: str, specimen: int, environment: str, p: Test1Protocol
                 ) -> list[dict]:
    fam = FAMILIES[material]
    rows: list[dict] = []

    def add(block: str, condition: str, repeat: int, **kw) -> None:
        row = _base_row(material, specimen, environment, block, p)
        row.update(kw, repeat=repeat)
        row["event_id"] = event_id_for(material, specimen, environment, block, condition,
                                       repeat)
        rows.append(row)

    for v in p.normal_speeds_mm_per_s:
        for d in p.normal_depths_mm:
            add("normal", f"v{v}|d{d}", 0, speed_mm_per_s=v, depth_mm=d,
                hold_s=p.normal_dwell_s, daq_hz=_daq_for_press(d + 0.1, v, p))
    for d in p.relaxation_depths_mm:
        for v in p.relaxation_speeds_mm_per_s:
            for r in range(p.relaxation_repeats):
                add("relaxation", f"v{v}|d{d}|h{p.relaxation_hold_s}", r, speed_mm_per_s=v,
                    depth_mm=d, hold_s=p.relaxation_hold_s, daq_hz=p.relaxation_daq_hz)
        for r in range(p.extended_repeats):
            add("relaxation", f"v{p.extended_speed_mm_per_s}|d{d}|h{p.extended_hold_s}", r,
                speed_mm_per_s=p.extended_speed_mm_per_s, depth_mm=d,
                hold_s=p.extended_hold_s, daq_hz=p.relaxation_daq_hz)
    for v in p.sliding_speeds_mm_per_s:
        for level, dl in enumerate(p.sliding_load_depths_mm):
            load = round(fam.k_n_per_mm_n * dl**fam.n, 3)
            for r in range(p.sliding_repeats):
                add("sliding", f"v{v}|L{level}", r, speed_mm_per_s=v, normal_load_n=load,
                    load_level=level, stroke_mm=p.sliding_stroke_mm,
                    daq_hz=_daq_for_slide(v, p))
    for a in p.oblique_angles_deg:
        axial = p.oblique_depth_mm / math.cos(math.radians(a))
        daq = _daq_for_press(axial + 0.1, p.oblique_speed_mm_per_s, p)
        for r in range(p.oblique_flat_repeats):
            add("oblique", f"a{a}|flat", r, angle_deg=a, depth_mm=p.oblique_depth_mm,
                speed_mm_per_s=p.oblique_speed_mm_per_s, hold_s=p.oblique_dwell_s,
                daq_hz=daq)
        for r in range(p.oblique_curved_repeats):
            add("oblique", f"a{a}|curved{p.curved_radius_mm}", r, angle_deg=a,
                depth_mm=p.oblique_depth_mm, speed_mm_per_s=p.oblique_speed_mm_per_s,
                hold_s=p.oblique_dwell_s, daq_hz=daq, surface="curved",
                surface_radius_mm=p.curved_radius_mm)
    return rows


def _cyclic_events(material: str, specimen: int, p: Test1Protocol) -> list[dict]:
    depths = p.cyclic_depths_mm()
    rows = []
    for cyc in p.measured_cycles():
        d = float(depths[cyc - 1])
        row = _base_row(material, specimen, p.cyclic_environment, "cyclic", p)
        row.update(speed_mm_per_s=p.cyclic_speed_mm_per_s, depth_mm=d, hold_s=0.0,
                   cycle_index=int(cyc), daq_hz=_daq_for_press(d + 0.1,
                                                                p.cyclic_speed_mm_per_s, p))
        row["event_id"] = event_id_for(material, specimen, p.cyclic_environment, "cyclic",
                                       f"c{cyc}|d{d}", 0)
        rows.append(row)
    return rows


def _split(row: dict, p: Test1Protocol) -> str:
    if row["specimen"] in p.held_out_specimens:
        return "unseen_specimen"
    b = row["block"]
    if b in ("normal", "sliding") and row["speed_mm_per_s"] == p.unseen_speed_mm_per_s:
        return "unseen_speed"
    if b == "sliding" and row["load_level"] == p.unseen_load_level:
        return "unseen_load"
    if b == "oblique" and row["surface"] == "curved":
        return "flat_to_curved"
    if b == "relaxation" and row["hold_s"] == p.extended_hold_s:
        return "extended_relaxation"
    return "train"


def test1_schedule(seed: int = 0, *, protocol: Test1Protocol | None = None,
                   materials: Sequence[str] | None = None,
                   specimens: Sequence[int] | None = None,
                   environments: Sequence[str] | None = None) -> pd.DataFrame:
    """Return the Test 1 commanded-event sheet, one row per planned event.

    Parameters
    ----------
    seed : int
        Study seed; it only randomises the run order.
    protocol : Test1Protocol, optional
        Factors; the default reproduces the published counts (19,168 events).
    materials, specimens, environments : sequence, optional
        Restrict the sheet (reduced schedules for tests and pilots); event ids, factors and
        splits of the kept events are unchanged.

    Returns
    -------
    pandas.DataFrame
        Columns: ``event_id`` (stable, content-derived), ``material``, ``specimen``,
        ``specimen_id``, ``environment``, ``block``, ``split``, ``surface``,
        ``surface_radius_mm``, ``angle_deg``, ``speed_mm_per_s`` (approach speed; tangential
        speed for sliding), ``depth_mm`` (target normal indentation), ``normal_load_n``
        (sliding preload), ``load_level``, ``hold_s``, ``stroke_mm``, ``cycle_index``,
        ``repeat``, ``profile``, ``accel_mm_per_s2``, ``max_speed_mm_per_s``, ``daq_hz``,
        ``day``, ``session``, ``run_order``.

    Notes
    -----
    Run order: one day per (environment group, material) with the environment order and
    the materials within it randomised; within a day one session per specimen in random
    order, events shuffled within a session. The destructive cyclic block runs last, one
    day per material, one session per specimen, cycles in sequence.
    """
    p = Test1Protocol() if protocol is None else protocol
    mats = list(MATERIALS if materials is None else materials)
    specs = list(range(1, p.n_specimens + 1) if specimens is None else specimens)
    envs = list(ENVIRONMENTS if environments is None else environments)
    for m in mats:
        if m not in FAMILIES:
            raise ValueError(f"unknown material {m!r}; expected one of {list(MATERIALS)}")
    for e in envs:
        if e not in ENVIRONMENTS:
            raise ValueError(f"unknown environment {e!r}; expected one of {list(ENVIRONMENTS)}")
    rng = _rng(seed, "test1-schedule")
    rows: list[dict] = []
    day = session = 0
    env_order = [envs[i] for i in rng.permutation(len(envs))]
    for env in env_order:
        for m in [mats[i] for i in rng.permutation(len(mats))]:
            day += 1
            for s in [specs[i] for i in rng.permutation(len(specs))]:
                session += 1
                cell = _cell_events(m, s, env, p)
                for i in rng.permutation(len(cell)):
                    rows.append({**cell[i], "day": day, "session": session})
    if p.cyclic_environment in envs:
        for m in [mats[i] for i in rng.permutation(len(mats))]:
            day += 1
            train = [s for s in specs if s not in p.held_out_specimens]
            for s in [train[i] for i in rng.permutation(len(train))]:
                session += 1
                rows.extend({**r, "day": day, "session": session}
                            for r in _cyclic_events(m, s, p))
    df = pd.DataFrame(rows)
    if df.empty:
        return df
    df["split"] = [_split(r, p) for r in rows]
    df["run_order"] = np.arange(1, len(df) + 1)
    cols = ["event_id", "material", "specimen", "specimen_id", "environment", "block",
            "split", "surface", "surface_radius_mm", "angle_deg", "speed_mm_per_s",
            "depth_mm", "normal_load_n", "load_level", "hold_s", "stroke_mm", "cycle_index",
            "repeat", "profile", "accel_mm_per_s2", "max_speed_mm_per_s", "daq_hz", "day",
            "session", "run_order"]
    df = df[cols].astype({"specimen": "int64", "cycle_index": "int64", "repeat": "int64",
                          "load_level": "int64", "day": "int64", "session": "int64",
                          "daq_hz": "float64"})
    if df["event_id"].duplicated().any():  # pragma: no cover - guards the id scheme
        raise RuntimeError("duplicate event ids in the Test 1 schedule")
    return df.reset_index(drop=True)


def split_event_ids(schedule: pd.DataFrame) -> dict[str, list[str]]:
    """Return the event ids of every split of §7.6 (``train`` and the five held-out sets)."""
    return {s: schedule.loc[schedule["split"] == s, "event_id"].tolist() for s in SPLITS}


# ------------------------------------------------------------------------ truths


@lru_cache(maxsize=4096)
def _specimen(seed: int, material: str, specimen: int, environment: str,
              spread: SpreadParams) -> bench.SpecimenParams:
    rng = _rng(seed, "specimen", material, str(specimen))
    return bench.draw_specimen(FAMILIES[material], specimen, environment, rng, spread)


def specimen_truths(seed: int, schedule: pd.DataFrame | None = None, *,
                    spread: SpreadParams | None = None) -> pd.DataFrame:
    """Return the virtual bench's true constants, one row per specimen and environment.

    Parameters
    ----------
    seed : int
        Study seed.
    schedule : DataFrame, optional
        Restrict to the (material, specimen, environment) cells it contains; default all
        4 x 12 x 3.
    spread : SpreadParams, optional

    Returns
    -------
    pandas.DataFrame
        ``material, specimen, environment, modulus_kpa, k_n_per_mm_n, exponent_n,
        c_n_s_per_m, f05_n, mu_s, mu_k, k_t_n_per_mm, rho, tau_s, toe_um, adhesion_n,
        softening_ref, set_ref_mm, damage_depth_mm, damage_criterion, source``.
    """
    sp = SpreadParams() if spread is None else spread
    if schedule is None:
        cells = [(m, s, e) for m in MATERIALS for s in range(1, 13) for e in ENVIRONMENTS]
    else:
        cells = sorted(set(zip(schedule["material"], schedule["specimen"].astype(int),
                               schedule["environment"], strict=True)),
                       key=lambda c: (MATERIALS.index(c[0]), c[1], ENVIRONMENTS.index(c[2])))
    rows = []
    for m, s, e in cells:
        t = _specimen(int(seed), m, int(s), e, sp)
        dd = bench.true_damage_depth(t)
        rows.append({
            "material": m, "specimen": int(s), "environment": e,
            "modulus_kpa": t.modulus / 1e3, "k_n_per_mm_n": t.k_n_per_mm_n,
            "exponent_n": t.n, "c_n_s_per_m": t.c, "f05_n": t.f05, "mu_s": t.mu_s,
            "mu_k": t.mu_k, "k_t_n_per_mm": t.k_t / 1e3, "rho": t.rho, "tau_s": t.tau,
            "toe_um": t.toe * 1e6, "adhesion_n": t.adhesion,
            "softening_ref": t.softening_ref, "set_ref_mm": t.set_ref * 1e3,
            "damage_depth_mm": dd.depth * 1e3, "damage_criterion": dd.criterion,
            "source": SOURCE,
        })
    return pd.DataFrame(rows)


# --------------------------------------------------------------------------- commands


@lru_cache(maxsize=1024)
def _cyclic_states(seed: int, material: str, specimen: int, environment: str,
                   spread: SpreadParams, p: Test1Protocol) -> tuple[np.ndarray, np.ndarray]:
    spec = _specimen(seed, material, specimen, environment, spread)
    return bench.cyclic_state(spec, p.cyclic_depths_mm() * 1e-3)


def _command(row: dict, seed: int, spread: SpreadParams, p: Test1Protocol) -> EventCommand:
    b = row["block"]
    common = {"block": b, "speed": row["speed_mm_per_s"] * 1e-3,
              "accel": row["accel_mm_per_s2"] * 1e-3, "daq_hz": float(row["daq_hz"])}
    if b == "sliding":
        return EventCommand(**common, normal_load=float(row["normal_load_n"]),
                            stroke=row["stroke_mm"] * 1e-3)
    radius = row["surface_radius_mm"]
    cmd = EventCommand(**common, depth=row["depth_mm"] * 1e-3, hold=float(row["hold_s"]),
                       angle=math.radians(row["angle_deg"]),
                       surface_radius=radius * 1e-3 if np.isfinite(radius) else math.inf)
    if b == "cyclic":
        s, perm = _cyclic_states(seed, row["material"], int(row["specimen"]),
                                 row["environment"], spread, p)
        i = int(row["cycle_index"]) - 1
        cmd = EventCommand(**{**asdict(cmd), "softening": float(s[i]),
                              "permanent_set": float(perm[i])})
    return cmd


# ------------------------------------------------------------------------------- fits

REVIEW_RMSE_PCT = bench.RMSE_REVIEW_THRESHOLD_PCT


def _table_arrays(w: bench.Waveform) -> dict[str, np.ndarray]:
    """Waveform channels in file units, quantised exactly as the sensors resolve them."""
    return {
        "time_s": np.round(w.time, 9),
        "displacement_mm": np.round(w.displacement * 1e6) / 1e3,
        "normal_force_n": np.round(w.normal_force * 1e3) / 1e3,
        "tangential_force_n": np.round(w.tangential_force * 1e3) / 1e3,
        "tangential_displacement_mm": np.round(w.tangential_displacement * 1e6) / 1e3,
    }


def _fit_arrays(row: dict, a: dict[str, np.ndarray], anomaly: str) -> dict:
    """Per-event fit from file-unit arrays; the one path shared by in-process and ingest."""
    t = np.asarray(a["time_s"], dtype=float)
    x = np.asarray(a["displacement_mm"], dtype=float) * 1e-3
    fn = np.asarray(a["normal_force_n"], dtype=float)
    ft = np.asarray(a["tangential_force_n"], dtype=float)
    xt = np.asarray(a["tangential_displacement_mm"], dtype=float) * 1e-3
    b = row["block"]
    out: dict = {"n_samples": int(t.size)}
    if b in ("normal", "cyclic"):
        onset = 0.0
        if b == "cyclic":
            sh = bench.fit_shifted(t, x, fn)
            onset = sh.delta0 if np.isfinite(sh.delta0) else 0.0
            out["onset_mm"] = sh.delta0 * 1e3
        r = bench.fit_normal(t, x, fn, onset=onset)
        out.update({
            "k_n_per_mm_n": r.k_n_per_mm_n, "exponent_n": r.n, "c_n_s_per_m": r.c,
            "c_se_n_s_per_m": r.c_se, "f05_n": r.f05, "rmse_pct": r.rmse_pct,
            "peak_force_n": r.peak_force, "max_depth_mm": r.max_depth * 1e3,
            "loading_work_mj": r.loading_work * 1e3, "unloading_work_mj": r.unloading_work * 1e3,
            "loop_area_mj": (r.loading_work - r.unloading_work) * 1e3,
            "n_fit_points": r.n_points, "fit_ok": r.success,
        })
        if b == "normal":
            sh = bench.fit_shifted(t, x, fn)
            out.update({"shifted_k_n_per_mm_m": sh.k_n_per_mm_m, "shifted_m": sh.m,
                        "shifted_delta0_mm": sh.delta0 * 1e3,
                        "shifted_rmse_pct": sh.rmse_pct})
    elif b == "relaxation":
        r = bench.fit_relaxation(t, x, fn)
        out.update({"f0_n": r.f0, "rho": r.rho, "tau_s": r.tau, "rmse_pct": r.rmse_pct,
                    "hold_s_measured": r.hold, "fit_ok": r.success})
    elif b == "sliding":
        r = bench.fit_sliding(t, fn, ft, xt)
        out.update({"mu_s": r.mu_s, "mu_k": r.mu_k, "k_t_n_per_mm": r.k_t / 1e3,
                    "mean_normal_force_n": r.normal_force,
                    "stick_slip_sd": r.stick_slip_amplitude, "fit_ok": r.success})
    elif b == "oblique":
        r = bench.fit_oblique(t, x, fn, ft, xt)
        out.update({"peak_normal_force_n": r.normal_force,
                    "peak_tangential_force_n": r.tangential_force, "slip_mm": r.slip * 1e3,
                    "slipped_measured": r.slipped, "fit_ok": r.success})
    else:
        raise ValueError(f"unknown block {b!r}")
    # §7.2 (iii): flagged for review when the force RMSE exceeds the threshold (normal-law
    # fits) or the rig log records an anomaly; flagged fits stay in every summary
    reasons = []
    if not out["fit_ok"]:
        reasons.append("fit_failed")
    elif b in ("normal", "cyclic") and out["rmse_pct"] > REVIEW_RMSE_PCT:
        reasons.append("rmse")
    if anomaly:
        reasons.append(f"anomaly:{anomaly}")
    out["review_reason"] = ";".join(reasons)
    out["accepted"] = not reasons
    return out


_META = ("event_id", "material", "specimen", "specimen_id", "environment", "block", "split",
         "surface", "surface_radius_mm", "angle_deg", "speed_mm_per_s", "depth_mm", "normal_load_n", "hold_s",
         "cycle_index")


def _fit_row(row: dict, a: dict[str, np.ndarray], attempt: int, anomaly: str) -> dict:
    out = {k: row[k] for k in _META}
    out.update(attempt=int(attempt), anomaly=anomaly, source=SOURCE)
    out.update(_fit_arrays(row, a, anomaly))
    return out


# ---------------------------------------------------------------------- virtual bench

MAX_ATTEMPTS = 5


def _run_rows(rows: list[dict], seed: int, spread: SpreadParams, sensor: SensorParams,
              p: Test1Protocol, keep: bool, fit: bool = True
              ) -> tuple[list[dict], list[dict], list[dict]]:
    attempts, fits, waves = [], [], []
    for row in rows:
        spec = _specimen(seed, row["material"], int(row["specimen"]), row["environment"],
                         spread)
        cmd = _command(row, seed, spread, p)
        for attempt in range(1, MAX_ATTEMPTS + 1):
            w = bench.simulate_event(cmd, spec, event_rng(seed, row["event_id"], attempt),
                                     sensor)
            status = "aborted" if w.aborted else "completed"
            attempts.append({"event_id": row["event_id"], "attempt": attempt,
                             "status": status, "anomaly": w.anomaly,
                             "n_samples": int(w.time.size), "block": row["block"],
                             "source": SOURCE})
            if w.aborted:
                continue
            a = _table_arrays(w)
            if fit:
                fits.append(_fit_row(row, a, attempt, w.anomaly))
            if keep:
                waves.append({"event_id": row["event_id"], "attempt": attempt,
                              "anomaly": w.anomaly, **a})
            break
    return attempts, fits, waves


def run_events(rows: Sequence[dict], seed: int, *, keep_waveforms: bool = False,
               fit: bool = True, spread: SpreadParams | None = None,
               sensor: SensorParams | None = None, protocol: Test1Protocol | None = None
               ) -> tuple[list[dict], list[dict], list[dict]]:
    """Run schedule rows on the virtual bench in this process (the per-event path).

    The same code :func:`run_virtual_bench` runs in each worker: every attempt draws from
    :func:`event_rng` ``(seed, event_id, attempt)``, so one event gives the same attempts,
    fit and waveform whichever rows it is run with (the campaign engine runs one per trial).

    Returns
    -------
    attempts, fits, waveforms : list of dict
        Attempt log rows, fit rows (as in :attr:`VirtualBenchResult.fits`) and, with
        ``keep_waveforms``, one dict of file-unit channel arrays per completed event.
    """
    return _run_rows(list(rows), int(seed), SpreadParams() if spread is None else spread,
                     SensorParams() if sensor is None else sensor,
                     Test1Protocol() if protocol is None else protocol, keep_waveforms, fit)


@dataclass
class VirtualBenchResult:
    """Output of :func:`run_virtual_bench`.

    Attributes
    ----------
    attempts : DataFrame
        One row per attempt (19,168 planned events plus re-runs of aborted attempts):
        ``event_id, attempt, status ("completed" | "aborted"), anomaly, n_samples, block,
        source``.
    fits : DataFrame
        One row per completed event: schedule metadata and the block's fitted quantities.
    waveforms : DataFrame or None
        Long table of the completed attempts' samples (see :data:`WAVEFORM_COLUMNS`).
    truths : DataFrame
        :func:`specimen_truths` of the schedule's cells.
    """

    attempts: pd.DataFrame
    fits: pd.DataFrame
    waveforms: pd.DataFrame | None
    truths: pd.DataFrame
    meta: dict = field(default_factory=dict)


def _waves_frame(waves: list[dict]) -> pd.DataFrame:
    if not waves:
        return pd.DataFrame(columns=[*WAVEFORM_COLUMNS, "attempt", "anomaly", "source"])
    lens = [w["time_s"].size for w in waves]
    df = pd.DataFrame({
        "event_id": np.repeat([w["event_id"] for w in waves], lens),
        **{c: np.concatenate([w[c] for w in waves]) for c in WAVEFORM_COLUMNS[1:]},
        "attempt": np.repeat([w["attempt"] for w in waves], lens).astype("int64"),
        "anomaly": np.repeat([w["anomaly"] for w in waves], lens),
    })
    df["source"] = SOURCE
    return df


def run_virtual_bench(schedule: pd.DataFrame, seed: int, *, n_jobs: int = 1,
                      keep_waveforms: bool = True, spread: SpreadParams | None = None,
                      sensor: SensorParams | None = None,
                      protocol: Test1Protocol | None = None,
                      chunk_size: int = 500, fit: bool = True) -> VirtualBenchResult:
    """Run a schedule on the virtual bench: generate, abort/re-run, fit.

    Every attempt draws from :func:`event_rng` ``(seed, event_id, attempt)``, so results do
    not depend on order, chunking or ``n_jobs``. Aborted attempts are re-run (attempt
    2, 3, ...) and carry no fit (§7.1).

    Parameters
    ----------
    schedule : DataFrame
        From :func:`test1_schedule` (or a subset of it).
    seed : int
        Study seed.
    n_jobs : int, optional
        Worker processes (joblib, loky) over chunks of ``chunk_size`` events.
    keep_waveforms : bool, optional
        Keep the long waveform table (about 45 M samples for the full protocol; pass False
        there).
    spread, sensor, protocol : optional
        Virtual-bench and protocol parameters.
    chunk_size : int, optional
        Events per worker task.
    fit : bool, optional
        Fit every completed event (default); False only generates (``fits`` is empty).

    Returns
    -------
    VirtualBenchResult
    """
    sp = SpreadParams() if spread is None else spread
    se = SensorParams() if sensor is None else sensor
    p = Test1Protocol() if protocol is None else protocol
    rows = schedule.to_dict("records")
    chunks = [rows[i:i + chunk_size] for i in range(0, len(rows), chunk_size)]
    if n_jobs == 1 or len(chunks) <= 1:
        parts = [_run_rows(c, int(seed), sp, se, p, keep_waveforms, fit) for c in chunks]
    else:
        from joblib import Parallel, delayed

        parts = Parallel(n_jobs=n_jobs)(delayed(_run_rows)(c, int(seed), sp, se, p,
                                                           keep_waveforms, fit)
                                        for c in chunks)
    attempts = pd.DataFrame([a for part in parts for a in part[0]])
    fits = pd.DataFrame([f for part in parts for f in part[1]])
    waves = _waves_frame([w for part in parts for w in part[2]]) if keep_waveforms else None
    return VirtualBenchResult(attempts=attempts, fits=_order_fit_columns(fits),
                              waveforms=waves, truths=specimen_truths(seed, schedule, spread=sp),
                              meta={"seed": int(seed), "source": SOURCE,
                                    "n_events": len(rows)})


def _order_fit_columns(fits: pd.DataFrame) -> pd.DataFrame:
    if fits.empty:
        return fits
    first = [*_META, "attempt", "anomaly", "source", "n_samples"]
    rest = [c for c in fits.columns if c not in first]
    return fits[first + rest].reset_index(drop=True)


# ------------------------------------------------------------------------------ ingest


_UNIT_RE = re.compile(r"^(?P<stem>time|displacement|normal_force|tangential_force|"
                      r"tangential_displacement)_(?P<unit>[a-z]+)$")
_EXPECTED_UNIT = {"time": "s", "displacement": "mm", "normal_force": "n",
                  "tangential_force": "n", "tangential_displacement": "mm"}
_RANGES = {  # physical envelope of the rig (§7.1): values outside suggest wrong units
    "time_s": (0.0, 3600.0, "the 0-3600 s record window"),
    "displacement_mm": (-50.0, 50.0, "the +-50 mm actuator travel"),
    "normal_force_n": (-10.0, 10.0, "the 10 N load-cell range"),
    "tangential_force_n": (-10.0, 10.0, "the 10 N load-cell range"),
    "tangential_displacement_mm": (-50.0, 50.0, "the +-50 mm stage travel"),
}


def read_waveforms(path: str | Path) -> pd.DataFrame:
    """Read a waveform file (``.csv``, ``.parquet``/``.pq`` or ``.xlsx``) without checks.

    Via :func:`graspcampaign.rig.ingest.read_table` (an unsupported, missing or unreadable
    file raises :class:`IngestError`); CSV channels are parsed as numbers, only an empty cell
    is missing.
    """
    return read_table(path, csv_options={"dtype": {"event_id": str, "anomaly": str},
                                         "keep_default_na": False, "na_values": [""]},
                      excel_options={"dtype": {"event_id": str}})


def validate_waveforms(data: pd.DataFrame | str | Path, known_event_ids: Iterable[str],
                       file_label: str | None = None) -> pd.DataFrame:
    """Validate a waveform table and return it with clean dtypes.

    Checks, in order: required columns (a column with the right quantity but another unit
    suffix is reported as wrong units), numbers, finite values, the rig's physical ranges
    (values outside them usually mean wrong units), known event ids, duplicate samples
    (same ``event_id`` and ``time_s``), strictly increasing time within each event.

    Parameters
    ----------
    data : DataFrame or path
        The table, or a CSV/Parquet/XLSX file to read with :func:`read_waveforms`.
    known_event_ids : iterable of str
        Event ids of the study's schedule.
    file_label : str, optional
        Name used in messages; default the file name (or ``"<dataframe>"``).

    Returns
    -------
    pandas.DataFrame
        The validated table (``event_id`` str, channels float64), in file order.

    Raises
    ------
    IngestError
        One sentence naming the file, the 1-based data row (header excluded) and the column.
    """
    df, label = _table_and_label(data, file_label, read_waveforms)
    df = df.reset_index(drop=True)
    df.columns = [str(c).strip() for c in df.columns]
    units = {c: _EXPECTED_UNIT[c.rsplit("_", 1)[0]] for c in WAVEFORM_COLUMNS[1:]}
    problems = header_problems(list(df.columns), list(WAVEFORM_COLUMNS), units, _UNIT_RE)
    if problems:
        raise IngestError(f"{label}, header: {'; '.join(problems)} (`graspcampaign schedule "
                          "test1_bench --template` writes a sheet with every column).")
    if len(df) == 0:
        raise _fail(label, None, "event_id", "the file has no data rows")
    out = pd.DataFrame({"event_id": df["event_id"]})
    ids = df["event_id"]
    bad = ids.isna() | (ids.astype(str).str.strip() == "")
    if bad.any():
        raise _fail(label, int(np.flatnonzero(bad.to_numpy())[0]) + 1, "event_id",
                    "event id is empty")
    out["event_id"] = ids.astype(str).str.strip()
    for c in WAVEFORM_COLUMNS[1:]:
        raw = df[c]
        num = pd.to_numeric(raw, errors="coerce")
        nonnum = num.isna() & raw.notna() & ~raw.astype(str).str.strip().str.lower().isin(
            ["nan", "inf", "-inf", "+inf", "infinity", "-infinity"])
        if nonnum.any():
            i = int(np.flatnonzero(nonnum.to_numpy())[0])
            raise _fail(label, i + 1, c, f"value {raw.iloc[i]!r} is not a number")
        vals = num.to_numpy(dtype=float)
        notfinite = ~np.isfinite(vals)
        if notfinite.any():
            i = int(np.flatnonzero(notfinite)[0])
            problem = ("value nan (an empty cell or NaN) is not finite" if np.isnan(vals[i])
                       else f"value {vals[i]:g} is not finite")  # not np.float64(inf)
            raise _fail(label, i + 1, c, problem)
        lo, hi, what = _RANGES[c]
        outside = (vals < lo) | (vals > hi)
        if outside.any():
            i = int(np.flatnonzero(outside)[0])
            raise _fail(label, i + 1, c, f"value {vals[i]:g} lies outside {what} "
                        "(wrong units?)")
        out[c] = vals
    known = set(known_event_ids)
    unknown = ~out["event_id"].isin(known)
    if unknown.any():
        i = int(np.flatnonzero(unknown.to_numpy())[0])
        raise _fail(label, i + 1, "event_id",
                    f"event id '{out['event_id'].iloc[i]}' is not in the schedule")
    dup = out.duplicated(["event_id", "time_s"], keep="first")
    if dup.any():
        i = int(np.flatnonzero(dup.to_numpy())[0])
        key = out.iloc[i]
        first = out.index[(out["event_id"] == key["event_id"])
                          & (out["time_s"] == key["time_s"])][0]
        raise _fail(label, i + 1, "time_s", f"duplicate sample of event '{key['event_id']}' "
                    f"at {key['time_s']:g} s (first seen in row {first + 1})")
    prev = out.groupby("event_id", sort=False)["time_s"].shift()
    back = (out["time_s"] <= prev).to_numpy()
    if back.any():
        i = int(np.flatnonzero(back)[0])
        raise _fail(label, i + 1, "time_s", f"time {out['time_s'].iloc[i]:g} s does not "
                    f"increase within event '{out['event_id'].iloc[i]}' (previous sample "
                    f"{prev.iloc[i]:g} s)")
    if "attempt" in df.columns:
        out["attempt"] = _attempts(df["attempt"], label)
    if "anomaly" in df.columns:
        anomaly = df["anomaly"].astype(object)
        out["anomaly"] = anomaly.where(anomaly.notna(), "").astype(str).str.strip()
    if "source" in df.columns:
        out["source"] = _sources(df["source"], label)
    for extra in ("attempt", "anomaly", "source"):
        if extra in out:
            _check_constant(out, extra, label)
    return out


def _attempts(raw: pd.Series, label: str) -> np.ndarray:
    """Parse the optional ``attempt`` column: an integer from 1 (the first try) on."""
    values = []
    for i, value in enumerate(raw.tolist()):
        text = str(value).strip()
        try:
            number = float(text)
        except ValueError:
            number = math.nan
        if not (math.isfinite(number) and number == int(number) and number >= 1):
            shown = value.item() if isinstance(value, np.generic) else value  # no np reprs
            raise _fail(label, i + 1, "attempt", f"value {shown!r} is not an attempt number (an "
                        "integer 1, 2, ... counting the tries of the event)")
        values.append(int(number))
    return np.asarray(values, dtype=np.int64)


def _sources(raw: pd.Series, label: str) -> np.ndarray:
    """Parse the optional ``source`` column: ``measured`` (a rig) or ``virtual`` (a virtual bench)."""
    values = []
    for i, value in enumerate(raw.tolist()):
        text = "" if value is None or (isinstance(value, float) and math.isnan(value)) \
            else str(value).strip()
        if not text:
            raise _fail(label, i + 1, "source", f"value is empty; expected one of "
                        f"{', '.join(SOURCES)}")
        if text not in SOURCES:
            raise _fail(label, i + 1, "source", f"value {text!r} is not one of "
                        f"{', '.join(SOURCES)}")
        values.append(text)
    return np.asarray(values, dtype=object)


def _check_constant(table: pd.DataFrame, column: str, label: str) -> None:
    """A per-event column (attempt, anomaly, source) must not change within an event."""
    first = table.groupby("event_id", sort=False)[column].transform("first")
    changed = (table[column] != first).to_numpy()
    if changed.any():
        i = int(np.flatnonzero(changed)[0])
        value, before = (v.item() if isinstance(v, np.generic) else v  # no np reprs
                         for v in (table[column].iloc[i], first.iloc[i]))
        raise _fail(label, i + 1, column, f"value {value!r} differs from {before!r} earlier in "
                    f"event '{table['event_id'].iloc[i]}' (one value per event)")


def waveform_template() -> tuple[pd.DataFrame, pd.DataFrame]:
    """Return the (empty) waveform sheet a rig fills in, and the description of its columns.

    Returns
    -------
    sheet : pandas.DataFrame
        No rows; the columns :data:`WAVEFORM_COLUMNS` then the optional ``attempt``, ``anomaly``,
        ``source``.
    columns : pandas.DataFrame
        ``column, type, unit, allowed, required`` per column (ranges: the rig envelope of §7.1).
    """
    rows = [{"column": "event_id", "type": "str", "unit": "-",
             "allowed": "an event_id of the schedule", "required": "every row"}]
    for name in WAVEFORM_COLUMNS[1:]:
        lo, hi, what = _RANGES[name]
        unit = {"s": "s", "mm": "mm", "n": "N"}[name.rsplit("_", 1)[1]]
        rows.append({"column": name, "type": "float", "unit": unit,
                     "allowed": f"float in [{lo:g}, {hi:g}] ({what})", "required": "every row"})
    rows += [
        {"column": "attempt", "type": "int", "unit": "1",
         "allowed": "integer >= 1, one value per event", "required": "optional column (1)"},
        {"column": "anomaly", "type": "str", "unit": "-", "allowed": "rig-log note, one per event",
         "required": "optional column"},
        {"column": "source", "type": "str", "unit": "-", "allowed": ", ".join(SOURCES),
         "required": "optional column (measured)"},
    ]
    columns = pd.DataFrame(rows)
    return pd.DataFrame({c: pd.Series(dtype=object) for c in columns["column"]}), columns


def fit_waveforms(waveforms: pd.DataFrame, schedule: pd.DataFrame,
                  anomalies: pd.Series | dict | None = None) -> pd.DataFrame:
    """Fit every event of a (validated) waveform table -- the ingest path.

    Parameters
    ----------
    waveforms : DataFrame
        Output of :func:`validate_waveforms`.
    schedule : DataFrame
        The study's sheet (gives each event's block and factors).
    anomalies : Series or dict, optional
        Rig-log anomaly per event id; default the table's ``anomaly`` column if present.

    Returns
    -------
    pandas.DataFrame
        Same columns as :attr:`VirtualBenchResult.fits`; ``source`` is copied from the
        table when present, and is ``"measured"`` when the table has no ``source`` column
        (a real rig's file).
    """
    sched = schedule.set_index("event_id", drop=False)
    log_anomalies = None if anomalies is None else dict(anomalies)
    rows = []
    for eid, g in waveforms.groupby("event_id", sort=False):
        row = sched.loc[eid].to_dict()
        if log_anomalies is not None:
            anomaly = str(log_anomalies.get(eid, "") or "")
        elif "anomaly" in g:
            anomaly = str(g["anomaly"].iloc[0] or "")
        else:
            anomaly = ""
        attempt = int(g["attempt"].iloc[0]) if "attempt" in g else 1
        fit = _fit_row(row, channels(g), attempt, anomaly)
        # a file without a source column comes from a rig: never label it virtual
        fit["source"] = str(g["source"].iloc[0]) if "source" in g else "measured"
        rows.append(fit)
    return _order_fit_columns(pd.DataFrame(rows))


# --------------------------------------------------------------------------- summaries


def transfer_errors(fits: pd.DataFrame, waveforms: pd.DataFrame | None = None,
                    protocol: Test1Protocol | None = None) -> pd.DataFrame:
    """:func:`graspcampaign.rig.test1_summary.transfer_errors` with the protocol's curved
    radius (the flat-to-curved split's specimens)."""
    p = Test1Protocol() if protocol is None else protocol
    return _transfer_errors(fits, waveforms, curved_radius_mm=p.curved_radius_mm)


# -------------------------------------------------------------------------------- PSO

PSO_LAMBDA1_UPPER = 5.0
"""Upper bound of lambda1 for trace re-identification (decision): Eq. 14 with the Table 4
moduli and R = 5 mm needs lambda1 ~ 2.1-2.3 for Table 4's K, beyond the §11 bound of 1.5."""
PSO_POINTS_PER_TRACE = 60
PSO_CONVERGENCE_FACTOR = 1.5
"""A restart converged if its final cost is within 1.5x the lowest cost any logged run's
parameters reach on that restart's own traces (decision)."""


def _converged(runs: list, costs: list) -> np.ndarray:
    """Convergence of each run judged on its own objective (its own traces).

    Restarts fit different random trace draws, so their final costs measure different
    objectives; a run has converged when no logged run's parameters do better than
    ``1 / PSO_CONVERGENCE_FACTOR`` of its cost on its own traces.
    """
    xs = np.array([res.best_x for res in runs])
    return np.array([res.best_cost <= PSO_CONVERGENCE_FACTOR * min(float(np.min(cost(xs))),
                                                                     res.best_cost)
                     for res, cost in zip(runs, costs, strict=True)])


def _pso_cost(traces: list[tuple], psi: float, backend: str = "numba"):
    """The §7.5 PSO cost over ``traces``: mean over traces of the Eq. 13 force RMSE (% of
    peak) of each particle's ``K = 2 lambda1 Psi sqrt(R)``, ``C = 4 pi R lambda2`` and ``n``
    (:meth:`graspcampaign.core.bench.TraceSet.mean_rmse_pct`; ``backend="numpy"`` is its
    reference). K and C are linear in lambda1 and lambda2 (Eq. 14): their unit values are
    computed once."""
    points = bench.TraceSet.from_traces(traces)
    k_unit = float(contact_stiffness_k(1.0, psi, bench.FINGERTIP_RADIUS))
    c_unit = float(contact_damping_c(1.0, bench.FINGERTIP_RADIUS))

    def cost(pos: np.ndarray) -> np.ndarray:
        return points.mean_rmse_pct(k_unit * pos[:, 0], pos[:, 2], c_unit * pos[:, 1],
                                    backend=backend)

    return cost


def _pso_draw(pool: list[tuple], seed: int, material: str, run: int, traces_per_run: int
              ) -> tuple[list[tuple], np.random.Generator]:
    """The traces of run ``run`` of ``material`` and the generator that then draws its swarm,
    both from ``(seed, "pso", material, run)``."""
    rng = _rng(seed, "pso", material, str(run))
    pick = rng.choice(len(pool), size=min(traces_per_run, len(pool)), replace=False)
    return [pool[i] for i in sorted(pick)], rng


def _pso_run(traces: list[tuple], psi: float, rng: np.random.Generator,
             bounds: tuple[np.ndarray, np.ndarray], n_particles: int, n_iterations: int):
    """Minimise :func:`_pso_cost` over ``traces`` with the swarm drawn from ``rng`` (a task:
    it carries its own traces and generator state, not the material's pool)."""
    from graspcampaign.core.identify import pso_minimize

    return pso_minimize(_pso_cost(traces, psi), *bounds, n_particles=n_particles,
                        n_iterations=n_iterations, rng=rng)


def _map(fn, tasks: list[tuple], n_jobs: int) -> list:
    """``[fn(*task) for task in tasks]``, over ``n_jobs`` local processes when > 1."""
    if n_jobs == 1 or len(tasks) <= 1:
        return [fn(*t) for t in tasks]
    from joblib import Parallel, delayed

    return Parallel(n_jobs=min(n_jobs, len(tasks)))(delayed(fn)(*t) for t in tasks)


def pso_reidentify(waveforms: pd.DataFrame, schedule: pd.DataFrame, seed: int, *,
                   n_restarts: int = 30, n_particles: int = 40, n_iterations: int = 1250,
                   traces_per_run: int = 12, max_reruns: int = 30,
                   lambda1_upper: float = PSO_LAMBDA1_UPPER, n_jobs: int = 1) -> pd.DataFrame:
    """Re-identify (lambda1, lambda2, n, b, k, c) from normal-indentation traces (§7.5).

    For each material, ``n_restarts`` PSO runs (:func:`graspcampaign.core.identify.
    pso_minimize`, w = 0.7, c1 = c2 = 1.5; default 40 particles x 1250 iterations = 5e4
    evaluations, the converged budget of §5.3/§11) minimise the mean force RMSE (% of peak)
    of Eq. 13 with ``K = 2 lambda1 Psi sqrt(R)`` and ``C = 4 pi R lambda2`` (Eq. 14, Psi of
    the family's mean modulus). Each restart draws its own random swarm *and* its own
    ``traces_per_run`` traces from the material's normal-indentation traces in
    ``waveforms``, so the spread over restarts reflects trace-to-trace variability. A run
    counts as converged when its cost is within 1.5x the lowest cost that any logged run's
    parameters reach on its own traces (:func:`_converged`; the restarts' own costs are not
    comparable, each fits other traces); diverged runs stay in the log and re-runs are added
    until ``n_restarts`` converge (at most ``max_reruns``).

    The MSD constants b, k, c do not enter a single-contact bench trace: they are searched
    within their §11 bounds but unconstrained by the data, so their spread is the search
    prior (stated plainly, not a finding).

    Parameters
    ----------
    waveforms : DataFrame
        Validated waveform table holding the traces.
    schedule : DataFrame
        Gives each trace's material and block (normal-indentation traces are used).
    seed : int
        Study seed; run ``r`` of material ``m`` draws from ``(seed, "pso", m, r)``.
    n_jobs : int, optional
        Local worker processes; every run is one task (all materials' first ``n_restarts``
        at once, then re-runs), so the result does not depend on ``n_jobs``.

    Returns
    -------
    pandas.DataFrame
        One row per logged run: ``material, run, lambda1, lambda2, n, b, k, c,
        k_n_per_mm_n, c_n_s_per_m, cost_rmse_pct, converged, n_traces, n_evaluations,
        at_bound, source`` (``at_bound``: parameters on a search bound, comma-joined).
    """
    from graspcampaign.core.identify import at_bound, paper_bounds

    lower, upper = paper_bounds()
    upper = upper.copy()
    upper[0] = lambda1_upper
    sched = schedule.set_index("event_id")
    pools, psis, sources = {}, {}, {}
    for m in [m for m in MATERIALS if m in set(sched["material"])]:
        ids = sched.index[(sched["material"] == m) & (sched["block"] == "normal")]
        g = waveforms[waveforms["event_id"].isin(ids)]
        pool = normal_traces(g, PSO_POINTS_PER_TRACE, min_points=6)
        if pool:
            pools[m] = pool
            psis[m] = bench.specimen_effective_modulus(FAMILIES[m].modulus_mean)
            sources[m] = str(g["source"].iloc[0]) if "source" in g else SOURCE

    def run_all(tasks: list[tuple[str, int]]) -> list[tuple]:
        drawn = [_pso_draw(pools[m], int(seed), m, r, traces_per_run) for m, r in tasks]
        results = _map(_pso_run, [(traces, psis[m], rng, (lower, upper), n_particles,
                                   n_iterations) for (m, _), (traces, rng)
                                  in zip(tasks, drawn, strict=True)], n_jobs)
        return [(res, traces) for res, (traces, _) in zip(results, drawn, strict=True)]

    # runs are independent streams: compute the first n_restarts of every material at once,
    # then re-runs in batches of the shortfall (each new run adds at most one converged run,
    # so no batch runs past the point where the run-by-run rule would stop)
    done = {m: [] for m in pools}
    todo = [(m, r) for m in pools for r in range(n_restarts)]
    limit = n_restarts + max_reruns
    while todo:
        for (m, _), out in zip(todo, run_all(todo), strict=True):
            done[m].append(out)
        todo = []
        for m, outs in done.items():
            if len(outs) >= limit:
                continue
            costs = [_pso_cost(traces, psis[m]) for _, traces in outs]
            short = n_restarts - int(_converged([res for res, _ in outs], costs).sum())
            if short > 0:
                todo += [(m, r) for r in range(len(outs), min(len(outs) + short, limit))]
    rows = []
    for m, outs in done.items():
        runs = [res for res, _ in outs]
        converged = _converged(runs, [_pso_cost(traces, psis[m]) for _, traces in outs])
        for r, res in enumerate(runs):
            lam1, lam2, n, b, k, c = (float(v) for v in res.best_x)
            rows.append({
                "material": m, "run": r + 1, "lambda1": lam1, "lambda2": lam2, "n": n,
                "b": b, "k": k, "c": c,
                "k_n_per_mm_n": float(contact_stiffness_k(lam1, psis[m],
                                                          bench.FINGERTIP_RADIUS)),
                "c_n_s_per_m": float(contact_damping_c(lam2, bench.FINGERTIP_RADIUS)),
                "cost_rmse_pct": res.best_cost,
                "converged": bool(converged[r]),
                "n_traces": min(traces_per_run, len(pools[m])),
                "n_evaluations": res.n_evaluations,
                "at_bound": ",".join(at_bound(res.best_x, lower, upper)),
                "source": sources[m],
            })
    return pd.DataFrame(rows)


