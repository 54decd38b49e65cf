"""Test 1 per-event fits (paper §7.2-7.3): each block's fitted quantities and the review flag of
§7.2 (iii), from file-unit channel arrays -- the one path shared by the virtual bench
(:mod:`graspcampaign.rig.test1_bench`) and measured files (:func:`fit_waveforms`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from graspcampaign.core import bench
from graspcampaign.rig.test1_summary import SOURCE, channels

__all__ = [
    "META_COLUMNS",
    "REVIEW_RMSE_PCT",
    "fit_row",
    "fit_waveforms",
    "order_fit_columns",
]


REVIEW_RMSE_PCT = bench.RMSE_REVIEW_THRESHOLD_PCT


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
            "k_n_per_mm_n": r.k_n_per_mm_n, "n_exp": r.n, "c_n_s_per_m": r.c,
            "c_se_n_s_per_m": r.c_se, "f05_n": r.f05, "rmse_pct": r.rmse_pct,
            "peak_force_n": r.peak_force, "max_depth_mm": r.max_depth * 1e3,
            "loading_work_mj": r.loading_work * 1e3, "unloading_work_mj": r.unloading_work * 1e3,
            "loop_area_mj": (r.loading_work - r.unloading_work) * 1e3,
            "n_fit_points": r.n_points, "fit_ok": r.success,
        })
        if b == "normal":
            sh = bench.fit_shifted(t, x, fn)
            out.update({"shifted_k_n_per_mm_m": sh.k_n_per_mm_m, "shifted_m_exp": sh.m,
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


META_COLUMNS = ("event_id", "material", "specimen", "specimen_id", "environment", "block", "split",
                "surface", "surface_radius_mm", "angle_deg", "speed_mm_per_s", "depth_mm",
                "normal_load_n", "hold_s", "cycle_index")


def fit_row(row: dict, a: dict[str, np.ndarray], attempt: int, anomaly: str) -> dict:
    """One fits row: the schedule row's ``META_COLUMNS``, the attempt and the event's fits."""
    out = {k: row[k] for k in META_COLUMNS}
    out.update(attempt=int(attempt), anomaly=anomaly, source=SOURCE)
    out.update(_fit_arrays(row, a, anomaly))
    return out


def order_fit_columns(fits: pd.DataFrame) -> pd.DataFrame:
    """The fits with ``META_COLUMNS``, attempt, anomaly, source and n_samples first."""
    if fits.empty:
        return fits
    first = [*META_COLUMNS, "attempt", "anomaly", "source", "n_samples"]
    rest = [c for c in fits.columns if c not in first]
    return fits[first + rest].reset_index(drop=True)


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
        fit = fit_row(row, channels(g), attempt, anomaly)
        # a file without a source column comes from a rig: never label it virtual
        fit["source"] = str(g["source"].iloc[0]) if "source" in g else "measured"
        rows.append(fit)
    return order_fit_columns(pd.DataFrame(rows))
