"""Report figures in the paper's style: one function per figure, each returning a Figure.

Every function takes tidy, already-summarised DataFrames (the report sections compute them from
the records) and returns a :class:`matplotlib.figure.Figure` built without pyplot, so nothing here
needs a display or touches global figure state (headless by construction; the Agg canvas renders
the PNG). Axes carry units, every figure has a legend, and the paper's value is drawn as a black
marker or line wherever the paper gives one.

Column conventions: rates in percent (``ours_pct``, ``wilson_low_pct``, ``wilson_high_pct``,
``paper_pct``), as produced by :func:`graspcampaign.report.table.rate_table`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping, Sequence

import matplotlib as mpl
import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle

PAPER_RC = {
    "font.size": 9, "axes.titlesize": 10, "axes.labelsize": 9, "legend.fontsize": 8,
    "xtick.labelsize": 8, "ytick.labelsize": 8, "axes.grid": True, "grid.alpha": 0.3,
    "grid.linewidth": 0.6, "axes.spines.top": False, "axes.spines.right": False,
    "legend.frameon": False, "lines.linewidth": 1.5, "errorbar.capsize": 3,
}
SUCCESS_COLOUR = "#2e7d32"
FAILURE_COLOUR = "#c62828"
PAPER_COLOUR = "black"
PROPOSED = "heuristic"
PLANNER_COLOURS = {
    "heuristic": "#1f5aa6", "no_pso": "#6a8fc7", "antipodal": "#e08a1e", "random": "#8c8c8c",
    "centroid": "#b5b5b5", "force_balance": "#7b4ea3", "no_s1": "#5b84c4", "no_s2": "#6f93cc",
    "no_s3": "#83a2d4", "no_pc": "#97b1dc", "no_pe": "#abc0e4",
}
PLANNER_LABELS = {
    "heuristic": "full H(G)", "no_s1": "\u2212S1", "no_s2": "\u2212S2", "no_s3": "\u2212S3",
    "no_pc": "\u2212Pc", "no_pe": "\u2212Pe", "random": "random", "centroid": "centroid",
    "antipodal": "antipodal", "no_pso": "no PSO", "force_balance": "force balance",
}
MU_COLOURS = ("#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02")


def paper_style(func: Callable[..., Figure]) -> Callable[..., Figure]:
    """Build the figure under the report's rcParams (fonts, grid, spines)."""
    @functools.wraps(func)
    def wrapper(*args, **kwargs) -> Figure:
        with mpl.rc_context(PAPER_RC):
            return func(*args, **kwargs)
    return wrapper


def _label(planner: str) -> str:
    return PLANNER_LABELS.get(planner, str(planner))


def _colour(planner: str, i: int = 0) -> str:
    return PLANNER_COLOURS.get(planner, MU_COLOURS[i % len(MU_COLOURS)])


def _rate_bars(ax, x: np.ndarray, rates: pd.DataFrame, width: float, colours: Sequence[str],
               label: str | None = None) -> None:
    """Bars of ``ours_pct`` with asymmetric Wilson error bars."""
    ours = rates["ours_pct"].to_numpy(dtype=float)
    low = rates["wilson_low_pct"].to_numpy(dtype=float)
    high = rates["wilson_high_pct"].to_numpy(dtype=float)
    err = np.vstack([np.nan_to_num(ours - low), np.nan_to_num(high - ours)])
    ax.bar(x, np.nan_to_num(ours), width, color=colours, edgecolor="white", label=label,
           yerr=err, ecolor="#333333", error_kw={"elinewidth": 1.0})


def _ticks_with_n(rates: pd.DataFrame) -> list[str]:
    return [f"{_label(p)}\nn={n}" for p, n in zip(rates["planner"], rates["n"], strict=True)]


def _paper_marks(ax, x: np.ndarray, paper_pct: Sequence, width: float) -> bool:
    """Draw the paper's values as black bars across the bar; return whether any was drawn."""
    drawn = False
    for xi, p in zip(x, paper_pct, strict=True):
        if p is None or (isinstance(p, float) and math.isnan(p)):
            continue
        ax.hlines(float(p), xi - width * 0.45, xi + width * 0.45, colors=PAPER_COLOUR,
                  linewidth=2.2, zorder=5)
        ax.plot([xi], [float(p)], marker="D", color=PAPER_COLOUR, markersize=3.5, zorder=6)
        drawn = True
    return drawn


def _paper_handle() -> Line2D:
    return Line2D([], [], color=PAPER_COLOUR, marker="D", markersize=3.5, linewidth=2.2,
                  label="paper's value")


# --------------------------------------------------------------------------------------------
# Fig. 15: per-shape grasp metrics
# --------------------------------------------------------------------------------------------


@paper_style
def fig15_shape_metrics(per_shape: pd.DataFrame, h_range: Sequence[float] | None = None,
                        residual_limit_n: float = 0.5) -> Figure:
    """Fig. 15: H(G), force residual, torque and slip margin per shape, coloured by success.

    ``per_shape`` columns: ``shape``, ``h_total``, ``residual_norm_n``, ``torque_norm_nm``,
    ``slip_margin_n`` (medians over the shape's trials), ``success_rate`` in [0, 1], ``n`` and
    ``paper_success`` (True/False/None).
    """
    fig = Figure(figsize=(9.0, 6.6), layout="constrained")
    axes = fig.subplots(2, 2).ravel()
    x = np.arange(len(per_shape))
    colours = [SUCCESS_COLOUR if r >= 0.5 else FAILURE_COLOUR for r in per_shape["success_rate"]]
    ticks = []
    checks = per_shape["failure_check"] if "failure_check" in per_shape else [""] * len(x)
    for (shape, paper, rate, n), check in zip(
            per_shape[["shape", "paper_success", "success_rate", "n"]].itertuples(index=False),
            checks, strict=True):
        first = str(check).split(" ")[0] if isinstance(check, str) and check else ""
        ours = f"{int(round(rate * n))}/{n}" if n > 1 else (
            "ok" if rate >= 0.5 else f"fail ({first})" if first else "fail")
        paper_txt = "" if paper is None or pd.isna(paper) else \
            ("\npaper: ok" if paper else "\npaper: fail")
        ticks.append(f"{shape.replace('_', chr(10))}\nours: {ours}{paper_txt}")
    panels = [
        ("h_total", "(a) heuristic H(G) [\u2013]", None),
        ("residual_norm_n", "(b) force residual \u2016R\u2016 [N]", residual_limit_n),
        ("torque_norm_nm", "(c) torque residual \u2016\u03c4\u2016 [N\u00b7m]", None),
        ("slip_margin_n", "(d) slip margin [N]", 0.0),
    ]
    for ax, (col, title, line) in zip(axes, panels, strict=True):
        values = per_shape[col].to_numpy(dtype=float) if col in per_shape else np.full(len(x), np.nan)
        ax.bar(x, np.nan_to_num(values), 0.7, color=colours)
        ax.set_title(title, loc="left")
        ax.set_xticks(x, ticks, fontsize=7)
        if line is not None:
            ax.axhline(line, color="#333333", linestyle="--", linewidth=1.0)
    if h_range is not None:
        axes[0].axhspan(h_range[0], h_range[1], color=PAPER_COLOUR, alpha=0.12, zorder=0)
    for ax in axes[::2]:
        ax.set_ylabel("chosen grasp, median over trials")
    handles = [Patch(color=SUCCESS_COLOUR, label="success (all checks pass)"),
               Patch(color=FAILURE_COLOUR, label="failure"),
               Line2D([], [], color="#333333", linestyle="--",
                      label=f"criterion: \u2016R\u2016 < {residual_limit_n} N; slip margin > 0")]
    if h_range is not None:
        handles.append(Patch(color=PAPER_COLOUR, alpha=0.12,
                             label=f"paper's H range {h_range[0]}\u2013{h_range[1]}"))
    fig.legend(handles=handles, loc="outside lower center", ncol=2)
    return fig


# --------------------------------------------------------------------------------------------
# Fig. 16 and Fig. 18: success rates by planner
# --------------------------------------------------------------------------------------------


@paper_style
def fig16_ablation(rates: pd.DataFrame) -> Figure:
    """Fig. 16: success rate per ablation variant with Wilson 95% bars, the paper's marked."""
    fig = Figure(figsize=(6.4, 3.4), layout="constrained")
    ax = fig.subplots()
    x = np.arange(len(rates))
    colours = [_colour(p, i) for i, p in enumerate(rates["planner"])]
    _rate_bars(ax, x, rates, 0.7, colours)
    marked = _paper_marks(ax, x, rates["paper_pct"].tolist(), 0.7)
    ax.set_xticks(x, _ticks_with_n(rates))
    ax.set_ylabel("success rate [%]")
    ax.set_xlabel("planner (heuristic with one term removed, or a baseline)")
    ax.set_ylim(0, 105)
    handles = [Patch(color=_colour(PROPOSED), label="ours (executed trials)"),
               Line2D([], [], color="#333333", marker="|", linestyle="none", markersize=8,
                      label="Wilson 95% interval")]
    if marked:
        handles.append(_paper_handle())
    ax.legend(handles=handles, loc="upper right")
    return fig


@paper_style
def fig18_baselines(by_planner: pd.DataFrame, by_shape: pd.DataFrame) -> Figure:
    """Fig. 18: (a) overall success per planner; (b) per shape; Wilson bars, paper marked."""
    fig = Figure(figsize=(10.0, 3.6), layout="constrained")
    ax_a, ax_b = fig.subplots(1, 2, width_ratios=[1, 2.2])
    x = np.arange(len(by_planner))
    planners = by_planner["planner"].tolist()
    _rate_bars(ax_a, x, by_planner, 0.7, [_colour(p, i) for i, p in enumerate(planners)])
    marked = _paper_marks(ax_a, x, by_planner["paper_pct"].tolist(), 0.7)
    ax_a.set_xticks(x, _ticks_with_n(by_planner))
    ax_a.set_ylabel("success rate [%]")
    ax_a.set_ylim(0, 105)
    ax_a.set_title("(a) overall", loc="left")

    shapes = list(dict.fromkeys(by_shape["shape"]))
    width = 0.8 / max(len(planners), 1)
    for i, planner in enumerate(planners):
        sub = by_shape[by_shape["planner"] == planner].set_index("shape").reindex(shapes)
        sub = sub.assign(n=sub["n"].fillna(0).astype(int))
        xs = np.arange(len(shapes)) + (i - (len(planners) - 1) / 2) * width
        _rate_bars(ax_b, xs, sub, width, [_colour(planner, i)] * len(shapes), _label(planner))
        marked |= _paper_marks(ax_b, xs, sub["paper_pct"].tolist(), width)
    ax_b.set_xticks(np.arange(len(shapes)), [s.replace("_", " ") for s in shapes])
    ax_b.set_ylabel("success rate [%]")
    ax_b.set_xlabel("object shape")
    ax_b.set_ylim(0, 105)
    ax_b.set_title("(b) by shape (Wilson 95% bars)", loc="left")
    handles, _ = ax_b.get_legend_handles_labels()
    if marked:
        handles.append(_paper_handle())
    ax_b.legend(handles=handles, loc="upper right", ncol=min(len(handles), 5))
    return fig


# --------------------------------------------------------------------------------------------
# Fig. 17: wrench-balance traces
# --------------------------------------------------------------------------------------------


@paper_style
def fig17_wrench(traces: pd.DataFrame, *, settle_band: Sequence[float] | None = None,
                 slip_saturates_above: float | None = None, force_command_n: float | None = None,
                 residual_limit_n: float = 0.5) -> Figure:
    """Fig. 17: residual, torque, slip margin and finger-1 force per iteration, one line per μ.

    ``traces`` columns: ``mu``, ``iteration``, ``residual_norm_n``, ``torque_norm_nm``,
    ``slip_margin_rel`` and ``normal_force_1_n`` (one trial per μ).
    """
    fig = Figure(figsize=(9.0, 6.0), layout="constrained")
    axes = fig.subplots(2, 2, sharex=True).ravel()
    panels = [
        ("residual_norm_n", "(a) force residual \u2016R\u2016 [N]"),
        ("torque_norm_nm", "(b) torque residual \u2016\u03c4\u2016 [N\u00b7m]"),
        ("slip_margin_rel",
         "(c) slip margin (\u03bcf\u2099 \u2212 \u2016f\u209c\u2016)/(\u03bcf\u2099) [\u2013]"),
        ("normal_force_1_n", "(d) finger-1 normal force [N]"),
    ]
    for i, (mu, grp) in enumerate(traces.groupby("mu", sort=True)):
        grp = grp.sort_values("iteration")
        for ax, (col, _) in zip(axes, panels, strict=True):
            if col in grp:
                ax.plot(grp["iteration"], grp[col], color=MU_COLOURS[i % len(MU_COLOURS)],
                        label=f"\u03bc = {mu:g}")
    for ax, (_, title) in zip(axes, panels, strict=True):
        ax.set_title(title, loc="left")
    for ax in axes[2:]:
        ax.set_xlabel("iteration of Algorithm 2")
    axes[0].axhline(residual_limit_n, color="#333333", linestyle="--", linewidth=1.0,
                    label=f"criterion {residual_limit_n} N")
    if settle_band is not None:
        axes[0].axvspan(settle_band[0], settle_band[1], color=PAPER_COLOUR, alpha=0.12,
                        label=f"paper: settles in {settle_band[0]}\u2013{settle_band[1]} it.")
    if slip_saturates_above is not None:
        axes[2].axhline(slip_saturates_above, color=PAPER_COLOUR, linestyle=":",
                        label=f"paper: > {slip_saturates_above} for \u03bc \u2265 0.3")
    axes[2].axhline(0.0, color="#333333", linestyle="--", linewidth=1.0, label="slip boundary")
    if "slip_margin_rel" in traces and traces["slip_margin_rel"].min() < -1.0:
        # the first iterations (seed contact) can reach -100 and would hide the saturation
        axes[2].set_ylim(-1.0, 1.1)
        axes[2].set_title(panels[2][1] + ", clipped at \u22121", loc="left")
    if force_command_n is not None:
        axes[3].axhline(force_command_n, color=PAPER_COLOUR, linestyle=":",
                        label=f"paper: \u2248{force_command_n:g} N command")
    for ax in axes:
        ax.legend(loc="best")
    return fig


# --------------------------------------------------------------------------------------------
# Fig. 19: sensitivity heatmaps
# --------------------------------------------------------------------------------------------


@paper_style
def fig19_heatmap(rate_pct: pd.DataFrame, *, xlabel: str, ylabel: str, title: str,
                  region: pd.DataFrame | None = None, region_label: str = "paper's stable region",
                  value_label: str = "success rate [%]", vmax: float | None = 100.0) -> Figure:
    """Fig. 19 panel: a value per cell (rows = y levels, columns = x levels), region outlined."""
    fig = Figure(figsize=(5.2, 4.2), layout="constrained")
    ax = fig.subplots()
    values = rate_pct.to_numpy(dtype=float)
    image = ax.imshow(values, origin="lower", aspect="auto", cmap="RdYlGn" if vmax == 100.0
                      else "viridis", vmin=0.0, vmax=vmax)
    ax.set_xticks(range(values.shape[1]), [f"{v:g}" for v in rate_pct.columns])
    ax.set_yticks(range(values.shape[0]), [f"{v:g}" for v in rate_pct.index])
    ax.grid(False)
    for (r, c), v in np.ndenumerate(values):
        if not math.isnan(v):
            ax.text(c, r, f"{v:.0f}", ha="center", va="center", fontsize=7)
    handles = []
    if region is not None:
        for (r, c), inside in np.ndenumerate(region.to_numpy(dtype=bool)):
            if inside:
                ax.add_patch(Rectangle((c - 0.5, r - 0.5), 1, 1, fill=False, linewidth=1.6,
                                       edgecolor=PAPER_COLOUR))
        handles.append(Patch(fill=False, edgecolor=PAPER_COLOUR, linewidth=1.6, label=region_label))
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, loc="left")
    fig.colorbar(image, ax=ax, label=value_label)
    if handles:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(0, -0.12), frameon=False)
    return fig


# --------------------------------------------------------------------------------------------
# Fig. 20: mesh resolution
# --------------------------------------------------------------------------------------------


@paper_style
def fig20_mesh_resolution(trials: pd.DataFrame, per_nodes: pd.DataFrame,
                          paper_runtime_ms: Mapping[int, float] | None = None,
                          residual_band_n: Sequence[float] | None = None,
                          residual_limit_n: float = 0.5) -> Figure:
    """Fig. 20: (a) runtime per evaluation vs nodes with O(n), O(√n) guides; (b) final residual.

    ``trials`` columns: ``nodes``, ``runtime_ms``, ``residual_norm_n`` (one row per trial);
    ``per_nodes``: ``nodes``, ``runtime_median_ms``, ``residual_median_n``.
    """
    fig = Figure(figsize=(9.0, 3.6), layout="constrained")
    ax_a, ax_b = fig.subplots(1, 2)
    ours = PLANNER_COLOURS[PROPOSED]
    ax_a.scatter(trials["nodes"], trials["runtime_ms"], s=8, alpha=0.35, color=ours,
                 label="ours, single trials", rasterized=True)
    ax_a.plot(per_nodes["nodes"], per_nodes["runtime_median_ms"], marker="o", color=ours,
              label="ours, median")
    n0, t0 = float(per_nodes["nodes"].iloc[0]), float(per_nodes["runtime_median_ms"].iloc[0])
    grid = np.geomspace(per_nodes["nodes"].min(), per_nodes["nodes"].max(), 50)
    ax_a.plot(grid, t0 * grid / n0, color="#777777", linestyle="--", label="O(n) guide")
    ax_a.plot(grid, t0 * np.sqrt(grid / n0), color="#777777", linestyle=":",
              label="O(\u221an) guide")
    if paper_runtime_ms:
        xs, ys = zip(*sorted(paper_runtime_ms.items()), strict=True)
        ax_a.plot(xs, ys, linestyle="none", marker="D", color=PAPER_COLOUR,
                  label="paper (MATLAB workstation)")
    ax_a.set_xscale("log")
    ax_a.set_yscale("log")
    ax_a.set_xlabel("mesh nodes n [\u2013]")
    ax_a.set_ylabel("runtime per grasp evaluation [ms]")
    ax_a.set_title("(a) runtime (guides anchored at our smallest mesh)", loc="left")
    ax_a.legend(loc="upper left")

    ax_b.scatter(trials["nodes"], trials["residual_norm_n"], s=8, alpha=0.35, color=ours,
                 label="ours, single trials", rasterized=True)
    ax_b.plot(per_nodes["nodes"], per_nodes["residual_median_n"], marker="o", color=ours,
              label="ours, median")
    ax_b.axhline(residual_limit_n, color="#333333", linestyle="--",
                 label=f"criterion {residual_limit_n} N")
    if residual_band_n is not None:
        ax_b.axhspan(residual_band_n[0], residual_band_n[1], color=PAPER_COLOUR, alpha=0.12,
                     label=f"paper's scatter {residual_band_n[0]}\u2013{residual_band_n[1]} N")
    ax_b.set_xscale("log")
    ax_b.set_xlabel("mesh nodes n [\u2013]")
    ax_b.set_ylabel("final force residual \u2016R\u2016 [N]")
    ax_b.set_title("(b) final force-balance residual", loc="left")
    ax_b.legend(loc="best")
    return fig


# --------------------------------------------------------------------------------------------
# Fig. 21: PSO repeatability
# --------------------------------------------------------------------------------------------


@paper_style
def fig21_pso(normalised: pd.DataFrame, cv_pct: Mapping[str, float],
              paper_cv_pct: Mapping[str, str], bands: pd.DataFrame | None) -> Figure:
    """Fig. 21: (a) identified values / their mean per parameter; (b) best-cost bands.

    ``normalised`` has one column per parameter (one row per run); ``cv_pct`` our CV per
    parameter; ``paper_cv_pct`` the paper's CV as text per parameter; ``bands`` columns
    ``n_evaluations``, ``mean``, ``p10``, ``p25``, ``p75``, ``p90`` of the best cost.
    """
    fig = Figure(figsize=(10.0, 3.8), layout="constrained")
    ax_a, ax_b = fig.subplots(1, 2, width_ratios=[1.3, 1])
    params = list(normalised.columns)
    data = [normalised[p].dropna().to_numpy(dtype=float) for p in params]
    ax_a.boxplot(data, positions=range(len(params)), widths=0.55, showfliers=False,
                 medianprops={"color": PLANNER_COLOURS[PROPOSED]})
    rng = np.random.default_rng(0)  # jitter of the dots only; no statistic depends on it
    for i, values in enumerate(data):
        ax_a.scatter(i + rng.uniform(-0.15, 0.15, values.size), values, s=9, alpha=0.6,
                     color=PLANNER_COLOURS[PROPOSED], zorder=3)
    ax_a.axhline(1.0, color="#333333", linestyle="--", linewidth=1.0)
    dash = "\u2014"
    labels = [f"{_param_label(p)}\nCV {cv_pct[p]:.0f}%\n"
              f"paper {str(paper_cv_pct.get(p, dash)).replace(' (range)', '')}" for p in params]
    ax_a.set_xticks(range(len(params)), labels, fontsize=7)
    ax_a.set_ylabel("identified value / mean over runs [\u2013]")
    ax_a.set_title(f"(a) identified values, {len(normalised)} runs", loc="left")
    ax_a.legend(handles=[Line2D([], [], color=PLANNER_COLOURS[PROPOSED], marker="o",
                                linestyle="none", markersize=4, label="ours, one PSO run"),
                         Line2D([], [], color="#333333", linestyle="--", label="mean")],
                loc="upper right")
    if bands is not None and len(bands):
        x = bands["n_evaluations"].to_numpy(dtype=float)
        c = PLANNER_COLOURS[PROPOSED]
        ax_b.fill_between(x, bands["p10"], bands["p90"], color=c, alpha=0.15,
                          label="10\u201390% of runs")
        ax_b.fill_between(x, bands["p25"], bands["p75"], color=c, alpha=0.3,
                          label="25\u201375% of runs")
        ax_b.plot(x, bands["mean"], color=c, label="mean")
        positive = bands[["p10", "mean"]].to_numpy(dtype=float)
        if np.all(positive > 0) and positive.max() / positive.min() > 50:
            ax_b.set_yscale("log")
        ax_b.legend(loc="upper right")
    else:
        ax_b.text(0.5, 0.5, "no pso_trace table in this run", ha="center", va="center",
                  transform=ax_b.transAxes)
    ax_b.set_xlabel("function evaluations [\u2013]")
    ax_b.set_ylabel("best cost J [\u2013]")
    ax_b.set_title("(b) convergence bands of the best cost", loc="left")
    return fig


def _param_label(param: str) -> str:
    return {"lambda1": "\u03bb1", "lambda2": "\u03bb2", "n_exp": "n"}.get(param, param)
