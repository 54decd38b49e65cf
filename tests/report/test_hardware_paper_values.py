"""Where the paper's values stand in the Test 2-3 reports: beside the flag they score (§9.5), the
population they are of (Table 8's natural block), the section that prints them (§8.1, §9.1, Table 9),
as whole numbers where they count trials (split from test_hardware_report.py, which passed 500 lines).
The reduced virtual-rig runs of the shared results tree (conftest.py)."""

from __future__ import annotations

import pandas as pd
import pytest
from statsmodels.stats.proportion import proportion_confint
from synthetic_runs import md_table, read_table, report_md, study_paper_block

STUDIES = ["test2_grasp", "test3_disturbance"]


def test_section_9_5s_scores_stand_beside_the_retention_flag_only(sim_root):
    """§9.5: "the pre-disturbance retention flag is scored positive when the planner's believed retention
    margin under the commanded disturbance exceeds unity — … 88.8 % accuracy (precision 0.93, recall
    0.94" — ours `predicted_stable`. Its scores stood beside the residual flag's row too (that flag is
    §8.1's Test 2 flag, which §9.5 does not score)."""
    t = read_table(sim_root / "test3_disturbance" / "default", "test3_retention_classifier")
    t = t.set_index(["flag", "belief_error", "scope"]).sort_index()
    paper = ["paper_accuracy", "paper_precision", "paper_recall"]
    assert t.loc["predicted_stable_residual", paper].isna().all().all()
    assert t.loc[("predicted_stable", "paper", "all"), paper].tolist() == [0.888, 0.93, 0.94]
    assert t.drop(index=("predicted_stable", "paper", "all"))[paper].isna().all().all()


def test_the_natural_surface_of_block_a_stands_beside_the_papers_table_8_rate(sim_root):
    """Fig. 33a's natural bar is Table 8's lateral-pull block (proposed planner, natural friction, 87.1 %
    of 240, paper.txt): test3_coating's natural row said "no paper value" beside the paper's 4.34 N
    threshold of the same trials. Its verdict: the paper's rate against our Wilson 95 % interval."""
    run = sim_root / "test3_disturbance" / "default"
    row = read_table(run, "test3_coating").set_index("friction_level").loc["natural"]
    md = md_table(report_md(run), "test3_coating").set_index("surface").loc["natural"]
    assert (row["paper_success_pct"], row["paper_threshold_n"]) == (87.1, 4.34)
    assert md["paper %"] == "87.1"
    low, high = (100 * v for v in proportion_confint(round(row["n"] * row["success_pct"] / 100), row["n"],
                                                     method="wilson"))
    assert row["differs"] == (not low - 0.1 < 87.1 < high + 0.1)  # one unit of the paper's last digit
    assert "paper" in row["verdict"] and "no paper value" not in row["verdict"]


@pytest.mark.parametrize(("study", "campaign", "per_planner"), [
    ("test2_grasp", "§8.1", "§8.1"),  # §8.1: 1785 commanded, 30 aborted, 819 + 936 per planner
    ("test3_disturbance", "§9.1", "Table 9")])  # §9.1: 1245 commanded, 15 aborted; Table 9's n
def test_the_trial_counts_cite_their_own_campaigns_section(sim_root, study, campaign, per_planner):
    """Both counts tables cited "§8.1, §9.1" on every row: Test 2's page cited Test 3's section and the
    reverse."""
    name = "test2_counts" if study == "test2_grasp" else "test3_counts"
    md = md_table(report_md(sim_root / study / "default"), name)
    planner = md["quantity"].str.startswith("executed, ")
    assert planner.sum() == 5 and (~planner).sum() == 4
    assert set(md.loc[~planner, "paper §"]) == {campaign} and set(md.loc[planner, "paper §"]) == {per_planner}


@pytest.mark.parametrize("study", STUDIES)
def test_the_papers_trial_counts_are_whole_numbers_in_the_csv(sim_root, study):
    """``n_paper`` (Tables 6 and 9: the paper's trials per row) prints 830, not 830.0; empty where the
    paper has no row (the counterfactual belief reading)."""
    name, key = ("table6", "shape") if study == "test2_grasp" else ("table9", "planner")
    path = sim_root / study / "default" / "report" / "tables" / f"{name}.csv"
    text = pd.read_csv(path, dtype=str, keep_default_na=False)
    rows = study_paper_block(study)[name]
    expected = [str(rows[k]["n"]) if b == "paper" and k in rows else ""
                for k, b in zip(text[key], text["belief_error"], strict=True)]
    assert text["n_paper"].tolist() == expected


def test_section_9_5s_certified_counts_are_shares_beside_the_papers(sim_root):
    """§9.5: "only 51 of the 680 grasps certified as retained subsequently failed" (§9.1: 1230 executed).
    As counts, a reduced run's 26 certified "differed by −654" for being reduced; as shares with their
    Wilson interval (statsmodels) they compare at any scale."""
    from graspcampaign.campaign.records import RunStore

    run = sim_root / "test3_disturbance" / "default"
    rec = RunStore(run).read().to_pandas()
    e = rec[(rec["status"] == "ok") & ~rec["aborted"].astype(bool)]
    flagged = e["predicted_stable"].astype(bool)
    claims = read_table(run, "test3_claims").set_index("quantity")
    for quantity, k, n, ours, of in (
            ("trials certified as retained by the retention flag (paper 680 of 1230)", 680, 1230,
             flagged.sum(), len(e)),
            ("certified grasps that failed (paper 51 of 680)", 51, 680,
             (flagged & ~e["success"].astype(bool)).sum(), flagged.sum())):
        r = claims.loc[quantity]
        low, high = proportion_confint(ours, of, method="wilson")
        assert (r["unit"], r["n"]) == ("%", of), quantity
        assert [r["value"], r["low"], r["high"]] == pytest.approx([100 * ours / of, 100 * low, 100 * high])
        assert float(r["paper"]) == pytest.approx(100 * k / n)
