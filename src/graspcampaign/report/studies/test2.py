"""Report of ``test2_grasp`` (§8; Tables 6-7, Figs. 28-31) and the parts Test 3 shares; on the virtual rig
Tables 6-9 show the records and their ``belief_error = none`` counterfactual (trace table ``belief_none``)."""

from __future__ import annotations

from dataclasses import asdict

import numpy as np
import pandas as pd

from graspcampaign.analysis import hardware as hw
from graspcampaign.analysis.rates import power_two_proportions
from graspcampaign.analysis.records import Estimate, known
from graspcampaign.analysis.vocabulary import PROPOSED, colour, label, things
from graspcampaign.report import format as fmt
from graspcampaign.report import style
from graspcampaign.report.document import Col, Figure, Table, cols, pct_col
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Claims, Finding, Paired, Rates, ReportSpec, paper_of, share, verdicts
from graspcampaign.report.studies.flags import RESIDUAL, classifier, confusion, group_c, scores
from graspcampaign.report.studies.opening import ex, finding, frames

PLANNERS, ME = ("heuristic", "centroid", "no_pso", "force_balance", "random"), f"planner == '{PROPOSED}'"
READINGS, PAPER_ROWS = {"belief_error": ["paper", "none"]}, "belief_error == 'paper'"


# --------------------------------------------------------------------------- shared with Test 3
def paper_table(name, caption, key, row, items, rates=(), medians=(), *, where=None, boot=False,
                extra=None) -> Table:
    """A :func:`hw.summary` table per ``key`` and belief reading; items ``(column, paper, header, digits)``: a
    rate (digits None), number or text ("") beside ``paper``: ``row(p, key)``'s attribute or ``f(p, key)``
    (column ``paper_<column>``; the paper's count of trials ``n_paper``)."""
    def columns(col: str, digits) -> tuple[str, str]:
        """An item's column and the column of the paper's value beside it."""
        c = f"{col}{'_pct' * (digits is None)}"
        return c, "n_paper" if c == "n" else f"paper_{c}"

    def compute(run: Run) -> pd.DataFrame:
        d = frames(run) if where is None else where(frames(run))
        out = hw.summary(d, [key, "belief_error"], rates, medians, order=READINGS, seed=run.seed,
                         cluster="object_id" if boot else None)
        for col, paper, _, digits in (i for i in items if i[1]):
            out[columns(col, digits)[1]] = [None if b != "paper" else paper_of(
                run, paper if callable(paper) else lambda p, k, a=paper: getattr(row(p, k), a), k)
                for k, b in zip(out[key], out["belief_error"], strict=True)]
        out = out.astype({"n_paper": "Int64"}) if "n_paper" in out else out  # a count, missing where none
        out = extra(run, d, out) if extra else out
        return verdicts(out, "success_pct", "paper_success_pct", "success_low_pct", "success_high_pct",
                        unit="%")
    cols = [Col("belief_error", "belief error")]
    for col, paper, head, digits in items:
        c, paper_c = columns(col, digits)
        # the paper's value headed in the unit of ours: "paper %", "paper n", "paper [N]", "paper"
        bracket = head[head.rfind("["):] if head.endswith("]") else ""
        unit = "%" if digits is None else "n" if c == "n" else bracket
        cols += [pct_col(col, head) if digits is None else Col(c, head, digits if digits != "" else None),
                 *[Col(paper_c, f"paper {unit}".rstrip(), 1 if digits is None else digits)] * bool(paper),
                 *[Col("difference", "difference [pp]", 1, signed=True)] * (col == "success"),
                 *[Col("bootstrap_low_pct", "object bootstrap 95% [%]", 1, low="bootstrap_low_pct",
                       high="bootstrap_high_pct", why="bootstrap_why")] * (col == "success" and boot)]
    return Table(name, caption, compute, [*cols, Col("verdict", "verdict (success)")], by=[key])


def per_planner(d: pd.DataFrame) -> dict[str, pd.Series]:
    """Scopes ``all`` and each planner (masks over ``d``)."""
    return {"all": d["planner"].notna(), **{q: d["planner"] == q for q in PLANNERS}}


def counts(table: str):
    """The trial counts (commanded, executed, aborted, errored, per planner) beside the paper's: Test 2's
    (``table7``) from §8.1, Test 3's (``table9``) from §9.1 and, per planner, its Table 9."""
    section, planners = {"table7": ("§8.1", "§8.1"), "table9": ("§9.1", "Table 9")}[table]

    def rows(run: Run):
        r, d, p = run.records, ex(run), run.paper
        yield from ((q, section, v, x, "", 0) for q, v, x in (
            ("commanded attempts", len(r), p.commanded), ("executed trials", len(d), p.executed),
            ("aborted before load (rig faults)", int((r["status"] == "ok").sum()) - len(d), p.aborted),
            ("trial errors (software)", int((r["status"] == "error").sum()), None)))
        yield from ((f"executed, {label('planner', q)}", planners, int((d["planner"] == q).sum()),
                     paper_of(run, lambda p, q: getattr(p, table)[q].n, q), "", 0) for q in PLANNERS)
    return rows


def belief_tables(prefix: str) -> list[Table]:
    """What each planner believes against what the rig realises; its success under both readings."""
    # headers in the finding's symbols (they printed "g geo", "mu s", "sf")
    med = {"g_geo_believed": "G_geo believed", "g_geo_actual": "G_geo actual", "g_geo_gap": "G_geo gap",
           "mu_s_believed": "μ_s believed", "mu_s_actual": "μ_s actual", "mu_s_gap": "μ_s gap",
           "creep_believed": "creep believed", "sf_predicted": "SF predicted", "sf_actual": "SF actual"}
    rates = {c: c.replace("_", " ") for c in ("grip_capped", "valid_geometry", "gate_removed")}

    def beliefs(run: Run) -> pd.DataFrame:
        d, by = frames(run), ["planner", "belief_error"]
        out = hw.summary(d, by, rates, list(med), order=READINGS)
        return out.merge(d.groupby(by)["belief_model"].first(), on=by)

    return [Table(f"{prefix}_belief", "What each planner believes and what the rig realises (§8.1, §9.3; "
                  "rig/belief.py): medians (gap: the median of each trial's believed − actual, not the "
                  "difference of the two medians), grips at the damage cap, valid "
                  "grasps (fingers within the 5 mm fingertip radius), successes the δ ≤ r gate removed",
                  beliefs, [Col("belief_error", "belief error"), Col("belief_model", "belief model"),
                            Col("n", "n"), *(Col(c, f"median {head}", sig=3) for c, head in med.items()),
                            *(pct_col(c, h, of=f"n_{c}") for c, h in rates.items())], by=["planner"]),
            Table(f"{prefix}_belief_pairs", "How much of the ranking the belief mechanism explains: "
                  "success on the same trials with the planners' own beliefs (`paper`) and with the "
                  "trial's actual quantities (`none`, same execution noise); McNemar exact p; rank",
                  lambda run: hw.belief_pairs(frames(run)), [
                      *cols("pairs", "success_paper_pct", "success_none_pct"),
                      Col("difference_pp", "none − paper [pp]", 1, signed=True), Col("compared_only",
                                                                                     "paper only"),
                      Col("reference_only", "none only"), Col("p_exact", "p (exact)", sig=2, why="test_why"),
                      *(Col(f"rank_{r}", f"rank, {r}", 0) for r in ("paper", "none"))],
                  by=["planner"], empty="this run has no `belief_error = none` counterfactual (a real "
                  "rig has no oracle)")]


def matched_mcnemar(name: str, caption: str) -> Table:
    """McNemar of the proposed planner against each baseline on the occurrence-matched pairs, beside
    the paper's (against the centroid planner only)."""
    def paper(p, compared: str) -> str | None:
        m = p.mcnemar_centroid
        return f"χ² {fmt.number(m.chi2)}; {m.won} won, {m.lost} lost" if compared == "centroid" else None

    return Paired(name, caption, pair_on="match_key", paper=paper,
                  trials=lambda run: ex(run)[ex(run)["matched"].astype(bool)])


def legends_below(fig) -> None:
    """Every panel's legend moved under its axes (:func:`style.legend_below`), with the panel's other
    labelled lines: inside, over rates up to 100 %, it covered the paper's marks."""
    for ax in fig.axes:
        if (old := ax.get_legend()) is not None:
            for handle, text in zip(old.legend_handles, old.texts, strict=True):
                handle.set_label(text.get_text())
            handles = [*old.legend_handles, *(h for h, t in zip(*ax.get_legend_handles_labels(), strict=True)
                                               if t not in {x.get_text() for x in old.texts})]
            style.legend_below(ax, handles, ncol=min(len(handles), 3))


def planner_bars(table: str):
    """Panel: success per planner with the planners' own beliefs and with exact ones (hatched)."""
    def draw(run: Run, ax) -> None:
        t = run.tables[table]
        for i, (r, g) in enumerate(t.groupby("belief_error", sort=False)):
            style.bars(ax, np.arange(len(g)) + 0.2 * (2 * i - t["belief_error"].nunique() + 1),
                       g["success_pct"], g["success_low_pct"], g["success_high_pct"],
                       [colour("planner", q) for q in g["planner"]], 0.4, list(g["paper_success_pct"]))
            for patch in ax.patches[-len(g):]:
                patch.set_hatch("//" * (r == "none"))
        ax.set_xticks(np.arange(len(g)), [style.tick_n(label("planner", q), t.loc[t["planner"] == q, "n"])
                                          for q in g["planner"]], fontsize=7)
        style.rate_axes(ax)
        ax.set_title("(a) all trials; hatched: exact beliefs")
        style.legend_below(ax, [style.interval_handle(), style.paper_handle()], ncol=2)
    return draw


def median_trial(trials: pd.DataFrame, column: str) -> pd.Series:
    """The trial whose ``column`` is nearest its median (the first in run order on a tie)."""
    t = trials.dropna(subset=[column]).sort_values("run_order")
    return t.loc[(t[column] - t[column].median()).abs().idxmin()]


# --------------------------------------------------------------------------- Test 2
def fig28(run: Run, fig) -> None:
    style.panels(("table6", PAPER_ROWS, "shape", "(a) proposed, by shape"), ("test2_materials", None,
           "material", "(b) by material, all planners"), ("test2_outcomes", None, "outcome",
           "(c) outcome classes, proposed", "share of trials [%]"))(run, fig)
    reference = paper_of(run, lambda p: p.fig28_reference_pct) or np.nan
    fig.axes[0].axhline(reference, color=style.CRITERION, ls="--",
                        label=f"paper's {fmt.number(reference)}% reference")
    legends_below(fig)


def fig29(run: Run, fig) -> None:
    """Every planner's trials pooled, in :data:`style.POOLED` (no planner's colour)."""
    a, *hist = style.two_per_row(fig, 3)
    e = ex(run).dropna(subset=["normal_force_pred_read_n", "normal_force_mean_n"])
    style.parity(a, e["normal_force_pred_read_n"], e["normal_force_mean_n"], [
        (0, run.tables["test2_force_accuracy"]["parity_slope"].iloc[0], "ours, through the origin",
         {"color": style.POOLED}),
        (0, paper_of(run, lambda p: p.parity_slope), "paper", {"ls": "--", "color": style.PAPER})],
        "trial-mean normal force [N]", "(a) parity, all planners", run.rig, style.POOLED)
    for ax, col, what, key in zip(hist, ("force_err_pct", "deformation_err_pct"), ("normal-force",
                                  "deformation"), ("force_err_median_pct", "deformation_err_median_pct"),
                                  strict=True):
        d = ex(run).dropna(subset=[col])
        err = d[col]
        # log bins: the errors span four decades (a 98th-percentile clip left a spike and an
        # unreadable axis); errors below 0.1 % fall in the first bin
        floor = 0.1
        bins = np.geomspace(floor, max(float(err.max()), 10 * floor), 41)
        ax.hist(err.clip(lower=floor), bins=bins, color=style.POOLED_FILL, label=f"ours, n={len(err)}")
        if col == "deformation_err_pct":  # drawn over: the trials dividing by a near-zero measurement
            low = err[hw.below_quantum(d)]
            ax.hist(low.clip(lower=floor), bins=bins, color=style.CRITERION,
                    label=f"denominator < {fmt.number(hw.VISION_QUANTUM_MM)} mm, n={len(low)}")
        ax.set_xscale("log")
        ax.axvline(err.median(), color=style.POOLED, label="ours: median")
        ax.axvline(paper_of(run, getattr, key) or np.nan, color=style.PAPER, ls="--", label="paper: median")
        ax.set(xlabel=f"absolute {what} prediction error [%]", ylabel="trials [count]",
               title=f"({'b' if ax is hist[0] else 'c'}) {what} error")
        style.legend_below(ax, ncol=2)  # clear of the bars and the medians


LIFT_HEIGHT_MM = 50.0
"""Fig. 30's commanded lift [mm]: the protocol's ``rig.protocol_design.LIFT_HEIGHT_MM`` (§8.3, "the object
lifts smoothly to 50 mm"), the one the rig commands; the records hold no lift height, and the paper's
``lift_height_mm`` is the paper's, never the run's (the report does not import rig)."""
CLOSING_TRAVEL_MM = 10.0
"""Fig. 30 draws 10 mm of closing at the trial's closing speed: a schematic length, the records hold no
closing travel (the figure is labelled a schematic of the commanded phases)."""


def representative(run: Run) -> pd.Series:
    """Fig. 30's trial (chosen once a run): the median-force stable proposed natural-friction sphere grasp."""
    return run.memo("fig30_trial", lambda: median_trial(ex(run, PROPOSED).query(
        "shape == 'sphere' and outcome == 'stable' and friction_level == 'natural'"), "normal_force_mean_n"))


def unread_slip(t: pd.Series) -> str:
    """Fig. 30's and Fig. 35's caption clause for a trial that recorded no peak slip (not drawn)."""
    return "; peak slip not drawn (not recorded)" if pd.isna(t["peak_slip_mm"]) else ""


def fig30_caption(run: Run) -> str:
    """Fig. 30's caption, with the readings of its trial not recorded (not drawn), if any: fingers without
    a force, the peak slip."""
    t = representative(run)
    unread = [j for j in (1, 2, 3) if pd.isna(t[f"normal_force_{j}_n"])]
    return ("Fig. 30 (schematic of the median-force stable proposed sphere grasp): commanded phases, "
            "recorded hold forces and peak slip as levels" + hold_gap(run, t) + (
                f"; {len(unread)} of 3 fingers not drawn (finger {fmt.listed(map(str, unread))}: no force "
                "recorded)" if unread else "") + unread_slip(t))


def hold_gap(run: Run, t: pd.Series) -> str:
    """Fig. 30's caption clause where the trial's mean hold force lies outside the paper's steady-hold band:
    by how much, and, where a grip law commanded the force (``grip_force_n``; NaN under ``paper``), the
    force it commanded and the paper's band as multiples of it (no clause inside the band)."""
    band, held = paper_of(run, lambda p: p.hold_force_per_finger_n), t["normal_force_mean_n"]
    if not band or pd.isna(held) or band[0] <= held <= band[1]:
        return ""
    side = "below" if held < band[0] else "above"
    text = (f"; its mean hold, {fmt.number(held, sig=3)} N per finger, is {side} the paper's steady hold "
            f"({fmt.paper_text(band)} N)")
    grip = t.get("grip_force_n")
    if pd.isna(grip) or grip <= 0:
        return text
    return (text + f": the grip law commands {fmt.number(grip, sig=3)} N per finger, safety factor "
            f"{fmt.number(t['sf_predicted'])} for this {fmt.number(t['mass_kg'])} kg object, and the paper's "
            f"band is {fmt.interval(band[0] / grip, band[1] / grip, 1)} times that")


def fig30(run: Run, fig) -> None:
    t = representative(run)
    lift = LIFT_HEIGHT_MM
    t0 = CLOSING_TRAVEL_MM / t["closing_speed_mm_per_s"]
    t1 = t0 + lift / t["lift_speed_mm_per_s"]
    t2, band, slip = t1 + t["hold_s"], paper_of(run, lambda p: p.hold_force_per_finger_n), "#c62828"
    force = {j: float(t[f"normal_force_{j}_n"]) for j in (1, 2, 3) if pd.notna(t[f"normal_force_{j}_n"])}
    # the prediction over the fingers read, as the parity and the errors (hw.pred_read)
    pred, slip_max = t["normal_force_pred_read_n"], paper_of(run, lambda p: p.hold_slip_max_mm)
    style.schematic(fig, t, ((0, t0, "closing", "#e3f2fd"), (t0, t1, "lift", "#fff8e1"), (t1, t2, "hold",
                                                                                   "#e8f5e9")), [
        # the recorded forces are the hold's (§8.1: "settle to a steady hold"), drawn over it as the peak slip
        *(([t1, t2], [force[j]] * 2, f"finger {j}, recorded ({fmt.number(force[j], sig=3)} N)",
           {"color": colour("finger", f"finger{j}"), "ls": ls, "lw": lw}) for j, ls, lw in style.FINGER_LINES
          if j in force),
        # every level's legend entry gives its value, as the fingers' do
        ([t1, t2], [pred] * 2, f"predicted, mean{' of the fingers drawn' * (len(force) < 3)} "
                               f"({fmt.number(pred, sig=3)} N)",
         {"ls": ":", "color": "#333333"}),
        *[(None, band, f"paper: steady hold ({fmt.paper_text(band)} N)",
           {"color": style.PAPER, "alpha": 0.12})] * bool(band)], [
        ([0, t0, t1, t2], [0, 0, lift, lift], "lift height, commanded [mm]", {"color": "#333333"}),
        *[([t1, t2], [t["peak_slip_mm"]] * 2,
           f"peak slip, recorded ({fmt.number(t['peak_slip_mm'], sig=3)} mm)",
           {"color": slip})] * pd.notna(t["peak_slip_mm"]),  # none recorded: not drawn (the caption)
        ([0, t2], [2.0, 2.0], "2 mm success criterion", {"color": slip, "ls": "--"}),
        ([0, t2], [slip_max] * 2, f"paper: slip below {fmt.paper_text(slip_max)} mm",
         {"color": style.PAPER, "ls": ":"})],
        "recorded hold values over the commanded phases")
    fig.axes[0].set_ylabel("normal force per finger [N]")
    fig.axes[1].set(ylabel="height, slip [mm]", xlabel="time from the start of closing [s]")


def groups(run: Run) -> pd.DataFrame:
    d, key = ex(run, PROPOSED), {"ABD": "validation_success_pct", "all": "proposed_success_pct",
                                 "C": "group_c_pct"}
    e = d["group"] == "E"
    parts = {**{g: d["group"] == g for g in sorted(d["group"].unique())},
             "ABD": d["group"].isin(["A", "B", "D"]), "all": d["group"].notna(),
             **{f"E {w} {fmt.number(v)} mm/s": e & (d[f"{w}_speed_mm_per_s"] == v)
                for w in ("closing", "lift") for v in sorted(d[e][f"{w}_speed_mm_per_s"].unique())}}
    out = hw.summary(hw.scoped(d, parts), ["scope"], ["is_stable"], order={"scope": list(parts)})
    out["paper"] = [paper_of(run, getattr, "group_e_success_pct_range" if s[:2] == "E " else key[s])
                    if s[:2] == "E " or s in key else None for s in out["scope"]]
    # the decimals the paper prints: §8.6 "between 90 and 100 %" for group E, one elsewhere
    out["digits"] = [0 if s[:2] == "E " else 1 for s in out["scope"]]
    out["paper_text"] = [p and fmt.paper_text(p, d) for p, d in zip(out["paper"], out["digits"], strict=True)]
    return verdicts(out, "success_pct", "paper", "success_low_pct", "success_high_pct", "digits", unit="%")


def outcomes(run: Run) -> pd.DataFrame:
    o = hw.summary(ex(run, PROPOSED), ["planner"], [f"is_{k}" for k in hw.CLASSES]).iloc[0]
    out = pd.DataFrame([{"outcome": v, "n": o[f"n_{k}"], "rate_pct": o[f"{k}_pct"], "wilson_low_pct": o[
        f"{k}_low_pct"], "wilson_high_pct": o[f"{k}_high_pct"]} for k, v in hw.CLASSES.items()])
    ref = {"stable": "proposed_stable_pct", "success": "proposed_marginal_pct"}
    t7 = {"failure_slip": "slip_pct", "failure_drop": "drop_pct", "failure_damage": "damage_pct"}
    out["paper_pct"] = [paper_of(run, getattr, ref[v]) if v in ref else paper_of(
        run, lambda p, v: getattr(p.table7[PROPOSED], t7[v]), v) if v in t7 else None for v in out["outcome"]]
    out["digits"] = [0 if v in ref else 1 for v in out["outcome"]]  # §8.2 prints "71 %" and "7 %"
    return verdicts(out, "rate_pct", "paper_pct", "wilson_low_pct", "wilson_high_pct", "digits", unit="%")


def power(run: Run) -> pd.DataFrame:
    m, p = run.tables["test2_mcnemar"].set_index("compared"), run.paper.matched_pct
    arms = [(p[PROPOSED] / 100, p[q] / 100, f"paper matched: proposed vs {q}") for q in ("centroid",
                                                                                       "no_pso")]
    if "centroid" in m.index:
        r = m.loc["centroid"]
        arms.append((*((r["both_success"] + r[k]) / r["pairs"] for k in ("reference_only", "compared_only")),
                     "ours matched: proposed vs centroid"))
    return pd.DataFrame([{"rates": r, "p1": p1, "p2": p2, "design": ("independent", "paired")[pr],
                          **asdict(power_two_proportions(p1, p2, power=pw, paired=pr))} for p1, p2, r in arms
                         if 0 < p1 < 1 and 0 < p2 < 1 and p1 != p2 for pw in (0.8, 0.9) for pr in (0, 1)])


def mcnemar_rows(mc: pd.Series, paper, section: str):
    """Claims rows: McNemar χ², won and lost pairs of the proposed planner against the centroid."""
    for q, col, key, digits in (("McNemar χ² proposed vs centroid", "chi2_cc", "chi2", 1),
                                ("pairs won by proposed (vs centroid)", "reference_only", "won", 0),
                                ("pairs lost by proposed (vs centroid)", "compared_only", "lost", 0)):
        yield q, section, Estimate(mc[col], n=mc["pairs"]), getattr(paper, key), "", digits


def residual_flag_rows(run: Run):
    """§8.1's and §8.4's counts of the residual flag as shares beside the paper's (claims rows), each over
    the trials with the flag recorded (:func:`~graspcampaign.analysis.records.known`): a trial without it
    is neither certified nor labelled unstable (``astype(bool)`` read a NaN as certified)."""
    p, flag, a = run.paper, RESIDUAL, ex(run)  # success: executed()'s bool (missing: not a success)
    d, g = known(ex(run, PROPOSED), [flag]), p.classifier_group_c.proposed
    for where, part, paper, said in (
            ("group C trials", d[d["group"] == "C"], g.certified_pct, f"{g.certified} of {g.trials}"),
            ("trials outside group C", d[d["group"] != "C"], g.certified_elsewhere_pct,
             f"≈ {fmt.number(g.certified_elsewhere_pct, 0)}%")):  # §8.1 prints "49%" and "≈ 90%"
        yield (f"proposed planner's {where} certified by the residual flag (paper {said})", g.section,
               lambda part=part: share(part, part[flag]), paper, "%", 0)
    # §8.4's counts of the flag as shares with Wilson 95 % intervals, so a reduced run compares too: the
    # paper's share from its two printed counts ("just 50 of its 677 certified grasps (7.4 %)")
    won, certified = known(a[a["success"]], [flag]), d[d[flag]]
    for q, frame, event, k, n in (
            ("successes, all planners", a, a["success"], p.measured_successes, p.executed),
            ("successes labelled unstable by the residual flag", won, ~won[flag],
             p.successes_labelled_unstable, p.measured_successes),
            ("proposed planner's trials certified by the residual flag", d, d[flag], p.proposed_certified,
             p.table7[PROPOSED].n),
            ("proposed planner's certified grasps that failed", certified, ~certified["success"],
             p.proposed_certified_failed, p.proposed_certified)):
        yield (f"{q} (paper {k} of {n})", "§8.4", lambda frame=frame, event=event: share(frame, event),
               100 * k / n, "%", 1)


def claims(run: Run):
    """§8 headline numbers not in a table above, beside the paper's."""
    p, t, d = run.paper, run.tables, ex(run, PROPOSED)
    yield ("proposed drop, damage or contact loss", "§8.2, Fig. 28c", share(d, d["is_drop"] | d["is_damage"]
           | d["is_contact_loss"]), (0.0, p.proposed_drop_damage_contact_pct_max), "%", 1)
    acc, mc = t["test2_force_accuracy"].iloc[0], t["test2_mcnemar"].set_index("compared").loc["centroid"]
    # digits: the decimals §8.3 prints ("slope 0.98", "R² = 0.720", "13.8 %", "14.1 %", "3.6 mm"), the
    # verdict rule's unit of the paper's last printed digit
    for q, col, key, unit, digits in (
            ("parity slope (through the origin)", "parity_slope", "parity_slope", "", 2),
            ("parity R² (uncentred)", "parity_r2", "parity_r2", "", 3),
            ("median |normal-force error|", "force_err_pct", "force_err_median_pct", "%", 1),
            ("median |deformation error|", "deformation_err_pct", "deformation_err_median_pct", "%", 1),
            ("median contact-point error", "contact_point_error_mm", "contact_point_err_median_mm", "mm", 1)):
        n = acc["n_parity" if col.startswith("parity") else f"n_{things(col)}"]
        yield q, "§8.3, Fig. 29", Estimate(acc[col], n=n), getattr(p, key), unit, digits
    yield from residual_flag_rows(run)
    yield from mcnemar_rows(mc, p.mcnemar_centroid, "§8.5")
    yield ("discordant-pair odds ratio", "§8.5", Estimate(*mc[["odds_ratio", "odds_ratio_low",
           "odds_ratio_high", "pairs"]]), p.mcnemar_centroid.odds_ratio, "", 1)
    for (_, r), (q, key, col, digits) in zip(t["test2_tests"].iterrows(), (
            ("χ² planner × success (proposed, centroid, random)", "chi2_planner_success", "statistic", 1),
            ("Kruskal–Wallis p, force error across planners", "force_err_kruskal_p", "p", fmt.P),
            ("Kruskal–Wallis H, peak slip across friction levels", "slip_friction_kruskal_h", "statistic",
             0)), strict=True):  # §8.6 prints "H = 578"
        yield q, "§8.5-8.6", Estimate(r[col], n=r["n"]), getattr(p, key), "", digits


SPEC = ReportSpec("test2_grasp", [
    Finding(finding),
    Claims("test2_counts", "Trial counts beside the paper's (a reduced study has fewer)", counts("table7")),
    paper_table("table6", "Table 6: the proposed planner per shape and belief reading (all its trials), at "
                "natural friction, its median absolute prediction errors", "shape", lambda p, k: p.table6[k],
                [("n", "n", "n", 0), ("success", "success_pct", "success", None),
                 ("natural", "natural_pct", "natural friction", None),
                 ("force_err_pct", "force_err_pct", "median |F_n| error [%]", 1),
                 ("deformation_err_pct", "deformation_err_pct", "median deformation error [%]", 1)],
                ["natural"], ["force_err_pct", "deformation_err_pct"], where=lambda d: d.query(ME)),
    paper_table("table7", "Table 7: executed trials per planner and belief reading: success (Wilson, object "
                "bootstrap 95%); stable, slip, drop, damage as primary outcome classes", "planner",
                lambda p, k: p.table7[k], [("n", "n", "n", 0), *((k, f"{k}_pct", k, None) for k in (
                    "success", "stable", "slip", "drop", "damage"))],
                [f"is_{k}" for k in ("stable", "slip", "drop", "damage")], boot=True),
    *belief_tables("test2"),
    Table("test2_groups", "The proposed planner per group (A-E, M matched), the validation pool ABD, all "
          "trials and group E per closing and lift speed (§8.2, §8.6)", groups, [
              Col("scope", "group"), Col("n", "n"), Col("paper_text", "paper %"),
              pct_col("success", "success"), pct_col("stable", "stable"),
              Col("verdict", "verdict (success)")]),
    Table("test2_outcomes", "Primary outcome class of each trial of the proposed planner (§8.2, Fig. 28c; "
          "slip, drop, damage: Table 7); success = stable + marginal success", outcomes, [
              Col("n", "n"), Col("rate_pct", "share % (Wilson 95%)", 1, low="wilson_low_pct",
                                 high="wilson_high_pct"), Col("paper_pct", "paper %", "digits"),
              Col("verdict", "verdict")], by=["outcome"]),
    Rates("test2_materials", "Success per material, all planners (§8.2, Fig. 28b)", ["material"],
          lambda p, k: p.success_by_material_pct[k["material"]]),
    Rates("test2_matched", "Matched ablation: success per planner on the same objects and conditions (§8.5, "
          "Fig. 31b)", ["planner"], lambda p, k: p.matched_pct[k["planner"]],
          where=lambda r: r["matched"].astype(bool)),
    Table("test2_force_accuracy", "Prediction accuracy (§8.3): normal-force parity through the origin "
          "(uncentred, centred R²), median absolute errors, each over its n (a recorded 0 has no relative "
          "error); of the deformation errors, n over a recorded mean below the "
          f"{fmt.number(hw.VISION_QUANTUM_MM)} mm vision quantisation (§8.1)",
          lambda run: hw.force_accuracy(ex(run)), [
              Col("n_parity", "n"), Col("parity_slope", "parity slope", 3),
              Col("parity_r2", "parity R² (uncentred)", 3),
              Col("parity_r2_centred", "parity R² (centred)", 3),
              Col("force_err_pct", "median |F_n| error [%]", 1), Col("n_force_err", "n (F_n error)"),
              Col("deformation_err_pct", "median deformation error [%]", 1),
              Col("n_deformation_err", "n (deformation)"),
              Col("n_deformation_below_quantum", f"n (deformation < {fmt.number(hw.VISION_QUANTUM_MM)} mm)"),
              Col("contact_point_error_mm", "median contact-point error [mm]", 2),
              Col("n_contact_point_error", "n (contact point)")], by=["scope"]),
    classifier("test2_classifier", lambda run: f"Pre-execution flags against {run.rig} success (§8.4, "
               "Fig. 31c): the believed-stability flag (`predicted_stable`) is §9.5's SF_predicted > 1, "
               "optimistic where the beliefs are wrong; the residual flag (`predicted_stable_residual`) "
               "§8.1's residual ≤ τ_F = 0.0886 N, the flag the paper's "
               "scores belong to: friction-blind, it carries no information about a friction hold. Every "
               "paper value (§8.4's scores; the precisions inside and outside group C, each for the trials "
               "its section states: §8.1 the proposed planner's, §8.4 all planners') stands beside the "
               "residual flag alone: the paper scores no believed-SF flag",
               lambda d: {
                   **per_planner(d), "baselines": d["planner"] != PROPOSED,
                   "group C, proposed": d.eval(f"{ME} and group == 'C'"),
                   "outside C, proposed": d.eval(f"{ME} and group != 'C'"),
                   "group C, all planners": d["group"] == "C", "outside C, all planners": d["group"] != "C"},
               lambda p: {("all", RESIDUAL): scores(p.classifier),
                          (PROPOSED, RESIDUAL): scores(p.classifier_proposed),
                          ("baselines", RESIDUAL): (None, p.classifier_baselines_precision, None),
                          **group_c(p.classifier_group_c)}),
    matched_mcnemar("test2_mcnemar", "Matched ablation (§8.5): McNemar, proposed against each baseline on "
                    "occurrence-matched pairs (object, condition, repeat)"),
    Table("test2_tests", "χ² of planner × success; Kruskal–Wallis of the force error across planners, "
          "the peak slip across friction levels (§8.5-8.6; no multiplicity correction, as the paper)",
          lambda run: pd.DataFrame([hw.chi2_planners(ex(run), seed=run.seed), *(
              hw.kruskal(ex(run), v, k) for v, k in (("force_err_pct", "planner"),
                                                    ("peak_slip_mm", "friction_level")))]), lambda run, f: [
                  *cols("test", "n", "statistic", "dof", "p"),
                  *(Col(c, f"median, {label('planner', c[7:])}", sig=3) for c in f if c[:7] == "median_")]),
    Claims("test2_claims", "§8 numbers not in a table above, beside the paper's", claims),
    Table("test2_power", "Power (§8.5, §11): trials per arm to detect p1 vs p2 at α = 0.05 (independent: "
          "Cohen's h; matched pairs: McNemar, Connor 1987)", power),
    Figure("fig28_outcomes", "Fig. 28 (paper in black): proposed success per shape (dashed: the paper's 75% "
           "reference), success per material, proposed outcome classes; Wilson 95%", fig28, (10.0, 8.0)),
    Figure("fig29_prediction_accuracy", lambda run: f"Fig. 29: (a) {run.rig} against predicted trial-mean "
           "normal force; (b) normal-force and (c) deformation errors with their medians (log axis: every "
           f"trial shown; dark in (c): trials whose {run.rig} mean deformation, the error's denominator, is "
           f"below the {fmt.number(hw.VISION_QUANTUM_MM)} mm vision quantisation, §8.1)", fig29, (10.0, 7.6)),
    Figure("fig30_representative_grasp", fig30_caption, fig30, (9.5, 5.4)),
    Figure("fig31_planner_comparison", "Fig. 31: success per planner (a) with own and exact beliefs "
           "(hatched), (b) matched ablation; (c) the believed-stability flag (`predicted_stable`) against "
           "the outcome, ours alone: the paper's Fig. 31c scores are of the residual flag, beside it in "
           "table test2_classifier",
           style.panels(planner_bars("table7"), ("test2_matched", None, "planner", "(b) matched ablation"),
                        confusion(None, "predicted stable: believed SF > 1")), (10.0, 8.0)),
])
