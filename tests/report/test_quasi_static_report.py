"""Quasi-static reports (baseline_grid, ablation, grip_laws) on synthetic runs.

The opening paragraphs' numbers, the mechanism, readings, grip-need, epsilon and H-epsilon tables,
McNemar within each grip law and the at-bound caption are recomputed here from the records with
pandas, scipy and statsmodels, never with the report's helpers.
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
import pytest
from scipy import stats
from statsmodels.stats.contingency_tables import mcnemar as sm_mcnemar
from statsmodels.stats.proportion import proportion_confint
from synthetic_runs import (
    PLANNERS,
    SHAPES,
    candidates,
    caption,
    make_run,
    md_table,
    ok_records,
    opening,
    quasi_static_outputs,
    read_table,
    report_md,
)

from graspcampaign.analysis.vocabulary import label
from graspcampaign.report import format as fmt
from graspcampaign.report.build import build_reports

SHOWN = ["heuristic", "antipodal", "centroid", "random", "ferrari_canny"]  # the vocabulary's, every report's
LAWS = ["paper", "slip", "oracle"]
G = 9.81  # core.statics.GRAVITY


PREPARED = [{"shape": s, "mass_kg": 0.2, "mu": 0.3, "nodes": 390, "body_id": f"b{i}", "lambda1": 1.5,
             "lambda2": 0.05 if i else 0.9, "n_exp": 1.0, "b": 0.6, "k": 0.1, "c": 0.002, "best_cost": 1.0,
             "n_evaluations": 120, "wall_time_s": 0.3, "flat_parameters": "lambda2,b,k,c",
             "at_bound": "lambda1,lambda2,n" if i else "lambda1,n", "at_bound_lambda1": True,
             "at_bound_lambda2": bool(i), "at_bound_n": True, "at_bound_b": False, "at_bound_k": False,
             "at_bound_c": False} for i, s in enumerate(SHAPES[:2])]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    root = tmp_path_factory.mktemp("qs") / "results"
    grid = make_run(root, "baseline_grid", "quasi_static", {"shape": SHAPES, "mass_kg": [0.2, 0.6],
                                                            "mu": [0.1, 0.5], "planner": PLANNERS},
                    seeds=3, paper=None, outputs=quasi_static_outputs, tables=candidates, prepared=PREPARED)
    laws = make_run(root, "grip_laws", "quasi_static", {"shape": SHAPES, "mass_kg": [0.2], "mu": [0.3],
                                                        "planner": PLANNERS, "grip_law": LAWS},
                    seeds=6, paper=None, outputs=quasi_static_outputs, tables=candidates,
                    method_factors=["planner", "grip_law"])
    ablation = make_run(root, "ablation", "quasi_static", {"shape": SHAPES, "mass_kg": [0.4], "mu": [0.3],
                                                           "planner": ["heuristic", "no_s1", "random",
                                                                       "ferrari_canny"], "grip_law": LAWS},
                        seeds=2, paper=None, outputs=quasi_static_outputs, tables=candidates,
                        method_factors=["planner", "grip_law"])
    build_reports(["baseline_grid", "grip_laws", "ablation"], root=root)
    return {"grid": grid, "laws": laws, "ablation": ablation}


def figures(store) -> set[str]:
    return {p.stem for p in (store.path / "report" / "figures").glob("*.png")}


def test_grid_opening_paragraph_numbers_are_the_records(runs):
    """The opening gives the main finding and the mechanism in a few numbers from the records and
    points to the tables for the rest (it listed every planner's bound, the one-fingertip passes, the
    design-limit counts and the gate's removals, each printed by a table below)."""
    store = runs["grid"]
    ok = ok_records(store)
    text = opening(store)
    released = int((ok["n_released"] >= 1).sum())
    assert f"(released in {released} of {len(ok)} triples, {100 * released / len(ok):.1f}%)" in text
    # the main finding first: the proposed planner's rate and Wilson interval (statsmodels), then why
    h = ok.loc[ok["planner"] == "heuristic", "success"].astype(bool)
    low, high = proportion_confint(h.sum(), len(h), method="wilson")
    # a planner differs when the paper's rate (campaigns/baseline_grid.yaml) lies outside our Wilson
    # interval by more than its last printed digit (0.1 pp), counted from the records (statsmodels)
    paper = pd.Series({"heuristic": 67.6, "antipodal": 40.0, "random": 11.0, "centroid": 0.0})
    wins = ok.groupby("planner")["success"].agg(["sum", "size"]).loc[paper.index]
    lows, highs = (100 * end for end in proportion_confint(wins["sum"], wins["size"], method="wilson"))
    differ = int(((paper <= lows - 0.1) | (paper >= highs + 0.1)).sum())
    assert text.startswith(
        f"**The paper's rates cannot come from its own Algorithm 2.** The proposed planner "
        f"passes {100 * h.mean():.1f}% of {len(h)} triples (Wilson 95% {100 * low:.1f}–{100 * high:.1f}; "
        f"paper 67.6%); {differ} of 4 planners with a paper value {'differs' if differ == 1 else 'differ'} "
        "from it (table success_by_planner). Why: line 7")
    # the bound ρ·W < τ_F (τ_F = 0.5 N here) against each paper rate
    passable = ok.assign(p=ok["rho"] * ok["mass_kg"] * G < 0.5).groupby("planner")["p"].mean() * 100
    capped = int((passable[paper.index] < paper).sum())
    assert f"which caps {capped} of 4 planners below the paper's rate (table mechanism)." in text
    assert text.endswith("SPEC §8; `docs/decisions.md`, *Physical validity, grip laws, Ferrari–Canny ε*.")
    for tabled in ("won–lost", "fingertip", "design limit", "validity gate", "as many are released"):
        assert tabled not in text, tabled
    assert len(text) <= 900


def test_grid_mechanism_readings_and_epsilon_tables(runs):
    store = runs["grid"]
    ok = ok_records(store)
    mech = read_table(store, "mechanism").set_index("planner")
    assert list(mech.index) == SHOWN
    assert mech["released"].to_dict() == (ok["n_released"] >= 1).groupby(ok["planner"]).sum().to_dict()
    reading = read_table(store, "readings").set_index("planner")
    for column in ("success", "success_unbounded", "success_vertical", "success_no_torque"):
        expected = ok[column].astype(bool).groupby(ok["planner"]).agg(["sum", "mean"])
        assert reading[column].to_dict() == expected["sum"].to_dict()
        assert reading[f"{column}_pct"].to_dict() == pytest.approx((100 * expected["mean"]).to_dict())
    # the Wilson intervals are headed as every other rate's (they printed "success % (95%)")
    shown = md_table(report_md(store), "readings")
    assert list(shown.columns[2:6]) == ["success % (Wilson 95%)", "without the validity gate % (Wilson 95%)",
                                        "|R_z| reading % (Wilson 95%)", "torque check off % (Wilson 95%)"]
    no_torque_only = ok["success_no_torque"].astype(bool) & ~ok["success"]
    assert reading["torque_binds"].to_dict() == no_torque_only.groupby(ok["planner"]).sum().to_dict()
    eps = read_table(store, "epsilon").set_index("planner")
    assert eps["force_closure"].to_dict() == (ok["epsilon_fc"] > 0).groupby(ok["planner"]).sum().to_dict()
    median = ok.groupby("planner")["epsilon_fc"].median()
    assert eps["epsilon_median"].to_dict() == pytest.approx(median.to_dict())
    fc = ok[ok["planner"] == "ferrari_canny"]
    table = read_table(store, "h_epsilon").set_index("reading")
    assert table.loc["median per trial", "rho"] == pytest.approx(fc["spearman_h_epsilon"].median())
    cand = store.read("tables/candidates").to_pandas()
    # scipy.stats.spearmanr over the pooled candidates
    pooled = stats.spearmanr(cand["h_total"], cand["epsilon_fc"]).statistic
    assert table.loc["pooled", "rho"] == pytest.approx(pooled)
    assert table.loc["pooled", "n_pairs"] == len(cand) == 50 * len(fc)
    text = report_md(store)
    assert "on a PSO search bound: λ1 = 1.5 in 2 of 2, λ2 = 0.05 in 1 of 2, n = 1 in 2 of 2" in text
    assert "J is flat in λ2, b, k, c in 2 of 2 bodies" in text
    assert "not computed" not in text
    assert figures(store) == {"fig18_baselines", "h_epsilon"}


def test_the_h_epsilon_caption_gives_the_resamples_and_seed_that_reproduce_its_intervals(runs):
    """An outsider reproduces every interval of table h_epsilon from its caption alone: scipy's
    percentile bootstrap of each per-trial median, then the trial-cluster resamples of the pooled ρ
    (each candidate repeated as often as its trial is drawn, scipy's spearmanr), one generator. The
    caption said neither count nor seed (the pooled ρ takes 2000 resamples, the rest 10000)."""
    store = runs["grid"]
    text = caption(store, "h_epsilon")
    found = re.search(r"(\d+) resamples of each per-trial median, then (\d+) of the pooled ρ, from one "
                      r"generator of seed (\d+)", text)
    assert found, text
    per_trial, pooled, seed = map(int, found.groups())
    ok = ok_records(store).sort_values("trial_index")
    fc = ok[ok["planner"] == "ferrari_canny"]
    table, rng = read_table(store, "h_epsilon").set_index("reading"), np.random.default_rng(seed)
    for reading, column in (("median per trial", "spearman_h_epsilon"),
                            ("median per trial, force closure", "spearman_h_epsilon_fc")):
        ci = stats.bootstrap((fc[column].to_numpy(float),), np.median, n_resamples=per_trial,
                             method="percentile", rng=rng).confidence_interval
        assert table.loc[reading, ["low", "high"]].tolist() == pytest.approx([ci.low, ci.high], rel=1e-12)
    cand = store.read("tables/candidates").to_pandas()
    trials = sorted(cand["trial_id"].unique())
    pairs = [cand.loc[cand["trial_id"] == t, ["h_total", "epsilon_fc"]].to_numpy(float) for t in trials]
    rhos = []
    for _ in range(pooled):
        drawn = np.concatenate([pairs[i] for i in rng.integers(0, len(trials), len(trials))])
        rhos.append(stats.spearmanr(drawn[:, 0], drawn[:, 1]).statistic)
    expected = np.nanquantile(rhos, [0.025, 0.975])
    assert table.loc["pooled", ["low", "high"]].tolist() == pytest.approx(expected, rel=1e-9)


def test_grip_laws_mcnemar_pairs_within_each_law(runs):
    store = runs["laws"]
    ok = ok_records(store)
    table = read_table(store, "mcnemar").set_index(["grip_law", "compared"])
    assert list(table.index) == [(law, p) for law in LAWS for p in SHOWN[1:]]
    wide = ok.pivot(index=["scene_id", "grip_law"], columns="planner", values="success")
    for (law, other), row in table.iterrows():
        pair = wide.xs(law, level="grip_law")[["heuristic", other]].dropna().astype(bool)
        n10 = int((pair["heuristic"] & ~pair[other]).sum())
        n01 = int((~pair["heuristic"] & pair[other]).sum())
        assert (row["pairs"], row["reference_only"], row["compared_only"]) == (len(pair), n10, n01)
        if n01 + n10:
            cells = np.array([[0, n01], [n10, 0]])
            # statsmodels mcnemar: chi2 with continuity correction, and the exact binomial test
            assert row["chi2_cc"] == pytest.approx(sm_mcnemar(cells, exact=False, correction=True).statistic)
            assert row["p_exact"] == pytest.approx(sm_mcnemar(cells, exact=True).pvalue)
    # the opening counts the significant pairs over every law (each pair is the mcnemar table's)
    won = lost = 0
    for row in table.to_dict("records"):
        n10, n01 = int(row["reference_only"]), int(row["compared_only"])
        if n10 + n01 and stats.binomtest(n10, n10 + n01).pvalue < 0.05:
            won, lost = won + (n10 > n01), lost + (n10 < n01)
    assert (f"(McNemar, exact p < 0.05; table mcnemar), it beats {won} and loses to {lost} of "
            f"{len(table)} planner–law pairs.") in opening(store)


def test_grip_laws_rates_readings_checks_and_need(runs):
    store = runs["laws"]
    ok = ok_records(store)
    rates = read_table(store, "success_by_planner").set_index(["planner", "grip_law"])
    assert list(rates.index) == [(p, law) for p in SHOWN for law in LAWS]  # planners side by side
    expected = ok.groupby(["planner", "grip_law"])["success"].mean() * 100
    pd.testing.assert_series_equal(rates["rate_pct"].sort_index(), expected.sort_index(), check_names=False)
    assert rates.loc[("heuristic", "oracle"), "paper_pct"] == 67.6  # Fig. 18, beside every law
    # ... and judged under Algorithm 2 only: the paper ran no other law (Sec. 6.5: "was not run")
    paper_values = {"heuristic": 67.6, "antipodal": 40.0, "random": 11.0, "centroid": 0.0}
    for (planner, law), row in rates.iterrows():
        if law != "paper" or planner not in paper_values:
            assert pd.isna(row["differs"]) and pd.isna(row["difference"]), (planner, law)
            continue
        g = ok[(ok["planner"] == planner) & (ok["grip_law"] == law)]
        low, high = proportion_confint(int(g["success"].sum()), len(g), method="wilson")
        assert bool(row["differs"]) == (not 100 * low <= paper_values[planner] <= 100 * high)
    verdicts = rates.xs("oracle", level="grip_law")["verdict"]
    assert set(verdicts[verdicts.index != "ferrari_canny"]) == {"no verdict: the paper ran Algorithm 2 only"}
    reading = read_table(store, "readings").set_index(["grip_law", "planner"])
    exp = ok.assign(nt=ok["success_no_torque"].astype(bool)).groupby(["grip_law", "planner"])["nt"].mean()
    assert reading["success_no_torque_pct"].to_dict() == pytest.approx((100 * exp).to_dict())
    checks = read_table(store, "failure_checks").set_index(["grip_law", "planner"])
    crosstab = pd.crosstab([ok["grip_law"], ok["planner"]], ok["failure_check"])
    for key in crosstab.index:
        for check in crosstab.columns:
            assert checks.loc[key, check] == crosstab.loc[key, check]
    need = read_table(store, "grip_need").set_index(["grip_law", "planner"])
    assert {law for law, _ in need.index} == {"slip", "oracle"}
    oracle = ok[ok["grip_law"] == "oracle"]
    capped = oracle["grip_capped"].astype(bool)
    assert need.xs("oracle")["holdable"].to_dict() == (~capped).groupby(oracle["planner"]).sum().to_dict()
    text = opening(store)
    # the "Why" (and its count of triples no equal grip holds) only where the proposed planner loses a
    # pair: the other planner's discordant successes outnumber its own at exact (binomial) p < 0.05
    pairs = read_table(store, "mcnemar")
    loses = sum(r < c and stats.binomtest(int(r), int(r + c)).pvalue < 0.05
                for r, c in zip(pairs["reference_only"], pairs["compared_only"], strict=True))
    why = (f"Why: H(G) is geometric and sees neither gravity nor the tilt of the contact plane; horizontal "
           f"normals (the centroid planner's triple) let an equal grip balance by symmetry, while under "
           f"oracle no equal grip holds on {int(np.isinf(oracle['grip_needed_n']).sum())} of "
           f"{len(oracle)} triples (normals per planner: table grip_need)")
    assert f"and loses to {loses} of {len(pairs)} planner–law pairs. " in text
    assert (why in text) == (loses > 0) and ("Why" in text) == (loses > 0)
    proposed = ok[ok["planner"] == "heuristic"].groupby("grip_law")["success"].mean() * 100
    assert "the proposed planner passes " + fmt.listed(
        [f"{proposed[law]:.1f}% under {label('grip_law', law)}" for law in LAWS]) in text
    assert "The torque check alone" not in text and len(text) <= 900  # the readings table's counts
    assert "not computed" not in report_md(store)
    assert figures(store) == {"fig18_grip_laws", "h_epsilon"}


def test_successes_beyond_the_design_limit_are_counted_in_the_finding_and_captions(runs):
    """Under every grip law, the successes deeper than 1 mm and at the grip cap, from the records,
    are said in the success table's caption (not again under the figure). The opening starts with its
    main finding, the paper's ordering, and gives the design limit once, short: the count over every
    law, pointing to that caption."""
    for store, figure in ((runs["laws"], "fig18_grip_laws"), (runs["ablation"], "fig16_ablation")):
        ok = ok_records(store)
        parts = []
        for law in LAWS:
            g = ok[(ok["grip_law"] == law) & ok["success"].astype(bool)]
            cap = g["grip_capped"].astype(bool)
            over = f"{label('grip_law', law)} {int((g['delta_max_mm'] > 1).sum())} of {len(g)}" if len(g) \
                else f"{label('grip_law', law)} no success"  # not '0 of 0'
            if cap.any():
                span = fmt.span(g.loc[cap, "delta_max_mm"])  # the records' range, one rounding
                over += f" ({int(cap.sum())} at the grip cap, δmax = {span} mm ≤ r = 5 mm)"
            parts.append(over)
        sentence = "Successes deeper than the paper's 1 mm design limit: " + "; ".join(parts)
        assert sentence in caption(store, "success_by_planner")
        assert f"*{sentence}" not in report_md(store)  # (the figure caption continues a sentence)
        figure_caption = next(line for line in report_md(store).splitlines() if line.startswith("![")
                              and f"{figure}.png" in line)  # the rates only: not a third copy
        assert "design limit" not in figure_caption and figure_caption.endswith(
            "black marks are the paper's (Algorithm 2) values](figures/" + f"{figure}.png)")
    text, won = opening(runs["laws"]), ok_records(runs["laws"]).query("success")["delta_max_mm"]
    # the paper's rates as the success table prints them (campaigns/baseline_grid.yaml; was "40%")
    assert text.startswith("The paper's ordering (Fig. 18: proposed H(G) 67.6%, antipodal 40.0%, "
                           "random 11.0%, centroid 0.0%)")
    assert (f"{(won > 1).sum()} of the {len(won)} successes lie deeper than the paper's 1 mm design limit "
            "(per law: table design_limit).") in text
    assert text.count("design limit") == 1


def test_the_papers_ordering_is_claimed_only_where_our_rates_order_the_planners_strictly(runs, tmp_path):
    """Planners tied at one rate have no ordering: a run where every trial fails (all at 0%, the
    ties in the study's planner order, which is the paper's) claims the ordering under no law."""
    paper = ["heuristic", "antipodal", "random", "centroid"]  # Fig. 18, highest first
    rates = ok_records(runs["laws"]).groupby(["grip_law", "planner"])["success"].mean().unstack()
    strict = [label("grip_law", law) for law in LAWS if (rates.loc[law, paper].diff().iloc[1:] < 0).all()]
    assert f") appears under {fmt.listed(strict, 'none of the laws')}: the proposed" in opening(runs["laws"])

    def fail(factors, rng):  # every trial fails its residual check, so τ_T removes no pass either
        return {**quasi_static_outputs(factors, rng), "success": False, "failure_check": "residual",
                "success_no_torque": False}

    store = make_run(tmp_path / "results", "grip_laws", "quasi_static",
                     {"shape": SHAPES[:2], "mass_kg": [0.2], "mu": [0.3], "planner": PLANNERS,
                      "grip_law": LAWS}, seeds=2, paper=None, outputs=fail,
                     method_factors=["planner", "grip_law"])
    build_reports(["grip_laws"], root=tmp_path / "results")
    assert ") appears under none of the laws: the proposed" in opening(store)
    assert "it beats 0 and loses to 0 of 12 planner–law pairs" in opening(store)  # no pair differs
    assert "τ_T binds" not in opening(store)


def test_the_laws_that_show_the_papers_ordering_are_listed_in_english(tmp_path):
    """A list in a sentence reads 'a, b and c' (fmt.listed): the laws under which the paper's
    ordering appears read 'Algorithm 2 (paper), slip-margin grip and oracle equal grip' (they were
    joined by commas only). Here each planner passes on a fixed number of the three shapes, so every
    law orders the planners strictly as Fig. 18 does (3, 2, 1, 0 of 3)."""
    passes = {"heuristic": 3, "antipodal": 2, "random": 1}

    def ordered(factors, rng):
        won = SHAPES.index(factors["shape"]) < passes.get(factors["planner"], 0)
        return {**quasi_static_outputs(factors, rng), "success": won, "success_no_torque": won,
                "failure_check": "none" if won else "residual"}

    store = make_run(tmp_path / "results", "grip_laws", "quasi_static",
                     {"shape": SHAPES[:3], "mass_kg": [0.2], "mu": [0.3], "planner": PLANNERS,
                      "grip_law": LAWS}, seeds=1, paper=None, outputs=ordered,
                     method_factors=["planner", "grip_law"])
    build_reports(["grip_laws"], root=tmp_path / "results")
    rates = ok_records(store).groupby(["grip_law", "planner"])["success"].sum().unstack()
    assert (rates[["heuristic", "antipodal", "random", "centroid"]].diff(axis=1).iloc[:, 1:] < 0).all().all()
    assert ") appears under Algorithm 2 (paper), slip-margin grip and oracle equal grip: the proposed" \
        in opening(store)


def test_ablation_gains_its_grip_law_columns(runs):
    store = runs["ablation"]
    rates = read_table(store, "success_by_planner")
    assert set(rates["grip_law"]) == set(LAWS) and (rates.groupby("planner").size() == 3).all()
    assert set(read_table(store, "mcnemar")["grip_law"]) == set(LAWS)
    assert "not computed" not in report_md(store)
    # the paper's power (Sec. 6.3) qualifies the success table, beside our Wilson intervals: its caption
    # says it, the opening does not (it said it beside ours, which the table prints)
    assert ("At the paper's 50 trials per variant its interval is roughly ±12 pp (Sec. 6.3)."
            in caption(store, "success_by_planner"))
    assert "±12 pp" not in opening(store) and "Power" not in opening(store)
    assert figures(store) == {"fig16_ablation", "h_epsilon"}



def test_readings_caption_sets_the_papers_tau_t_claim_beside_the_records(runs):
    for store in runs.values():
        ok = ok_records(store)
        alone = ok["success_no_torque"].astype(bool) & ~ok["success"]
        first = int((ok["failure_check"] == "torque").sum())
        assert alone.any()  # the synthetic records let τ_T bind, so the caption must say so
        text = caption(store, "readings")
        assert "τ_T off (Sec. 3.7: τ_T never binds; here it does: τ_T alone removed " \
               f"{int(alone.sum())} passes" in text
        assert f"torque is the first failing check of {first} of {len(ok)} trials" in text


def test_ablation_finding_scopes_its_numbers_to_each_grip_law(runs):
    """Each grip law the paper did not run: its passes and its most frequent first failing check,
    from the records (it listed every law's cap, grip and check counts, which the tables print)."""
    store = runs["ablation"]
    ok, text = ok_records(store), opening(store)
    said = []
    for law, words in (("slip", "slip-margin grip"), ("oracle", "oracle equal grip")):
        g = ok[ok["grip_law"] == law]
        failed = g.loc[g["failure_check"] != "none", "failure_check"].value_counts()
        top = failed[failed == failed.max()].index  # a tie: the first in the order the checks run
        check = min(top, key=["residual", "torque", "slip", "geometry"].index)
        said.append(f"{int(g['success'].sum())} of {len(g)} ({words}; {failed[check]} fail first on {check})")
    assert (f"The grip laws the paper did not run (Sec. 6.5, 12) pass {said[0]} and {said[1]}; per "
            "planner: tables grip_need and failure_checks.") in text
    assert "Under Algorithm 2," not in text and "design limit" not in text  # table design_limit's
    assert text.endswith("`docs/decisions.md`, *Physical validity, grip laws, Ferrari–Canny ε*.")
    assert len(text) <= 900


def test_ablation_opening_grip_counts_are_in_its_grip_need_table(runs):
    """Each law's cap and no-equal-grip counts of the opening can be checked in a table of the
    report: grip_need, per grip law and planner, equals the records' grip_capped and grip_needed_n."""
    store = runs["ablation"]
    ok = ok_records(store)
    other = ok[ok["grip_law"] != "paper"].assign(
        holdable=~ok["grip_capped"].astype(bool), no_equal_grip=np.isinf(ok["grip_needed_n"]),
        capped_passes=ok["grip_capped"].astype(bool) & ok["success"].astype(bool))
    expected = other.groupby(["grip_law", "planner"])[["holdable", "no_equal_grip", "capped_passes"]].sum()
    need = read_table(store, "grip_need").set_index(["grip_law", "planner"])
    assert need.loc[expected.index, expected.columns].to_dict() == expected.to_dict()
    assert need["n"].to_dict() == other.groupby(["grip_law", "planner"]).size().to_dict()
    assert "per planner: tables grip_need and failure_checks." in opening(store)


def test_h_epsilon_histogram_counts_trials_in_whole_numbers(runs):
    import json

    import matplotlib.pyplot as plt

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.quasi_static import h_epsilon_figure

    store = runs["ablation"]
    fig = plt.figure()
    h_epsilon_figure(Run(store.read().to_pandas(), json.loads(store.manifest_path.read_text()),
                         store=store), fig)
    ticks = fig.axes[1].get_yticks()
    plt.close(fig)
    assert len(ticks) >= 2 and np.array_equal(ticks, np.round(ticks))


def test_headline_rows_are_algorithm_2s_trials_only(runs):
    from statsmodels.stats.proportion import proportion_confint

    root = runs["ablation"].path.parent.parent
    rows = pd.read_csv(root / "headline.csv").set_index("headline")
    for headline, store in (("Heuristic ablation", runs["ablation"]), ("Baseline grid", runs["grid"])):
        ok = ok_records(store)
        paper = ok[ok["grip_law"] == "paper"]  # the paper's rates are Algorithm 2's
        mine = paper[paper["planner"] == "heuristic"]
        row = rows.loc[headline]
        low, high = proportion_confint(mine["success"].sum(), len(mine), method="wilson")
        assert (row["n"], row["rate_pct"]) == (len(mine), pytest.approx(100 * mine["success"].mean()))
        assert (row["wilson_low_pct"], row["wilson_high_pct"]) == pytest.approx((100 * low, 100 * high))
        baselines = paper[(paper["planner"] != "heuristic") & ~paper["planner"].str.startswith("no_s")]
        rates = baselines.groupby("planner")["success"].mean() * 100  # ablation variants are no baseline
        assert set(row["ours_baselines"].split(", ")) == {f"{label('planner', p)} {r:.1f}%"
                                                          for p, r in rates.items()}
        shown = [float(x.rsplit(" ", 1)[1].rstrip("%")) for x in row["ours_baselines"].split(", ")]
        assert shown == sorted(shown, reverse=True)
    assert rows.loc["Heuristic ablation", "testbed"].endswith("; grip law Algorithm 2 (paper) only")
    # a count is an integer in the CSV (675, not 675.0)
    text = (root / "headline.csv").read_text()
    assert ",675," in text and ",675.0," not in text
