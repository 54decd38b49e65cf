"""Report of ``test3_disturbance`` (§9; Tables 8-9, Figs. 33-36) from Test 2's parts; thresholds are compared
only where a ramp ended in slip (a ramp that reached its cap is a lower bound)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd

from graspcampaign.analysis import disturbance as ds
from graspcampaign.analysis import hardware as hw
from graspcampaign.analysis.records import Estimate
from graspcampaign.analysis.vocabulary import COATINGS, PROPOSED, colour, label
from graspcampaign.core.bench_specimen import FAMILIES
from graspcampaign.core.words import counted
from graspcampaign.report import format as fmt
from graspcampaign.report import style
from graspcampaign.report.document import Col, cols, pct_col
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Claims, Figure, Finding, ReportSpec, Table, paper_of, share, verdicts
from graspcampaign.report.studies import flags
from graspcampaign.report.studies import test2 as t2

NATURAL = "friction_level == 'natural'"


class Arrest(NamedTuple):
    """The proposed planner's drops against the arrest bound μ_s/μ_k (:func:`arrest`)."""

    below: int  # drops read whose recorded ``sf_actual`` lies below their material's μ_s/μ_k
    n_read: int  # drops with an ``sf_actual`` reading and a material of Table 4
    ratio: str  # μ_s/μ_k's range over the proposed planner's materials, as printed
    unread: int  # drops without an ``sf_actual`` reading
    other: int  # drops with one, of a material not in Table 4
    n_dropped: int  # all the proposed planner's drops


def arrest(run: Run) -> Arrest:
    """The proposed planner's drops against the safety factor that arrests a slip: a slip that started is
    arrested only while the kinetic budget (μ_k/μ_s of the static one) carries the weight, i.e. SF ≥
    μ_s/μ_k of its material. Returns how many dropped trials' recorded ``sf_actual`` lies below it, of how
    many read (with an ``sf_actual`` reading and a material of Table 4), μ_s/μ_k's range as printed, the
    drops without an ``sf_actual`` reading, those of a material not in Table 4, and all the drops (the
    opening and table test3_claims say them: computed once per run)."""
    return run.memo("arrest", lambda: _arrest(run))


def _arrest(run: Run) -> Arrest:
    d = t2.ex(run, PROPOSED)
    bound = d["material"].map({m: f.mu_s / f.mu_k for m, f in FAMILIES.items()})  # NaN: not in Table 4
    ratio, dropped = fmt.span(bound.dropna().unique(), digits=2), d[d["is_drop"]]
    no_sf, no_ratio = dropped["sf_actual"].isna(), bound[dropped.index].isna()  # neither below nor above
    read = dropped[~no_sf & ~no_ratio]
    below = int((read["sf_actual"].astype(float) < bound[read.index]).sum())
    return Arrest(below, len(read), ratio, int(no_sf.sum()), int((no_ratio & ~no_sf).sum()), len(dropped))


def drops(run: Run) -> str:
    """The proposed planner's drops and, where the records show it, their cause (:func:`arrest`): the
    dropped trials whose recorded ``sf_actual`` lies below the bound are counted, of those with an
    ``sf_actual`` reading and a material of Table 4 (the others said apart)."""
    d, paper = t2.ex(run, PROPOSED), paper_of(run, lambda p: p.table9[PROPOSED].drop_pct)
    a = arrest(run)  # each drop left out said once
    needs = " and ".join([*["an `sf_actual` reading"] * bool(a.unread),
                          *["a Table 4 material"] * bool(a.other)])
    with_sf = f" with {needs}" if needs else ""  # what a drop read has ("": every drop is read)
    apart = [f"{a.unread} more without " + ("an `sf_actual` reading" if a.other else "one")] \
        * bool(a.unread) + [f"{a.other} more of a material not in Table 4"] * bool(a.other)
    more = f" ({', '.join(apart)})" if apart else ""
    text = f"The proposed planner drops {fmt.number(100 * d['is_drop'].mean(), 1)}% of trials (paper " \
           f"{fmt.number(paper, 1)}%)"
    if a.below:  # short: the opening's 900 characters (test_openings)
        return (f"{text}: {a.below} of {a.n_read}{with_sf} below the safety factor μ_s/μ_k = {a.ratio} "
                f"that arrests a slip{more}. ")
    text += f". No slip is arrested below a safety factor of μ_s/μ_k = {a.ratio}"
    if a.n_read:
        held = _none_of(a.n_read, with_sf, "held one below it", "did not hold one below it")
        return f"{text}; {held}{more}. "
    if a.n_dropped:
        return f"{text}; {_none_of(a.n_dropped, '', f'has {needs}', f'does not have {needs}')}. "
    return text + ". "


def _none_of(n: int, which: str, held: str, not_held: str) -> str:
    """``none of its 3 drops <which> <held>``, or of one drop ``its one drop <which> <not_held>``
    (it once read "none of its 1 drops")."""
    return f"none of its {n} drops{which} {held}" if n != 1 else f"its one drop{which} {not_held}"


def table8(run: Run, d: pd.DataFrame, out: pd.DataFrame) -> pd.DataFrame:
    fits = [hw.parity_by(g, "block", "threshold", "threshold_pred").assign(belief_error=b)
            for b, g in d.groupby("belief_error")]
    units = {"A": "N", "B": "% W", "C": "N·m", "D": "mm slip", "E": "mm slip"}
    out = out.merge(pd.concat(fits), on=["block", "belief_error"], how="left")
    return out.assign(unit=out["block"].map(units))


def table9(run: Run, d: pd.DataFrame, out: pd.DataFrame) -> pd.DataFrame:
    w = [None if b != "paper" else paper_of(run, lambda p, k: p.table9[k].wilson_pct, k)
         for k, b in zip(out["planner"], out["belief_error"], strict=True)]
    return out.assign(paper_wilson=[x and fmt.paper_text(x, 1) for x in w])


def first_finger(run: Run) -> pd.DataFrame:
    scopes = t2.per_planner(e := t2.ex(run))
    out = hw.summary(hw.scoped(e, scopes).dropna(subset=["first_finger_correct"]), ["scope"],
                     ["first_finger_correct"], order={"scope": list(scopes)})
    return out[["scope", "n", *(f"first_finger_correct_{s}" for s in ("pct", "low_pct", "high_pct"))]]


def coating(run: Run) -> pd.DataFrame:
    out = hw.summary(t2.ex(run, PROPOSED).query("block == 'A'"), ["friction_level"],
                     medians=["lat_threshold_n"],
                     order={"friction_level": ["natural", *COATINGS]})
    ref = [paper_of(run, lambda p, k: p.coating[k], k) for k in out["friction_level"]]
    # natural friction: the same 240 block-A trials as Table 8's lateral-pull row (87.1 %)
    out["paper_success_pct"] = [r.success_pct if r else paper_of(run, lambda p: p.table8["A"].success_pct)
                                if k == "natural" else None
                                for k, r in zip(out["friction_level"], ref, strict=True)]
    out["paper_threshold_n"] = [r.threshold_n if r else paper_of(run, lambda p: p.lateral_threshold_median_n)
                                if k == "natural" else None
                                for k, r in zip(out["friction_level"], ref, strict=True)]
    # the decimals the paper prints: Table 8's 87.1 % and 4.34 N at natural friction; §9.2's coatings "4.31 N
    # at 90 % success", "0.84 N (35 %)", "0.185 N (0 %)" (its three decimals, not the bar label's 0.18)
    natural = out["friction_level"] == "natural"
    out["digits"] = natural.map({True: 1, False: 0})
    out["threshold_digits"] = [3 if k == "low" else 2 for k in out["friction_level"]]
    return verdicts(out, "success_pct", "paper_success_pct", "success_low_pct", "success_high_pct", "digits",
                    unit="%")


def claims(run: Run):
    """§9 headline numbers not in a table above, beside the paper's."""
    p, e, t = run.paper, t2.ex(run), run.tables
    d, nat = t2.ex(run, PROPOSED), t2.ex(run, PROPOSED).query(NATURAL)
    yield ("proposed success, natural friction", "§9.2", share(nat, nat["success"]),
           p.natural_success_pct, "%", 0)  # §9.2: "roughly 86 %"
    # the extremes skip a direction (cell) without a value: Python's min/max kept a NaN met first
    for i, f in enumerate(("min", "max")):
        yield (f"{('lowest', 'highest')[i]} median threshold over pull directions", "§9.2, Fig. 33b",
               t["test3_directions"]["lat_threshold_n"].agg(f), p.direction_threshold_range_n[i],
               "N", 1)  # §9.2 prints "4.0 N to 4.6 N"
    for key, v in p.vertical_levels_pct.items():
        g = nat.query(f"block == 'B' and disturbance_kind == '{key.split('_')[0]}'")
        g = g[np.isclose(g["load_frac_w"].astype(float), float(key.split("_")[1]))]
        yield (f"vertical {key.replace('_', ' to ')} W, success", "§9.2",
               lambda g=g: share(g, g["success"]), v, "%", 0)  # §9.2: "95 %, 82 %, and 48 %", "100 %", "95 %"
    c = d.query("block == 'C'")
    yield ("median yaw torque at slip, with the coating probes", "§9.2", Estimate(
        c["threshold"].median(), n=c["threshold"].count()), p.yaw_torque_with_probes_nm, "N·m", 2)  # 0.10 N m
    rot = c.query(NATURAL).dropna(subset=["threshold"])["rotation_at_limit_deg"].astype(float)
    yield ("median rotation at the yaw limit", "§9.2", Estimate(rot.median(), n=len(rot)),
           p.yaw_rotation_median_deg, "°", 1)
    a = t["test3_threshold_agreement"].iloc[0]
    for q, col, key, unit, digits in (  # §9.3 prints "slope 1.26", "R^2 = 0.56", "+0.24 N", "± 3.9 N"
            (f"OLS slope, {run.rig} on predicted", "ols_slope", "threshold_ols_slope", "", 2),
            ("OLS R²", "ols_r2", "threshold_ols_r2", "", 2),
            (f"Bland–Altman bias ({run.rig} − predicted)", "bias_n", "bland_altman_bias_n", "N", 2),
            ("Bland–Altman limits, half width", "loa_half_n", "bland_altman_loa_half_width_n", "N", 1)):
        yield q, "§9.3, Fig. 34", Estimate(a.get(col, np.nan), n=a["n"]), getattr(p, key), unit, digits
    ramps = d.dropna(subset=["lat_threshold_n"])  # the agreement table's uncensored block-A ramps
    yield (f"lateral thresholds with error > 50 % (paper {p.threshold_err_over_50pct} of "
           f"{p.lateral_threshold_trials})", "§9.3", lambda: share(ramps, ramps[
        "lat_threshold_err_pct"] > 50), 100 * p.threshold_err_over_50pct / p.lateral_threshold_trials, "%", 1)
    yield ("median torque-threshold error", "§9.3", Estimate(c["threshold_err_pct"].median(), n=c[
        "threshold_err_pct"].count()), p.torque_threshold_err_pct, "%", 1)
    # §9.3: "The planner also identifies which finger slips first on 84.9 % of trials", of the proposed
    # planner, whose predictions the paragraph reads (it pooled every planner's: table test3_first_finger)
    ff = d.dropna(subset=["first_finger_correct"])
    yield ("first finger to slip predicted, proposed planner", "§9.3", lambda: share(ff, ff[
        "first_finger_correct"].astype(bool)), p.first_finger_accuracy_pct, "%", 1)
    dd = nat.query("block == 'D'")
    for what, col, ref in (("retained (success)", "success", p.impulse_retained_pct),
                           ("dropped", "drop_flag", p.impulse_drop_pct)):
        for level, v in ref.items():
            g = dd[np.isclose(dd["load_frac_w"].astype(float), float(level))]
            yield (f"impulse {fmt.number(float(level))} W, {what}", "§9.4",
                   lambda g=g, c=col: share(g, g[c]), v, "%", 0)  # §9.4: "98 % and 93 %", "78 %", "40 %"
    cells = nat.query("block == 'E'").groupby(["frequency_hz", "amplitude_n"])["peak_slip_mm"].median()
    for i, f in enumerate(("min", "max")):
        yield (f"sinusoids: {('lowest', 'highest')[i]} median slip over (f, A) cells", "§9.4",
               cells.agg(f), p.sinusoid_slip_mm_range[i], "mm", 1)  # "0.2 mm to 1.9 mm"
    mp = d[d["matched"].astype(bool)]
    yield ("matched set success, proposed", "§9.5", lambda: share(mp, mp["success"]),
           p.matched_proposed_pct, "%", 0)  # "reaches 95 %"
    mc = t["test3_mcnemar"].set_index("compared").loc["centroid"]
    yield ("matched difference, proposed − centroid", "§9.5", 100 * (mc["reference_only"] - mc[
        "compared_only"]) / mc["pairs"], p.matched_difference_centroid_pp, "pp", 1)
    yield from t2.mcnemar_rows(mc, p.mcnemar_centroid, "§9.5")
    yield ("success margin over the random planner", "§9.5", 100 * (d["success"].mean() - e.query(
        "planner == 'random'")["success"].mean()), p.margin_over_random_pp, "pp", 1)
    lat, pulls = nat.query("block == 'A'")["threshold_measured_n"].astype(float).fillna(0.0), \
        "natural-friction pulls"
    for q, v, x, u in ((f"{pulls} sustaining > 3 N", lambda: share(lat, lat > 3.0), "above_3n_pct", "%"),
                       ("lateral level held by half the proposed grasps", lat.median(), "half_at_n", "N"),
                       (f"{pulls} sustaining > 5 N", lambda: share(lat, lat > 5.0), "above_5n_pct", "%")):
        yield q, "§9.5, Fig. 36b", v, getattr(p.survival, x), u, 0 if u == "%" else 1  # 70 %, 4.4 N, 23 %
    # §9.5's counts as shares beside ours (Wilson 95 %), so a reduced run compares too: "only 51 of the
    # 680 grasps certified as retained subsequently failed", of §9.1's executed trials
    # both flags bool as executed() gives them (BOOLEAN_COLUMNS: a missing one is not set, and no stored
    # executed trial lacks one); Test 2's residual flag, not among them, is read by records.known
    a = t2.ex(run)
    kept = a[a["predicted_stable"]]
    for q, frame, event, k, n in (
            ("trials certified as retained by the retention flag", a, a["predicted_stable"],
             p.retention_certified, p.executed),
            ("certified grasps that failed", kept, ~kept["success"],
             p.retention_certified_failed, p.retention_certified)):
        yield (f"{q} (paper {k} of {n})", "§9.5", lambda frame=frame, event=event: share(frame, event),
               100 * k / n, "%", 1)
    for _, r in t["test3_logistic"].query("term != 'intercept'").iterrows():
        yield (f"logistic coefficient of failure: {r['term']}", "§9.5", Estimate(
            *r[["coef", "ci_low", "ci_high", "n"]]), getattr(p.logistic, r["term"]), "", 2)
    logit = t["test3_logistic"]
    yield ("trials of the logistic regression (blocks B, D, E, all planners)", "§9.5",
           logit["n"].iloc[0] if len(logit) else np.nan, p.logistic.n, "", 0)  # "n = 680"
    chi = t["test3_chi2"].iloc[0]
    yield ("χ² planner × retention (proposed, centroid, random)", "§9.5", Estimate(
        chi["statistic"], n=chi["n"]), p.chi2_planner_retention, "", 0)  # "χ^2 = 221"
    a = arrest(run)  # the opening's count (§9.6: drops 10.1 %)
    yield (f"proposed drops below the safety factor μ_s/μ_k = {a.ratio} that arrests a slip (n: its drops "
           "with an SF reading and a Table 4 material)", "§9.6", Estimate(a.below, n=a.n_read), None, "", 0)


def no_threshold(ax, at: float, n: int, aside: float = 0.0) -> None:
    """Say at ``at`` on the axis, upright from 0, why a category has no median threshold: ``n`` trials
    none of whose ramps was uncensored, or no trial (Fig. 33a's surfaces, 33c's pull directions), ``aside``
    points to the right (clear of a paper's diamond at ``at``); drawn over the paper's lines, outlined in
    white as they are."""
    ax.annotate(f"{counted(int(n), 'trial')}, no threshold" if n > 0 else "no trial", (at, 0),
                xytext=(aside, 3), textcoords="offset points", rotation=90, ha="center", va="bottom",
                fontsize=7, color=style.CRITERION, zorder=7, path_effects=style.HALO)  # over a paper mark


def thresholds(run: Run, ax) -> None:
    """Fig. 33a: the median threshold per surface; a surface without one (table test3_coating's
    ``n_lat_threshold`` 0) says why where its bar would stand, as 33c's directions do."""
    t = run.tables["test3_coating"]
    x = np.arange(len(t))
    ax.bar(x, t["lat_threshold_n"], 0.7, color=colour("planner", PROPOSED), label="ours, uncensored ramps")
    for at, n in zip(x[t["lat_threshold_n"].isna().to_numpy()], t.loc[t["lat_threshold_n"].isna(), "n"],
                     strict=True):
        no_threshold(ax, at, n, aside=10.0)  # the paper's diamond, 5 pt, is at the bar's centre
    style.paper_marks(ax, x, list(t["paper_threshold_n"]), 0.7)
    ax.set(xticks=x, xticklabels=[f"{k}\nn={n}" for k, n in zip(t["friction_level"], t["n_lat_threshold"],
                                                                  strict=True)],
           ylabel="median lateral threshold at slip [N]", title="(a) block A: median threshold")
    ax.legend(handles=[*ax.get_legend_handles_labels()[0], style.paper_handle()], loc="upper right")


def directions(run: Run, ax) -> None:
    """Fig. 33c: the median threshold per pull direction; a direction without one (no trial, or no
    uncensored ramp: table test3_directions) breaks the line and says why where it lies."""
    d, rng = run.tables["test3_directions"], paper_of(run, lambda p: p.direction_threshold_range_n)
    design = np.arange(0, 360, 45)  # block A's eight pull directions (§9.2; rig/protocol_design.py)
    d = d.set_index("direction_deg").reindex(sorted({*design, *d["direction_deg"]})).reset_index()
    ax.plot(d["direction_deg"], d["lat_threshold_n"], "o-", color=colour("planner", PROPOSED), label="ours")
    for a, n in d.loc[d["lat_threshold_n"].isna(), ["direction_deg", "n"]].itertuples(index=False):
        no_threshold(ax, a, n)
    ax.axhspan(*(rng or (np.nan,) * 2), color=style.PAPER, alpha=0.15, label="paper: range")
    ax.set(xticks=design, xlabel="pull direction (azimuth) [°]", ylim=(0, None),
           ylabel="median lateral threshold [N]", title="(c) natural friction, by direction")
    ax.legend(loc="lower right")


def survival(run: Run, ax) -> None:
    for q, g in ds.lateral_survival(t2.ex(run), np.arange(0.0, 8.01, 0.05)).groupby("planner", sort=False):
        ax.step(g["level_n"], 100 * g["surviving_fraction"], where="post", color=colour("planner", q),
                label=f"ours, {label('planner', q)} (n={g['n'].iloc[0]})")
    if (s := paper_of(run, lambda p: p.survival)) is not None:
        ax.plot([3.0, s.half_at_n, 5.0], [s.above_3n_pct, 50, s.above_5n_pct], "D", color=style.PAPER,
                label="paper")
        ax.plot([s.centroid_failed_by_n], [0], "s", mfc="none", color=style.PAPER,
                label=f"paper: centroid grasp already failed by {fmt.number(s.centroid_failed_by_n)} N")
    ax.set(xlabel="lateral pull level [N]", ylabel="natural-friction pulls holding [%]",
           title="(b) survival of the lateral threshold")
    ax.legend(loc="upper right")


def fig33(run: Run, fig) -> None:
    style.panels(thresholds, ("test3_coating", None, "friction_level", "(b) block A: success"), directions,
                 ("table8", t2.PAPER_ROWS, "block", "(d) proposed, by block"))(run, fig)
    t2.legends_below(fig)


def fig34(run: Run, fig) -> None:
    a, b, c = style.two_per_row(fig, 3)
    d = t2.ex(run, PROPOSED).dropna(subset=["lat_threshold_n"])
    m, p, g = d["lat_threshold_n"], d["threshold_pred"], run.tables["test3_threshold_agreement"].iloc[0]
    ours = colour("planner", PROPOSED)
    style.parity(a, p, m, [(g.get("ols_intercept_n"), g.get("ols_slope"), "ours: OLS", {"color": ours}),
                     (0, paper_of(run, lambda p: p.threshold_ols_slope), "paper's slope",
                      {"ls": "--", "color": style.PAPER})], "lateral threshold [N]",
           "(a) parity, proposed, block A", run.rig, ours)
    b.scatter((m + p) / 2, m - p, s=7, alpha=0.5, color=ours, label="ours")
    bias, half = (paper_of(run, getattr, k) for k in ("bland_altman_bias_n", "bland_altman_loa_half_width_n"))
    lines = [(g.get(k), ls, ours, "ours") for k, ls in (("bias_n", "-"), ("loa_low_n", "--"),
                                                         ("loa_high_n", "--"))]
    lines += [(bias + k * half, ls, style.PAPER, "paper") for k, ls in ((0, "-"), (-1, ":"), (1, ":"))
              if bias is not None]
    named = set()  # an entry per style drawn: the limits are dashed (ours) or dotted (paper's), not solid
    for v, ls, col, who in lines:
        what = f"{who}: {'bias' if ls == '-' else '95% limits'}"
        b.axhline(np.nan if v is None else v, ls=ls, lw=1, color=col, label=None if what in named else what)
        named.add(what)
    b.set(xlabel=f"mean of {run.rig} and predicted [N]", ylabel=f"{run.rig} − predicted [N]",
          title="(b) Bland–Altman")
    style.legend_below(b, ncol=2)
    t = run.tables["table9"].query(t2.PAPER_ROWS)
    x = np.arange(len(t))
    c.bar(x, t["lat_threshold_err_pct"], 0.7, color=[colour("planner", q) for q in t["planner"]])
    style.paper_marks(c, x, list(t["paper_lat_threshold_err_pct"]), 0.7)
    c.set_xticks(x, [f"{style.tick(label('planner', q))}\nn={n}" for q, n in zip(
        t["planner"], t["n_lat_threshold"], strict=True)], fontsize=7)  # as style.rate_bars
    c.set(ylabel="median |lateral-threshold error| [%]", title="(c) by planner, uncensored block A")
    style.legend_below(c, [style.paper_handle()])


def representative_pull(run: Run) -> pd.Series:
    """Fig. 35's trial (chosen once a run): the median-threshold proposed natural-friction pull of block A."""
    return run.memo("fig35_trial", lambda: t2.median_trial(t2.ex(run, PROPOSED).query(
        f"block == 'A' and {NATURAL}"), "lat_threshold_n"))


def fig35_caption(run: Run) -> str:
    """Fig. 35's caption, saying when its trial recorded no peak slip (not drawn)."""
    return ("Fig. 35 (schematic of one recorded trial, the median-threshold proposed natural-friction pull): "
            "hold, commanded ramp to the recorded threshold at 2 mm slip, predicted threshold, recorded peak "
            "slip" + t2.unread_slip(representative_pull(run)))


def fig35(run: Run, fig) -> None:
    t = representative_pull(run)
    h, thr, paper = t["hold_s"], t["lat_threshold_n"], paper_of(run, lambda p: p.lateral_threshold_median_n)
    t1 = h + thr / t["ramp_rate_n_per_s"]
    end = 1.15 * t1
    style.schematic(fig, t, ((0, h, "hold", "#e8f5e9"), (h, t1, "ramp to slip", "#fff8e1")), [
        ([0, h, t1, t1, end], [0, 0, thr, 0, 0], "applied force, commanded ramp", {"color": "#333333"}),
        # every level's legend entry gives its value (Fig. 30's fingers do)
        ([h, end], [thr] * 2, f"recorded threshold at slip ({fmt.number(thr, sig=3)} N)",
         {"color": "#c62828"}),
        ([h, end], [t["threshold_pred"]] * 2, f"predicted F_lat ({fmt.number(t['threshold_pred'], sig=3)} N)",
         {"ls": "--", "color": colour("planner", PROPOSED)}),
        ([0, end], [paper] * 2, f"paper: natural-friction median ({fmt.paper_text(paper)} N)",
         {"ls": ":", "color": style.PAPER})], [
        ([0, end], [2.0, 2.0], "2 mm slip criterion (detection)", {"color": "#c62828", "ls": "--"}),
        *[([t1, end], [t["peak_slip_mm"]] * 2,
           f"recorded peak slip after release ({fmt.number(t['peak_slip_mm'], sig=3)} mm"
           + ", object lost" * bool(t["drop_flag"]) + ")", {"color": "#333333"})]
        * pd.notna(t["peak_slip_mm"])],  # none recorded: not drawn (the caption says so)
        "lateral pull over the commanded phases")
    fig.axes[0].set_ylabel("lateral force [N]")
    fig.axes[1].set(ylabel="slip [mm]", xlabel="time from the start of the hold [s]")


SPEC = ReportSpec("test3_disturbance", [
    Finding(lambda run: t2.finding(run, drops)),
    Claims("test3_counts", "Trial counts beside the paper's (a reduced study has fewer)",
              t2.counts("table9")),
    t2.paper_table("table8", "Table 8: the proposed planner's natural-friction blocks per belief reading; "
                "headline = median lateral threshold (A), downward payload at slip (B), yaw torque (C), "
                "peak slip (D, E: no threshold); prediction error and centred parity R² over the "
                "uncensored thresholds; blocks A and C succeed only when the threshold reaches the proof "
                "load (one weight laterally, the weight at the shape's radius in yaw)", "block",
                lambda p, k: p.table8[k], [
                    ("n", "n", "n", 0), ("success", "success_pct", "success", None),
                    ("headline", "headline", "headline", fmt.EACH), ("unit", None, "unit", ""),
                    ("n_headline", None, "thresholds", 0),
                    ("threshold_err_pct", "pred_err_pct", "median |prediction error| [%]", 1),
                    ("parity_r2_centred", lambda p, k: p.block_parity_r2[k], "parity R² (centred)", 2)],
                medians=["headline", "threshold_err_pct"], extra=table8,
                where=lambda d: d.query(f"planner == '{PROPOSED}' and {NATURAL}")),
    t2.paper_table("table9", "Table 9: all executed trials per planner and belief reading: success (Wilson, "
                "the paper's Wilson and our object-bootstrap 95%); stable, drop and damage as primary "
                "outcome classes; median lateral threshold and its prediction error (uncensored block A)",
                "planner", lambda p, k: p.table9[k], [
                    ("n", "n", "n", 0), ("success", "success_pct", "success", None),
                    ("paper_wilson", None, "paper Wilson 95% [%]", ""),
                    *((k, f"{k}_pct", k, None) for k in ("stable", "drop", "damage")),
                    ("n_lat_threshold", None, "thresholds", 0),
                    ("lat_threshold_n", "lat_threshold_n", "median lateral threshold [N]", 2),
                    ("lat_threshold_err_pct", "threshold_err_pct", "median |threshold error| [%]", 1)],
                ["is_stable", "is_drop", "is_damage"], ["lat_threshold_n", "lat_threshold_err_pct"],
                boot=True, extra=table9),
    *t2.belief_tables("test3"),
    Table("test3_coating", "Block A of the proposed planner per surface (§9.2, Fig. 33a): success and "
          "median uncensored lateral threshold beside the paper's", coating, [
              Col("friction_level", "surface"), Col("n", "n"), pct_col("success", "success"),
              Col("paper_success_pct", "paper %", "digits"), Col("n_lat_threshold", "thresholds"),
              Col("lat_threshold_n", "median threshold [N]", 2),
              Col("paper_threshold_n", "paper [N]", "threshold_digits"),
              Col("verdict", "verdict (success)")]),
    Table("test3_directions", "Natural-friction block A of the proposed planner per pull direction (§9.2, "
          "Fig. 33b)", lambda run: hw.summary(t2.ex(run, PROPOSED).query(f"block == 'A' and {NATURAL}"), [
              "direction_deg"], medians=["lat_threshold_n"]).sort_values("direction_deg")[[
                  "direction_deg", "n", "success_pct", "lat_threshold_n", "n_lat_threshold"]], [
              Col("direction_deg", "pull direction [°]", 0), Col("n", "n"),
              Col("success_pct", "success [%]", 1), Col("n_lat_threshold", "thresholds"),
              Col("lat_threshold_n", "median threshold [N]", 2)]),
    Table("test3_threshold_agreement", lambda run: f"Predicted against {run.rig} lateral thresholds of "
          "the proposed planner (§9.3, Fig. 34): Bland–Altman [N], OLS with intercept, median absolute error",
          lambda run: pd.DataFrame([ds.threshold_agreement(t2.ex(run))]), [
              Col("n", "n"), *cols("bias_n", "sd_n", "loa_low_n", "loa_high_n"),
              Col("ols_slope", "OLS slope", 3), Col("ols_intercept_n", "OLS intercept [N]", 3),
              Col("ols_r2", "OLS R²", 3), Col("ols_p", "OLS p", sig=2),
              Col("median_err_pct", "median |error| [%]", 1), Col("n_err_over_50pct", "errors > 50 %")],
          by=["planner"]),
    Table("test3_first_finger", lambda run: f"First finger to slip, predicted against the {run.rig} "
          "one, over the trials whose first finger is known (§9.3); Wilson 95% intervals", first_finger,
          [Col("n", "n"), pct_col("first_finger_correct", "first finger correct")], by=["scope"]),
    flags.classifier("test3_retention_classifier", "The retention flag against success (§9.5, Fig. 36c): "
               "the retention flag (`predicted_stable`, as `retention_pred`) is the believed retention "
               "margin under the commanded disturbance > 1, optimistic where the beliefs are wrong; the "
               "residual flag (`predicted_stable_residual`) is Algorithm 2's residual ≤ τ_F, the paper's "
               "§8.1 flag: friction-blind, it carries no information about a friction hold. §9.5's scores "
               "stand beside the retention flag alone, the flag they are of",
               t2.per_planner,
               lambda p: {("all", "predicted_stable"): flags.scores(p.retention_classifier)}),
    Table("test3_logistic", "Logistic regression of failure over the fixed-load blocks B, D, E (§9.5): "
          "applied load [N], mass [kg], believed μ_s, proposed-planner indicator (Wald 95%)",
          lambda run: ds.failure_logistic(t2.ex(run))),
    t2.matched_mcnemar("test3_mcnemar", "Matched paired set (§9.5): McNemar tests of the proposed planner "
                       "against each baseline on occurrence-matched pairs"),
    Table("test3_chi2", "χ² of planner × retention over the proposed, centroid and random arms (§9.5)",
          lambda run: pd.DataFrame([hw.chi2_planners(t2.ex(run), seed=run.seed)])),
    Claims("test3_claims", "§9 headline numbers not in a table above, beside the paper's (rates with "
           "Wilson 95% intervals, logistic coefficients with their Wald intervals)", claims),
    Figure("fig33_thresholds", "Fig. 33 (the paper's values in black): block A (a) median threshold and (b) "
           "success per surface (the paper's Fig. 33a), (c) natural-friction threshold per pull direction "
           "(33b), (d) proposed success per block at natural friction (33c)", fig33, (10.0, 8.4)),
    Figure("fig34_threshold_prediction", lambda run: f"Fig. 34: (a) predicted against {run.rig} lateral "
           "thresholds of the proposed planner with the OLS fit, (b) Bland–Altman, (c) median "
           "lateral-threshold error per planner", fig34, (10.0, 8.0)),
    Figure("fig35_representative_pull", fig35_caption, fig35, (9.5, 5.2)),
    Figure("fig36_robustness", lambda run: "Fig. 36: (a) success per planner with the planners' own beliefs "
           "and with exact ones (hatched), (b) share of natural-friction pulls holding each level (a grasp "
           f"lost before the pull counts as 0 N), (c) the retention flag (`predicted_stable`) against the "
           f"{run.rig} outcome", style.panels(t2.planner_bars("table9"), survival, flags.confusion(
               lambda p: p.retention_classifier, "predicted to retain: believed margin > 1")),
           (10.0, 8.0)),
])
