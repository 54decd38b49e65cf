"""Report of ``sensitivity`` (Sec. 6.6, Fig. 19): success over three parameter planes."""

from __future__ import annotations

import math

import matplotlib as mpl
import numpy as np
import pandas as pd
from matplotlib.lines import Line2D

from graspcampaign.analysis.records import Estimate, at_bound, rate
from graspcampaign.report import style
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Claims, Figure, Finding, GateRemoved, Rate, ReportSpec, Table, Value

PANELS = {"mu_mass": ("mu", "mass_kg", "friction coefficient μ [–]", "object mass m [kg]"),
          "lambda": ("lambda1", "lambda2", "λ1 [–]", "λ2 [–]"),
          "n_b": ("n_exp", "b_n_s_per_m", "contact exponent n [–]", "nodal damping b [internal units]")}
EPS = 1e-9  # level comparisons of float factors
#: how a heatmap aggregates its cells: aggregation, scale, colour-scale top (None: the largest), cell text
CELLS = {"rate": ("mean", 100.0, 100.0, "{:.0f}"), "median": ("median", 1.0, None, "{:.1f}"),
         "log": ("median", 1.0, None, "{:.0e}")}


def panel_rows(run: Run, name: str) -> pd.DataFrame:
    return run.ok[run.ok["panel"] == name] if "panel" in run.ok else run.ok.iloc[:0]


def rate_cols(g: pd.DataFrame, outcome: str, prefix: str) -> dict:
    """``<prefix>_pct`` and its Wilson 95 % ``<prefix>_low_pct``/``_high_pct`` of ``outcome`` in ``g``."""
    e = rate(g, outcome=outcome)
    return {f"{prefix}_pct": e.value, f"{prefix}_low_pct": e.low, f"{prefix}_high_pct": e.high}


def _edges(levels) -> np.ndarray:
    v = np.asarray(levels, dtype=float)
    if v.size == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def heatmap(ax, fig, run: Run, panel: str, value: str, label: str, cmap: str = "RdYlGn",
            cells: str = "rate") -> None:
    """``value`` per cell of ``panel`` (:data:`CELLS`) at the factors' true axis values; non-finite cells
    blank and marked n/a."""
    (x, y, xl, yl), (how, scale, vmax, text) = PANELS[panel], CELLS[cells]
    part = panel_rows(run, panel)
    g = scale * part.assign(**{value: part[value].astype(float)}).pivot_table(
        index=y, columns=x, values=value, aggfunc=how).sort_index().sort_index(axis=1)
    ax.set(xlabel=xl, ylabel=yl)
    values = g.to_numpy(dtype=float)
    finite = values[np.isfinite(values) & ((values > 0) if cells == "log" else True)]
    if not finite.size:  # the panel says why instead of failing the figure
        ax.text(0.5, 0.5, f"not drawn: no finite value of\n{label}", ha="center", va="center",
                transform=ax.transAxes)
        return
    xs, ys = g.columns.to_numpy(float), g.index.to_numpy(float)
    norm = mpl.colors.LogNorm(finite.min(), max(finite.max(), 10 * finite.min())) if cells == "log" else \
        mpl.colors.Normalize(0.0, vmax if vmax is not None else finite.max())
    mesh = ax.pcolormesh(_edges(xs), _edges(ys), np.ma.masked_invalid(values), cmap=cmap, norm=norm)
    for (r, c), v in np.ndenumerate(values) if values.size <= 225 else ():
        ax.text(xs[c], ys[r], text.format(v) if math.isfinite(v) else "n/a", ha="center", va="center",
                fontsize=5.5)
    ax.grid(False)
    fig.colorbar(mesh, ax=ax, label=label, shrink=0.85)


def _panels(run: Run) -> pd.DataFrame:
    rows = []
    for panel in [k for k in PANELS if len(panel_rows(run, k))]:
        g, (x, y) = panel_rows(run, panel), PANELS[panel][:2]
        rows.append({"panel": panel, "cells": g.groupby([x, y]).ngroups, "trials": len(g),
                     "loop_at_n_max_pct": 100 * g["loop_capped"].mean(),
                     "delta_max_median_mm": g["delta_max_mm"].median(),
                     "runtime_median_ms": g["runtime_ms"].median(), **rate_cols(g, "success", "success"),
                     **rate_cols(g, "success_vertical", "vertical")})
    return pd.DataFrame(rows)


def _figure(run: Run, fig) -> None:
    p, panels = run.paper, [k for k in PANELS if len(panel_rows(run, k))]
    for ax, panel in zip(np.atleast_1d(fig.subplots(1, len(panels))), panels, strict=True):
        xl, yl = PANELS[panel][2:]
        tag, handles = "abc"[list(PANELS).index(panel)], []
        if panel == "n_b":
            heatmap(ax, fig, run, panel, "runtime_ms", "median runtime [ms]", "viridis", "median")
            ax.set_title(f"({tag}) runtime, n × b (paper: flat)")
        else:
            heatmap(ax, fig, run, panel, "success", "success rate [%]")
            ax.set_title(f"({tag}) success, {xl.split(' [')[0]} × {yl.split(' [')[0]}")
        if panel == "mu_mass":
            ax.plot([p.stable_mu_min, p.stable_mu_min, ax.get_xlim()[1]],
                    [ax.get_ylim()[0], p.stable_mass_max_kg, p.stable_mass_max_kg], color=style.PAPER,
                    linewidth=2, linestyle="--")
            handles.append(Line2D([], [], color=style.PAPER, linestyle="--", label=f"paper: stable for "
                                  f"μ ≥ {p.stable_mu_min}, m ≤ {p.stable_mass_max_kg}"))
        elif panel == "lambda":
            for value, ls, words in ((p.lambda1_stable_below, "--", "stable for λ1 ≲"),
                                     (p.nonconvergence_strip_lambda1_from, ":", "non-convergence for λ1 ≥")):
                ax.axvline(value, color=style.PAPER, linestyle=ls, linewidth=2)
                handles.append(Line2D([], [], color=style.PAPER, linestyle=ls,
                                      label=f"paper: {words} {value}"))
        if handles:
            style.legend_below(ax, handles, ncol=1)


SUPPLEMENT = (("mu_mass", "success_vertical", "success, |R_z| reading [%]", "RdYlGn", "rate"),
              ("lambda", "loop_capped", "loop still moving at N_max [%]", "magma_r", "rate"),
              ("lambda", "delta_max_mm", "median δ_max [mm] (log)", "cividis", "log"),
              ("n_b", "success_vertical", "success, |R_z| reading, n × b [%]", "RdYlGn", "rate"))


def _supplement(run: Run, fig) -> None:
    tiles = [t for t in SUPPLEMENT if len(panel_rows(run, t[0]))]
    axes = np.atleast_1d(fig.subplots(math.ceil(len(tiles) / 2), 2)).ravel()
    for ax, tile in zip(axes, tiles, strict=False):
        heatmap(ax, fig, run, *tile)
        ax.set_title(tile[2])
    for ax in axes[len(tiles):]:
        ax.set_visible(False)


def finding(run: Run) -> str:
    (a, b, c), p, text = (panel_rows(run, k) for k in PANELS), run.paper, []
    if len(a):
        by_mu, by_m = a.groupby("mu")["success"].mean(), a.groupby("mass_kg")["success"].mean()
        text.append(f"(a) Our success varies with mass ({100 * by_m.iloc[0]:.0f}% at {by_m.index[0]:g} "
                    f"kg, {100 * by_m.iloc[-1]:.0f}% at {by_m.index[-1]:g} kg) and hardly with friction "
                    f"(per-μ rates {100 * by_mu.min():.0f}–{100 * by_mu.max():.0f}%): Algorithm 2 releases "
                    "contacts until the remaining normals carry the weight (η ≈ 0), so the slip check rarely "
                    f"binds and the paper's μ ≥ {p.stable_mu_min} boundary does not appear.")
    if len(b):
        text.append("(b) λ2 scales only the damping C, whose rate term vanishes in the static loop, and "
                    "Algorithm 2 is invariant to a common scale of K except through the 0.5 mm seed: λ1 "
                    f"moves the penetration (median δ_max {b['delta_max_mm'].median():.3g} mm) but barely "
                    f"the verdict ({100 * b['success'].mean():.0f}% over the panel); no λ1 ≈ "
                    f"{p.lambda1_stable_below} boundary and no non-convergence strip appear.")
    if len(c):
        text.append("(c) b is an MSD constant the quasi-static evaluator never reads, so the b axis is flat "
                    "by construction.")
    return " ".join(text) + (" (`docs/decisions.md`, *Sensitivity, mesh resolution, surrogate (issue 7)*; "
                             "SPEC §8.)")


def _where(panel: str, part=None, holds: bool = True):
    """Executed trials of ``panel`` where ``part(ok, paper)`` holds (or not; a mask over ``run.ok``)."""
    return lambda run: (run.ok["panel"] == panel) & ((part(run.ok, run.paper) == holds) if part else True)


def _inside(ok, p) -> pd.Series:  # the paper's stable region of panel a
    return (ok["mu"] >= p.stable_mu_min - EPS) & (ok["mass_kg"] <= p.stable_mass_max_kg + EPS)


def _below(ok, p) -> pd.Series:  # panel b below the paper's λ1 boundary
    return ok["lambda1"] <= p.lambda1_stable_below + EPS


def _strip(ok, p) -> pd.Series:  # panel b inside the paper's non-convergence strip
    return ok["lambda1"] >= p.nonconvergence_strip_lambda1_from - EPS


def _identified(low_mu: bool, what: str):
    """The median identified λ1 of panel a's trials at μ < 0.1 (or ≥), or the share on a PSO bound."""
    def value(run: Run) -> Estimate:
        part = run.ok[_where("mu_mass", lambda ok, p: (ok["mu"] < 0.1 - EPS) == low_mu)(run)]
        if not len(part):
            raise ValueError("no trial in this part of the panel")
        if what == "bound":
            return rate(part.assign(on_bound=at_bound(part, "lambda1")), outcome="on_bound")
        return Estimate(float(part["contact_lambda1"].median()), n=len(part))
    return value


def _runtime_ratio(axis: str):
    def value(run: Run) -> float:
        med = panel_rows(run, "n_b").groupby(axis)["runtime_ms"].median()
        return float(med.max() / med.min())
    return value


SPEC = ReportSpec("sensitivity", [
    Finding(finding),
    Table("sensitivity_panels", "Sensitivity panels: success under both residual readings (vertical: the "
          "|R_z| reading; Wilson 95%), trials whose Algorithm 2 was still moving at N_max, median "
          "penetration and runtime per evaluation",
          _panels, ["panel", "cells", "trials", "success_pct", "vertical_pct", "loop_at_n_max_pct",
                    "delta_max_median_mm", "runtime_median_ms"]),
    Figure("fig19_sensitivity", "Fig. 19 (ours): (a) success over μ × m with the paper's stable region "
           "(dashed); (b) success over λ1 × λ2 with the paper's λ1 boundary (dashed) and non-convergence "
           "strip (dotted); (c) median runtime over n × b; per-cell values", _figure, (15.0, 4.9)),
    Figure("fig19_supplement", "Beyond Fig. 19: the |R_z| reading over μ × m and n × b; trials still moving "
           "at N_max and median penetration over λ1 × λ2", _supplement, (10.0, 8.6)),
    Claims("sensitivity_claims", "The paper's Fig. 19 statements (in words) beside the matching counts of "
           "ours; rates over executed trials with Wilson 95%", [
               Rate("(a) stable region: success inside it", "Fig. 19a", _where("mu_mass", _inside)),
               Rate("(a) stable region: success outside it", "Fig. 19a", _where("mu_mass", _inside, False)),
               Rate("(a) stable region: |R_z| reading inside it", "Fig. 19a", _where("mu_mass", _inside),
                    outcome="success_vertical"),
               Rate("(a) sharp drop above the mass limit when μ < the friction limit", "Sec. 6.6",
                    _where("mu_mass", lambda ok, p: (ok["mu"] < p.stable_mu_min - EPS)
                           & (ok["mass_kg"] > p.stable_mass_max_kg + EPS))),
               Value("(a) median identified λ1 at μ < 0.1 (the paper: pushed to its bound)", "Sec. 6.6",
                     _identified(True, "median"), digits=3),
               Value("(a) identified λ1 on its PSO search bound at μ < 0.1", "Sec. 6.6",
                     _identified(True, "bound"), unit="%", digits=1),
               Value("(a) median identified λ1 at μ ≥ 0.1", "Sec. 6.6", _identified(False, "median"),
                     digits=3),
               Value("(a) identified λ1 on its PSO search bound at μ ≥ 0.1", "Sec. 6.6",
                     _identified(False, "bound"), unit="%", digits=1),
               Rate("(b) stable for λ1 below the paper's boundary: success there", "Fig. 19b",
                    _where("lambda", _below)),
               Rate("(b) success above the boundary", "Fig. 19b", _where("lambda", _below, False)),
               Rate("(b) non-convergence strip: loop still moving at N_max inside it", "Sec. 10",
                    _where("lambda", _strip), outcome="loop_capped"),
               Rate("(b) loop still moving at N_max outside the strip", "Sec. 10",
                    _where("lambda", _strip, False), outcome="loop_capped"),
               Value("(c) runtime max/min over n levels (the paper: nearly flat)", "Fig. 19c",
                     _runtime_ratio("n_exp"), digits=2),
               Value("(c) runtime max/min over b levels", "Fig. 19c", _runtime_ratio("b_n_s_per_m"),
                     digits=2)]),
    GateRemoved(["panel"]),
])
