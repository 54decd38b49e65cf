"""Reports of the sensitivity and mesh_resolution studies, rendered from reduced runs (the
surrogate's report is tested in test_surrogate_report.py)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from statsmodels.stats.proportion import proportion_confint
from synthetic_runs import md_table, read_table, report_md

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study
from graspcampaign.report.build import build_reports
from graspcampaign.report.render import Run

REDUCED = {
    "sensitivity": ["params.levels=2", "seeds=2"],
    "mesh_resolution": ["seeds=2", "params.resolutions=[144,1750]", "params.timing_repeats=2",
                        "params.budget_shapes=[sphere]", "params.budget_nodes=[144]",
                        "params.budget_seeds=2", "params.budgets=[1,30]",
                        "params.baseline_shapes=[sphere]", "params.baseline_masses_kg=[0.4]",
                        "params.baseline_mus=[0.3]", "params.baseline_seeds=2"],
}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    root = tmp_path_factory.mktemp("results")
    stores = {}
    for study, overrides in REDUCED.items():
        cfg = compose_study(study, ["runner.backend=sequential", f"output.root={root}",
                                    *overrides])
        stores[study] = RunStore(run_study(cfg).path)
    build_reports(list(REDUCED), root=root)
    return stores


def test_sensitivity_report(runs):
    store = runs["sensitivity"]
    records = store.read().to_pandas()
    panels = read_table(store, "sensitivity_panels").set_index("panel")
    assert panels["trials"].to_dict() == records.groupby("panel").size().to_dict()
    k = int(records.loc[records["panel"] == "mu_mass", "success"].sum())
    low, high = proportion_confint(k, 8, method="wilson")  # statsmodels reference
    assert panels.loc["mu_mass", ["success_pct", "success_low_pct", "success_high_pct"]].tolist() == \
        pytest.approx([100 * k / 8, 100 * low, 100 * high])
    claims = read_table(store, "sensitivity_claims").set_index("quantity")
    inside = records[(records["panel"] == "mu_mass") & (records["mu"] >= 0.2)
                     & (records["mass_kg"] <= 0.5)]
    row = claims.loc["(a) stable region: success inside it"]
    assert (row["n"], row["value"]) == (len(inside), 100 * inside["success"].mean())
    md = report_md(store)
    assert "## What this shows" in md and "Where ours differ" not in md
    # contacts deeper than the fingertip radius (5 mm) are counted apart, never a median of metres
    ok = records[records["status"] == "ok"]
    deep = ok["delta_max_mm"] > 5.0
    assert panels["beyond_radius"].to_dict() == deep.groupby(ok["panel"]).sum().to_dict()
    physical = ok[~deep].groupby("panel")["delta_max_mm"].median()
    assert panels["delta_max_median_mm"].to_dict() == pytest.approx(
        {p: physical.get(p, np.nan) for p in panels.index}, nan_ok=True)
    per_mu = ok[ok["panel"] == "mu_mass"].groupby("mu")["success"].mean()
    assert ("does not vary with friction" in md) == (per_mu.nunique() == 1)
    assert "(a) μ × m" in md and "| mu_mass |" not in md  # panels by their words
    bound = claims.loc[[q for q in claims.index if "on its PSO search bound" in q]]
    if bound["value"].notna().all() and len(bound) == 2:
        # μ < 0.1, μ ≥ 0.1: statsmodels' Wilson intervals of the counts on the bound
        (lo1, hi1), (lo2, hi2) = (100 * np.array(proportion_confint(round(v * n / 100), n, method="wilson"))
                                  for v, n in zip(bound["value"], bound["n"], strict=True))
        # most on the bound (interval above 50%), fewer at μ ≥ 0.1 (intervals apart); overlap: not compared
        expected = [False if lo1 > 50 else True if hi1 < 50 else None,
                    False if hi2 < lo1 else True if lo2 > hi1 else None]
        assert [None if pd.isna(d) else bool(d) for d in bound["differs"]] == expected
        assert bound["paper"].notna().all()  # the paper's Sec. 6.6 claim is compared
    for name in ("fig19_sensitivity", "fig19_supplement"):
        assert (store.path / "report" / "figures" / f"{name}.png").stat().st_size > 10_000


def test_identified_lambda1_rows_count_each_identification_once(runs):
    """A μ × m cell's seeds share one PSO identification (prepared/): the λ1 rows are over those
    identifications, not over trials (which counted each one once per seed and narrowed its interval)."""
    store = runs["sensitivity"]
    cells = store.read().to_pandas().query("panel == 'mu_mass'")[["shape", "mass_kg", "mu"]].drop_duplicates()
    bodies = store.read("prepared").to_pandas().merge(cells)
    claims = read_table(store, "sensitivity_claims").set_index("quantity")
    for words, low in (("< 0.1", True), ("≥ 0.1", False)):
        part = bodies[(bodies["mu"] < 0.1) == low]
        median = claims.loc[f"(a) median identified λ1 at μ {words}"]
        assert (median["n"], median["value"]) == (len(part), pytest.approx(part["lambda1"].median()))
        on_bound = part["at_bound_lambda1"].astype(bool)
        k, n = int(on_bound.sum()), len(part)
        ci = proportion_confint(k, n, method="wilson")
        row = claims.loc[f"(a) identified λ1 on its PSO search bound at μ {words}"]
        assert (row["n"], row["value"]) == (n, pytest.approx(100 * k / n))
        assert [row["low"], row["high"]] == pytest.approx([100 * ci[0], 100 * ci[1]])


def test_mesh_resolution_report_prints_the_cost_ratio(runs):
    store = runs["mesh_resolution"]
    records = store.read().to_pandas()
    res = records[records["panel"] == "resolution"]
    ratio = read_table(store, "cost_ratio")
    top = res[res["nodes"] == 1750]
    expected = (top["eval_time_min_s"] / top["eval_time_reference_min_s"]).median()
    by_median = (top["eval_time_s"] / top["eval_time_reference_s"]).median()
    assert ratio["value"].tolist() == pytest.approx([expected, by_median] * 2, rel=1e-12)
    # the paper's ratio; then this tool's speed target (issue 7's), which has no paper value
    assert ratio["paper"].iloc[:2].tolist() == [1.95] * 2 and ratio["paper"].iloc[2:].isna().all()
    within, printed = round(expected, 2) <= 1.5, " at its printed precision" * bool(expected > 1.5)
    assert ratio["verdict"].iloc[2] == (f"within this tool's speed target ≤ 1.50{printed}" if within
                                        else "above this tool's speed target ≤ 1.50")
    runtime = read_table(store, "mesh_resolution_runtime").set_index("nodes")["loop_at_n_max_pct"]
    assert runtime.to_dict() == pytest.approx((100 * res.groupby("nodes")["loop_capped"].mean()).to_dict())
    md = report_md(store)
    # a ratio below 1 does not "grow": the sentence names both meshes and the number of trials
    assert (f"One evaluation on the largest mesh (1750 nodes) costs {expected:.2f} times one on the 144-node "
            f"reference mesh (paper 1.95: {ratio['verdict'].iloc[0].split(':')[0]}; "
            f"{ratio['verdict'].iloc[2]}{TOOL}") in md
    assert ("): too few trials to tell growth from timing noise (2 trials; a 95% interval needs 3), the "
            "design predicts none:") in md
    rerun = read_table(store, "n_max_rerun").set_index("planner")
    nm = records[records["panel"] == "n_max"]
    failed = nm[~nm["success"].astype(bool)]
    assert rerun["failures_at_n_max"].sum() == len(failed)
    assert rerun["budget_capped"].sum() == failed["budget_capped"].sum()
    # the finding's "horizontal residual" count, from the records: failing the ‖R‖ check at the doubled
    # budget with |R_z| at most 1% of ‖R‖ (was: "what remains is the horizontal part", for every failure)
    flat = failed[(failed["failure_check_rerun"] == "residual")
                  & (np.abs(failed["residual_z_rerun_n"]) <= 0.01 * failed["residual_norm_rerun_n"])]
    assert rerun["horizontal_residual_rerun"].sum() == len(flat)
    assert (f"{len(failed)} baseline-grid failures, {int(failed['budget_capped'].sum())} pass at the doubled "
            f"N_max and {len(flat)} still fail there on a horizontal residual") in md
    budget = read_table(store, "success_vs_n_cand")
    assert set(budget["planner"]) == {"heuristic", "reference"}
    assert set(budget.loc[budget["planner"] == "heuristic", "n_cand"]) == {1, 30}
    assert (budget["h_gap_to_reference"] >= -1e-12).all()
    assert "| reference search | every triple (exhaustive) |" in md  # not "N_cand 0"
    assert (budget["vertical_low_pct"] <= budget["vertical_pct"]).all()
    assert (budget["vertical_pct"] <= budget["vertical_high_pct"]).all()
    assert "were not cross-checked" in md  # the baseline_grid records are absent here
    assert (store.path / "report" / "figures" / "fig20_mesh_resolution.png").exists()


def test_fig20s_load_corrected_line_scales_the_fastest_reference_by_the_fastest_ratio(runs):
    """The stored ratio is of fastest repeats; Fig. 20a had scaled the reference's median by it, mixing
    the two estimators. The line is recomputed from the records with pandas."""
    import matplotlib.pyplot as plt

    from graspcampaign.campaign.paper import study_paper
    from graspcampaign.report.studies.mesh_resolution import fig20

    store = runs["mesh_resolution"]
    run = Run(store.read().to_pandas(), store.check(), study_paper("mesh_resolution"), store)
    res = run.ok[run.ok["panel"] == "resolution"]
    fig = plt.figure()
    fig20(run, fig)
    [line] = [h for h in fig.axes[0].lines if h.get_label().startswith("ours, load-corrected (fastest")]
    expected = 1e3 * res["eval_time_reference_min_s"].median() * res.groupby("nodes")[
        "cost_ratio_vs_reference"].median()
    assert line.get_ydata() == pytest.approx(expected.to_numpy())
    # node counts read plainly at the meshes run (were 2×10², 3×10²...), in (a) at the paper's too (its
    # 1750-node runtime had no tick); the |R_z| reading is drawn beside the ‖R‖ check, not under it (both
    # 0 hid it)
    ticks = [[t.get_text() for t in ax.get_xticklabels()] for ax in fig.axes[:2]]
    ours, paper = set(res["nodes"].unique()), {int(n) for n in run.paper.runtime_ms}
    assert ticks == [[str(n) for n in sorted(ours | paper)], [str(n) for n in sorted(ours)]]
    checks = {h.get_label(): h.get_xdata() for h in fig.axes[2].lines}
    [reading] = [x for k, x in checks.items() if k.endswith("|R_z| reading")]
    assert not set(reading) & set(np.concatenate([x for k, x in checks.items() if not k.endswith("reading")]))
    plt.close(fig)


def test_a_run_resumed_across_the_fastest_repeat_change_gives_the_median_repeat_ratio_everywhere():
    """A run resumed across the change of ``cost_ratio_vs_reference`` (median over median repeats, then
    fastest over fastest) has rows with and without ``eval_time_reference_min_s``; the cost_ratio table
    then used the median repeats, but the runtime table's ratio and Fig. 20a's load-corrected line took
    the column's median, mixing the two estimators. Both are recomputed from the records with pandas."""
    from types import SimpleNamespace

    import matplotlib.pyplot as plt

    from graspcampaign.report.studies.mesh_resolution import SPEC, fig20

    rng = np.random.default_rng(4)
    rows = []
    for nodes in (144, 1750):
        for i in range(4):
            own, own_min, ref, ref_min = rng.uniform([1e-3, 0.5e-3, 1e-3, 0.5e-3], [9e-3, 1e-3, 9e-3, 1e-3])
            stored_before = i % 2 == 0  # its ratio is of the median repeats, with no fastest repeat
            rows.append({"panel": "resolution", "status": "ok", "nodes": nodes, "reference_nodes": 144,
                         "n_faces": 2 * nodes - 4, "eval_time_s": own, "eval_time_reference_s": ref,
                         "eval_time_min_s": np.nan if stored_before else own_min,
                         "eval_time_reference_min_s": np.nan if stored_before else ref_min,
                         "cost_ratio_vs_reference": own / ref if stored_before else own_min / ref_min,
                         "search_time_s": 1e-4, "equilibrium_time_s": 1e-4, "residual_norm_n": 0.1,
                         "loop_capped": False, "success": True})
    records = pd.DataFrame(rows)
    run = Run(records, {"config": {"evaluator": {"tau_f_n": 0.5}}},
              SimpleNamespace(runtime_ms={"144": 1.0, "1750": 2.0}, residual_scatter_n=(0.1, 1.0)))
    expected = (records["eval_time_s"] / records["eval_time_reference_s"]).groupby(records["nodes"]).median()
    assert not np.allclose(expected, records.groupby("nodes")["cost_ratio_vs_reference"].median())
    runtime = next(i for i in SPEC.items if getattr(i, "name", "") == "mesh_resolution_runtime")
    table = runtime.compute(run).set_index("nodes")["cost_ratio_vs_reference"]
    assert table.to_numpy() == pytest.approx(expected.to_numpy())
    fig = plt.figure()
    fig20(run, fig)
    [line] = [h for h in fig.axes[0].lines if h.get_label().startswith("ours, load-corrected (median")]
    reference_ms = 1e3 * records["eval_time_reference_s"].median()
    assert line.get_ydata() == pytest.approx(reference_ms * expected.to_numpy())
    plt.close(fig)


def test_a_run_without_the_papers_meshes_is_not_compared_with_the_papers_ratio(sim_root):
    """The reduced run's largest mesh is 390 nodes: its ratio was compared with the paper's 1750/144
    one, "neither stage touches the mesh" was said whatever the ratio, and one trial was "trials"."""
    store = RunStore(sim_root / "mesh_resolution" / "default")
    res = store.read().to_pandas().query("panel == 'resolution' and status == 'ok'")
    top = res.loc[res["nodes"] == res["nodes"].max(), "cost_ratio_vs_reference"]
    assert res["nodes"].max() != 1750 and len(top) == 1
    ratio = read_table(store, "cost_ratio")
    # the paper gives a ratio, for meshes this run lacks (was: "no paper value"); the target is ours
    assert ratio["paper"].iloc[:2].tolist() == [1.95] * 2 and ratio["paper"].iloc[2:].isna().all()
    assert (ratio["verdict"] == "not compared: this run has no 1750-node mesh (the paper's ratio is "
                                "1750 / 144 nodes)").all()
    assert ratio["quantity"].iloc[0] == f"cost ratio, {res['nodes'].max()} / 144 nodes, fastest repeats"
    md = report_md(store)
    assert (f"costs {top.median():.2f} times one on the 144-node reference mesh (not compared: this run has "
            "no 1750-node mesh, paper 1.95; table cost_ratio): too few trials to tell growth from timing "
            "noise (1 trial; a 95% interval needs 3), the design predicts none") in md


def test_a_non_finite_sweep_level_is_reported_not_raised(runs, tmp_path):
    """Issue 15 item 2: a sweep level that makes a heatmap non-finite."""
    import shutil

    from typer.testing import CliRunner

    from graspcampaign.campaign.runner import ERROR_COLUMNS
    from graspcampaign.cli.main import app

    source = runs["sensitivity"]
    copy = tmp_path / "results" / "sensitivity" / "default"
    shutil.copytree(source.path, copy, ignore=shutil.ignore_patterns("report"))
    store = RunStore(copy)
    records = store.read().to_pandas()
    level = sorted(records.loc[records["panel"] == "lambda", "lambda1"].unique())[0]
    records.loc[(records["panel"] == "lambda") & (records["lambda1"] == level),
                "delta_max_mm"] = np.inf
    records.loc[records["panel"] == "n_b", "runtime_ms"] = np.nan
    shutil.rmtree(copy / "records")
    for column in ERROR_COLUMNS:  # text as the runner stores it, not pandas' NaN
        records[column] = records[column].astype(object).where(records[column].notna(), None)
    store.write_shard("records", "aaaaaaaaaa", records.to_dict("records"), strings=ERROR_COLUMNS)
    result = CliRunner().invoke(app, ["report", "--root", str(tmp_path / "results"),
                                      "--figure-format", "svg"])
    assert result.exit_code == 0, result.output
    md = report_md(copy)
    panels = pd.read_csv(copy / "report" / "tables" / "sensitivity_panels.csv")
    assert panels.set_index("panel")["runtime_median_ms"].isna().loc["n_b"]
    shown = md_table(md, "sensitivity_panels").set_index("panel")
    assert shown.loc["(c) n × b", "runtime median [ms]"] == "—"
    svg = (copy / "report" / "figures" / "fig19_sensitivity.svg").read_text()
    assert "not drawn: no finite value of" in svg  # panel (c) says why; (a), (b) are drawn
    assert (copy / "report" / "tables" / "sensitivity_panels.csv").exists()


def _panel_a(cells: dict) -> Run:
    """A sensitivity run of panel (a) from ``{(mass, μ): (successes, trials)}``."""
    from types import SimpleNamespace

    from graspcampaign.report.studies.sensitivity import SPEC, _panels

    records = pd.DataFrame([{"panel": "mu_mass", "status": "ok", "mass_kg": m, "mu": mu, "success": i < won,
                             "success_vertical": i < won, "delta_max_mm": 1.0, "loop_capped": False,
                             "runtime_ms": 1.0} for (m, mu), (won, n) in cells.items() for i in range(n)])
    paper = SimpleNamespace(stable_mu_min=0.2, stable_mass_max_kg=0.5)
    run = Run(records, {"config": {"evaluator": {"n_max": 50}}}, paper)
    run.tables["sensitivity_panels"] = _panels(run)
    claims = next(i for i in SPEC.items if getattr(i, "name", "") == "sensitivity_claims")
    run.tables["sensitivity_claims"] = claims.compute(run)  # the finding reads its boundaries there
    return run


def test_the_finding_says_success_varies_only_where_a_test_of_equal_rates_says_so():
    """Mass 40 of 100 against 10 of 100 varies; friction 26 of 100 against 24 of 100 does not detectably
    (p from scipy's chi-square on the records' own table); one success in 200 is no variation."""
    from scipy.stats import chi2_contingency

    from graspcampaign.report import format as fmt
    from graspcampaign.report.studies.sensitivity import finding

    run = _panel_a({(0.1, 0.05): (20, 50), (0.1, 0.5): (20, 50), (0.8, 0.05): (6, 50), (0.8, 0.5): (4, 50)})
    p = {k: chi2_contingency(pd.crosstab(run.ok[k], run.ok["success"]), correction=False).pvalue
         for k in ("mass_kg", "mu")}
    text = finding(run)
    assert (f"Success varies with mass (χ² p = {fmt.p_value(p['mass_kg'])}) and does not detectably vary "
            f"with friction (p = {fmt.p_value(p['mu'])}).") in text  # the test named once: both are χ²
    text = finding(_panel_a({(0.1, 0.05): (1, 100), (0.8, 0.05): (0, 100)}))
    assert "does not detectably vary with mass (Monte Carlo χ² p = 1.0)" in text
    assert "is 0.5% at the one friction level (nothing to compare)" in text
    text = finding(_panel_a({(0.1, 0.05): (0, 3), (0.8, 0.5): (0, 3)}))
    assert "does not vary with mass (0.0% at each of its 2 levels)" in text


def test_a_monte_carlo_p_that_no_resample_reached_is_given_as_the_bound_the_resamples_can_give():
    """6 of 6 at one mass, 0 of 60 at the other: only the observed table (1 of C(66, 6) with these
    margins, scipy's hypergeometric) has its χ², so none of equal_rates_test's default 9999 random
    tables reaches it and the Monte Carlo p is its floor 1/(9999 + 1), not a measured 1.0e-4."""
    from scipy.stats import hypergeom

    from graspcampaign.report import format as fmt
    from graspcampaign.report.studies.sensitivity import finding

    exact = hypergeom(66, 6, 6).pmf(6)  # the chance of the observed table
    assert exact * 9999 < 1e-3
    text = finding(_panel_a({(0.1, 0.05): (6, 6), (0.8, 0.05): (0, 60)}))
    assert f"varies with mass (Monte Carlo χ² p ≤ {fmt.p_value(1 / 10000)})" in text


def test_the_opening_counts_the_boundaries_whose_wilson_intervals_separate_our_rates():
    """The opening said "the paper's μ ≥ 0.2 boundary does not appear" whatever the records; now it
    counts the Fig. 19 boundaries whose two sides' Wilson intervals (statsmodels) do not overlap."""
    from graspcampaign.report.studies.sensitivity import finding

    for inside, outside in ((50, 0), (26, 24)):  # panel (a): (mass, μ) inside, outside the region
        run = _panel_a({(0.4, 0.5): (inside, 50), (0.8, 0.05): (outside, 50)})
        low = proportion_confint(inside, 50, method="wilson")[0]
        high = proportion_confint(outside, 50, method="wilson")[1]
        apart = low > high
        assert (f"{int(apart)} of 1 Fig. 19 boundaries {'separates' if apart else 'separate'} our rates ("
                + ("stable region (a); " if apart else "") + "table sensitivity_claims)") in finding(run)
        assert ("Why:" in finding(run)) != apart


def test_the_panels_are_selected_once_per_run():
    from graspcampaign.report.studies.sensitivity import panel_rows

    run = _panel_a({(0.1, 0.05): (1, 2)})
    assert panel_rows(run, "mu_mass") is panel_rows(run, "mu_mass") and len(panel_rows(run, "mu_mass")) == 2


@pytest.mark.parametrize(("passed", "deep", "expected"), [
    # no trial passed without the gate: nothing to remove, not "0 of 0 successes"
    ([False] * 4, [True, True, False, False],
     "removed none (no trial succeeded without it): 2 of 4 executed"),
    ([True, True, True, False], [True, False, False, True], "removed 1 of 3 successes: 2 of 4 executed"),
])
def test_the_gate_sentence_counts_only_successes_there_were(passed, deep, expected):
    from types import SimpleNamespace

    from graspcampaign.analysis.records import gate_table
    from graspcampaign.report.spec import gate_text

    records = pd.DataFrame({"panel": "resolution", "status": "ok", "success_unbounded": passed,
                            "valid_geometry": [not d for d in deep],
                            "success": [p and not d for p, d in zip(passed, deep, strict=True)]})
    text = gate_text(SimpleNamespace(tables={"gate_removed": gate_table(records, ["panel"])}))
    assert f"The validity gate {expected} trials have a contact deeper than the fingertip radius" in text
    assert "(table gate_removed; `docs/decisions.md`, *Physical validity, grip laws, Ferrari–Canny ε*)" \
        in text


def test_the_gate_sentence_counts_the_deep_contacts_of_the_trials_read():
    # "1 of 5 executed trials have a contact deeper than the fingertip radius" counted in 5 the two
    # trials of an older file without a valid_geometry reading (null); 1 of the 3 read is deep (by hand)
    from types import SimpleNamespace

    from graspcampaign.analysis.records import gate_table
    from graspcampaign.report.spec import gate_text

    records = pd.DataFrame({"panel": "resolution", "status": "ok", "success_unbounded": [False] * 5,
                            "valid_geometry": [None, True, False, None, True], "success": [False] * 5})
    text = gate_text(SimpleNamespace(tables={"gate_removed": gate_table(records, ["panel"])}))
    assert ("removed none (no trial succeeded without it): 1 of 3 executed trials with a validity reading "
            "(`valid_geometry`) have a contact deeper than the fingertip radius, which is no contact (no "
            "reading in 2 of 5; table gate_removed; ") in text


def _timings(fastest, median, min_column=True, itself=((1.0, 1.0),)):
    """A resolution panel: per trial on 1750 nodes, and on the 144-node reference mesh against itself
    (``itself``), the two meshes' fastest and median repeats [s] in the given ratios (the reference
    mesh's 1 ms fastest, 2 ms median); its cost_ratio table computed, as the opening reads it."""
    from types import SimpleNamespace

    from graspcampaign.report.studies.mesh_resolution import COST

    per_mesh = {144: itself, 1750: zip(fastest, median, strict=True)}
    rows = [{"panel": "resolution", "status": "ok", "nodes": n, "reference_nodes": 144,
             "eval_time_min_s": 1e-3 * f, "eval_time_reference_min_s": 1e-3, "eval_time_s": 2e-3 * m,
             "eval_time_reference_s": 2e-3, "cost_ratio_vs_reference": f if min_column else m}
            for n, ratios in per_mesh.items() for f, m in ratios]
    records = pd.DataFrame(rows)
    if not min_column:  # a run stored before the fastest repeat was recorded: its ratio is of medians
        records = records.drop(columns=["eval_time_min_s", "eval_time_reference_min_s"])
    run = Run(records, {}, SimpleNamespace(runtime_ratio_1750_144=1.95, runtime_ratio_target=1.5))
    run.tables["cost_ratio"] = COST.compute(run)
    return run


DESIGN = (" neither stage's work depends on the mesh size")
TOOL = ", not a paper value; "


@pytest.mark.parametrize(("fastest", "median", "min_column", "expected"), [
    # 1.503 prints 1.50, within the target as printed, and so is 1.49: one reading (the finding's own rule
    # said the estimator decides); the same reading leaves the median repeats to the table
    ([1.50, 1.503, 1.51], [1.48, 1.49, 1.50], True,
     "costs 1.50 times one on the 144-node reference mesh (paper 1.95: differs by −0.45; within this "
     "tool's speed target ≤ 1.50 at its printed precision" + TOOL + "table cost_ratio): a growth (95% "
     "interval 1.50–1.51, above 1), which the design does not predict:" + DESIGN),
    # 0.999 and 1.004 both print 1.00 (the finding had read the second as growth)
    ([0.99, 0.999, 1.01], [0.995, 1.004, 1.02], True,
     "costs 1.00 times one on the 144-node reference mesh (paper 1.95: differs by −0.95; within this "
     "tool's speed target ≤ 1.50" + TOOL + "table cost_ratio): no growth detectable at this n (95% "
     "interval 0.99–1.01), as the design predicts:" + DESIGN),
    ([1.1, 1.2, 1.3], [3.0, 3.68, 4.0], True,
     "costs 1.20 times one on the 144-node reference mesh (paper 1.95: differs by −0.75; within this "
     "tool's speed target ≤ 1.50, not a paper value; by the median repeats 3.68, which reads above this "
     "tool's speed target ≤ 1.50, a growth (95% interval 3.00–4.00, above 1): the estimator decides; table "
     "cost_ratio): a growth (95% interval 1.10–1.30, above 1), which the design does not predict"),
    # above the target: "above this tool's speed target", as the row says it (the opening said "differs",
    # which reads as a difference from the paper), and the target said once
    ([1.1, 1.2, 1.3], [3.0, 3.68, 4.0], False,
     "costs 3.68 times one on the 144-node reference mesh (paper 1.95: differs by +1.73; above this tool's "
     "speed target ≤ 1.50" + TOOL + "table cost_ratio): a growth (95% interval 3.00–4.00, above 1), which "
     "the design does not predict"),
])
def test_the_cost_ratio_finding_reads_the_tables_verdicts_and_the_median_rows_are_context(
        fastest, median, min_column, expected):
    """The finding had its own verdict rule on raw ratios (1.503 "above" a target the table said it met
    as printed); now its words are the cost_ratio table's verdicts, the median-repeat rows are context
    (not compared) beside the verdict's fastest-repeat rows, and the finding says whether the median
    value reads the same as printed. Table values recomputed from the records with pandas."""
    from graspcampaign.report.studies.mesh_resolution import COST, finding

    run = _timings(fastest, median, min_column)
    top = run.records[run.records["nodes"] == 1750]
    values = {"median": (top["eval_time_s"] / top["eval_time_reference_s"]).median()}
    if min_column:
        values = {"fastest": (top["eval_time_min_s"] / top["eval_time_reference_min_s"]).median(), **values}
    table = COST.compute(run).set_index("quantity")
    for repeats, value in values.items():
        row = table.loc[f"cost ratio, 1750 / 144 nodes, {repeats} repeats, against this tool's speed target "
                        "(≤ 1.5; not a paper value)"]
        assert table.loc[f"cost ratio, 1750 / 144 nodes, {repeats} repeats", "value"] == row["value"] == \
            pytest.approx(value)
        assert row["verdict"] == ("not compared: shown to check the estimator choice" if repeats == "median"
                                  and min_column else
                                  "within this tool's speed target ≤ 1.50" if value <= 1.5
                                  else "within this tool's speed target ≤ 1.50 at its printed precision"
                                  if round(value, 2) <= 1.5 else "above this tool's speed target ≤ 1.50")
    assert len(table) == 2 * len(values)
    assert f"One evaluation on the largest mesh (1750 nodes) {expected}" in finding(run)


@pytest.mark.parametrize(("fastest", "itself", "expected"), [
    # the brief's seeds=2 run: 1.09 had read "a growth the design does not predict"; two trials
    # neither show growth nor its absence
    ([1.05, 1.13], [(0.99, 0.99)], "too few trials to tell growth from timing noise (2 trials; a 95% "
                                   "interval needs 3), the design predicts none"),
    # above 1 but not above the reference mesh's own spread against itself
    ([1.1, 1.15, 1.2], [(0.9, 0.9), (1.0, 1.0), (1.2, 1.2)], "no growth detectable at this n (95% interval "
     "1.10–1.20; the reference mesh against itself 0.90–1.20), as the design predicts"),
    ([1.3, 1.35, 1.4], [(0.9, 0.9), (1.0, 1.0), (1.2, 1.2)], "a growth (95% interval 1.30–1.40, above 1 and "
     "the reference mesh against itself 0.90–1.20), which the design does not predict"),
])
def test_growth_needs_an_interval_above_1_and_above_the_reference_mesh_against_itself(fastest, itself,
                                                                                     expected):
    """Timing noise of ±0.1 (the reference mesh against itself) had been read as growth from a median
    of two trials; the bounds are the trials' extremes, a percentile bootstrap's at 3 trials."""
    from graspcampaign.report.studies.mesh_resolution import finding

    run = _timings(fastest, fastest, itself=itself)
    assert f"): {expected}:" in finding(run)


def test_the_cost_ratio_finding_takes_the_verdict_rules_word_and_nothing_else(monkeypatch):
    """The finding cut each row's word out of the cost_ratio table's verdict sentence (its text up to a
    colon), so a sentence worded otherwise garbled it; it then called a second public rule
    (``fmt.judge``) beside ``fmt.verdict``. Now it takes ``fmt.verdict``'s word: a reworded reason
    leaves the finding as it was, a reworded word shows in it."""
    from graspcampaign.report import format as fmt
    from graspcampaign.report.studies.mesh_resolution import finding

    before, rule = finding(_timings([1.50, 1.503, 1.51], [1.48, 1.49, 1.50])), fmt.verdict
    assert "(paper 1.95: differs by −0.45; within this tool's speed target ≤ 1.50 at its " in before

    def reworded(*args, **kwargs):
        judged = rule(*args, **kwargs)
        return judged._replace(word=judged.word.upper(), why=judged.why.replace(" ", "_"))

    monkeypatch.setattr(fmt, "verdict", reworded)
    assert finding(_timings([1.50, 1.503, 1.51], [1.48, 1.49, 1.50])) == before.replace(
        "differs by −0.45", "DIFFERS BY −0.45").replace(
            "within this tool's speed target ≤ 1.50 at its printed precision",
            "WITHIN THIS TOOL'S SPEED TARGET ≤ 1.50 AT ITS PRINTED PRECISION")

