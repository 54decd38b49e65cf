"""Test 1 bench-calibration protocol (paper §7): the commanded-event schedule.

This module holds the schedule (:func:`test1_schedule`, :func:`split_event_ids`) and re-exports the
rest of the protocol, which lives in concept modules:

* :mod:`graspcampaign.rig.test1_protocol` -- groups, blocks, splits, published counts,
  :class:`Test1Protocol`, :func:`event_id_for`, :func:`event_rng`.
* :mod:`graspcampaign.rig.test1_bench` -- :func:`specimen_truths` (the virtual bench's true
  constants) and :func:`run_virtual_bench` / :func:`run_events` (attempts log, per-event fits and
  optionally waveforms; every produced row carries ``source = "virtual"``).
* :mod:`graspcampaign.rig.test1_fits` -- the per-event fits shared by the virtual bench and
  :func:`fit_waveforms` (the same fits from a table).
* :mod:`graspcampaign.rig.test1_ingest` -- :func:`validate_waveforms` / :func:`read_waveforms`
  (ingest checks raising :class:`IngestError`) and :func:`waveform_template`.
* :mod:`graspcampaign.rig.test1_pso` -- :func:`pso_reidentify` (§7.5).
* :mod:`graspcampaign.rig.test1_summary` and :mod:`graspcampaign.analysis.calibration` --
  cross-event summaries: :func:`oblique_summary`, :func:`cyclic_summary`, :func:`damage_depths`,
  :func:`table4`, :func:`table5`.

Public entry points return pandas DataFrames with a unit in every dimensional column.

Waveform table columns: ``event_id, time_s, displacement_mm, normal_force_n,
tangential_force_n, tangential_displacement_mm`` plus optional metadata (``attempt``,
``anomaly``, ``source``).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from graspcampaign.analysis.calibration import MATERIALS, cyclic_summary, oblique_summary, table4, table5
from graspcampaign.core import bench
from graspcampaign.core.bench import FAMILIES
from graspcampaign.rig.ingest import IngestError

# re-exported: they live in graspcampaign.rig.test1_bench
from graspcampaign.rig.test1_bench import (
    MAX_ATTEMPTS,
    VirtualBenchResult,
    run_events,
    run_virtual_bench,
    specimen_truths,
)

# re-exported: they live in graspcampaign.rig.test1_fits
from graspcampaign.rig.test1_fits import REVIEW_RMSE_PCT, fit_waveforms

# re-exported: they live in graspcampaign.rig.test1_ingest
from graspcampaign.rig.test1_ingest import read_waveforms, validate_waveforms, waveform_template

# re-exported: they live in graspcampaign.rig.test1_protocol
from graspcampaign.rig.test1_protocol import (
    BLOCKS,
    ENVIRONMENTS,
    PUBLISHED,
    SCHEDULE_COLUMNS,
    SPLITS,
    Test1Protocol,
    event_id_for,
    event_rng,
    keyed_rng,
)

# re-exported: they live in graspcampaign.rig.test1_pso
from graspcampaign.rig.test1_pso import (
    PSO_CONVERGENCE_FACTOR,
    PSO_LAMBDA1_UPPER,
    PSO_POINTS_PER_TRACE,
    pso_reidentify,
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
    "split_event_ids",
    "test1_schedule",
    "transfer_errors",
    # re-exported: they live in graspcampaign.rig.test1_protocol
    "BLOCKS",
    "ENVIRONMENTS",
    "PUBLISHED",
    "SPLITS",
    "Test1Protocol",
    "event_id_for",
    "event_rng",
    # re-exported: they live in graspcampaign.rig.test1_bench
    "MAX_ATTEMPTS",
    "VirtualBenchResult",
    "run_events",
    "run_virtual_bench",
    "specimen_truths",
    # re-exported: they live in graspcampaign.rig.test1_fits
    "REVIEW_RMSE_PCT",
    "fit_waveforms",
    # re-exported: they live in graspcampaign.rig.test1_ingest
    "read_waveforms",
    "validate_waveforms",
    "waveform_template",
    # re-exported: they live in graspcampaign.rig.test1_pso
    "PSO_CONVERGENCE_FACTOR",
    "PSO_LAMBDA1_UPPER",
    "PSO_POINTS_PER_TRACE",
    "pso_reidentify",
    # re-exported: they live in graspcampaign.rig.test1_summary
    "SOURCE",
    "WAVEFORM_COLUMNS",
    "channels",
    "damage_depths",
    "normal_traces",
    "pso_transfer_errors",
    # re-exported: they live in graspcampaign.analysis.calibration
    "MATERIALS",
    "cyclic_summary",
    "oblique_summary",
    "table4",
    "table5",
    # re-exported: it lives in graspcampaign.rig.ingest
    "IngestError",
]


DAQ_RATES_HZ = (50.0, 100.0, 200.0, 250.0, 500.0)
"""Selectable DAQ rates within the 50-500 Hz of §7.1."""


def _daq_for_press(distance_mm: float, speed_mm_per_s: float, p: Test1Protocol) -> float:
    t_load = bench.trapezoid_duration(distance_mm * 1e-3, speed_mm_per_s * 1e-3,
                                      p.accel_mm_per_s2 * 1e-3)
    for rate in DAQ_RATES_HZ:
        if rate * t_load >= p.min_loading_samples:
            return rate
    return DAQ_RATES_HZ[-1]


def _daq_for_slide(speed_mm_per_s: float, p: Test1Protocol) -> float:
    for rate in DAQ_RATES_HZ:
        if speed_mm_per_s * 1e3 / rate <= p.max_slide_step_um:
            return rate
    return DAQ_RATES_HZ[-1]


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
    rng = keyed_rng(seed, "test1-schedule")
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
    df = df[list(SCHEDULE_COLUMNS)].astype({"specimen": "int64", "cycle_index": "int64", "repeat": "int64",
                          "load_level": "int64", "day": "int64", "session": "int64",
                          "daq_hz": "float64"})
    if df["event_id"].duplicated().any():  # pragma: no cover - guards the id scheme
        raise RuntimeError("duplicate event ids in the Test 1 schedule")
    return df.reset_index(drop=True)


def split_event_ids(schedule: pd.DataFrame) -> dict[str, list[str]]:
    """Return the event ids of every split of §7.6 (``train`` and the five held-out sets)."""
    return {s: schedule.loc[schedule["split"] == s, "event_id"].tolist() for s in SPLITS}


# --------------------------------------------------------------------------- summaries


def transfer_errors(fits: pd.DataFrame, waveforms: pd.DataFrame | None = None,
                    protocol: Test1Protocol | None = None) -> pd.DataFrame:
    """:func:`graspcampaign.rig.test1_summary.transfer_errors` with the protocol's curved
    radius (the flat-to-curved split's specimens)."""
    p = Test1Protocol() if protocol is None else protocol
    return _transfer_errors(fits, waveforms, curved_radius_mm=p.curved_radius_mm)
