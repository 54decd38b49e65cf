"""Test 1 virtual bench (paper §7.1): the true specimen constants, the command of each planned
event, and the run of schedule rows -- simulate, abort and re-run, fit.

Every attempt draws from :func:`graspcampaign.rig.test1_protocol.event_rng`; every produced row
carries ``source = "virtual"``. The per-event fits are :mod:`graspcampaign.rig.test1_fits` (the
path shared with the ingest of measured files).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from functools import lru_cache

import numpy as np
import pandas as pd

from graspcampaign.analysis.calibration import MATERIALS
from graspcampaign.core import bench
from graspcampaign.core.bench import FAMILIES, EventCommand, SensorParams, SpreadParams
from graspcampaign.rig.test1_fits import fit_row, order_fit_columns
from graspcampaign.rig.test1_protocol import ENVIRONMENTS, Test1Protocol, event_rng, keyed_rng
from graspcampaign.rig.test1_summary import SOURCE, WAVEFORM_COLUMNS

__all__ = [
    "MAX_ATTEMPTS",
    "VirtualBenchResult",
    "event_command",
    "run_events",
    "run_virtual_bench",
    "specimen_params",
    "specimen_truths",
    "waveform_arrays",
]


# ------------------------------------------------------------------------ truths


@lru_cache(maxsize=4096)
def specimen_params(seed: int, material: str, specimen: int, environment: str,
                    spread: SpreadParams) -> bench.SpecimenParams:
    """The drawn constants of one specimen in one environment (the same for every event on it)."""
    rng = keyed_rng(seed, "specimen", material, str(specimen))
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
        ``material, specimen, environment, modulus_kpa, k_n_per_mm_n, n_exp,
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
        t = specimen_params(int(seed), m, int(s), e, sp)
        dd = bench.true_damage_depth(t)
        rows.append({
            "material": m, "specimen": int(s), "environment": e,
            "modulus_kpa": t.modulus / 1e3, "k_n_per_mm_n": t.k_n_per_mm_n,
            "n_exp": t.n, "c_n_s_per_m": t.c, "f05_n": t.f05, "mu_s": t.mu_s,
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
    spec = specimen_params(seed, material, specimen, environment, spread)
    return bench.cyclic_state(spec, p.cyclic_depths_mm() * 1e-3)


def event_command(row: dict, seed: int, spread: SpreadParams, p: Test1Protocol) -> EventCommand:
    """The bench command of one schedule row (SI units; cyclic rows carry the specimen's state)."""
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


def waveform_arrays(w: bench.Waveform) -> dict[str, np.ndarray]:
    """Waveform channels in file units, quantised exactly as the sensors resolve them."""
    return {
        "time_s": np.round(w.time, 9),
        "displacement_mm": np.round(w.displacement * 1e6) / 1e3,
        "normal_force_n": np.round(w.normal_force * 1e3) / 1e3,
        "tangential_force_n": np.round(w.tangential_force * 1e3) / 1e3,
        "tangential_displacement_mm": np.round(w.tangential_displacement * 1e6) / 1e3,
    }


# ---------------------------------------------------------------------- virtual bench

MAX_ATTEMPTS = 5


def _run_rows(rows: list[dict], seed: int, spread: SpreadParams, sensor: SensorParams,
              p: Test1Protocol, keep: bool, fit: bool = True
              ) -> tuple[list[dict], list[dict], list[dict]]:
    attempts, fits, waves = [], [], []
    for row in rows:
        spec = specimen_params(seed, row["material"], int(row["specimen"]), row["environment"],
                               spread)
        cmd = event_command(row, seed, spread, p)
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
            a = waveform_arrays(w)
            if fit:
                fits.append(fit_row(row, a, attempt, w.anomaly))
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
    # the per-event text is repeated by index into a string array (pyarrow take): repeating
    # Python strings as a numpy unicode array and converting that took 2.5 s per 3 M samples
    wave_of_sample = np.repeat(np.arange(len(waves)), lens)
    df = pd.DataFrame({
        "event_id": pd.array([w["event_id"] for w in waves], dtype="str").take(wave_of_sample),
        **{c: np.concatenate([w[c] for w in waves]) for c in WAVEFORM_COLUMNS[1:]},
        "attempt": np.repeat([w["attempt"] for w in waves], lens).astype("int64"),
        "anomaly": pd.array([w["anomaly"] for w in waves], dtype="str").take(wave_of_sample),
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
    return VirtualBenchResult(attempts=attempts, fits=order_fit_columns(fits),
                              waveforms=waves, truths=specimen_truths(seed, schedule, spread=sp),
                              meta={"seed": int(seed), "source": SOURCE,
                                    "n_events": len(rows)})
