"""baseline_grid report on a synthetic run: tables checked against pandas, Fig. 18, McNemar,
the design limit, the headline page and strict tables.json.

Each run is built by ``synthetic_runs.make_run`` from the campaign's own design expansion. Every
expected number is recomputed directly from the records with pandas, statsmodels or scipy, never
with the report's helpers.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats as sps
from statsmodels.stats.contingency_tables import mcnemar as sm_mcnemar
from statsmodels.stats.proportion import proportion_confint
from synthetic_runs import SHAPES, make_run, md_table, ok_records, quasi_static_outputs, read_table, report_md

from graspcampaign.analysis.vocabulary import label
from graspcampaign.report.build import build_reports

# --------------------------------------------------------------------------------------------
# baseline_grid: the Done-when test (tables against pandas), Fig. 18, McNemar, design limit
# --------------------------------------------------------------------------------------------

GRID_PAPER = {"figure": "Fig. 18", "trials_per_planner": 675,
              "success_pct": {"heuristic": 67.6, "antipodal": 40.0, "random": 11.0,
                              "centroid": 0.0},
              "success_by_shape_pct": {"rounded_cube": {"heuristic": 56.0, "antipodal": 33.0}}}


@pytest.fixture(scope="module")
def grid_run(tmp_path_factory):
    root = tmp_path_factory.mktemp("grid") / "results"
    store = make_run(root, "baseline_grid", "quasi_static",
                     {"shape": SHAPES, "mass_kg": [0.2, 0.6], "mu": [0.1, 0.5],
                      "planner": ["heuristic", "antipodal", "random", "centroid"]},
                     seeds=3, paper=None, outputs=quasi_static_outputs, error_every=17)
    # json beside the default md and csv: test_tables_json_is_strict reads it (one report, not two)
    build_reports(["baseline_grid"], root=root, formats=["md", "csv", "json"])
    return root, store


def test_grid_rates_match_pandas(grid_run):
    root, store = grid_run
    raw = store.read().to_pandas()
    ok = ok_records(store)
    table = read_table(store, "success_by_planner").set_index("planner")
    assert list(table.index) == ["heuristic", "antipodal", "centroid", "random"]  # the vocabulary's
    expected = ok.groupby("planner")["success"].agg(["sum", "size"])
    errors = raw[raw["status"] == "error"].groupby("planner").size()
    assert errors.sum() > 0
    for planner, row in table.iterrows():
        s, n = expected.loc[planner]
        assert row["n"] == n and row["successes"] == s
        assert row["n_error"] == errors.get(planner, 0)
        assert row["n"] + row["n_error"] == (raw["planner"] == planner).sum()
        assert row["rate_pct"] == pytest.approx(100 * s / n, abs=1e-12)
        # statsmodels.stats.proportion.proportion_confint(s, n, method="wilson")
        low, high = proportion_confint(s, n, alpha=0.05, method="wilson")
        assert row["wilson_low_pct"] == pytest.approx(100 * max(low, 0), abs=1e-9)
        assert row["wilson_high_pct"] == pytest.approx(100 * min(high, 1), abs=1e-9)
        assert row["paper_pct"] == GRID_PAPER["success_pct"][planner]
        assert row["difference"] == pytest.approx(100 * s / n - row["paper_pct"], abs=1e-9)
        assert row["n_clusters"] == ok.loc[ok["planner"] == planner, "shape"].nunique()
        assert row["bootstrap_low_pct"] <= row["rate_pct"] <= row["bootstrap_high_pct"]


def test_grid_by_shape_and_condition_match_pandas(grid_run):
    _, store = grid_run
    ok = ok_records(store)
    by_shape = read_table(store, "success_by_shape")
    expected = ok.groupby(["shape", "planner"])["success"].mean() * 100
    got = by_shape.set_index(["shape", "planner"])["rate_pct"]
    pd.testing.assert_series_equal(got.sort_index(), expected.sort_index(), check_names=False)
    cube = by_shape.set_index(["shape", "planner"])
    assert cube.loc[("rounded_cube", "heuristic"), "paper_pct"] == 56.0
    assert cube.loc[("rounded_cube", "antipodal"), "paper_pct"] == 33.0
    assert cube.loc[("pear", "centroid"), "paper_pct"] == 0.0  # 0% overall is 0% per shape
    assert math.isnan(cube.loc[("pear", "heuristic"), "paper_pct"])
    by_mu = read_table(store, "success_by_mu").set_index(["planner", "mu"])["rate_pct"]
    exp_mu = ok.groupby(["planner", "mu"])["success"].mean() * 100
    pd.testing.assert_series_equal(by_mu.sort_index(), exp_mu.sort_index(), check_names=False)


def test_grid_mcnemar_pairs_by_scene(grid_run):
    _, store = grid_run
    ok = ok_records(store)
    wide = ok.pivot(index="scene_id", columns="planner", values="success")
    table = read_table(store, "mcnemar").set_index("compared")
    assert list(table.index) == ["antipodal", "centroid", "random"]  # the vocabulary's order
    for other, row in table.iterrows():
        pair = wide[["heuristic", other]].dropna().astype(bool)
        n10 = int((pair["heuristic"] & ~pair[other]).sum())
        n01 = int((~pair["heuristic"] & pair[other]).sum())
        assert (row["pairs"], row["reference_only"], row["compared_only"]) == (len(pair), n10, n01)
        # statsmodels mcnemar(exact=False, correction=True) on [[., n01], [n10, .]]
        ref = sm_mcnemar(np.array([[0, n01], [n10, 0]]), exact=False, correction=True)
        assert row["chi2_cc"] == pytest.approx(ref.statistic, rel=1e-12)
        # scipy.stats.binomtest(n10, n01 + n10).pvalue
        assert row["p_exact"] == pytest.approx(sps.binomtest(n10, n01 + n10).pvalue, rel=1e-12)
        assert row["unpaired"] == wide[["heuristic", other]].notna().sum(axis=1).eq(1).sum()


def test_grid_design_limit_and_failure_checks(grid_run):
    _, store = grid_run
    ok = ok_records(store)
    limit = read_table(store, "design_limit").set_index("planner")
    for planner, grp in ok.groupby("planner"):
        row = limit.loc[planner]
        assert row["exceeds"] == (grp["delta_max_mm"] > 1).sum()
        assert row["n"] == len(grp)
        assert row["successes_exceeding"] == ((grp["delta_max_mm"] > 1) & grp["success"]).sum()
        # depths beyond the 5 mm fingertip radius are counted apart, not in the statistics
        physical = grp["delta_max_mm"] <= 5.0
        assert row["beyond_radius"] == (~physical).sum()
        assert row["delta_max_median_mm"] == pytest.approx(grp.loc[physical, "delta_max_mm"].median())
        assert row["delta_max_max_mm"] == grp.loc[physical, "delta_max_mm"].max()
    checks = read_table(store, "failure_checks").set_index("planner")
    expected = pd.crosstab(ok["planner"], ok["failure_check"])
    for planner in expected.index:
        for check in expected.columns:
            assert checks.loc[planner, check] == expected.loc[planner, check]
    assert checks["none"].sort_index().equals(ok.groupby("planner")["success"].sum().sort_index())


def test_grid_markdown_states_differences_and_figure(grid_run):
    root, store = grid_run
    md = report_md(store)
    heuristic = read_table(store, "success_by_planner").set_index("planner").loc["heuristic"]
    assert f"| {heuristic['verdict']} |" in md and f"({_signed(heuristic['difference'])})" in md
    assert "Where we differ" not in md  # the verdicts are in the tables, not repeated as bullets
    assert "errored, excluded from every denominator" in md
    assert "shape-clustered percentile bootstrap" in md and "10000 resamples, seed 11" in md
    assert "Data source:** simulation" in md
    assert md.index("## What this shows") < md.index("success_by_planner.csv")
    png = store.path / "report" / "figures" / "fig18_baselines.png"
    assert png.stat().st_size > 10_000
    assert "[Table 1 headline](headline.md)" in (root / "index.md").read_text()


def _signed(x: float) -> str:
    text = f"{x:+.1f}".replace("-", "\u2212")
    return f"{text} pp"


def test_headline_page_gathers_rates(grid_run):
    root, store = grid_run
    headline = pd.read_csv(root / "headline.csv")
    grid = headline[headline["study"] == "baseline_grid"].iloc[0]
    ok = ok_records(store)
    mine = ok[ok["planner"] == "heuristic"]
    assert grid["n"] == len(mine)
    assert grid["rate_pct"] == pytest.approx(100 * mine["success"].mean())
    assert grid["paper_pct"] == 67.6 and grid["n_paper"] == 675
    assert grid["paper_baselines"].startswith("antipodal 40.0%")
    missing = headline[headline["study"] == "test3_disturbance"]
    assert set(missing["verdict"]) == {"no records yet"}
    assert 80.8 in missing["paper_pct"].tolist()
    md = (root / "headline.md").read_text()
    assert "Baseline grid" in md and "not** comparable" in md


def test_tables_json_is_strict(grid_run):
    _, store = grid_run
    data = json.loads((store.path / "report" / "tables.json").read_text(),
                      parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))
    assert {"success_by_planner", "mcnemar", "design_limit"} <= set(data)


def test_dynamic_check_lists_the_planners_in_the_order_baseline_grid_lists_them(grid_run):
    """dynamic_check re-simulates baseline_grid's trials: its per-planner rows read in the grid report's
    planner order (the vocabulary's; the grid's design order differed from it, and dynamic_check, which
    has no planner factor, took the vocabulary's)."""
    from types import SimpleNamespace

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.dynamic_check import agreement

    root, store = grid_run
    grid = md_table(report_md(store), "success_by_planner")["planner"]
    ok = ok_records(store)  # one dynamic grasp per source trial and preset, labels as in the source
    records = pd.concat([ok.assign(model_preset=preset) for preset in ("table2", "firm")], ignore_index=True)
    records = records.assign(qs_success=records["success"], dynamic_status="stable")
    run = Run(records, {"config": {"factors": {"model_preset": ["table2", "firm"]}}}, SimpleNamespace())
    rows = agreement(run, ["model_preset", "planner"])
    for preset in ("table2", "firm"):
        planners = rows.loc[rows["model_preset"] == preset, "planner"].map(lambda p: label("planner", p))
        assert planners.tolist() == grid.tolist()
