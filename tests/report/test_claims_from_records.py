"""Causal and comparative sentences of the openings hold on the records they are printed over: each
case takes a reduced run of the shared results tree (conftest.py), sets the records (or the table a
sentence reads them from) so the sentence's claim would be false, and checks the opening no longer
makes it. The Tests 2-3 "Why" clause: test_test23_opening.py."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from scipy.stats import binomtest
from synthetic_runs import below_arrest

from graspcampaign.campaign.paper import study_paper
from graspcampaign.campaign.records import RunStore
from graspcampaign.report.build import spec_for
from graspcampaign.report.document import Document
from graspcampaign.report.render import Run, render


def _rendered(root, study: str, records=lambda r: r) -> Run:
    """The run of ``study`` with ``records`` applied to its records, every item rendered."""
    store = RunStore(root / study / "default")
    run = Run(records(store.read().to_pandas()), store.check(), study_paper(study), store)
    render(spec_for(study, ""), run, Document("", run.source, []))
    return run


def test_the_grid_opening_says_the_rates_cannot_come_from_algorithm_2_only_where_it_caps_a_planner(sim_root):
    # "**The paper's rates cannot come from its own Algorithm 2.**" opened the paragraph even where
    # the mechanism table capped no planner below its paper rate (every triple with ρ·W < τ_F)
    from graspcampaign.report.studies.quasi_static import grid_finding

    run = _rendered(sim_root, "baseline_grid")
    assert grid_finding(run).startswith("**The paper's rates cannot come from its own Algorithm 2.** ")
    m = run.tables["mechanism"]
    run.tables["mechanism"] = m.assign(rho_passable=m["n"])  # every triple could pass
    text = grid_finding(run)
    assert "cannot come from" not in text and "which caps" not in text  # no "caps 0 of 4 planners"
    assert "only triples with ρ·W < τ_F can pass (table mechanism)." in text  # a planner still differs


def test_the_grid_opening_counts_the_planners_the_mechanism_caps(sim_root):
    # "which caps 0 of 4 planners below the paper's rate" was printed wherever a planner differed;
    # the count is of the planners with a paper value whose share of triples with ρ·W < τ_F lies
    # below that value: here set by hand, one planner (the proposed, paper 67.6%) at 0 passable
    from graspcampaign.report.studies.quasi_static import grid_finding

    run = _rendered(sim_root, "baseline_grid")
    m = run.tables["mechanism"]
    run.tables["mechanism"] = m.assign(rho_passable=m["n"].where(m["planner"] != "heuristic", 0))
    judged = int((m["n"].gt(0) & m["planner"].isin(run.paper.success_pct)).sum())  # with a paper value
    assert f"can pass, which caps 1 of {judged} planners below the paper's rate (table mechanism)." \
        in grid_finding(run)
    one = run.tables["mechanism"]
    run.tables["mechanism"] = one[one["planner"] == "heuristic"]  # the one planner judged
    assert "can pass, which caps 1 of 1 planner below the paper's rate" in grid_finding(run)


def test_the_grid_opening_gives_its_why_only_where_a_planner_differs_or_is_capped(sim_root):
    # "Why: line 7 drives every upper contact to δ = 0 … caps k of n planners" followed the counts
    # whatever they were, "0 of 4 planners … differ" and "caps 0 of 4" together included
    from graspcampaign.report.studies.quasi_static import grid_finding

    run = _rendered(sim_root, "baseline_grid")
    rates, m = run.tables["success_by_planner"], run.tables["mechanism"]
    compared = int(rates["differs"].notna().sum())
    run.tables["success_by_planner"] = rates.assign(differs=rates["differs"].where(rates["differs"].isna(),
                                                                                   False))
    assert "Why: line 7 drives every upper contact" in grid_finding(run)  # still capped
    run.tables["mechanism"] = m.assign(rho_passable=m["n"])  # and no planner capped: no gap
    text = grid_finding(run)
    assert f"0 of {compared} planners with a paper value differ from it (table success_by_planner). " \
           "SPEC §8; " in text
    assert "Why" not in text and "line 7" not in text


def test_the_weights_opening_gives_no_why_where_h_matches_the_paper_at_every_scale(sim_root):
    from graspcampaign.report.studies.weights import finding

    run = _rendered(sim_root, "heuristic_weights")
    assert "Why: S1 follows the published Eq. 7" in finding(run)
    scale = run.tables["h_by_scale"]
    run.tables["h_by_scale"] = scale.assign(differs=False)
    text = finding(run)
    assert f"matches the paper's at {len(scale)} of {len(scale)} scales" in text and "Why" not in text


def test_the_sensitivity_opening_counts_the_slip_checks_the_records_hold(sim_root):
    # it said "so the slip check rarely binds" whatever the records' failing checks were
    from graspcampaign.report.studies.sensitivity import finding

    def slipping(records: pd.DataFrame) -> pd.DataFrame:
        ok = records["status"] == "ok"
        return records.assign(failure_check=records["failure_check"].where(~ok, "slip"))

    records = RunStore(sim_root / "sensitivity" / "default").read().to_pandas()
    n = int((records["status"] == "ok").sum())
    run = _rendered(sim_root, "sensitivity", slipping)
    text = finding(run)
    assert "rarely binds" not in text
    assert f", and the slip check fails first in {n} of {n} (table sensitivity_panels); " in text
    assert run.tables["sensitivity_panels"]["slip_first"].sum() == n  # the opening's count, per panel


def test_the_sensitivity_opening_gives_the_friction_utilisation_the_records_hold(sim_root):
    # "the remaining normals carry the weight (η ≈ 0)" was asserted, not read; here every executed
    # trial needs half its normal force in friction, |η| = 0.5 (signs alternate: |η|, not η, is the
    # utilisation), and a trial without a loaded tangent contact has none (NaN)
    from graspcampaign.report.studies.sensitivity import finding

    def utilised(records: pd.DataFrame) -> pd.DataFrame:
        return records.assign(eta=np.resize([0.5, -0.5, np.nan], len(records)))

    text = finding(_rendered(sim_root, "sensitivity", utilised))
    assert "η ≈ 0" not in text
    assert "Why: Algorithm 2 releases contacts until the remaining normals carry the weight (median |η| " \
           "0.50 in each panel), and the slip check" in text
    assert "(median |η| " not in finding(_rendered(sim_root, "sensitivity", lambda r: r.drop(columns="eta")))


def test_the_test1_opening_says_smaller_fit_errors_only_where_the_claims_show_them(sim_root):
    from graspcampaign.report.studies.test1 import finding

    run = _rendered(sim_root, "test1_bench")
    claims = run.tables["test1_claims"]
    run.tables["test1_claims"] = claims.assign(source="virtual")
    assert "(smaller fit errors and loops, C not identifiable at 1 mN, λ1 where Eq. 14" in finding(run)
    rows = claims["quantity"].isin(["force-fit RMSE, accepted fits: mean", "loop area: median"])
    run.tables["test1_claims"] = claims.assign(value=claims["value"].where(~rows, 1e3))  # above the paper's
    text = finding(run)
    assert "smaller" not in text and "near 2.1" not in text
    assert "(C not identifiable at 1 mN, λ1 where Eq. 14 with Table 4's moduli puts it)" in text


def test_the_wrench_opening_names_the_runs_grip_command_not_the_papers(sim_root):
    """The opening said "Under the fixed 70 N grip command" for a run given
    ``paper.finger_force_command_n=70``, whose fingers closed at the study's 65 N: the command it
    names is the run's, the force every trace ends at (the closing ramp ends there)."""
    import dataclasses

    from graspcampaign.report.studies import wrench

    store = RunStore(sim_root / "wrench_balance" / "default")
    ends = store.read("tables/iterations").to_pandas().groupby("trial_id")["normal_force_1_n"].last()
    assert ends.nunique() == 1  # one command for every friction level
    paper = dataclasses.replace(study_paper("wrench_balance"), finger_force_command_n=70.0)
    run = Run(store.read().to_pandas(), store.check(), paper, store)
    render(spec_for("wrench_balance", ""), run, Document("", run.source, []))
    assert wrench.finding(run).startswith(f"Under the fixed {ends.iloc[0]:.0f} N grip command ")


def test_the_wrench_opening_gives_no_why_where_every_quantity_agrees(sim_root, monkeypatch):
    from graspcampaign.report.studies import wrench

    run = _rendered(sim_root, "wrench_balance")
    assert "Why: at Table 3's contact constants" in wrench.finding(run)
    per_mu = wrench._per_mu
    monkeypatch.setattr(wrench, "_per_mu", lambda run: per_mu(run).assign(differs=False))
    text = wrench.finding(run)
    assert "quantities differ (table wrench_balance). At Table 3's contact constants" in text
    # no cause without a difference, but a contact deeper than the fingertip radius is still flagged
    assert "Why" not in text and text.count("a non-physical state") == 1
    monkeypatch.setattr(wrench, "_beyond_radius_from", lambda run, trace: math.nan)  # within the radius
    text = wrench.finding(run)
    assert text.endswith("quantities differ (table wrench_balance).")
    assert "Why" not in text and "non-physical" not in text


def test_the_surrogate_opening_gives_no_why_where_every_scenario_passes_within_the_radius(sim_root):
    from graspcampaign.report.studies.surrogate import finding

    def physical(records: pd.DataFrame) -> pd.DataFrame:
        return records.assign(residual_ok=True, delta_max_mm=0.5)  # every check passed, 0.5 mm < r

    assert "Why: in SI, Algorithm 2 as published" in finding(_rendered(sim_root, "surrogate"))
    assert "Why" not in finding(_rendered(sim_root, "surrogate", physical))


def test_the_test3_opening_gives_no_cause_of_the_drops_where_none_held_a_low_safety_factor(sim_root):
    # "drops X% (paper Y%): no slip is arrested below a safety factor of μ_s/μ_k = …" made the Coulomb
    # fact the drops' cause whatever the dropped trials' recorded SF; here each held 2.0, above Table 4's
    # highest μ_s/μ_k (0.772/0.544 = 1.42)
    from graspcampaign.report.studies.test3 import drops

    def held(records: pd.DataFrame) -> pd.DataFrame:
        return records.assign(sf_actual=records["sf_actual"].mask(records["outcome"] == "failure_drop", 2.0))

    records = RunStore(sim_root / "test3_disturbance" / "default").read().to_pandas()
    ours = records.query("planner == 'heuristic' and status == 'ok' and not aborted")
    n = int((ours["outcome"] == "failure_drop").sum())
    assert n > 0 and ": no slip" not in (text := drops(_rendered(sim_root, "test3_disturbance", held)))
    assert text.endswith(f"%). No slip is arrested below a safety factor of μ_s/μ_k = 1.35–1.42; none of its "
                         f"{n} drops held one below it. ")


def _proposed_drops(root) -> pd.DataFrame:
    """The proposed planner's executed, unaborted drops of the reduced Test 3 run, by trial_id."""
    records = RunStore(root / "test3_disturbance" / "default").read().to_pandas()
    ours = records.query("planner == 'heuristic' and status == 'ok' and not aborted")
    return ours[ours["outcome"] == "failure_drop"].sort_values("trial_id")


def test_the_test3_opening_counts_the_drops_below_the_arrest_bound_of_those_with_an_sf_reading(sim_root):
    # "k of N below the safety factor μ_s/μ_k …" took N as every drop, a drop without a recorded
    # `sf_actual` among them (counted neither below nor above): N is now the drops with the reading and
    # the rest are said apart. Table 4's μ_s/μ_k from synthetic_runs (below_arrest).
    from graspcampaign.report.studies.test3 import drops

    dropped = _proposed_drops(sim_root)
    blank = set(dropped["trial_id"].iloc[:2])  # two drops lose their SF reading

    def unread(sf=None):
        def change(r: pd.DataFrame) -> pd.DataFrame:
            sf_actual = r["sf_actual"].mask(r["outcome"] == "failure_drop", sf) if sf else r["sf_actual"]
            return r.assign(sf_actual=sf_actual.mask(r["trial_id"].isin(blank)))
        return change

    kept = dropped[~dropped["trial_id"].isin(blank)]
    below = below_arrest(kept)
    assert len(dropped) > 2 and below > 0
    assert drops(_rendered(sim_root, "test3_disturbance", unread())).endswith(
        f"%): {below} of {len(kept)} with an `sf_actual` reading below the safety factor μ_s/μ_k = 1.35–1.42 "
        "that arrests a slip (2 more without one). ")
    assert drops(_rendered(sim_root, "test3_disturbance", unread(2.0))).endswith(  # none held one below
        f"; none of its {len(kept)} drops with an `sf_actual` reading held one below it "
        "(2 more without one). ")
    blank = set(dropped["trial_id"])
    assert drops(_rendered(sim_root, "test3_disturbance", unread())).endswith(
        f"; none of its {len(dropped)} drops has an `sf_actual` reading. ")


def test_the_drops_below_the_arrest_bound_are_one_named_result_computed_once_per_run(sim_root):
    # `arrest` returned a 6-tuple its two readers (the opening, the last row of test3_claims) unpacked by
    # position, and computed it for each: now one named result per run, the one both read. Its counts
    # from the records with Table 4 typed from the paper (below_arrest).
    from graspcampaign.report.studies.test3 import arrest

    run = _rendered(sim_root, "test3_disturbance")  # the opening and the claims table both rendered
    dropped = _proposed_drops(sim_root)
    result = arrest(run)
    assert result is arrest(run)
    assert (result.below, result.n_read, result.ratio, result.unread, result.other, result.n_dropped) == (
        below_arrest(dropped), len(dropped), "1.35–1.42", 0, 0, len(dropped))


def test_the_test3_opening_says_one_drop_in_the_singular(sim_root):
    # with one drop read it said "none of its 1 drops with an `sf_actual` reading held one below it"
    from graspcampaign.report.studies.test3 import drops

    dropped = _proposed_drops(sim_root)
    blank = set(dropped["trial_id"].iloc[1:])  # every drop but the first loses its SF reading

    def one_read(r: pd.DataFrame) -> pd.DataFrame:
        sf_actual = r["sf_actual"].mask(r["outcome"] == "failure_drop", 2.0)  # above the arrest bound
        return r.assign(sf_actual=sf_actual.mask(r["trial_id"].isin(blank)))

    assert len(dropped) > 2
    assert drops(_rendered(sim_root, "test3_disturbance", one_read)).endswith(
        f"; its one drop with an `sf_actual` reading did not hold one below it ({len(dropped) - 1} more "
        "without one). ")


def test_the_test3_opening_counts_the_drops_below_the_arrest_bound_of_those_of_a_table4_material(sim_root):
    # a drop whose material is not in Table 4 has no μ_s/μ_k to compare its SF with (neither below nor
    # above) yet stayed in N, as a drop without `sf_actual` did before: N is now the drops with both, and
    # each drop left out is said once, for the first it lacks. Table 4 typed from the paper as above.
    from graspcampaign.report.studies.test3 import drops

    dropped = _proposed_drops(sim_root)
    ids = list(dropped["trial_id"])

    def text(other, blank=(), sf=None) -> str:
        """The sentence with the drops ``other`` of a material not in Table 4, ``blank`` without SF."""
        def change(r: pd.DataFrame) -> pd.DataFrame:
            sf_actual = r["sf_actual"].mask(r["outcome"] == "failure_drop", sf) if sf else r["sf_actual"]
            return r.assign(material=r["material"].mask(r["trial_id"].isin(other), "cardboard"),
                            sf_actual=sf_actual.mask(r["trial_id"].isin(blank)))
        return drops(_rendered(sim_root, "test3_disturbance", change))

    kept = dropped[~dropped["trial_id"].isin(ids[:3])]
    below = below_arrest(kept)
    assert len(dropped) > 3 and below > 0
    assert text(ids[:2], ids[2:3]).endswith(
        f"%): {below} of {len(kept)} with an `sf_actual` reading and a Table 4 material below the "
        "safety factor μ_s/μ_k = 1.35–1.42 that arrests a slip (1 more without an `sf_actual` reading, "
        "2 more of a material not in Table 4). ")
    kept = dropped[~dropped["trial_id"].isin(ids[:2])]  # every drop has its SF
    below = below_arrest(kept)
    assert text(ids[:2]).endswith(f"%): {below} of {len(kept)} with a Table 4 material below the "
                                  "safety factor μ_s/μ_k = 1.35–1.42 that arrests a slip (2 more of a "
                                  "material not in Table 4). ")
    assert text(ids[:2], ids[2:3], sf=2.0).endswith(  # none held one below
        f"; none of its {len(dropped) - 3} drops with an `sf_actual` reading and a Table 4 material held one "
        "below it (1 more without an `sf_actual` reading, 2 more of a material not in Table 4). ")
    assert text(ids).endswith(f"; none of its {len(dropped)} drops has a Table 4 material. ")


def test_the_grip_laws_opening_gives_its_why_only_where_the_proposed_planner_loses_a_pair(sim_root):
    # "Why: H(G) is geometric …" followed the McNemar counts whatever they were, "loses to 0" included
    from graspcampaign.report.studies.quasi_static import grip_finding

    run = _rendered(sim_root, "grip_laws")
    tests = run.tables["mcnemar"]
    run.tables["mcnemar"] = tests.assign(p_exact=1.0)  # no pair differs
    text = grip_finding(run)
    assert f"it beats 0 and loses to 0 of {len(tests)} planner–law pairs. `docs/decisions.md`" in text
    assert "Why" not in text
    first = tests.index == tests.index[0]  # its first pair lost: the other planner alone succeeds 9 times
    run.tables["mcnemar"] = tests.assign(reference_only=tests["reference_only"].mask(first, 0),
                                         compared_only=tests["compared_only"].mask(first, 9),
                                         p_exact=np.where(first, binomtest(0, 9).pvalue, 1.0))
    text = grip_finding(run)
    assert f"it beats 0 and loses to 1 of {len(tests)} planner–law pairs. Why: H(G) is geometric" in text


def test_the_test1_opening_says_c_is_not_identifiable_only_where_its_interval_reaches_zero(sim_root):
    # "C not identifiable at 1 mN" was printed for any virtual-bench run, whatever the claims table's
    # standard error of C; here the normal fits' standard errors are scaled so that the median event's
    # Wald 95% interval, C ± 1.96 SE, excludes 0. The opening and Table 4's caption read one test
    from graspcampaign.report.studies.test1 import finding

    table4 = next(item for item in spec_for("test1_bench", "").items if getattr(item, "name", "") == "table4")
    median = "per-event C: median (paper: Table 4's family range)"
    se = "standard error of per-event C: median"
    run = _rendered(sim_root, "test1_bench")
    rows = run.tables["test1_claims"].set_index("quantity")["value"]
    assert abs(rows[median]) <= 1.96 * rows[se]  # as recorded: the interval reaches zero
    assert "C not identifiable at 1 mN" in finding(run)
    assert "per-event C is not identifiable at 1 mN" in table4.caption(run)
    scale = abs(rows[median]) / 2.5 / rows[se]  # the median SE becomes |median C| / 2.5

    def resolved(records: pd.DataFrame) -> pd.DataFrame:
        normal = records["block"] == "normal"
        return records.assign(c_se_n_s_per_m=records["c_se_n_s_per_m"].mask(normal, records["c_se_n_s_per_m"]
                                                                           * scale))

    run = _rendered(sim_root, "test1_bench", resolved)
    rows = run.tables["test1_claims"].set_index("quantity")["value"]
    assert abs(rows[median]) > 1.96 * rows[se]
    text = finding(run)
    assert "not identifiable" not in text and "not identifiable" not in table4.caption(run)
    assert "Why: the virtual bench differs by construction (" in text
    assert "loops, λ1 where Eq. 14 with Table 4's moduli puts it): " in text  # reduced run: "smaller … loops"


def test_the_table4_caption_gives_the_mean_of_c_it_once_said_a_few_wild_fits_rule(sim_root):
    # "a few wild fits rule its mean" whatever the fits; here every fit's C is 0.05 N s/m, resolved
    # (SE 0.001): the mean is the median, and C is identifiable
    def calm(records: pd.DataFrame) -> pd.DataFrame:
        normal = records["block"] == "normal"
        return records.assign(c_n_s_per_m=records["c_n_s_per_m"].mask(normal, 0.05),
                              c_se_n_s_per_m=records["c_se_n_s_per_m"].mask(normal, 0.001))

    def sig3(v: float) -> str:  # 3 significant digits, as Table 4 prints C
        return np.format_float_positional(v, 3, unique=False, fractional=False, trim="k").replace("-", "−")

    table4 = next(item for item in spec_for("test1_bench", "").items if getattr(item, "name", "") == "table4")
    caption = table4.caption(_rendered(sim_root, "test1_bench", calm))
    assert "wild" not in caption and "not identifiable" not in caption
    assert "per-event C (their mean: gel 0.0500 N s/m); a negative C" in caption
    records = RunStore(sim_root / "test1_bench" / "default").read().to_pandas()
    accepted = records.query("block == 'normal'")
    accepted = accepted[accepted["fit_ok"].astype(bool) & accepted["accepted"].astype(bool)]
    assert (f"(their mean: gel {sig3(accepted['c_n_s_per_m'].mean())} N s/m): per-event C is not "
            "identifiable") in table4.caption(_rendered(sim_root, "test1_bench"))
