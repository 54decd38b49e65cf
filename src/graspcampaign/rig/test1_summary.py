"""Test 1 study-level tables computed by the run's finalize stage (paper §7.4-7.6).

The per-event fits and the protocol's waveforms (regenerated virtual traces or a rig's files) go
in; full-precision DataFrames with a unit in every dimensional column come out: the damage depth
of every fatigued specimen, and the calibrated Eq. 13-14 law evaluated on held-out traces. Like
:func:`graspcampaign.rig.test1.pso_reidentify` they are part of running the protocol; the report
only reads the stored tables (``summary/damage_depth``, ``summary/transfer``,
``summary/pso_transfer``).

Waveform table columns: :data:`WAVEFORM_COLUMNS`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from graspcampaign.analysis.calibration import cyclic_summary
from graspcampaign.core import bench, bench_contact
from graspcampaign.core.bench import FAMILIES
from graspcampaign.core.contact import contact_damping_c, contact_stiffness_k, normal_force

WAVEFORM_COLUMNS = ("event_id", "time_s", "displacement_mm", "normal_force_n",
                    "tangential_force_n", "tangential_displacement_mm")
"""Required columns of a waveform file."""
SOURCE = "virtual"
"""Source label of rows produced without a ``source`` column (the virtual bench)."""
STABILISED_CYCLES = 4
"""Measured cycles at the end of each fatigue level averaged as its stabilised state."""
STIFFNESS_TARGET, SET_LIMIT_MM = 0.85, 0.5
"""Damage criteria: K/K1 below §7.4's durability target, or a permanent set above 0.5 mm (10 % of
the fingertip radius; ours, docs/decisions.md *Test 1 bench protocol (issue 8)*)."""


def damage_depths(fits: pd.DataFrame, *, stiffness_target: float = STIFFNESS_TARGET,
                  set_limit_mm: float = SET_LIMIT_MM) -> pd.DataFrame:
    """Damage-depth threshold of every fatigued specimen (§7.4): :func:`graspcampaign.core.
    bench.damage_depth` on each level's stabilised state (mean of its last measured cycles)."""
    rows = []
    for (m, s, e), g in cyclic_summary(fits).groupby(["material", "specimen", "environment"],
                                                     sort=False):
        st = g.groupby("depth_mm", sort=True).tail(STABILISED_CYCLES).groupby("depth_mm")[
            ["k_ratio", "permanent_set_mm"]].mean()
        r = bench.damage_depth(st.index.to_numpy() * 1e-3, st["k_ratio"].to_numpy(),
                               st["permanent_set_mm"].to_numpy() * 1e-3,
                               stiffness_target, set_limit_mm * 1e-3)
        rows.append({"material": m, "specimen": s, "environment": e,
                     "k_ratio_final": float(st["k_ratio"].iloc[-1]),
                     "permanent_set_final_mm": float(st["permanent_set_mm"].iloc[-1]),
                     "damage_depth_mm": r.depth * 1e3,
                     "damage_depth_softening_mm": r.depth_softening * 1e3,
                     "damage_depth_set_mm": r.depth_set * 1e3, "criterion": r.criterion,
                     "extrapolated": r.extrapolated, "stiffness_target": stiffness_target,
                     "set_limit_mm": set_limit_mm, "source": g["source"].iloc[0]})
    return pd.DataFrame(rows)


def calibration(fits: pd.DataFrame, block: str, columns: list[str]) -> tuple[pd.DataFrame,
                                                                               pd.DataFrame]:
    """Training-split medians per (material, specimen, environment) and per (material,
    environment) (the latter stands in for specimens never seen)."""
    ok = fits[(fits["block"] == block) & (fits["split"] == "train")
              & fits["accepted"].astype(bool)]
    return (ok.groupby(["material", "specimen", "environment"])[columns].median(),
            ok.groupby(["material", "environment"])[columns].median())


def calibrated(row: dict, per_spec: pd.DataFrame, per_family: pd.DataFrame) -> pd.Series:
    """The calibration of ``row``'s specimen, or its family's for an unseen specimen."""
    if row["split"] != "unseen_specimen":
        key = (row["material"], row["specimen"], row["environment"])
        if key in per_spec.index:
            return per_spec.loc[key]
    return per_family.loc[(row["material"], row["environment"])]


def transfer_errors(fits: pd.DataFrame, waveforms: pd.DataFrame | None = None, *,
                    curved_radius_mm: float) -> pd.DataFrame:
    """Transfer error of the training-split calibration on every held-out event (§7.6).

    The calibration is the median of the training fits of the same specimen and environment
    (for ``unseen_specimen``: of the family's training specimens in that environment).

    * normal force (normal events of ``unseen_speed`` / ``unseen_specimen``; needs
      ``waveforms``): RMSE of the calibrated Eq. 13 on the event's loading branch, % of peak;
    * friction (sliding events of ``unseen_speed`` / ``unseen_load`` / ``unseen_specimen``):
      ``|mu_k - mu_k,cal| / mu_k,cal`` in %;
    * relaxation (``extended_relaxation``): ``|rho - rho_cal| / rho_cal`` in %;
    * flat-to-curved (oblique, curved): predicted peak normal force of the flat calibration
      with K scaled by ``sqrt(R_eff / R)`` (Eq. 14) against the measured one, in %.

    Returns
    -------
    pandas.DataFrame
        ``event_id, material, specimen, environment, split, quantity, error_pct, source``;
        training rows are included for the normal and friction quantities as the reference.
    """
    rows = []

    def add(r: dict, quantity: str, err: float) -> None:
        rows.append({"event_id": r["event_id"], "material": r["material"],
                     "specimen": r["specimen"], "environment": r["environment"],
                     "split": r["split"], "quantity": quantity, "error_pct": float(err),
                     "source": r["source"]})

    n_spec, n_fam = calibration(fits, "normal", ["k_n_per_mm_n", "n_exp", "c_n_s_per_m"])
    s_spec, s_fam = calibration(fits, "sliding", ["mu_k"])
    r_spec, r_fam = calibration(fits, "relaxation", ["rho"])
    ok = fits[fits["fit_ok"].astype(bool)]
    for r in ok[ok["block"] == "sliding"].to_dict("records"):
        if r["split"] in ("train", "unseen_speed", "unseen_load", "unseen_specimen"):
            cal = calibrated(r, s_spec, s_fam)["mu_k"]
            add(r, "friction", abs(r["mu_k"] - cal) / cal * 100.0)
    ext = ok[(ok["block"] == "relaxation") & (ok["split"] == "extended_relaxation")]
    for r in ext.to_dict("records"):
        cal = calibrated(r, r_spec, r_fam)["rho"]
        add(r, "relaxation", abs(r["rho"] - cal) / cal * 100.0)
    curved = ok[(ok["block"] == "oblique") & (ok["split"] == "flat_to_curved")]
    for r in curved.to_dict("records"):
        law = calibrated(r, n_spec, n_fam)
        radius = r["surface_radius_mm"] if np.isfinite(r["surface_radius_mm"]) else \
            curved_radius_mm
        scale = bench_contact.curvature_scale(radius * 1e-3)
        pred = scale * law["k_n_per_mm_n"] * r["depth_mm"] ** law["n_exp"]
        add(r, "flat_to_curved", abs(pred - r["peak_normal_force_n"])
            / r["peak_normal_force_n"] * 100.0)
    if waveforms is not None:
        nrm = ok[(ok["block"] == "normal")
                 & ok["split"].isin(["train", "unseen_speed", "unseen_specimen"])]
        nrm = nrm[nrm["event_id"].isin(waveforms["event_id"].unique())].set_index("event_id")
        for eid, g in waveforms[waveforms["event_id"].isin(nrm.index)].groupby("event_id"):
            r = {**nrm.loc[eid].to_dict(), "event_id": eid}
            law = calibrated(r, n_spec, n_fam)
            depth, rate, force, peak = trace_points(channels(g))
            pred = normal_force(depth, rate, law["k_n_per_mm_n"], law["n_exp"],
                                law["c_n_s_per_m"])
            add(r, "normal_force", np.sqrt(np.mean((pred - force) ** 2)) / peak * 100.0)
    return pd.DataFrame(rows)


def channels(g: pd.DataFrame) -> dict[str, np.ndarray]:
    """One event's rows of a waveform table as float channel arrays in file units."""
    return {c: g[c].to_numpy(dtype=float) for c in WAVEFORM_COLUMNS[1:]}


def trace_points(a: dict[str, np.ndarray], n_points: int | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Depth [m], rate [m/s] and force [N] on the Eq. 13 fit window of one normal trace
    (:func:`graspcampaign.core.bench.loading_window`; evenly thinned to at most ``n_points``),
    and the trace's peak force [N]."""
    t = a["time_s"]
    x = a["displacement_mm"] * 1e-3
    f = a["normal_force_n"]
    rate = np.gradient(x, t)
    idx = np.flatnonzero(bench.loading_window(x, f))
    if n_points is not None and idx.size > n_points:
        idx = idx[np.linspace(0, idx.size - 1, n_points).round().astype(int)]
    return x[idx], rate[idx], f[idx], float(f.max())


def normal_traces(waveforms: pd.DataFrame, n_points: int | None = None, min_points: int = 1
                  ) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, float]]:
    """:func:`trace_points` of every event in ``waveforms`` (sorted by event id) that keeps
    at least ``min_points`` points."""
    traces = []
    for _, g in waveforms.groupby("event_id", sort=True):
        tr = trace_points(channels(g), n_points)
        if tr[0].size >= min_points:
            traces.append(tr)
    return traces


def pso_transfer_errors(runs: pd.DataFrame, waveforms: pd.DataFrame, schedule: pd.DataFrame,
                        splits: Sequence[str] = ("unseen_specimen", "unseen_speed")
                        ) -> pd.DataFrame:
    """Normal-force error of every PSO-identified parameter set on held-out traces (§7.5).

    Each run's law (``K = 2 lambda1 Psi sqrt(R)``, ``C = 4 pi R lambda2``, its ``n_exp``; Psi of
    the family's mean modulus, as in :func:`graspcampaign.rig.test1.pso_reidentify`) predicts
    the loading branch of every normal-indentation trace of its material in ``splits``; the
    error of one trace is its RMSE in % of the trace's peak force.

    Returns
    -------
    pandas.DataFrame
        One row per run: ``material, run, converged, n_traces, rmse_mean_pct,
        rmse_median_pct, rmse_max_pct, source``.
    """
    sched = schedule.set_index("event_id")
    rows = []
    for m, g_runs in runs.groupby("material", sort=False):
        ids = sched.index[(sched["material"] == m) & (sched["block"] == "normal")
                          & sched["split"].isin(list(splits))]
        traces = normal_traces(waveforms[waveforms["event_id"].isin(ids)])
        if not traces:
            continue
        psi = bench.specimen_effective_modulus(FAMILIES[m].modulus_mean)
        for r in g_runs.to_dict("records"):
            k = float(contact_stiffness_k(r["lambda1"], psi, bench.FINGERTIP_RADIUS))
            c = float(contact_damping_c(r["lambda2"], bench.FINGERTIP_RADIUS))
            err = np.array([np.sqrt(np.mean((normal_force(d, v, k, r["n_exp"], c) - f) ** 2))
                            / peak * 100.0 for d, v, f, peak in traces])
            rows.append({"material": m, "run": int(r["run"]), "converged": bool(r["converged"]),
                         "n_traces": len(traces), "rmse_mean_pct": float(err.mean()),
                         "rmse_median_pct": float(np.median(err)),
                         "rmse_max_pct": float(err.max()), "source": r.get("source", SOURCE)})
    return pd.DataFrame(rows)
