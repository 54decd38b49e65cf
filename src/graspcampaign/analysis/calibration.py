"""Test 1 bench calibration summaries (paper §7; Tables 4-5, Figs. 23-26): fits -> tables.

Every function takes the per-event fits (:func:`graspcampaign.rig.test1.fit_waveforms` or the
virtual bench), the waveform table or the PSO run log, and returns a DataFrame at full
precision with a unit in every dimensional column. Nothing here fits a model except the closed
forms it names (damage depth, Eq. 13-14 predictions of a calibrated law).

Waveform table columns: :data:`WAVEFORM_COLUMNS`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from graspcampaign.core import bench
from graspcampaign.core.bench import FAMILIES
from graspcampaign.core.contact import contact_damping_c, contact_stiffness_k, normal_force

MATERIALS = tuple(FAMILIES)
"""Material families in Table 4 order."""
WAVEFORM_COLUMNS = ("event_id", "time_s", "displacement_mm", "normal_force_n",
                    "tangential_force_n", "tangential_displacement_mm")
"""Required columns of a waveform file."""
SOURCE = "virtual"
"""Source label of rows produced without a ``source`` column (the virtual bench)."""


def oblique_summary(fits: pd.DataFrame) -> pd.DataFrame:
    """Slip margin and Coulomb stick/slip classification of every oblique event (§7.3).

    The calibrated ``mu_s`` of each specimen and environment is the median breakaway
    coefficient of its sliding events; the margin is ``mu_s f_n - f_t`` at the dwell; the
    Coulomb criterion predicts slip when ``tan(angle) > mu_s``.

    Returns
    -------
    pandas.DataFrame
        Oblique rows of ``fits`` plus ``mu_s_calibrated``, ``margin_n``,
        ``predicted_slip``, ``margin_negative``, ``classification_matches_margin``,
        ``classification_matches_measured``.
    """
    key = ["material", "specimen", "environment"]
    mu = (fits[fits["block"] == "sliding"].groupby(key)["mu_s"].median()
          .rename("mu_s_calibrated"))
    ob = fits[fits["block"] == "oblique"].join(mu, on=key)
    ob["margin_n"] = bench.slip_margin(ob["mu_s_calibrated"], ob["peak_normal_force_n"],
                                       ob["peak_tangential_force_n"])
    ob["predicted_slip"] = np.tan(np.radians(ob["angle_deg"])) > ob["mu_s_calibrated"]
    ob["margin_negative"] = ob["margin_n"] < 0
    ob["classification_matches_margin"] = ob["predicted_slip"] == ob["margin_negative"]
    ob["classification_matches_measured"] = (ob["predicted_slip"]
                                             == ob["slipped_measured"].astype(bool))
    return ob.reset_index(drop=True)


STABILISED_CYCLES = 4
"""Measured cycles at the end of each level averaged as its stabilised state."""


def cyclic_summary(fits: pd.DataFrame) -> pd.DataFrame:
    """Relative stiffness K/K_1 and permanent set of every measured fatigue cycle (§7.4).

    ``K/K_1`` is the ratio of the cycle's ``f05`` to cycle 1's (unit-clean, Table 4), the
    permanent set the shift of the cycle's contact onset (shifted-law ``delta_0``) from
    cycle 1's.
    """
    cy = fits[fits["block"] == "cyclic"].sort_values(["material", "specimen", "cycle_index"])
    key = ["material", "specimen", "environment"]
    first = cy.groupby(key)[["f05_n", "onset_mm"]].transform("first")
    cy = cy.assign(k_ratio=cy["f05_n"] / first["f05_n"],
                   permanent_set_mm=cy["onset_mm"] - first["onset_mm"])
    return cy.reset_index(drop=True)


def damage_depths(fits: pd.DataFrame, *, stiffness_target: float = 0.85,
                  set_limit_mm: float = 0.5) -> pd.DataFrame:
    """Damage-depth threshold of every fatigued specimen (§7.4), via
    :func:`graspcampaign.core.bench.damage_depth` on each level's stabilised state."""
    cy = cyclic_summary(fits)
    rows = []
    for (m, s, e), g in cy.groupby(["material", "specimen", "environment"], sort=False):
        lv = g.groupby("depth_mm", sort=True).tail(STABILISED_CYCLES).groupby("depth_mm")
        st = lv[["k_ratio", "permanent_set_mm"]].mean()
        r = bench.damage_depth(st.index.to_numpy() * 1e-3, st["k_ratio"].to_numpy(),
                               st["permanent_set_mm"].to_numpy() * 1e-3,
                               stiffness_target, set_limit_mm * 1e-3)
        rows.append({"material": m, "specimen": s, "environment": e,
                     "k_ratio_final": float(st["k_ratio"].iloc[-1]),
                     "permanent_set_final_mm": float(st["permanent_set_mm"].iloc[-1]),
                     "damage_depth_mm": r.depth * 1e3,
                     "damage_depth_softening_mm": r.depth_softening * 1e3,
                     "damage_depth_set_mm": r.depth_set * 1e3, "criterion": r.criterion,
                     "extrapolated": r.extrapolated, "source": g["source"].iloc[0]})
    return pd.DataFrame(rows)


def table4(fits: pd.DataFrame, truths: pd.DataFrame | None = None) -> pd.DataFrame:
    """Per-family means in the layout of Table 4 (accepted normal fits; other blocks'
    successful fits).

    ``E`` comes from ``truths`` (virtual bench) when given: the bench measures no modulus.
    """
    fits = fits[fits["fit_ok"].astype(bool)]
    nf = fits[(fits["block"] == "normal") & fits["accepted"].astype(bool)]
    g = nf.groupby("material")
    out = pd.DataFrame({
        "exponent_n": g["exponent_n"].mean(), "k_n_per_mm_n": g["k_n_per_mm_n"].mean(),
        "f05_n": g["f05_n"].mean(), "c_n_s_per_m": g["c_n_s_per_m"].mean()})
    sl = fits[fits["block"] == "sliding"].groupby("material")
    out["mu_s"] = sl["mu_s"].mean()
    out["mu_k"] = sl["mu_k"].mean()
    out["k_t_n_per_mm"] = sl["k_t_n_per_mm"].mean()
    rl = fits[fits["block"] == "relaxation"].groupby("material")
    out["rho"] = rl["rho"].mean()
    out["tau_s"] = rl["tau_s"].mean()
    if truths is not None:
        spec = truths.drop_duplicates(["material", "specimen"]).groupby("material")
        out.insert(0, "modulus_sd_kpa", spec["modulus_kpa"].std())
        out.insert(0, "modulus_mean_kpa", spec["modulus_kpa"].mean())
    order = [m for m in MATERIALS if m in out.index]
    return out.loc[order].reset_index()


def calibration(fits: pd.DataFrame, block: str, columns: list[str]) -> tuple[pd.DataFrame,
                                                                               pd.DataFrame]:
    """Training-split medians per (material, specimen, environment) and per (material,
    environment) (the latter stands in for specimens never seen)."""
    ok = fits[(fits["block"] == block) & (fits["split"] == "train")
              & fits["accepted"].astype(bool)]
    return (ok.groupby(["material", "specimen", "environment"])[columns].median(),
            ok.groupby(["material", "environment"])[columns].median())


def calibrated(row: dict, per_spec: pd.DataFrame, per_family: pd.DataFrame) -> pd.Series:
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

    n_spec, n_fam = calibration(fits, "normal", ["k_n_per_mm_n", "exponent_n", "c_n_s_per_m"])
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
        scale = bench._curvature_scale(radius * 1e-3)
        pred = scale * law["k_n_per_mm_n"] * r["depth_mm"] ** law["exponent_n"]
        add(r, "flat_to_curved", abs(pred - r["peak_normal_force_n"])
            / r["peak_normal_force_n"] * 100.0)
    if waveforms is not None:
        nrm = ok[(ok["block"] == "normal")
                 & ok["split"].isin(["train", "unseen_speed", "unseen_specimen"])]
        nrm = nrm[nrm["event_id"].isin(set(waveforms["event_id"]))].set_index("event_id")
        for eid, g in waveforms[waveforms["event_id"].isin(nrm.index)].groupby("event_id"):
            r = {**nrm.loc[eid].to_dict(), "event_id": eid}
            law = calibrated(r, n_spec, n_fam)
            depth, rate, force, peak = trace_points(channels(g))
            pred = normal_force(depth, rate, law["k_n_per_mm_n"], law["exponent_n"],
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

    Each run's law (``K = 2 lambda1 Psi sqrt(R)``, ``C = 4 pi R lambda2``, its ``n``; Psi of
    the family's mean modulus, as in :func:`pso_reidentify`) predicts the loading branch of
    every normal-indentation trace of its material in ``splits``; the error of one trace is
    its RMSE in % of the trace's peak force.

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
            err = np.array([np.sqrt(np.mean((normal_force(d, v, k, r["n"], c) - f) ** 2))
                            / peak * 100.0 for d, v, f, peak in traces])
            rows.append({"material": m, "run": int(r["run"]), "converged": bool(r["converged"]),
                         "n_traces": len(traces), "rmse_mean_pct": float(err.mean()),
                         "rmse_median_pct": float(np.median(err)),
                         "rmse_max_pct": float(err.max()), "source": r.get("source", SOURCE)})
    return pd.DataFrame(rows)


def table5(runs: pd.DataFrame) -> pd.DataFrame:
    """Mean, SD and CV (%) of each identified parameter over the converged runs (Table 5)."""
    ok = runs[runs["converged"].astype(bool)]
    out = []
    for p_ in ("lambda1", "lambda2", "n", "b", "k", "c"):
        mean, sd = float(ok[p_].mean()), float(ok[p_].std(ddof=1))
        out.append({"parameter": p_, "mean": mean, "sd": sd,
                    "cv_pct": 100.0 * sd / mean if mean else math.nan,
                    "n_runs": int(len(ok))})
    return pd.DataFrame(out)
