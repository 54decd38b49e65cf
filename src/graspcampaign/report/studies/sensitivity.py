"""Report of ``sensitivity`` (Sec. 6.6, Fig. 19): success over three parameter planes."""

from __future__ import annotations

import math
from dataclasses import replace

import matplotlib as mpl
import numpy as np
import pandas as pd
from matplotlib.lines import Line2D

from graspcampaign.analysis.association import RESAMPLES, equal_rates_test
from graspcampaign.analysis.quasi_static import loop_at_n_max_pct
from graspcampaign.analysis.rates import CONFIDENCE_LEVEL
from graspcampaign.analysis.records import Estimate, at_bound, beyond_radius, rate
from graspcampaign.report import format as fmt
from graspcampaign.report import spec, style
from graspcampaign.report.document import Col, Figure, Table
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Claims, Finding, GateRemoved, Rate, ReportSpec, Value, rate_cols

PANELS = {"mu_mass": ("mu", "mass_kg", "friction coefficient μ [–]", "object mass m [kg]"),
          "lambda": ("lambda1", "lambda2", "λ1 [–]", "λ2 [–]"),
          "n_b": ("n_exp", "b", "contact exponent n [–]", "nodal damping b [internal units]")}
EPS = 1e-9  # level comparisons of float factors
LOOP_AT_N_MAX = "still moving at N_max [%]"  # the header of this share in every study
#: how a heatmap aggregates its cells: aggregation, scale, colour-scale top (None: the largest), the cell
#: values' decimals
CELLS = {"rate": ("mean", 100.0, 100.0, 0), "median": ("median", 1.0, None, 1)}


def panel_rows(run: Run, name: str) -> pd.DataFrame:
    """The executed trials of panel ``name``, selected once per run."""
    return run.memo(f"panel/{name}", lambda: run.ok[run.ok["panel"] == name] if "panel" in run.ok
                    else run.ok.iloc[:0])


def _edge(levels, value: float, below_includes: bool) -> float:
    """The cell edge on a category axis of ``levels`` (cell i centred at i) between the levels below a
    paper boundary and those above it; ``value`` itself lies below when ``below_includes`` (m ≤ 0.5),
    above otherwise (μ ≥ 0.2): each cell lies wholly on the side the claims table counts it on."""
    v = np.asarray(levels, dtype=float)
    return float(np.sum(v <= value + EPS if below_includes else v < value - EPS)) - 0.5


def _category_axis(axis, levels) -> None:
    """One cell per level, at most about six tick labels (every k-th level), each the level's value."""
    step = math.ceil(len(levels) / 6)
    axis.set_ticks(range(0, len(levels), step), [fmt.number(v) for v in levels[::step]])


def _cell_text_pt(ax, fig, shape: tuple[int, int]) -> float | None:
    """Cell text size [pt] (≤ 9) fitting a three-character value into a cell of ``ax`` (about 80 % of its
    pre-layout box: constrained layout makes room for the colour bar); None below a legible 7 pt."""
    width, height = 0.8 * 72 * ax.get_position().size * fig.get_size_inches()
    size = min(9.0, width / shape[1] / 2.2, height / shape[0] / 1.5)
    return size if size >= 7.0 else None


def heatmap(ax, fig, run: Run, panel: str, value: str, label: str, cmap: str = "RdYlGn",
            cells: str = "rate") -> tuple[np.ndarray, np.ndarray]:
    """``value`` per cell of ``panel`` (:data:`CELLS`) on category axes, one cell per level (tick labels
    the levels); non-finite cells blank and marked n/a; per-cell values where they are legible. Return
    the x and y levels (place boundaries with :func:`_edge`)."""
    (x, y, xl, yl), (how, scale, vmax, digits) = PANELS[panel], CELLS[cells]
    part = panel_rows(run, panel)
    g = scale * part.assign(**{value: part[value].astype(float)}).pivot_table(
        index=y, columns=x, values=value, aggfunc=how).sort_index().sort_index(axis=1)
    ax.set(xlabel=xl, ylabel=yl)
    xs, ys, values = g.columns.to_numpy(float), g.index.to_numpy(float), g.to_numpy(dtype=float)
    finite = values[np.isfinite(values)]
    if not finite.size:  # the panel says why instead of failing the figure
        ax.text(0.5, 0.5, f"not drawn: no finite value of\n{label}", ha="center", va="center",
                transform=ax.transAxes)
        return xs, ys
    norm = mpl.colors.Normalize(0.0, vmax if vmax is not None else finite.max())
    mesh = ax.pcolormesh(np.arange(len(xs) + 1) - 0.5, np.arange(len(ys) + 1) - 0.5,
                         np.ma.masked_invalid(values), cmap=cmap, norm=norm)
    _category_axis(ax.xaxis, xs)
    _category_axis(ax.yaxis, ys)
    size = _cell_text_pt(ax, fig, values.shape)
    for (r, c), v in np.ndenumerate(values) if size else ():
        ax.text(c, r, fmt.number(v, digits) if math.isfinite(v) else "n/a", ha="center", va="center",
                fontsize=size, color=style.ink(mesh.to_rgba(v)) if math.isfinite(v) else "black")
    ax.set(xlim=(-0.5, len(xs) - 0.5), ylim=(-0.5, len(ys) - 0.5))
    ax.grid(False)
    fig.colorbar(mesh, ax=ax, label=label, shrink=0.85)
    return xs, ys


def _panels(run: Run) -> pd.DataFrame:
    rows = []
    for panel in [k for k in PANELS if len(panel_rows(run, k))]:
        g, (x, y) = panel_rows(run, panel), PANELS[panel][:2]
        deep = beyond_radius(g, run.radius_mm)
        rows.append({"panel": panel, "cells": g.groupby([x, y]).ngroups, "trials": len(g),
                     "loop_at_n_max_pct": loop_at_n_max_pct(g), "beyond_radius": int(deep.sum()),
                     "beyond_radius_pct": 100 * deep.mean(),
                     "delta_max_median_mm": g.loc[~deep, "delta_max_mm"].median(),
                     "delta_max_why": "no physical trial" if deep.all() else "",
                     "runtime_median_ms": g["runtime_ms"].median(),
                     # the opening's why: friction's share of the load, and the slip check failing first
                     "eta_median": g["eta"].abs().median() if "eta" in g else math.nan,
                     "slip_first": (g["failure_check"] == "slip").sum() if "failure_check" in g else pd.NA,
                     **rate_cols(g, "success", "success"),
                     **rate_cols(g, "success_vertical", "vertical")})
    return pd.DataFrame(rows)


def _figure(run: Run, fig) -> None:
    p, panels = run.paper, [k for k in PANELS if len(panel_rows(run, k))]
    deeper = run.tables["sensitivity_panels"].set_index("panel")["beyond_radius_pct"]
    for ax, panel in zip(style.two_per_row(fig, len(panels)), panels, strict=True):
        xl, yl = PANELS[panel][2:]
        tag, handles = "abc"[list(PANELS).index(panel)], []
        deep = deeper[panel]
        caveat = (f"\n{fmt.number(deep, 0)}% of trials deeper than r = {fmt.number(run.radius_mm)} mm "
                  "(non-physical)") * bool(deep)
        if panel == "n_b":
            heatmap(ax, fig, run, panel, "runtime_ms", "median runtime [ms]", "viridis", "median")
            ax.set_title(f"({tag}) runtime, n × b (paper: flat){caveat}")
        else:
            xs, ys = heatmap(ax, fig, run, panel, "success", "success rate [%]")
            ax.set_title(f"({tag}) success, {xl.split(' [')[0]} × {yl.split(' [')[0]}{caveat}")
        if panel == "mu_mass":
            mu, mass = _edge(xs, p.stable_mu_min, False), _edge(ys, p.stable_mass_max_kg, True)
            ax.plot([mu, mu, len(xs)], [-1, mass, mass], color=style.PAPER, linewidth=2, linestyle="--")
            handles.append(Line2D([], [], color=style.PAPER, linestyle="--", label=f"paper: stable for "
                                  f"μ ≥ {p.stable_mu_min}, m ≤ {p.stable_mass_max_kg}"))
        elif panel == "lambda":
            for value, below, ls, words in ((p.lambda1_stable_below, True, "--", "stable for λ1 ≲"),
                                            (p.nonconvergence_strip_lambda1_from, False, ":",
                                             "non-convergence for λ1 ≥")):
                ax.axvline(_edge(xs, value, below), color=style.PAPER, linestyle=ls, linewidth=2)
                handles.append(Line2D([], [], color=style.PAPER, linestyle=ls,
                                      label=f"paper: {words} {value}"))
        if handles:
            style.legend_below(ax, handles, ncol=1)


SUPPLEMENT = (("mu_mass", "success_vertical", "success, |R_z| reading [%]", "RdYlGn", "rate"),
              ("lambda", "loop_capped", "loop still moving at N_max [%]", "magma_r", "rate"),
              ("lambda", "valid_geometry", "trials with every contact within r [%]", "RdYlGn", "rate"),
              ("n_b", "success_vertical", "success, |R_z| reading, n × b [%]", "RdYlGn", "rate"))


def _supplement(run: Run, fig) -> None:
    """The :data:`SUPPLEMENT` tiles the run has, each titled by its fixed letter (the caption's)."""
    tiles = [(tag, t) for tag, t in zip("abcd", SUPPLEMENT, strict=True)
             if len(panel_rows(run, t[0])) and t[1] in run.ok]
    axes = np.atleast_1d(fig.subplots(math.ceil(len(tiles) / 2), 2)).ravel()
    for ax, (tag, tile) in zip(axes, tiles, strict=False):
        heatmap(ax, fig, run, *tile)
        ax.set_title(f"({tag}) {tile[2]}")
    for ax in axes[len(tiles):]:
        ax.set_visible(False)


def _levels_test(run: Run, column: str):
    """Panel (a)'s success per level of ``column`` (successes, trials) and the test of equal rates over
    them (None: fewer than two levels); its Monte Carlo p computed once per run, read by the opening
    (twice) and by table sensitivity_claims."""
    def compute():
        g = panel_rows(run, "mu_mass").groupby(column)["success"].agg(["sum", "size"])
        return g, equal_rates_test(g["sum"], g["size"], seed=run.seed) if len(g) > 1 else None  # run's seed
    return run.memo(f"equal_rates_test/{column}", compute)


def _varies(run: Run, column: str, factor: str, said: str = "") -> str:
    """Whether panel (a)'s success share differs between the levels of ``column`` (a test of equal
    rates at the report's 95 % level, its p in table sensitivity_claims), in the finding's words; the
    test's name is left out when it is ``said`` (the other factor's, said before)."""
    g, test = _levels_test(run, column)
    shares = fmt.span(100 * g["sum"] / g["size"], "%", digits=1)
    if test is None:
        return f"is {shares} at the one {factor} level (nothing to compare)"
    if not test.method:  # one share printed ("0.0%"): every level's
        return f"does not vary with {factor} ({shares} at each of its {test.groups} levels)"
    verb = "varies" if test.pvalue < 1 - CONFIDENCE_LEVEL else "does not detectably vary"
    floor = test.n_resamples and test.pvalue <= 1 / (test.n_resamples + 1)  # no resample reached it
    method = "" if test.method == said else f"{test.method} "
    return f"{verb} with {factor} ({method}p {'≤' if floor else '='} {fmt.p_value(test.pvalue)})"


def _levels_p(column: str):
    """The p of equal success over panel (a)'s levels of ``column`` (:func:`_levels_test`); none, said
    as the finding it is, when every trial failed or every trial succeeded."""
    def value(run: Run) -> Estimate:
        g, test = _levels_test(run, column)
        if test is None:
            raise ValueError("fewer than two levels")
        if not test.method:  # one outcome throughout: the rates are equal by construction
            outcome = "failed" if g["sum"].sum() == 0 else "succeeded"
            raise spec.Unmeasured(f"every trial {outcome}: no difference to test")
        return Estimate(test.pvalue, n=test.n)
    return value


#: Fig. 19's boundaries as pairs of sensitivity_claims rows, the side with the higher rate first.
REGION = ("(a) stable region: success inside it", "(a) stable region: success outside it")
LAMBDA = ("(b) stable for λ1 below the paper's boundary: success there", "(b) success above the boundary")
STRIP = ("(b) non-convergence strip: loop still moving at N_max inside it",
         "(b) loop still moving at N_max outside the strip")
BOUNDARIES = {"stable region (a)": REGION, "λ1 boundary (b)": LAMBDA, "non-convergence strip (b)": STRIP}


def _rate(row: pd.Series) -> str:
    """A claims row's rate as a sentence prints it: ``5.7% (3.6–8.9%)``."""
    return fmt.estimate(row["value"], row["low"], row["high"], 1, unit="%")


def finding(run: Run) -> str:
    """How many of Fig. 19's boundaries separate our rates (table sensitivity_claims' verdicts: the
    paper's words hold), panel (a)'s variation by the test of equal rates, and why."""
    a, claims = panel_rows(run, "mu_mass"), run.tables["sensitivity_claims"].set_index("quantity")
    rows = {name: claims.loc[list(pair)] for name, pair in BOUNDARIES.items()}
    rows = {name: r for name, r in rows.items() if r["value"].notna().all()}
    held = claims["differs"].eq(False)  # by _word_claims: Wilson intervals apart the paper's way
    seen = [name for name, r in rows.items() if held[r.index[0]]]
    p, inside, outside = run.paper, *(claims.loc[q] for q in REGION)
    side = {where: f"{_rate(r)} of {fmt.number(int(r['n']))} {where}" if pd.notna(r["value"])
            else f"no trial {where}"
            for where, r in (("inside it", inside), ("outside", outside))}  # a sweep on one side of it
    text = (f"Paper's stable region: μ ≥ {fmt.number(p.stable_mu_min)}, m ≤ "
            f"{fmt.number(p.stable_mass_max_kg)} kg (Fig. 19a); ours succeeds on {side['inside it']}, "
            f"{side['outside']} (Wilson 95%). "
            if pd.notna(inside["value"]) or pd.notna(outside["value"]) else "")
    verb = "separates" if len(seen) == 1 else "separate"
    text += (f"{len(seen)} of {len(rows)} Fig. 19 boundaries {verb} our rates "
             f"({fmt.listed(seen) + '; ' if seen else ''}table sensitivity_claims). " if rows else "")
    if len(a):
        said = getattr(_levels_test(run, "mass_kg")[1], "method", "")  # the test named once if both share it
        text += f"Success {_varies(run, 'mass_kg', 'mass')} and {_varies(run, 'mu', 'friction', said)}. "
    if len(seen) < len(rows):
        t = run.tables["sensitivity_panels"]  # per panel, as recorded (missing: not recorded)
        slip = "" if t["slip_first"].isna().all() else (
            f", and the slip check fails first in {int(t['slip_first'].sum())} of {int(t['trials'].sum())}")
        eta = fmt.span(t["eta_median"], digits=2)  # none: no contact carries friction
        eta = "" if eta == fmt.MISSING else f" (median |η| {eta}{' in each panel' * (fmt.DASH not in eta)})"
        text += (f"Why: Algorithm 2 releases contacts until the remaining normals carry the weight{eta}"
                 f"{slip} (table sensitivity_panels); the static loop reads neither damping, λ2 nor b "
                 "(panels b, c; `docs/decisions.md`, *Sensitivity, mesh resolution, surrogate*). ")
    return text.rstrip()


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
    """The median λ1 of panel a's PSO identifications (prepared/, one per body, which a cell's seeds
    share) at μ < 0.1 (or ≥), or the share of them on a PSO bound."""
    def value(run: Run) -> Estimate:
        keys = ["shape", "mass_kg", "mu"]
        bodies = run.stored("prepared")
        cells = panel_rows(run, "mu_mass")[keys].drop_duplicates()
        part = bodies.merge(cells, on=keys)
        part = part[(part["mu"] < 0.1 - EPS) == low_mu]
        if not len(part):
            raise ValueError("no identification in this part of the panel")
        if what == "bound":
            return rate(part.assign(on_bound=at_bound(part, "lambda1")), outcome="on_bound")
        return Estimate(float(part["lambda1"].median()), n=len(part))
    return value


BOUND = "(a) identified λ1 on its PSO search bound at μ "
DROP = ("(a) μ < the friction limit, m ≤ the mass limit: success there",
        "(a) sharp drop above the mass limit when μ < the friction limit")
BOUND_MOST = 50.0
"""The share [%] of identifications on λ1's bound that 'pushed toward the bound' means: most."""
#: The paper's words on a claims row beside another row, or beside a share [%]: (row, other, words,
#: higher). One rule: they hold where the row's Wilson interval lies wholly above the other's (higher)
#: or wholly below it, differ where it lies apart the other way, and are not shown by ours where the
#: two overlap.
WORDS = ((REGION[0], REGION[1], "higher than outside it", True),
         (LAMBDA[0], LAMBDA[1], "higher than above it", True),
         (STRIP[0], STRIP[1], "higher than outside it", True),
         (DROP[1], DROP[0], "a drop: lower than at m ≤ the mass limit", False),
         (BOUND + "< 0.1", BOUND_MOST, "pushed toward the bound", True),
         (BOUND + "≥ 0.1", BOUND + "< 0.1", "fewer than at μ < 0.1", False))


def _word_claims(frame: pd.DataFrame) -> pd.DataFrame:
    """Judge the paper's Fig. 19 and Sec. 6.6 words of :data:`WORDS` by the one verdict rule, ours
    read in the same words."""
    rows = frame.set_index("quantity")
    for row, other, claim, higher in WORDS:
        share = not isinstance(other, str)
        if row not in rows.index or not share and other not in rows.index:
            continue
        r = rows.loc[row]
        o = pd.Series({"value": other, "low": other, "high": other}) if share else rows.loc[other]
        if pd.isna(r["value"]) or pd.isna(o["value"]):
            continue
        above, below = r["low"] > o["high"], r["high"] < o["low"]
        ours = f"{_rate(r)} against {f'{fmt.number(other)}%' if share else _rate(o)}"
        if above if higher else below:
            judged = fmt.verdict(claim, claim)
        elif above or below:
            judged = fmt.verdict(f"{ours}, Wilson intervals apart the other way", claim)
        else:
            judged = fmt.verdict(ours, claim, because=f"not shown by ours: {ours}, Wilson intervals overlap")
        frame.loc[frame["quantity"] == row, ["paper", "differs", "verdict"]] = [claim, judged.differs,
                                                                                judged.words]
    return frame


FLAT = ("not compared: the paper's words are qualitative (Sec. 6.6 'nearly flat', Fig. 19c "
        "'insensitive'), with no ratio or threshold to judge ours by")


def _runtime_ratio(axis: str):
    def value(run: Run) -> float:
        med = panel_rows(run, "n_b").groupby(axis)["runtime_ms"].median()
        return float(med.max() / med.min())
    return value


CLAIMS = Claims("sensitivity_claims", "The paper's Fig. 19 statements (in words) beside the matching "
                "counts of ours; rates over executed trials with Wilson 95%, the λ1 rows over panel (a)'s "
                "PSO identifications (one per cell, its seeds share it). The paper's words (higher, lower, a "
                "drop, fewer) hold where the two rows' Wilson intervals lie apart that way, differ where "
                "they lie apart the other way and are not shown by ours where they overlap; its Sec. 6.6 "
                "words on λ1 (pushed toward its bound at μ < 0.1, the low-friction failure mode) are "
                "compared as: most (the interval above 50%) identifications on the bound at μ < 0.1, and "
                "fewer at μ ≥ 0.1. The p rows test equal success at every level of panel (a)'s mass or "
                f"friction (Pearson's χ², its Monte Carlo p over {RESAMPLES} resamples where an expected "
                f"count is below 5: {fmt.p_value(1 / (RESAMPLES + 1))} there is a bound, the smallest p they "
                "can give)", [
           Rate(REGION[0], "Fig. 19a", _where("mu_mass", _inside)),
           Rate(REGION[1], "Fig. 19a", _where("mu_mass", _inside, False)),
           Rate("(a) stable region: |R_z| reading inside it", "Fig. 19a", _where("mu_mass", _inside),
                outcome="success_vertical"),
           Rate(DROP[0], "Sec. 6.6", _where("mu_mass", lambda ok, p: (ok["mu"] < p.stable_mu_min - EPS)
                                            & (ok["mass_kg"] <= p.stable_mass_max_kg + EPS))),
           Rate(DROP[1], "Sec. 6.6", _where("mu_mass", lambda ok, p: (ok["mu"] < p.stable_mu_min - EPS)
                                            & (ok["mass_kg"] > p.stable_mass_max_kg + EPS))),
           Value("(a) median identified λ1 at μ < 0.1", "Sec. 6.6",
                 _identified(True, "median"), unit="–", digits=3),
           Value("(a) identified λ1 on its PSO search bound at μ < 0.1", "Sec. 6.6",
                 _identified(True, "bound"), unit="%", digits=1),
           Value("(a) median identified λ1 at μ ≥ 0.1", "Sec. 6.6", _identified(False, "median"),
                 unit="–", digits=3),
           Value("(a) identified λ1 on its PSO search bound at μ ≥ 0.1", "Sec. 6.6",
                 _identified(False, "bound"), unit="%", digits=1),
           Rate(LAMBDA[0], "Fig. 19b", _where("lambda", _below)),
           Rate(LAMBDA[1], "Fig. 19b", _where("lambda", _below, False)),
           Rate(STRIP[0], "Sec. 10", _where("lambda", _strip), outcome="loop_capped"),
           Rate(STRIP[1], "Sec. 10", _where("lambda", _strip, False), outcome="loop_capped"),
           *(Value(f"(a) equal success at every {factor} level: p", "Fig. 19a", _levels_p(column),
                   digits=fmt.P) for factor, column in (("mass", "mass_kg"), ("friction", "mu"))),
           *(Value(f"(c) runtime max/min over {axis} levels", "Sec. 6.6, Fig. 19c", _runtime_ratio(column),
                   lambda p: "nearly flat", "–", 2, because=FLAT) for axis, column in (("n", "n_exp"),
                                                                                      ("b", "b")))])


SPEC = ReportSpec("sensitivity", [
    Finding(finding),
    Table("sensitivity_panels", "Sensitivity panels: success under both residual readings (vertical: the "
          "|R_z| reading; Wilson 95%), trials whose Algorithm 2 was still moving at N_max, trials with a "
          "contact deeper than the fingertip radius r (non-physical: the fingertip centre inside the "
          "object), the median penetration over the physical trials (δmax ≤ r) and runtime per evaluation",
          _panels, ["cells", "trials", "success_pct", "vertical_pct", Col("n_vertical", "n (vertical)"),
                    Col("loop_at_n_max_pct", LOOP_AT_N_MAX, 1),
                    Col("beyond_radius", "δmax > r (non-physical)", share="beyond_radius_pct"),
                    Col("delta_max_median_mm", "median δmax, δmax ≤ r [mm]", sig=3, why="delta_max_why"),
                    "runtime_median_ms", Col("eta_median", "median |η|", 2),
                    Col("slip_first", "slip check failed first")], by=["panel"]),
    Figure("fig19_sensitivity", "Fig. 19 (ours): (a) success over μ × m with the paper's stable region "
           "(dashed); (b) success over λ1 × λ2 with the paper's λ1 boundary (dashed) and non-convergence "
           "strip (dotted); (c) median runtime over n × b; one cell per level, its value printed where it "
           "fits", _figure, (10.0, 8.6)),
    Figure("fig19_supplement", "Beyond Fig. 19: (a) success under the |R_z| reading over μ × m; (b) trials "
           "still moving at N_max and (c) trials whose every contact lies within the fingertip radius "
           "(physical) over λ1 × λ2; (d) success under the |R_z| reading over n × b",
           _supplement, (10.0, 8.6)),
    replace(CLAIMS, compute=lambda run: _word_claims(CLAIMS.compute(run))),
    GateRemoved(["panel"]),
])
