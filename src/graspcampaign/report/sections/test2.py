"""Report section of ``test2_grasp``: Tables 6-7 and Figs. 28-31 beside the paper (§8).

Reads only the run's records: one per commanded attempt, carrying the sheet's columns, the
planner's pre-execution predictions and the measured outcome (virtual rig, or an ingested file).
Every statistic comes from :mod:`graspcampaign.rig.analysis`, so an ingested run and an engine run
of the same records give the same report. Aborted attempts and errored trials enter no statistic.

Every number stands beside the paper's value from the study file's ``paper:`` block, with its n,
its 95 % interval where it is a rate (Wilson 1927; object-clustered bootstrap, Efron & Tibshirani
1993, for the per-planner success), the difference, and a plain sentence where ours differs.
Which data the section shows is stated first: virtual-rig rows are synthetic, never hardware
results. The helpers above ``section`` are shared with the Test 3 section.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import matplotlib as mpl
import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from graspcampaign import stats
from graspcampaign.analysis.records import executed as analysis_executed
from graspcampaign.core.bench import FAMILIES
from graspcampaign.report import style
from graspcampaign.report.build import LegacyReport as Report
from graspcampaign.report.sections import paper_value

RC = style.RC  # the report's one figure style

PAPER = "black"
PLANNER_ORDER = ("heuristic", "centroid", "no_pso", "force_balance", "random")
PLANNER_LABELS = {"heuristic": "proposed", "centroid": "centroid", "no_pso": "no-PSO",
                  "force_balance": "force-balance", "random": "random"}
PLANNER_COLOURS = {"heuristic": "#1f5aa6", "centroid": "#9e9e9e", "no_pso": "#6a8fc7",
                   "force_balance": "#7b4ea3", "random": "#c9a227"}
SHAPE_ORDER = ("sphere", "ellipsoid", "rounded_cube", "pear", "handle")
SHAPE_LABELS = {"sphere": "sphere", "ellipsoid": "ellipsoid", "rounded_cube": "rounded cube",
                "pear": "pear", "handle": "concave (handle)"}
MATERIAL_ORDER = ("gel", "silicone_soft", "bio_foam", "silicone_ref")
MATERIAL_LABELS = {"gel": "gel", "silicone_soft": "silicone, soft", "bio_foam": "bio foam",
                   "silicone_ref": "silicone, ref."}
OUTCOME_ORDER = ("stable", "success", "partial", "failure_slip", "failure_drop",
                 "failure_damage", "failure_contact_loss")
OUTCOME_LABELS = {"stable": "stable", "success": "success\n(marginal)", "partial": "partial",
                  "failure_slip": "slip", "failure_drop": "drop", "failure_damage": "damage",
                  "failure_contact_loss": "contact\nloss"}
DASH = "–"
MINUS = "−"


# =============================================================================================
# Shared helpers (also used by the Test 3 section)
# =============================================================================================
def executed(records: pd.DataFrame) -> pd.DataFrame:
    """Records of executed attempts: status ok and not aborted (booleans cleaned)."""
    return analysis_executed(records)


def ok_records(records: pd.DataFrame) -> pd.DataFrame:
    """Records without trial errors (aborted attempts kept; the analysis drops them)."""
    return (records[records["status"] == "ok"] if "status" in records else records).reset_index(
        drop=True)


def is_virtual(records: pd.DataFrame) -> bool:
    return "source" in records and bool((records["source"] == "virtual").any())


def data_tag(records: pd.DataFrame) -> str:
    """The label every figure carries: which data it shows."""
    if is_virtual(records):
        return "VIRTUAL RIG data (synthetic model output, not hardware measurements)"
    return "measured on hardware (ingested records)"


def wilson_pct(k: int, n: int) -> tuple[float, float, float]:
    """Return (rate, low, high) in percent, Wilson 95 %; nans when n = 0."""
    if n <= 0:
        return math.nan, math.nan, math.nan
    w = stats.wilson_interval(int(k), int(n))
    return 100.0 * w.estimate, 100.0 * w.low, 100.0 * w.high


def _missing(value: Any) -> bool:
    if value is None:
        return True
    try:
        return not math.isfinite(float(value))
    except (TypeError, ValueError):
        return False


def fmt(value: Any, digits: int | None = 1) -> str:
    """A number rounded once for display ("–" when missing; ``digits=None``: 2 significant)."""
    if _missing(value):
        return DASH
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        return str(int(value))
    text = f"{float(value):.2g}" if digits is None else f"{float(value):.{digits}f}"
    if text.startswith("-"):
        return MINUS + text[1:] if text.strip("-0.") else text[1:]
    return text


def fmt_signed(value: Any, digits: int | None = 1, unit: str = "") -> str:
    if _missing(value):
        return DASH
    text = fmt(value, digits)
    sign = "+" if not text.startswith(MINUS) and text.strip("0.") else ""
    return f"{sign}{text}{unit}"


def fmt_ci(value: Any, low: Any, high: Any, digits: int | None = 1) -> str:
    """``"43.0 (39.6–46.4)"``; just the value when there is no interval."""
    if _missing(low) or _missing(high):
        return fmt(value, digits)
    sep = " to " if float(low) < 0 or float(high) < 0 else DASH
    return f"{fmt(value, digits)} ({fmt(low, digits)}{sep}{fmt(high, digits)})"


def compare(ours: Any, paper: Any, *, n: Any = None, low: Any = None, high: Any = None,
            unit: str = "%", digits: int | None = 1) -> tuple[bool, str]:
    """Say in one plain sentence how our value stands against the paper's.

    Returns ``(differs, sentence)``. With an interval (rates, proportions): whether the paper's
    value lies inside our 95 % interval; without one: whether the two agree to the displayed
    precision. The difference is ours - paper (percentage points for rates in %).
    """
    diff_unit = " pp" if unit == "%" else (f" {unit}" if unit else "")
    show = " %" if unit == "%" else (f" {unit}" if unit else "")
    n_part = f", n = {int(n)}" if not _missing(n) else ""
    if _missing(paper):
        return False, "the paper reports no value"
    if _missing(ours):
        return False, (f"not measured here{n_part.replace(', ', ' (') + ')' if n_part else ''}; "
                       f"the paper reports {fmt(paper, digits)}{show}")
    diff = float(ours) - float(paper)
    size = f"{fmt(abs(diff), digits)}{diff_unit} {'higher' if diff > 0 else 'lower'}"
    if not _missing(low) and not _missing(high):
        ours_text = (f"ours {fmt(ours, digits)}{show} (95 % interval {fmt(low, digits)}{DASH}"
                     f"{fmt(high, digits)}{n_part})")
        if float(low) <= float(paper) <= float(high):
            return False, (f"{ours_text} is consistent with the paper's {fmt(paper, digits)}"
                           f"{show}, which lies inside our interval")
        return True, (f"{ours_text} is {size} than the paper's {fmt(paper, digits)}{show}, "
                      "which lies outside our interval")
    ours_text = f"ours {fmt(ours, digits)}{show}{' (' + n_part[2:] + ')' if n_part else ''}"
    if fmt(abs(diff), digits) == fmt(0.0, digits):
        return False, f"{ours_text} equals the paper's {fmt(paper, digits)}{show} as shown"
    return True, f"{ours_text} is {size} than the paper's {fmt(paper, digits)}{show}"


def claim(quantity: str, where: str, ours: Any, paper: Any, *, n: Any = None, low: Any = None,
          high: Any = None, unit: str = "%", digits: int | None = 1) -> dict[str, Any]:
    """One row of a claims table: ours (interval, n) beside the paper, difference, sentence."""
    def num(v):
        return math.nan if _missing(v) else float(v)

    differs, text = compare(ours, paper, n=n, low=low, high=high, unit=unit, digits=digits)
    return {"quantity": quantity, "section": where, "ours": num(ours), "ours_low": num(low),
            "ours_high": num(high), "n": None if _missing(n) else int(n), "paper": num(paper),
            "difference": num(ours) - num(paper), "unit": unit, "digits": digits,
            "differs": differs, "verdict": text}


def claim_rate(quantity: str, where: str, k: int, n: int, paper: Any) -> dict[str, Any]:
    """A rate claim [%] with its Wilson 95 % interval."""
    pct, low, high = wilson_pct(k, n)
    return claim(quantity, where, pct, paper, n=n, low=low, high=high, unit="%")


def claim_fraction(quantity: str, where: str, k: int, n: int, paper: Any) -> dict[str, Any]:
    """A proportion in [0, 1] (accuracy, precision, recall) with its Wilson interval."""
    pct, low, high = wilson_pct(k, n)
    return claim(quantity, where, pct / 100, paper, n=n, low=low / 100, high=high / 100,
                 unit="", digits=2)


def claims_table(report: Report, name: str, rows: list[dict[str, Any]], caption: str) -> None:
    """Add a claims table: ours (interval, n), the paper, the difference, a plain sentence."""
    full = pd.DataFrame(rows)
    digits = [r["digits"] for r in rows]
    units = [r["unit"] for r in rows]
    display = pd.DataFrame({
        "quantity": full["quantity"], "section": full["section"],
        "ours (95 % interval)": [fmt_ci(r["ours"], r["ours_low"], r["ours_high"], r["digits"])
                                 + ("" if _missing(r["ours"]) else " %" if r["unit"] == "%"
                                    else f" {r['unit']}" if r["unit"] else "") for r in rows],
        "n": [DASH if _missing(v) else str(int(v)) for v in full["n"]],
        "paper": [fmt(v, d) for v, d in zip(full["paper"], digits, strict=True)],
        "difference": [fmt_signed(v, d, " pp" if u == "%" else f" {u}" if u else "")
                       for v, d, u in zip(full["difference"], digits, units, strict=True)],
        "how ours stands": full["verdict"],
    })
    n_diff = int(full["differs"].sum())
    report.table(name, full.drop(columns=["digits"]), caption, display=display)
    report.text(f"Ours differs from the paper on {n_diff} of {len(full)} quantities "
                f"(a rate differs when the paper's value lies outside our 95 % interval; any "
                "other number when it differs at the shown precision).")


def flag_claims(rows: list[dict[str, Any]], quantity: str, where: str, predicted, actual,
                paper: dict) -> np.ndarray:
    """Append accuracy, precision and recall of a pre-execution flag against measured success.

    ``quantity`` is a template with ``{}`` for the metric's name. Each is a proportion with its
    Wilson interval over its own denominator (all trials, flagged trials, successes). Returns the
    confusion ``[[tn, fp], [fn, tp]]`` (zeros when there are no trials).
    """
    confusion = _confusion(predicted, actual)
    (tn, fp), (fn, tp) = confusion
    rows.append(claim_fraction(quantity.format("accuracy"), where, tp + tn, confusion.sum(),
                               paper_value(paper, "accuracy")))
    rows.append(claim_fraction(quantity.format("precision"), where, tp, tp + fp,
                               paper_value(paper, "precision")))
    rows.append(claim_fraction(quantity.format("recall"), where, tp, tp + fn,
                               paper_value(paper, "recall")))
    return confusion


def _confusion(predicted, actual) -> np.ndarray:
    """``[[tn, fp], [fn, tp]]`` of :func:`graspcampaign.stats.classifier_metrics`; zeros if empty."""
    p = np.asarray(predicted, dtype=bool)
    if not p.size:
        return np.zeros((2, 2), dtype=np.int64)
    return stats.classifier_metrics(p, np.asarray(actual, dtype=bool)).confusion


def differences_text(title: str, items: list[tuple[str, bool, str]]) -> str | None:
    """A bullet list of the plain sentences of the quantities that differ."""
    lines = [f"- **{label}**: {text}." for label, differs, text in items if differs]
    if not lines:
        return None
    return f"Where ours differs from {title} ({len(lines)} of {len(items)} values):\n\n" + \
        "\n".join(lines)


def add_differences(report: Report, title: str, items: list[tuple[str, bool, str]]) -> None:
    """Add the bullet list of :func:`differences_text` when any quantity differs."""
    text = differences_text(title, items)
    if text:
        report.text(text)


def with_intervals(df: pd.DataFrame, rate_columns: Sequence[str], n_column: str = "n"
                   ) -> pd.DataFrame:
    """Add Wilson 95 % bounds ``<rate>_low``/``<rate>_high`` [%] beside each rate column [%]."""
    out = df.copy()
    for col in rate_columns:
        bounds = [wilson_pct(round(p * n / 100), n)[1:] if not _missing(p) and n else
                  (math.nan, math.nan) for p, n in zip(out[col], out[n_column], strict=True)]
        at = out.columns.get_loc(col) + 1
        out.insert(at, f"{col}_high", [b[1] for b in bounds])
        out.insert(at, f"{col}_low", [b[0] for b in bounds])
    return out


def source_note(records: pd.DataFrame, manifest: dict, what: str, departures: str) -> str:
    """State which data the section shows; the virtual rig's known departures when virtual."""
    sources = records["source"].value_counts().to_dict() if "source" in records else {}
    parts = ", ".join(f"{n} `{s}`" for s, n in sorted(sources.items()))
    note = (f"**Data.** Records by source: {parts}. {what} Aborted attempts (rig faults before "
            "load) stay in the records for provenance and enter no statistic; rates are over "
            "executed trials, each with its n and 95 % interval, beside the paper's value.")
    if sources.get("virtual"):
        note += ("\n\n**VIRTUAL RIG data.** Every number and figure below comes from the virtual "
                 "rig (`rig/virtual.py`): a stochastic physical model of the gripper executing "
                 "each commanded trial, fed by the planner's own predictions. These are synthetic "
                 "data, not hardware measurements; they exercise the protocol, the ingest schema "
                 "and the statistics, and neither confirm nor refute the paper's values. No "
                 "constant of the rig was tuned towards the paper. " + departures)
    if manifest.get("source") == "measured" and sources.get("virtual"):
        note += ("\n\n*This run was filled by `graspcampaign ingest`, but its files carried "
                 "`source = virtual`: they are virtual-rig exports, not rig measurements.*")
    return note


def counts_table(report: Report, name: str, records: pd.DataFrame, paper: dict, by: str,
                 order: Sequence[str], paper_counts: dict, caption: str) -> None:
    """Commanded, aborted and executed attempts, and executed trials per ``by``, beside the paper."""
    ok = ok_records(records)
    aborted = ok["aborted"].astype("boolean").fillna(False).astype(bool) if "aborted" in ok \
        else pd.Series(False, index=ok.index)
    rows = [
        {"quantity": "commanded attempts (recorded)", "ours": len(records),
         "paper": paper.commanded},
        {"quantity": "aborted before load (rig faults)", "ours": int(aborted.sum()),
         "paper": paper.aborted},
        {"quantity": "executed trials", "ours": int((~aborted).sum()),
         "paper": paper.executed},
        {"quantity": "trial errors (software)", "ours": int((records["status"] != "ok").sum())
         if "status" in records else 0, "paper": None},
    ]
    ex = ok[~aborted]
    for key in order:
        rows.append({"quantity": f"executed, {by} {PLANNER_LABELS.get(key, key)}",
                     "ours": int((ex[by] == key).sum()), "paper": paper_counts.get(key)})
    full = pd.DataFrame(rows)
    display = full.assign(paper=[DASH if _missing(v) else str(int(v)) for v in full["paper"]])
    report.table(name, full, caption, display=display)


# -- figures -----------------------------------------------------------------------------------
def new_figure(records: pd.DataFrame, title: str, size: tuple[float, float], ncols: int,
               nrows: int = 1, **kw):
    """A headless figure with its subplots; the title says which data it shows."""
    fig = Figure(figsize=size, layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False, **kw)
    fig.suptitle(f"{title}\n{data_tag(records)}", fontsize=9.5,
                 color="#b00020" if is_virtual(records) else "black")
    return fig, axes.ravel()


def paper_handle(label: str = "paper's value") -> Line2D:
    return Line2D([], [], color=PAPER, marker="D", markersize=4, linestyle="none", label=label)


def ci_handle() -> Line2D:
    return Line2D([], [], color="#333333", marker="|", linestyle="none", markersize=9,
                  label="Wilson 95 % interval")


def rate_bars(ax, labels: Sequence[str], ks: Sequence[int], ns: Sequence[int],
              colours: Sequence[str], paper: Sequence[Any], *, width: float = 0.7) -> None:
    """Bars of rates [%] with Wilson bars and n above each; the paper's values as diamonds."""
    x = np.arange(len(labels))
    est = np.array([wilson_pct(k, n) for k, n in zip(ks, ns, strict=True)]).reshape(-1, 3)
    ours = np.nan_to_num(est[:, 0])
    err = np.vstack([np.nan_to_num(est[:, 0] - est[:, 1]), np.nan_to_num(est[:, 2] - est[:, 0])])
    ax.bar(x, ours, width, color=list(colours), yerr=err, ecolor="#333333",
           error_kw={"elinewidth": 1.0, "capsize": 3})
    for xi, hi, n in zip(x, np.nan_to_num(est[:, 2]), ns, strict=True):
        ax.annotate(f"n={n}", (xi, hi), xytext=(0, 2), textcoords="offset points", ha="center",
                    va="bottom", fontsize=6.5, color="#444444")
    for xi, p in zip(x, paper, strict=True):
        if not _missing(p):
            ax.plot([xi], [float(p)], marker="D", color=PAPER, markersize=4.5, zorder=6,
                    linestyle="none")
    ax.set_xticks(x, labels)
    ax.set_ylim(0, 109)


def confusion_panel(ax, predicted, actual, title: str, paper: dict, flag: str) -> None:
    """Confusion matrix of a pre-execution flag against measured success, paper's metrics beside."""
    p = np.asarray(predicted, dtype=bool)
    m = stats.classifier_metrics(p, np.asarray(actual, dtype=bool)) if p.size else None
    # rows: flag no/yes; columns: measured failed/succeeded (the transpose of m.confusion)
    cells = m.confusion.T if m is not None else np.zeros((2, 2), dtype=np.int64)
    ax.imshow(cells, cmap="Blues", vmin=0, vmax=max(int(cells.max()), 1))
    ax.grid(False)
    for (r, c), v in np.ndenumerate(cells):
        ax.text(c, r, str(int(v)), ha="center", va="center", fontsize=9,
                color="white" if v > 0.6 * max(cells.max(), 1) else "black")
    ax.set_xticks([0, 1], ["failed", "succeeded"])
    ax.set_yticks([0, 1], [f"{flag} = no", f"{flag} = yes"])
    ax.set_xlabel("measured outcome [trials]")
    ax.set_title(title, loc="left")

    def line(name, key):
        ours = getattr(m, key) if m is not None else math.nan
        return f"{name}: ours {fmt(ours, 2)} | paper {fmt(paper_value(paper, key), 2)}"

    text = "\n".join([f"n = {int(p.size)}", line("accuracy", "accuracy"),
                      line("precision", "precision"), line("recall", "recall"),
                      line("F1", "f1")])
    ax.legend(handles=[Patch(color="none", label=text)], loc="upper left",
              bbox_to_anchor=(1.02, 1.0), fontsize=7, handlelength=0)


def planners_in_order(df: pd.DataFrame) -> list[str]:
    """The planners present in ``df``, Table 7's order first, any others sorted after."""
    present = set(df["planner"])
    return [p for p in PLANNER_ORDER if p in present] + sorted(present - set(PLANNER_ORDER))


# =============================================================================================
# The Test 2 section
# =============================================================================================
DEPARTURES_T2 = (
    "Known departures of this model from the paper's hardware (docs/decisions.md, issue 9): "
    "the hardware score H~ has no gravity term, so the proposed planner's triples reach a lower "
    "geometric efficiency G_geo than the centroid planner's horizontal triangle and it succeeds "
    "less often than the centroid planner here; the residual-based `predicted_stable` flag "
    "(τ_F = 0.0886 N, §8.1) almost never certifies at the SI bench constants, so the §8.4 "
    "classifier is nearly degenerate; vision and force noise are small, so the force errors are "
    "far below the paper's.")


def section(report: Report, records: pd.DataFrame, manifest: dict, store=None) -> None:
    """Write the Test 2 section: counts, Tables 6-7, §8 claims, Figs. 28-31, power."""
    from graspcampaign.analysis import hardware as an

    paper = manifest["config"]["paper"]  # the typed paper values (build._legacy)
    report.text(source_note(records, manifest, "One record per commanded attempt of the Test 2 "
                            "sheet (§8.1; `graspcampaign schedule test2_grasp`).", DEPARTURES_T2))
    recs = ok_records(records)
    ex = executed(recs)
    if not len(ex):
        report.text("No executed Test 2 trials to report.")
        return
    counts_table(report, "test2_counts", records, paper, "planner", planners_in_order(ex),
                 {p: paper_value(paper, "table7", p, "n") for p in PLANNER_ORDER},
                 "Test 2 trial counts (§8.1), ours beside the paper's; a reduced study (params) "
                 "has proportionally fewer")
    _table6(report, ex, an, paper)
    _table7(report, recs, ex, an, paper, int((manifest.get("config") or {}).get("seed", 0)))
    _claims(report, recs, ex, an, paper)
    _extra_tables(report, recs, an)
    fig28(report, ex, an, paper)
    fig29(report, ex, an, paper)
    fig30(report, ex, paper)
    fig31(report, recs, ex, an, paper)
    _power(report, recs, an, paper)


# -- tables ------------------------------------------------------------------------------------
def _table6(report: Report, ex: pd.DataFrame, an, paper: dict) -> None:
    ref = paper_value(paper, "table6")
    summary = an.shape_summary(ex).set_index("shape")
    prop = ex[ex["planner"] == "heuristic"]
    rows, items = [], []
    for shape in [s for s in SHAPE_ORDER if s in summary.index]:
        g = prop[prop["shape"] == shape]
        nat = g[g["friction_level"] == "natural"]
        p = paper_value(ref, shape)
        s_pct, s_lo, s_hi = wilson_pct(int(g["success"].sum()), len(g))
        n_pct, n_lo, n_hi = wilson_pct(int(nat["success"].sum()), len(nat))
        r = summary.loc[shape]
        row = {"shape": shape, "n": len(g), "paper_n": paper_value(p, "n"),
               "success_pct": s_pct, "success_low_pct": s_lo, "success_high_pct": s_hi,
               "paper_success_pct": paper_value(p, "success_pct"),
               "natural_n": len(nat), "natural_success_pct": n_pct,
               "natural_low_pct": n_lo, "natural_high_pct": n_hi,
               "paper_natural_pct": paper_value(p, "natural_pct"),
               "force_err_pct": r["force_err_pct"], "paper_force_err_pct": paper_value(p, "force_err_pct"),
               "deformation_err_pct": r["deformation_err_pct"],
               "paper_deformation_err_pct": paper_value(p, "deformation_err_pct"),
               "flagged_n": int(r["flagged_n"]), "flagged_success_pct": r["flagged_success_pct"]}
        row["verdict"] = compare(s_pct, paper_value(p, "success_pct"), n=len(g), low=s_lo,
                                 high=s_hi)[1]
        rows.append(row)
        label = SHAPE_LABELS[shape]
        for q, o, pv, lo, hi, n in (
                ("success", s_pct, paper_value(p, "success_pct"), s_lo, s_hi, len(g)),
                ("natural-friction success", n_pct, paper_value(p, "natural_pct"), n_lo, n_hi, len(nat)),
                ("median |F_n| error", r["force_err_pct"], paper_value(p, "force_err_pct"), None, None,
                 len(g)),
                ("median deformation error", r["deformation_err_pct"],
                 paper_value(p, "deformation_err_pct"), None, None, len(g))):
            items.append((f"{label}, {q}", *compare(o, pv, n=n, low=lo, high=hi)))
    full = pd.DataFrame(rows)

    def vs(o, lo, hi, pv):
        return f"{fmt_ci(o, lo, hi)} vs {fmt(pv)}"

    display = pd.DataFrame({
        "shape": [SHAPE_LABELS[s] for s in full["shape"]],
        "n (paper)": [f"{n} ({fmt(pn)})" if not _missing(pn) else str(n)
                      for n, pn in zip(full["n"], full["paper_n"], strict=True)],
        "success % (Wilson) vs paper": [vs(*v) for v in full[
            ["success_pct", "success_low_pct", "success_high_pct", "paper_success_pct"]]
            .itertuples(index=False)],
        "Δ pp": [fmt_signed(o - pv if not _missing(pv) else math.nan) for o, pv in
                 zip(full["success_pct"], full["paper_success_pct"], strict=True)],
        "natural friction % (n) vs paper": [f"{fmt_ci(o, lo, hi)} (n={n}) vs {fmt(pv)}" for
                                             o, lo, hi, n, pv in full[
            ["natural_success_pct", "natural_low_pct", "natural_high_pct", "natural_n",
             "paper_natural_pct"]].itertuples(index=False)],
        "F_n err % vs paper": [f"{fmt(o)} vs {fmt(pv)}" for o, pv in
                               zip(full["force_err_pct"], full["paper_force_err_pct"],
                                   strict=True)],
        "deform. err % vs paper": [f"{fmt(o)} vs {fmt(pv)}" for o, pv in
                                   zip(full["deformation_err_pct"],
                                       full["paper_deformation_err_pct"], strict=True)],
    })
    report.table("table6", full, "Table 6 (ours beside the paper's): the proposed planner per "
                 "shape over all its trials (group C included), the natural-friction subset, and "
                 "median absolute errors of the trial-mean normal force and deformation "
                 "predictions; rates with Wilson 95 % intervals", display=display)
    add_differences(report, "Table 6", items)


def _table7(report: Report, recs: pd.DataFrame, ex: pd.DataFrame, an, paper: dict,
            seed: int) -> None:
    ref = paper_value(paper, "table7")
    summary = an.planner_summary(recs, seed=seed).set_index("planner")
    rows, items = [], []
    cols = (("stable", "stable_pct", "stable"), ("slip", "slip_pct", "failure_slip"),
            ("drop", "drop_pct", "failure_drop"), ("damage", "damage_pct", "failure_damage"))
    for planner in planners_in_order(ex):
        g = ex[ex["planner"] == planner]
        p = paper_value(ref, planner)
        s = summary.loc[planner]
        row = {"planner": planner, "n": len(g), "paper_n": paper_value(p, "n"),
               "success_pct": s["success_pct"], "wilson_low_pct": s["wilson_low_pct"],
               "wilson_high_pct": s["wilson_high_pct"],
               "bootstrap_low_pct": s["bootstrap_low_pct"],
               "bootstrap_high_pct": s["bootstrap_high_pct"], "n_objects": int(s["n_objects"]),
               "paper_success_pct": paper_value(p, "success_pct")}
        label = PLANNER_LABELS.get(planner, planner)
        items.append((f"{label}, success", *compare(
            s["success_pct"], paper_value(p, "success_pct"), n=len(g), low=s["wilson_low_pct"],
            high=s["wilson_high_pct"])))
        row["verdict"] = items[-1][2]
        for name, key, outcome in cols:
            k = int((g["outcome"] == outcome).sum())
            pct, lo, hi = wilson_pct(k, len(g))
            row.update({key: pct, f"{name}_low_pct": lo, f"{name}_high_pct": hi,
                        f"paper_{key}": paper_value(p, key)})
            items.append((f"{label}, {name} rate", *compare(pct, paper_value(p, key), n=len(g), low=lo,
                                                           high=hi)))
        row["partial_pct"] = s["partial_pct"]
        row["contact_loss_pct"] = s["contact_loss_pct"]
        rows.append(row)
    full = pd.DataFrame(rows)

    def cell(r, key, name):
        return (f"{fmt_ci(r[key], r[f'{name}_low_pct'], r[f'{name}_high_pct'])} vs "
                f"{fmt(r[f'paper_{key}'])}")

    display = pd.DataFrame({
        "planner": [PLANNER_LABELS.get(p, p) for p in full["planner"]],
        "n (paper)": [f"{n} ({fmt(pn)})" if not _missing(pn) else str(n)
                      for n, pn in zip(full["n"], full["paper_n"], strict=True)],
        "success % (Wilson) [object bootstrap] vs paper": [
            f"{fmt_ci(r['success_pct'], r['wilson_low_pct'], r['wilson_high_pct'])} "
            f"[{fmt(r['bootstrap_low_pct'])}{DASH}{fmt(r['bootstrap_high_pct'])}] vs "
            f"{fmt(r['paper_success_pct'])}" for r in full.to_dict("records")],
        "Δ pp": [fmt_signed(o - pv if not _missing(pv) else math.nan) for o, pv in
                 zip(full["success_pct"], full["paper_success_pct"], strict=True)],
        **{f"{name} % vs paper": [cell(r, key, name) for r in full.to_dict("records")]
           for name, key, _ in cols},
    })
    report.table("table7", full, "Table 7 (ours beside the paper's): executed trials per planner; "
                 "success with its Wilson 95 % interval and the object-clustered bootstrap "
                 f"(objects resampled, {stats.BOOTSTRAP_RESAMPLES} resamples, seed {seed}); "
                 "stable, slip, drop and damage as "
                 "primary outcome classes, each with its Wilson interval", display=display)
    add_differences(report, "Table 7", items)


def _claims(report: Report, recs: pd.DataFrame, ex: pd.DataFrame, an, paper: dict) -> None:
    prop = ex[ex["planner"] == "heuristic"]
    rows = []

    def rate(q, where, mask, pv):
        rows.append(claim_rate(q, where, int(mask.sum()), len(mask), pv))

    abd = prop[prop["group"].isin(["A", "B", "D"])]
    rate("proposed success, groups A, B, D", "§8.2", abd["success"], paper_value(paper,
        "validation_success_pct"))
    rate("proposed success, all its trials", "§8.5", prop["success"],
         paper_value(paper, "proposed_success_pct"))
    rate("proposed success, group C (failure boundary)", "§8.6",
         prop.loc[prop["group"] == "C", "success"], paper_value(paper, "group_c_pct"))
    rate("proposed stable holds", "§8.2, Fig. 28c", prop["outcome"] == "stable",
         paper_value(paper, "proposed_stable_pct"))
    rate("proposed marginal successes", "§8.2, Fig. 28c", prop["outcome"] == "success",
         paper_value(paper, "proposed_marginal_pct"))
    rate("proposed drop + damage + contact loss", "§8.2, Fig. 28c",
         prop["outcome"].isin(["failure_drop", "failure_damage", "failure_contact_loss"]),
         paper_value(paper, "proposed_drop_damage_contact_pct_max"))
    for m in MATERIAL_ORDER:
        g = ex[ex["material"] == m]
        if len(g):
            rate(f"success on {MATERIAL_LABELS[m]}, all planners", "§8.2, Fig. 28b",
                 g["success"], paper_value(paper, "success_by_material_pct", m))
    acc = an.force_accuracy(recs).set_index("scope")
    if "all" in acc.index:
        a = acc.loc["all"]
        rows.append(claim("parity slope (through origin)", "§8.3, Fig. 29a",
                          a.get("parity_slope"), paper_value(paper, "parity_slope"), n=a["n"], unit="",
                          digits=3))
        rows.append(claim("parity R² (uncentred)", "§8.3, Fig. 29a", a.get("parity_r2"),
                          paper_value(paper, "parity_r2"), n=a["n"], unit="", digits=3))
        rows.append(claim("median |normal-force error|", "§8.3, Fig. 29b", a["force_err_pct"],
                          paper_value(paper, "force_err_median_pct"), n=a["n"]))
        rows.append(claim("median |deformation error|", "§8.3, Fig. 29c",
                          a["deformation_err_pct"], paper_value(paper, "deformation_err_median_pct"),
                          n=a["n"]))
        rows.append(claim("median contact-point error", "§8.3", a["contact_point_err_mm"],
                          paper_value(paper, "contact_point_err_median_mm"), n=a["n"], unit="mm"))
    clf = paper_value(paper, "classifier")
    for scope, g, ref in (("all planners", ex, clf),
                          ("proposed planner", prop, paper_value(paper, "classifier_proposed"))):
        flag_claims(rows, f"stability flag {{}}, {scope}", "§8.4, Fig. 31c",
                    g["predicted_stable"], g["success"], ref)
    base = ex[ex["planner"] != "heuristic"]
    bp, ba = base["predicted_stable"].to_numpy(bool), base["success"].to_numpy(bool)
    rows.append(claim_fraction("stability flag precision, baselines", "§8.4",
                               int(np.sum(bp & ba)), int(bp.sum()),
                               paper_value(paper, "classifier_baselines_precision")))
    c = prop[prop["group"] == "C"]
    cp, ca = c["predicted_stable"].to_numpy(bool), c["success"].to_numpy(bool)
    rows.append(claim_fraction("stability flag precision, group C", "§8.1, §8.4",
                               int(np.sum(cp & ca)), int(cp.sum()),
                               paper_value(paper, "classifier_group_c_precision")))
    matched = ex[ex["matched"].astype(bool)]
    for planner in planners_in_order(matched):
        g = matched[matched["planner"] == planner]
        rate(f"matched ablation success, {PLANNER_LABELS.get(planner, planner)}",
             "§8.5, Fig. 31b", g["success"], paper_value(paper, "matched_pct", planner))
    mc = an.matched_mcnemar(recs).set_index("baseline")
    ref = paper_value(paper, "mcnemar_centroid")
    if "centroid" in mc.index:
        r = mc.loc["centroid"]
        rows.append(claim("McNemar χ² proposed vs centroid (matched)", "§8.5", r["chi2"],
                          paper_value(ref, "chi2"), n=r["n_pairs"], unit="", digits=1))
        rows.append(claim("pairs won by proposed (vs centroid)", "§8.5", r["won"], paper_value(ref, "won"),
                          n=r["n_pairs"], unit="", digits=0))
        rows.append(claim("pairs lost by proposed (vs centroid)", "§8.5", r["lost"],
                          paper_value(ref, "lost"), n=r["n_pairs"], unit="", digits=0))
        rows.append(claim("discordant-pair odds ratio", "§8.5", r["odds_ratio"],
                          paper_value(ref, "odds_ratio"), n=r["n_pairs"], low=r["odds_ratio_low"],
                          high=r["odds_ratio_high"], unit="", digits=1))
    chi = an.planner_chi2(recs).iloc[0]
    rows.append(claim("χ² planner × success (proposed, centroid, random)", "§8.5", chi["chi2"],
                      paper_value(paper, "chi2_planner_success"), n=chi["n"], unit="", digits=1))
    kw = an.force_error_kruskal(recs).iloc[0]
    rows.append(claim("Kruskal–Wallis p, force error across planners", "§8.5", kw["p"],
                      paper_value(paper, "force_err_kruskal_p"), n=kw["n"], unit="", digits=None))
    sk = an.slip_friction_kruskal(recs).iloc[0]
    rows.append(claim("Kruskal–Wallis H, slip across friction levels", "§8.6", sk["H"],
                      paper_value(paper, "slip_friction_kruskal_h"), n=sk["n"], unit="", digits=1))
    e = prop[prop["group"] == "E"]
    lo_hi = paper_value(paper, "group_e_success_pct_range")
    for col, unit in (("closing_speed_mm_per_s", "closing"), ("lift_speed_mm_per_s", "lift")):
        for speed, g in e.groupby(col):
            rate(f"group E success, {unit} {speed:g} mm/s", "§8.6", g["success"], lo_hi[0])
    claims_table(report, "test2_claims", rows,
                 "§8 headline numbers, ours beside the paper's (rates [%] and proportions with "
                 "Wilson 95 % intervals and n; for group E the paper gives a 90–100 % range and "
                 "its lower end is shown)")


def _extra_tables(report: Report, recs: pd.DataFrame, an) -> None:
    report.table("test2_groups", with_intervals(an.group_summary(recs),
                                                ["success_pct", "stable_pct"]),
                 "Proposed planner per group (A-E, M matched ablation), the validation pool ABD, "
                 "and group E per closing and lift speed: success and stable rates [%] with "
                 "Wilson 95 % bounds")
    report.table("test2_force_accuracy", an.force_accuracy(recs),
                 "Force and deformation prediction accuracy per planner (§8.3): parity slope "
                 "through the origin, uncentred and centred R², median absolute errors [%], "
                 "median contact-point error [mm]")
    report.table("test2_classifier", an.stability_classifier(recs),
                 "The pre-execution flag `predicted_stable` (predicted residual ≤ τ_F = 0.0886 N) "
                 "scored against measured success (§8.4), per planner and inside/outside group C")
    report.table("test2_mcnemar", an.matched_mcnemar(recs),
                 "Matched ablation (§8.5): McNemar tests of the proposed planner against each "
                 "baseline on occurrence-matched pairs (object, condition, repeat)")
    tests = pd.concat([an.planner_chi2(recs).assign(test="chi2 planner x success"),
                       an.force_error_kruskal(recs).assign(test="Kruskal-Wallis force error"),
                       an.slip_friction_kruskal(recs).assign(test="Kruskal-Wallis slip")],
                      ignore_index=True)
    report.table("test2_tests", tests, "χ² of planner × success and Kruskal–Wallis tests (§8.5, "
                 "§8.6), no multiplicity correction (as the paper)")


def _power(report: Report, recs: pd.DataFrame, an, paper: dict) -> None:
    mc = an.matched_mcnemar(recs).set_index("baseline")
    matched = paper_value(paper, "matched_pct")
    rows = []
    if paper_value(matched, "heuristic") and paper_value(matched, "centroid"):
        rows.append(an.power_analysis(matched["heuristic"] / 100, matched["centroid"] / 100)
                    .assign(rates="paper matched: proposed vs centroid"))
    if paper_value(matched, "heuristic") and paper_value(matched, "no_pso"):
        rows.append(an.power_analysis(matched["heuristic"] / 100, matched["no_pso"] / 100)
                    .assign(rates="paper matched: proposed vs no-PSO"))
    if "centroid" in mc.index:
        p1, p2 = mc.loc["centroid", "proposed_success_pct"], mc.loc["centroid",
                                                                   "baseline_success_pct"]
        if 0 < p1 < 100 and 0 < p2 < 100 and p1 != p2:
            rows.append(an.power_analysis(p1 / 100, p2 / 100)
                        .assign(rates="ours matched: proposed vs centroid"))
    if rows:
        table = pd.concat(rows, ignore_index=True)
        report.table("test2_power", table,
                     "Power analysis (§8.5, §11: the ablation lacked power): trials per arm to "
                     "detect the success-rate difference p1 vs p2 at α = 0.05 (independent arms: "
                     "Cohen's h; paired: McNemar, Connor 1987); the paper's matched set has 90 "
                     "per planner")


# -- figures -------------------------------------------------------------------------------------
def fig28(report: Report, ex: pd.DataFrame, an, paper: dict) -> None:
    """Fig. 28: (a) proposed success per shape; (b) per material, all planners; (c) outcomes."""
    with mpl.rc_context(RC):
        fig, (ax_a, ax_b, ax_c) = new_figure(ex, "Fig. 28: grasp-validation outcomes",
                                             (12.0, 3.9), 3)
        prop = ex[ex["planner"] == "heuristic"]
        shapes = [s for s in SHAPE_ORDER if s in set(prop["shape"])]
        ref = paper_value(paper, "table6")
        rate_bars(ax_a, [SHAPE_LABELS[s].replace(" (", "\n(") for s in shapes],
                  [int(prop.loc[prop["shape"] == s, "success"].sum()) for s in shapes],
                  [int((prop["shape"] == s).sum()) for s in shapes],
                  [PLANNER_COLOURS["heuristic"]] * len(shapes),
                  [paper_value(ref, s, "success_pct") for s in shapes])
        ax_a.axhline(float(paper.fig28_reference_pct), color="#555555", linestyle="--", linewidth=1.0)
        ax_a.set_ylabel("success rate [%]")
        ax_a.set_title("(a) proposed planner, by shape", loc="left")
        ax_a.tick_params(axis="x", labelsize=7)

        mats = [m for m in MATERIAL_ORDER if m in set(ex["material"])]
        ref_m = paper_value(paper, "success_by_material_pct")
        labels = [f"{MATERIAL_LABELS[m]}\nE = {FAMILIES[m].modulus_mean / 1e3:.0f} kPa"
                  for m in mats]
        rate_bars(ax_b, labels, [int(ex.loc[ex["material"] == m, "success"].sum()) for m in mats],
                  [int((ex["material"] == m).sum()) for m in mats], ["#8aa9d6"] * len(mats),
                  [paper_value(ref_m, m) for m in mats])
        ax_b.set_ylabel("success rate, all planners [%]")
        ax_b.set_title("(b) by material (Test 1 modulus, Table 4)", loc="left")
        ax_b.tick_params(axis="x", labelsize=7)

        t7 = paper_value(paper, "table7", "heuristic")
        ref_o = {"stable": paper_value(t7, "stable_pct"), "success": paper.proposed_marginal_pct,
                 "failure_slip": paper_value(t7, "slip_pct"), "failure_drop": paper_value(t7, "drop_pct"),
                 "failure_damage": paper_value(t7, "damage_pct")}
        colours = ["#2e7d32", "#81c784", "#ffb74d", "#e57373", "#c62828", "#6d4c41", "#757575"]
        rate_bars(ax_c, [OUTCOME_LABELS[o] for o in OUTCOME_ORDER],
                  [int((prop["outcome"] == o).sum()) for o in OUTCOME_ORDER],
                  [len(prop)] * len(OUTCOME_ORDER), colours, [ref_o.get(o) for o in OUTCOME_ORDER])
        ax_c.set_ylabel("share of the proposed planner's trials [%]")
        ax_c.set_title("(c) outcome classes, proposed planner", loc="left")
        ax_c.tick_params(axis="x", labelsize=6.5)
        fig.legend(handles=[Patch(color=PLANNER_COLOURS["heuristic"], label="ours, proposed"),
                            Patch(color="#8aa9d6", label="ours, all planners"), ci_handle(),
                            paper_handle("paper's value (Tables 6-7, §8.2)"),
                            Line2D([], [], color="#555555", linestyle="--",
                                   label="75 % reference")],
                   loc="outside lower center", ncol=5)
    report.figure("fig28_outcomes", fig,
                  "Fig. 28 (ours, paper's values as black diamonds): (a) proposed-planner success "
                  "by shape over all its trials, dashed 75 % reference; (b) success by material "
                  "over all planners, labelled with the Test 1 modulus; (c) outcome classes of "
                  "the proposed planner. Bars: Wilson 95 % intervals; n above each bar.")


def fig29(report: Report, ex: pd.DataFrame, an, paper: dict) -> None:
    """Fig. 29: (a) parity of trial-mean normal force; (b, c) force and deformation errors."""
    ok = ex[np.isfinite(ex["normal_force_mean_n"].astype(float))
            & np.isfinite(ex["normal_force_pred_mean_n"].astype(float))]
    pred = ok["normal_force_pred_mean_n"].astype(float).to_numpy()
    meas = ok["normal_force_mean_n"].astype(float).to_numpy()
    with mpl.rc_context(RC):
        fig, (ax_a, ax_b, ax_c) = new_figure(ex, "Fig. 29: force and deformation prediction "
                                             "accuracy", (12.0, 3.8), 3)
        for planner in planners_in_order(ok):
            sel = (ok["planner"] == planner).to_numpy()
            ax_a.scatter(pred[sel], meas[sel], s=7, alpha=0.5,
                         color=PLANNER_COLOURS.get(planner, "#888888"),
                         label=PLANNER_LABELS.get(planner, planner), rasterized=True)
        top = float(max(pred.max(initial=1.0), meas.max(initial=1.0))) * 1.05
        grid = np.linspace(0.0, top, 50)
        ax_a.plot(grid, grid, color="#777777", linestyle=":", label="identity")
        if len(pred) >= 2 and np.any(pred != 0):
            fit = stats.parity_fit(meas, pred)
            ax_a.plot(grid, fit.slope_through_origin * grid, color=PLANNER_COLOURS["heuristic"],
                      label=f"ours: slope {fit.slope_through_origin:.2f}, "
                            f"R² {fit.r2_uncentred:.2f} (n={fit.n})")
        if not _missing(paper_value(paper, "parity_slope")):
            ax_a.plot(grid, float(paper.parity_slope) * grid, color=PAPER, linestyle="--",
                      label=f"paper: slope {paper.parity_slope}, R² {paper.parity_r2}")
        ax_a.set_xlabel("predicted trial-mean normal force [N]")
        ax_a.set_ylabel("measured trial-mean normal force [N]")
        ax_a.set_title("(a) parity, all planners", loc="left")
        ax_a.legend(loc="upper left", fontsize=6.5)
        for ax, (mcol, pcol, name, key) in zip(
                (ax_b, ax_c),
                (("normal_force_mean_n", "normal_force_pred_mean_n", "normal-force",
                  "force_err_median_pct"),
                 ("deformation_mean_mm", "deformation_pred_mean_mm", "deformation",
                  "deformation_err_median_pct")), strict=True):
            m = ex[mcol].astype(float).to_numpy()
            p = ex[pcol].astype(float).to_numpy()
            keep = np.isfinite(m) & np.isfinite(p) & (m != 0)
            err = 100.0 * np.abs(p[keep] - m[keep]) / np.abs(m[keep])
            hi = float(np.percentile(err, 98)) if err.size else 1.0
            ax.hist(np.clip(err, 0, hi), bins=40, color="#8aa9d6",
                    label=f"ours (n={err.size}; clipped at the 98th percentile)")
            if err.size:
                ax.axvline(float(np.median(err)), color=PLANNER_COLOURS["heuristic"],
                           label=f"ours: median {np.median(err):.1f} %")
            if not _missing(paper_value(paper, key)):
                ax.axvline(float(paper_value(paper, key)), color=PAPER, linestyle="--",
                           label=f"paper: median {paper_value(paper, key)} %")
            ax.set_xlabel(f"absolute {name} prediction error [%]")
            ax.set_ylabel("trials [count]")
            ax.legend(loc="upper right", fontsize=6.5)
        ax_b.set_title("(b) normal-force error", loc="left")
        ax_c.set_title("(c) deformation error", loc="left")
    report.figure("fig29_prediction_accuracy", fig,
                  "Fig. 29 (ours, paper's values dashed black): (a) predicted vs measured "
                  "trial-mean normal force with the identity and the through-origin fits; "
                  "(b) absolute normal-force and (c) deformation prediction errors, medians "
                  "marked.")


def sheet_id(trial: pd.Series) -> str:
    """The sheet's id of a recorded trial (what the rig's operator reads)."""
    return str(trial["rig_trial_id"] if "rig_trial_id" in trial else trial["trial_id"])


def representative(df: pd.DataFrame, column: str) -> pd.Series | None:
    """The trial whose ``column`` is the median of ``df``'s (ties: first in sheet order)."""
    values = df[column].astype(float)
    df = df[np.isfinite(values)]
    if not len(df):
        return None
    values = df[column].astype(float)
    order = df.assign(_d=(values - float(np.median(values))).abs()).sort_values(
        ["_d", "run_order"], kind="stable")
    return order.iloc[0]


def fig30(report: Report, ex: pd.DataFrame, paper: dict) -> None:
    """Fig. 30: phases of a representative successful sphere grasp with its recorded values.

    The records hold per-trial summaries, not time series: the phase timing is drawn from the
    commanded speeds (closing, lift at 0.3 m/s² to 50 mm, 3 s hold) and the recorded hold
    values (per-finger normal force, peak slip) are drawn as levels over the hold.
    """
    from graspcampaign.core.disturbance import A_LIFT
    lift_height_mm = float(paper.lift_height_mm)

    pool = ex[(ex["planner"] == "heuristic") & (ex["shape"] == "sphere")
              & (ex["outcome"] == "stable") & (ex["friction_level"] == "natural")]
    trial = representative(pool, "normal_force_mean_n")
    if trial is None:
        report.text("Fig. 30 not drawn: no stable proposed-planner sphere trial.")
        return
    closing = float(trial["closing_speed_mm_per_s"])
    v_lift = float(trial["lift_speed_mm_per_s"]) * 1e-3
    t_close = 10.0 / closing  # 10 mm approach at the commanded closing speed (drawing only)
    t_acc = v_lift / A_LIFT
    t_lift = lift_height_mm * 1e-3 / v_lift + t_acc
    hold = float(trial["hold_s"])
    t0, t1, t2 = t_close, t_close + t_lift, t_close + t_lift + hold
    t = np.linspace(0.0, t2, 600)
    height = np.clip((t - t0 - t_acc / 2) / (t_lift - t_acc), 0.0, 1.0) * lift_height_mm
    with mpl.rc_context(RC):
        fig, (ax_f, ax_z) = new_figure(ex, "Fig. 30: representative successful grasp "
                                       f"({sheet_id(trial)})", (9.5, 5.4), 1, nrows=2,
                                       sharex=True)
        for ax in (ax_f, ax_z):
            for (a, b, name, c) in ((0.0, t0, "closing", "#e3f2fd"), (t0, t1, "lift", "#fff8e1"),
                                    (t1, t2, "hold (graded)", "#e8f5e9")):
                ax.axvspan(a, b, color=c, zorder=0, label=name if ax is ax_f else None)
        colours = ("#1b9e77", "#d95f02", "#7570b3")
        for j in (1, 2, 3):
            f = float(trial[f"normal_force_{j}_n"])
            ax_f.hlines(f, t0, t2, color=colours[j - 1], label=f"finger {j}: {f:.2f} N (recorded)")
        pred = float(trial["normal_force_pred_mean_n"])
        ax_f.hlines(pred, t0, t2, color="#333333", linestyle=":",
                    label=f"predicted per-finger mean {pred:.2f} N")
        band = paper_value(paper, "hold_force_per_finger_n")
        if band:
            ax_f.axhspan(band[0], band[1], color=PAPER, alpha=0.12,
                         label=f"paper: steady hold {band[0]}–{band[1]} N per finger")
        ax_f.set_ylabel("normal force per finger [N]")
        ax_f.set_ylim(0.0, max(2.0, 1.2 * float(trial["normal_force_mean_n"])))
        ax_f.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=6.5)
        ax_f.set_title("(top) recorded hold forces (the records hold no force time series)",
                       loc="left")
        ax_z.plot(t, height, color="#333333", label="lift height, commanded profile")
        ax_z.set_ylabel("lift height [mm]")
        ax_s = ax_z.twinx()
        slip = float(trial["peak_slip_mm"])
        ax_s.hlines(slip, t1, t2, color="#c62828", label=f"peak slip {slip:.2f} mm (recorded)")
        ax_s.axhline(2.0, color="#c62828", linestyle="--", linewidth=1.0,
                     label="2 mm success criterion")
        if paper_value(paper, "hold_slip_max_mm") is not None:
            ax_s.axhline(float(paper.hold_slip_max_mm), color=PAPER, linestyle=":",
                         label=f"paper: slip below {paper.hold_slip_max_mm} mm")
        ax_s.set_ylim(0.0, 3.0)
        ax_s.set_ylabel("slip [mm]", color="#c62828")
        ax_s.grid(False)
        ax_z.set_xlabel("time from the start of closing [s] (10 mm approach drawn)")
        handles = ax_z.get_legend_handles_labels()[0] + ax_s.get_legend_handles_labels()[0]
        ax_z.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.08, 1.0), fontsize=6.5)
        ax_z.set_title("(bottom) commanded lift and the recorded peak slip", loc="left")
    report.figure("fig30_representative_grasp", fig,
                  "Fig. 30 (schematic of one recorded trial): phases timed from the commanded "
                  "closing and lift speeds, the trial's recorded per-finger hold forces, its "
                  "predicted force and its peak slip as levels over the hold. The records keep "
                  "per-trial values only, so no transient is drawn; the paper's hold band and "
                  "slip are marked in black.")


def fig31(report: Report, recs: pd.DataFrame, ex: pd.DataFrame, an, paper: dict) -> None:
    """Fig. 31: (a) success per planner; (b) matched ablation; (c) stability confusion matrix."""
    planners = planners_in_order(ex)
    matched = ex[ex["matched"].astype(bool)]
    ref7 = paper_value(paper, "table7")
    refm = paper_value(paper, "matched_pct")
    with mpl.rc_context(RC):
        fig, (ax_a, ax_b, ax_c) = new_figure(ex, "Fig. 31: planner comparison and stability "
                                             "classification", (13.0, 3.9), 3)
        colours = [PLANNER_COLOURS.get(p, "#888888") for p in planners]
        labels = [PLANNER_LABELS.get(p, p) for p in planners]
        rate_bars(ax_a, labels, [int(ex.loc[ex["planner"] == p, "success"].sum()) for p in planners],
                  [int((ex["planner"] == p).sum()) for p in planners], colours,
                  [paper_value(ref7, p, "success_pct") for p in planners])
        ax_a.set_ylabel("success rate [%]")
        ax_a.set_title("(a) all executed trials", loc="left")
        ax_a.legend(handles=[ci_handle(), paper_handle()], loc="upper right", fontsize=6.5)
        mp = [p for p in planners if p in set(matched["planner"])]
        rate_bars(ax_b, [PLANNER_LABELS.get(p, p) for p in mp],
                  [int(matched.loc[matched["planner"] == p, "success"].sum()) for p in mp],
                  [int((matched["planner"] == p).sum()) for p in mp],
                  [PLANNER_COLOURS.get(p, "#888888") for p in mp], [paper_value(refm, p) for p in mp])
        ax_b.set_ylabel("success rate [%]")
        ax_b.set_title("(b) matched ablation (same objects and conditions)", loc="left")
        ax_b.legend(handles=[ci_handle(), paper_handle()], loc="upper right", fontsize=6.5)
        for ax in (ax_a, ax_b):
            ax.tick_params(axis="x", labelsize=7)
        confusion_panel(ax_c, ex["predicted_stable"], ex["success"],
                        "(c) predicted_stable vs measured success", paper_value(paper, "classifier"),
                        "predicted_stable")
    report.figure("fig31_planner_comparison", fig,
                  "Fig. 31 (ours, paper's values as black diamonds): (a) success per planner "
                  "over all executed trials and (b) on the matched ablation, Wilson 95 % "
                  "intervals, n above each bar; (c) the pre-execution stability flag against the "
                  "measured outcome, our metrics beside the paper's.")
