"""Report sections rendered from small synthetic runs; tables checked against pandas.

The records are built here column for column as docs/records.md specifies (base columns, factors,
the kind's outputs, trace tables), written through ``RunStore`` with a manifest from
``campaign.provenance``; trial ids and scene ids come from the campaign's own design expansion.
Every expected number is recomputed directly from those records with pandas, statsmodels or
scipy, never with the report's helpers.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable

import numpy as np
import pandas as pd
import pytest
from scipy import stats as sps
from statsmodels.stats.contingency_tables import mcnemar as sm_mcnemar
from statsmodels.stats.proportion import proportion_confint

from graspcampaign.analysis.rates import BOOTSTRAP_RESAMPLES
from graspcampaign.campaign.grid import expand
from graspcampaign.campaign.provenance import new_manifest, now_utc, write_manifest
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.schema import StudyCfg
from graspcampaign.report.build import build_reports

SHAPES = ["sphere", "ellipsoid", "rounded_cube", "pear", "handle"]
P_SUCCESS = {"heuristic": 0.7, "antipodal": 0.4, "random": 0.1, "centroid": 0.0, "no_s1": 0.7,
             "no_s2": 0.65}


def make_run(root, name: str, kind: str, factors: dict, seeds: int, paper: dict | None,
             outputs: Callable[[dict, np.random.Generator], dict], *, seed: int = 11,
             error_every: int = 0, tables: Callable[[str, dict, dict], dict] | None = None,
             prepared: list[dict] | None = None, source: str = "simulation",
             **study_kw) -> RunStore:
    """Write a run of ``name`` like the runner does: records (+ traces), then the manifest.

    ``paper`` None takes the study file's paper block (the typed values a real run carries).
    """
    if paper is None:
        from test_build import study_paper_block

        paper = study_paper_block(name)
    study = StudyCfg(name=name, kind=kind, seed=seed, seeds=seeds, factors=factors, paper=paper,
                     **study_kw)
    trials = expand(study)
    rng = np.random.default_rng(seed)
    rows, traces = [], {}
    for trial in trials:
        row = {"trial_id": trial.trial_id, "study": name, "run": "r1", "kind": kind,
               "trial_index": trial.index, "scene_id": trial.scene_id, "status": "ok",
               "error_type": None, "error_message": None, "wall_time_s": 0.01,
               "worker": "pid1", "host": "test", "source": source, **trial.factors}
        if error_every and trial.index % error_every == error_every - 1:
            row.update(status="error", error_type="RuntimeError", error_message="boom")
        else:
            out = outputs(trial.factors, rng)
            row.update(out)
            if tables:
                for tname, cols in tables(trial.trial_id, trial.factors, out).items():
                    traces.setdefault(tname, []).extend(cols)
        rows.append(row)
    store = RunStore(root / name / "r1")
    half = len(rows) // 2
    store.write_shard("records", "a", rows[:half])
    store.write_shard("records", "b", rows[half:])
    for tname, trows in traces.items():
        store.write_shard(f"tables/{tname}", "a", trows)
    if prepared:
        store.write_shard("prepared", "a", prepared)
    manifest = new_manifest(study, "r1", len(trials), source)
    manifest["finished_at"] = now_utc()
    write_manifest(store.manifest_path, manifest)
    return store


def quasi_static_outputs(factors: dict, rng: np.random.Generator) -> dict:
    """One quasi_static record (docs/records.md), outcome drawn per planner."""
    planner = factors.get("planner", "heuristic")
    success = bool(rng.random() < P_SUCCESS.get(planner, 0.5))
    check = "none" if success else str(rng.choice(["residual", "torque", "slip"]))
    deltas = rng.lognormal(np.log(0.8), 0.6, 3)
    forces = rng.uniform(1, 10, 3)
    out = {
        "nodes": factors.get("nodes", 390), "n_cand": 200, "success": success,
        "failure_check": check,
        "residual_norm_n": float(rng.uniform(0, 0.45) if success else rng.uniform(0.5, 4)),
        "torque_norm_nm": float(rng.uniform(0, 0.01)),
        "slip_margin_n": float(rng.uniform(0.1, 2) if success else rng.uniform(-2, 0.5)),
        "eta": float(rng.uniform(0, 0.8)), "delta_max_mm": float(deltas.max()),
        "exceeds_1mm": bool(deltas.max() > 1.0), "iterations": int(rng.integers(5, 100)),
        "h_total": float(rng.uniform(0.15, 0.28)), "s1": 0.1, "s2": 0.1, "s3": 0.05,
        "n_c": 0, "n_e": 0, "believed_quality": 0.5, "n_sharp_vertex": 0, "n_sharp_edge": 0,
        "lambda1": 0.332, "lambda2": 0.88, "n_exp": 0.487,
        "plan_time_s": 0.01 * (1 + factors.get("nodes", 390) / 1000) + rng.uniform(0, 1e-3),
        "eval_time_s": 0.02 + rng.uniform(0, 1e-3),
    }
    for j in range(3):
        out[f"delta_{j + 1}_mm"] = float(deltas[j])
        out[f"normal_force_{j + 1}_n"] = float(forces[j])
        out[f"vertex_{j + 1}"] = int(rng.integers(0, 390))
        out[f"contact_normal_z_{j + 1}"] = float(rng.uniform(-1, 1))
    # issue 13/17 columns (docs/records.md): the gate only removes passes, torque only binds
    unbounded = success or bool(rng.random() < 0.15)
    upper = int(rng.integers(0, 3))
    law = factors.get("grip_law", "paper")
    out.update({
        "grip_law": law, "success_unbounded": unbounded, "valid_geometry": success or not unbounded,
        "success_vertical": unbounded or bool(rng.random() < 0.2),
        "success_no_torque": success or check == "torque",
        "failure_check": "geometry" if unbounded and not success else check,
        "n_upper": upper, "n_released": upper if law == "paper" else 0, "n_loaded": 3 - upper,
        "support_share_max": float(rng.uniform(0.3, 1.0)), "rho": float(rng.uniform(0.0, 1.0)),
        "epsilon_fc": float(max(0.0, rng.normal(0.02, 0.05))), "pso_at_bound": "lambda1,n",
        "grip_capped": law != "paper" and bool(rng.random() < 0.8),
        "grip_needed_n": float("nan") if law == "paper" else float(rng.choice([2.0, 40.0, np.inf])),
    })
    if planner == "ferrari_canny":
        out.update(spearman_h_epsilon=float(rng.uniform(-0.8, 0.1)),
                   spearman_h_epsilon_fc=float(rng.uniform(-0.9, 0.2)))
    return out


def read_table(store: RunStore, name: str) -> pd.DataFrame:
    return pd.read_csv(store.path / "report" / "tables" / f"{name}.csv")


def ok_records(store: RunStore) -> pd.DataFrame:
    df = store.read().to_pandas()
    ok = df[df["status"] == "ok"]
    return ok.assign(success=ok["success"].astype(bool)) if "success" in ok else ok


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
    assert list(table.index) == ["heuristic", "antipodal", "random", "centroid"]  # config order
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
    assert list(table.index) == ["antipodal", "random", "centroid"]
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
    md = (store.path / "report" / "report.md").read_text()
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


# --------------------------------------------------------------------------------------------
# ablation, shapes, mesh_resolution, sensitivity
# --------------------------------------------------------------------------------------------


def test_ablation_section(tmp_path):
    store = make_run(tmp_path, "ablation", "quasi_static",
                     {"shape": SHAPES, "mass_kg": [0.4], "mu": [0.3],
                      "planner": ["heuristic", "no_s1", "no_s2", "random"]},
                     seeds=4, paper=None, outputs=quasi_static_outputs)
    build_reports(["ablation"], root=tmp_path)
    ok = ok_records(store)
    table = read_table(store, "success_by_planner").set_index("planner")
    pd.testing.assert_series_equal(table["rate_pct"].sort_index(),
                                   (ok.groupby("planner")["success"].mean() * 100).sort_index(),
                                   check_names=False)
    assert table.loc["random", "paper_pct"] == 6.0
    assert set(read_table(store, "mcnemar")["compared"]) == {"no_s1", "no_s2", "random"}
    md = (store.path / "report" / "report.md").read_text()
    assert "roughly ±12 pp" in md
    assert (store.path / "report" / "figures" / "fig16_ablation.png").exists()


def test_shapes_section_flags_disagreement(tmp_path):
    def outputs(factors, rng):
        out = quasi_static_outputs(factors, rng)
        win = factors["shape"] in ("sphere", "ellipsoid")  # ellipsoid disagrees; cube/pear too
        out.update(success=win, failure_check="none" if win else "slip")
        return out

    store = make_run(tmp_path, "shapes", "quasi_static",
                     {"shape": SHAPES, "mass_kg": [0.4], "mu": [0.3], "planner": ["heuristic"]},
                     seeds=1, paper=None, outputs=outputs)
    build_reports(["shapes"], root=tmp_path)
    table = read_table(store, "shapes").set_index("shape")
    ok = ok_records(store).set_index("shape")
    assert table.loc["sphere", "verdict"] == "as in the paper (yes)"
    assert table.loc["ellipsoid", "verdict"] == "differs: the paper reports no, ours is yes"
    assert table.loc["handle", "verdict"] == "as in the paper (no)"  # fails, as the paper
    assert table.loc["pear", "h_total"] == pytest.approx(ok.loc["pear", "h_total"])
    md = (store.path / "report" / "report.md").read_text()
    assert "2 of 5 shapes reach the paper's outcome (Fig. 15): sphere, concave handle." in md
    assert "Ours differs on ellipsoid (paper fails, ours 1/1" in md
    checks = read_table(store, "failure_checks").set_index("shape")
    assert checks.loc["handle", "paper"] == "slip" and checks.loc["sphere", "paper"] == "none"
    assert (store.path / "report" / "figures" / "fig15_shape_metrics.png").exists()


TABLE3 = {"lambda1": 0.332, "lambda2": 0.880, "n": 0.487, "b": 0.646, "k": 0.138, "c": 0.00247}


def _md_table(md: str, name: str) -> pd.DataFrame:
    """The Markdown table printed above ``tables/<name>.csv`` as text cells (minus signs as "-")."""
    lines = md.split(f"(`tables/{name}.csv`)", 1)[1].strip().split("\n\n", 1)[0].splitlines()
    rows = [[c.strip().replace("\u2212", "-") for c in line.strip("|").split("|")] for line in lines]
    return pd.DataFrame(rows[2:], columns=rows[0])


def test_pso_cv_table3_and_trace(tmp_path):
    def outputs(factors, rng):
        return {"lambda1": rng.uniform(0.1, 0.6), "lambda2": rng.uniform(0.3, 1.4),
                "n_exp": rng.normal(0.487, 0.08), "b": rng.uniform(0.2, 1.5),
                "k": rng.uniform(0.05, 0.3), "c": rng.uniform(5e-4, 0.01),
                "best_cost": rng.uniform(0.01, 1), "n_evaluations": 120, "n_particles": 8,
                "n_iterations": 15}

    def trace(trial_id, factors, out):
        cost = 50 * np.exp(-np.arange(15) / 4) + out["best_cost"]
        return {"pso_trace": [{"trial_id": trial_id, "iteration": i, "n_evaluations": 8 * (i + 1),
                               "best_cost": float(c)} for i, c in enumerate(cost)]}

    store = make_run(tmp_path, "pso_repeatability", "pso_repeatability",
                     {"shape": ["sphere"], "mass_kg": [0.4], "mu": [0.3]}, seeds=12,
                     paper=None,
                     outputs=outputs, tables=trace)
    build_reports(["pso_repeatability"], root=tmp_path)
    ok = ok_records(store)
    cv = read_table(store, "cv").set_index("parameter")
    for p in ("lambda1", "lambda2", "n_exp", "b", "k", "c"):
        # scipy.stats.variation(x, ddof=1): sample SD / mean
        assert cv.loc[p, "cv_pct"] == pytest.approx(100 * sps.variation(ok[p], ddof=1), rel=1e-12)
    assert cv.loc["n_exp", "paper_cv_pct"] == 19.0
    assert cv.loc["lambda1", "paper_cv_pct"] == 60.0
    t3 = read_table(store, "table3").set_index("parameter")
    assert t3.loc["n_exp", "paper"] == 0.487
    assert t3.loc["c", "ours_mean"] == pytest.approx(ok["c"].mean())
    best = ok.loc[ok["best_cost"].idxmin()]
    assert t3.loc["k", "ours_best_run"] == pytest.approx(best["k"])
    # each row keeps 3 significant digits: c ~ 0.005 beside b ~ 1 printed "0.01 | 0.00 | 0.00" when a
    # column was rounded once; the shown parameter is its label (λ1), the CSV keeps the id
    md = (store.path / "report" / "report.md").read_text()
    shown = _md_table(md, "table3").set_index("parameter")
    assert list(shown.index) == ["λ1", "λ2", "n", "b", "k", "c"]
    for p, label_ in zip(t3.index, shown.index, strict=True):
        for col, head in (("paper", "paper (Table 3)"), ("ours_mean", "ours mean"),
                          ("ours_median", "ours median")):
            assert float(shown.loc[label_, head]) == pytest.approx(t3.loc[p, col], rel=5e-3), (p, col)
    bands = read_table(store, "convergence")
    trace_df = store.read("tables/pso_trace").to_pandas()
    assert bands["p25"].to_numpy() == pytest.approx(
        trace_df.groupby("iteration")["best_cost"].quantile(0.25).to_numpy())
    assert (store.path / "report" / "figures" / "fig21_pso.png").exists()
    assert "**Best cost J [–] (the composite cost of Sec. 11) reached by each iteration: its mean" in md


def test_pso_cvs_of_parameters_j_does_not_depend_on_get_no_verdict(tmp_path):
    """λ2, b, k, c do not enter the quasi-static cost J (``flat_parameters``): their CVs are where the
    swarm stopped, so their rows carry no verdict and the finding counts only the judged ones;
    Fig. 21a's paper CVs carry their unit beside ours."""
    import matplotlib.pyplot as plt

    from graspcampaign.campaign.paper import study_paper
    from graspcampaign.report.render import Run
    from graspcampaign.report.studies import pso

    def outputs(factors, rng):
        return {"lambda1": 1.5, "lambda2": rng.uniform(0.3, 1.4), "n_exp": rng.normal(0.5, 0.05),
                "b": rng.uniform(0.2, 1.5), "k": rng.uniform(0.05, 0.3), "c": rng.uniform(5e-4, 0.01),
                "best_cost": rng.uniform(0, 1), "n_evaluations": 120, "flat_parameters": "lambda2,b,k,c"}

    store = make_run(tmp_path, "pso_repeatability", "pso_repeatability", {"shape": ["sphere"]}, seeds=6,
                     paper=None, outputs=outputs)
    build_reports(["pso_repeatability"], root=tmp_path)
    cv = read_table(store, "cv").set_index("parameter")
    flat = ["lambda2", "b", "k", "c"]
    assert all(v.startswith("no verdict: J does not depend on it") for v in cv.loc[flat, "verdict"])
    assert not any(v.startswith("no verdict") for v in cv.loc[["lambda1", "n_exp"], "verdict"])
    differ = sum(v.startswith("differs") for v in cv.loc[["lambda1", "n_exp"], "verdict"])
    md = (store.path / "report" / "report.md").read_text()
    assert f"{differ} of 2 judged parameters' CVs differ from the paper's (Sec. 6.8). " in md  # none pinned
    n_cv = 100 * sps.variation(ok_records(store)["n_exp"], ddof=1)  # λ1 is pinned: n alone varies
    assert f"among ours that J depends on and vary, n has the smallest CV ({n_cv:.1f}%)" in md
    run = Run(store.read().to_pandas(), store.check(), study_paper("pso_repeatability"), store)
    fig = plt.figure()
    pso.fig21(run, fig)
    ticks = [t.get_text() for t in fig.axes[0].get_xticklabels()]
    plt.close(fig)
    assert [t.split("\n")[2] for t in ticks] == ["paper 60%", "paper 60%", "paper 19%",
                                                 *3 * ["paper 47–77%"]]


def test_pso_cv_of_a_parameter_on_its_bound_in_every_run_says_it_measures_the_bound(tmp_path):
    """λ1 sits on its upper search bound in every run: its CV of 0 measures the bound, so its verdict says
    so; n, constant but inside the box, and b, on a bound but not in every run, keep the bare rule."""
    def outputs(factors, rng):
        b_on_bound = rng.uniform() < 0.5
        return {"lambda1": 1.5, "lambda2": rng.uniform(0.3, 1.4), "n_exp": 0.7,
                "b": 2.0 if b_on_bound else rng.uniform(0.2, 1.5), "k": rng.uniform(0.05, 0.3),
                "c": rng.uniform(5e-4, 0.01), "best_cost": rng.uniform(0, 1), "n_evaluations": 120,
                **{f"at_bound_{p}": p == "lambda1" or (p == "b" and b_on_bound)
                   for p in ("lambda1", "lambda2", "n", "b", "k", "c")}}

    store = make_run(tmp_path, "pso_repeatability", "pso_repeatability", {"shape": ["sphere"]}, seeds=8,
                     paper=None, outputs=outputs)
    build_reports(["pso_repeatability"], root=tmp_path)
    ok = ok_records(store)
    every_run = {p for p in ("lambda1", "lambda2", "n", "b", "k", "c") if ok[f"at_bound_{p}"].all()}
    assert every_run == {"lambda1"} and 0 < ok["at_bound_b"].sum() < len(ok)
    verdict = read_table(store, "cv").set_index("parameter")["verdict"]
    assert verdict["lambda1"] == ("differs by −60.0 pp; on its search bound (1.500) in every run, so CV 0.0% "
                                  "measures the bound, not repeatability")
    assert [p for p in verdict.index if "search bound" in verdict[p]] == ["lambda1"]
    assert verdict["n_exp"] == "differs by −19.0 pp"  # CV 0 inside the box: a bare verdict
    md = (store.path / "report" / "report.md").read_text()  # the count names the bound's share of it
    assert ("4 of 6 judged parameters' CVs differ from the paper's (Sec. 6.8), 1 of them because they sit "
            "on a search bound in every run.") in md


def test_pso_cv_verdicts_are_the_rules_words_told_the_records_bound_flags(tmp_path, verdict_calls):
    """Each CV row's verdict is the words the one verdict rule returned, not edited by the spec after it:
    the rule is told which parameters the records put on a search bound in every run (``at_bound_*``
    all true: pinned) and which J does not depend on (``flat_parameters``: not compared)."""
    from graspcampaign.campaign.paper import study_paper
    from graspcampaign.report.render import Run
    from graspcampaign.report.studies import pso

    def outputs(factors, rng):
        return {"lambda1": 1.5, "lambda2": 0.2, "n_exp": rng.normal(0.5, 0.05), "b": rng.uniform(0.2, 1.5),
                "k": rng.uniform(0.05, 0.3), "c": rng.uniform(5e-4, 0.01), "best_cost": rng.uniform(0, 1),
                "n_evaluations": 120, "flat_parameters": "lambda2,b,k,c",
                **{f"at_bound_{p}": p in ("lambda1", "lambda2") for p in ("lambda1", "lambda2", "n", "b",
                                                                          "k", "c")}}

    store = make_run(tmp_path, "pso_repeatability", "pso_repeatability", {"shape": ["sphere"]}, seeds=6,
                     paper=None, outputs=outputs)
    ok = ok_records(store)
    cv = pso._cv(Run(store.read().to_pandas(), store.check(), study_paper("pso_repeatability"), store))
    for r in cv.itertuples():
        told = [c for c in verdict_calls if c["words"] == r.verdict and c["ours"] == r.cv_pct]
        assert told, f"{r.parameter}: verdict {r.verdict!r} is no word of the verdict rule"
        on_bound = bool(ok[f"at_bound_{'n' if r.parameter == 'n_exp' else r.parameter}"].all())
        flat = r.parameter in ok["flat_parameters"].iloc[0].split(",")
        assert bool(told[-1].get("pinned")) == on_bound and bool(told[-1].get("because")) == flat, r.parameter
        assert (r.differs is None) == flat
        assert ("search bound (1.500)" in r.verdict) == (r.parameter == "lambda1")


def _wrench_report(tmp_path, outputs, trace):
    """A wrench_balance run at μ 0.1, 0.3, 0.5 from ``outputs``/``trace``, reported: its store, the
    wrench_balance table and that table's settling rows by μ."""
    store = make_run(tmp_path, "wrench_balance", "wrench_balance",
                     {"shape": ["sphere"], "mass_kg": [0.4], "mu": [0.1, 0.3, 0.5]}, seeds=1,
                     paper=None, outputs=outputs, tables=trace)
    build_reports(["wrench_balance"], root=tmp_path)
    table = read_table(store, "wrench_balance")
    return store, table, table[table["quantity"].str.startswith("iteration")].set_index("mu")


def test_wrench_balance_settling_from_trace(tmp_path):
    def outputs(factors, rng):
        return quasi_static_outputs({**factors, "planner": "heuristic"}, rng)

    def trace(trial_id, factors, out):
        it = np.arange(60)
        settle = {0.1: 20, 0.3: 35, 0.5: 50}[factors["mu"]]
        res = np.where(it < settle, 5.0, 0.1)
        return {"iterations": [{"trial_id": trial_id, "iteration": int(i),
                                "residual_norm_n": float(r), "torque_norm_nm": 1e-4,
                                "slip_margin_n": 1.0, "slip_margin_rel": factors["mu"] * 1.9,
                                "normal_force_1_n": 64.0} for i, r in zip(it, res, strict=True)]}

    store, table, settle = _wrench_report(tmp_path, outputs, trace)
    assert settle["ours"].to_dict() == {0.1: 20.0, 0.3: 35.0, 0.5: 50.0}
    assert settle.loc[0.3, "verdict"] == "inside the paper's range 30–40"
    assert settle.loc[0.1, "verdict"] == "differs: below the paper's range 30–40"
    assert settle.loc[0.5, "verdict"] == "differs: above the paper's range 30–40"
    slip = table[table["quantity"].str.startswith("final slip")].set_index("mu")
    assert slip.loc[0.5, "verdict"] == "inside the paper's range 0.80–1.00"
    assert slip.loc[0.1, "verdict"] == "the paper reports no value"  # stated for μ ≥ 0.3 only
    assert slip.loc[0.3, "verdict"].startswith("differs")  # 0.57 is not above 0.8
    assert (store.path / "report" / "figures" / "fig17_wrench.png").exists()
    # a trace stored before the kind recorded finger 1's depth: the report says it has none
    md = (store.path / "report" / "report.md").read_text()
    assert "this run's trace has no finger-1 depth (stored before the kind recorded it)" in md


def test_wrench_balance_never_settling_differs_and_non_physical_depths_flagged(tmp_path):
    """A residual that never settles differs from the paper; the commanded finger force is no
    agreement; depths beyond the fingertip radius are counted apart, and the finding names the
    iteration where the trace's stored finger-1 depth first exceeds r (the force, constant here,
    is not inverted for it)."""
    r_mm = 5.0  # Table 2; depths ramp 0.5 -> 20 mm
    depth_mm = np.linspace(0.5, 20.0, 30)
    cross = int(np.flatnonzero(depth_mm > r_mm)[0]) + 1

    def outputs(factors, rng):
        out = quasi_static_outputs({**factors, "planner": "heuristic"}, rng)
        return {**out, "delta_max_mm": {0.1: 20.0, 0.3: 3.0, 0.5: 0.6}[factors["mu"]]}

    def trace(trial_id, factors, out):
        res = np.full(30, 5.0) if factors["mu"] < 0.5 else np.where(np.arange(30) < 10, 5.0, 0.1)
        return {"iterations": [{"trial_id": trial_id, "iteration": i + 1, "residual_norm_n": float(res[i]),
                                "torque_norm_nm": 1e-4, "slip_margin_n": 1.0, "slip_margin_rel": 0.9,
                                "normal_force_1_n": 64.0, "depth_1_mm": float(depth_mm[i])}
                               for i in range(30)]}

    store, table, settle = _wrench_report(tmp_path, outputs, trace)
    assert settle.loc[[0.1, 0.3], "differs"].tolist() == [True, True]  # never settles: differs
    assert settle.loc[0.1, "ours"] != settle.loc[0.1, "ours"]  # nan: shown as "never settles"
    assert settle.loc[0.1, "verdict"].startswith("differs: above the paper's range")
    command = table[table["quantity"].str.startswith("final finger-1")]
    assert command["differs"].isna().all() and command["verdict"].str.startswith("commanded").all()
    compared = table[table["differs"].notna()]
    md = (store.path / "report" / "report.md").read_text()
    differ = int(compared["differs"].astype(bool).sum())
    assert f"{differ} of {len(compared)} compared quantities differ" in md
    assert f"deeper than the fingertip radius r = {r_mm:g} mm from iteration {cross} on" in md
    limit = read_table(store, "design_limit").set_index("mu")
    ok = ok_records(store).set_index("mu")["delta_max_mm"]
    assert limit["beyond_radius"].to_dict() == (ok > r_mm).astype(int).to_dict()
    assert limit.loc[0.1, ["delta_max_median_mm"]].isna().all()  # only a non-physical trial: no statistic
    assert limit.loc[0.3, "delta_max_median_mm"] == pytest.approx(3.0)


@pytest.mark.parametrize(("scales", "words"), [([1.0, 0.5, 2.0], "unit weights"),
                                               ([0.5, 2.0], "weight scale 0.5")])  # no unit-weight trial
def test_heuristic_weights_invariance(tmp_path, scales, words):
    from graspcampaign.campaign.paper import study_paper

    def outputs(factors, rng):
        s = factors["weight_scale"]
        key = f"{factors['seed']}-2-3"  # differs between seeds, never between scales of one seed
        return {"vertex_1": 1, "vertex_2": 2, "vertex_3": 3, "argmin_key": key,
                "argmin_key_ratio_2_1_1": key,
                "argmin_key_ratio_1_1_2": "9-9-9" if factors["seed"] == 0 else key,
                "h_total": 0.2 * s, "s1": 0.05, "s2": 0.1, "s3": 0.05, "n_c": 0, "n_e": 0,
                "h_reachable": (0.25 + 0.25 + 1 / 3 + 0.01 * (factors["seed"] - 1)) * s,  # median: seed 1
                "s1_reachable": 0.25 + 0.01 * factors["seed"],
                "s2_reachable": 0.25, "s3_reachable": 1 / 3}

    store = make_run(tmp_path, "heuristic_weights", "heuristic_weights",
                     {"weight_scale": scales}, seeds=3,
                     paper=None, outputs=outputs,
                     method_factors=["weight_scale"])
    build_reports(["heuristic_weights"], root=tmp_path)
    ok = ok_records(store)
    nearest = min(scales, key=lambda v: abs(v - 1))  # the finding's H is the scale nearest unit weights
    paper = study_paper("heuristic_weights").h_at_scale[str(nearest)]  # the study file's, not re-typed
    h_nearest = ok.loc[ok["weight_scale"] == nearest, "h_reachable"].median()
    assert f"H is {h_nearest:.3f} at {words} (paper {paper})" in \
        (store.path / "report" / "report.md").read_text()
    h = read_table(store, "h_by_scale").set_index("weight_scale")
    assert h.loc[2.0, "h_reachable"] == pytest.approx(2 * (0.5 + 1 / 3))
    assert h["verdict"].str.startswith("matches").all()
    # the spread column is the range over seeds and says so (it read "spread over seeds")
    shown = _md_table((store.path / "report" / "report.md").read_text(), "h_by_scale")
    ranges = ok.groupby("weight_scale")["h_reachable"].agg(lambda v: v.max() - v.min())
    assert shown["H range over seeds (max - min)"].astype(float).tolist() == \
        pytest.approx(ranges.round(3).tolist())
    comp = read_table(store, "components").set_index("quantity")
    assert comp.loc["argmin the same at every scale, in every seed", "verdict"] == \
        "as in the paper (yes)"
    # 1/3 in every seed against the printed 0.33: the zero-width interval reads as the value
    assert comp.loc["S3 of the reachable set at unit weights", "verdict"] == \
        "consistent: the paper's value lies within one printed digit (0.01) of our 95% interval (0.00)"
    # S1 varies by seed: the median over every trial at the nearest scale, with its n (was one trial, no n)
    at = ok[ok["weight_scale"] == nearest]
    s1 = comp.loc["S1 of the reachable set at unit weights"]
    assert (float(s1["value"]), s1["n"]) == (pytest.approx(at["s1_reachable"].median()), len(at))
    # ... and its percentile-bootstrap 95% interval (seed: the run's), as every median's (it had none)
    boot = sps.bootstrap((at["s1_reachable"].to_numpy(),), np.median, n_resamples=BOOTSTRAP_RESAMPLES,
                         method="percentile", rng=np.random.default_rng(11)).confidence_interval
    assert (s1["low"], s1["high"]) == (pytest.approx(boot.low), pytest.approx(boot.high))
    shown = _md_table((store.path / "report" / "report.md").read_text(), "components").set_index("quantity")
    median = at["s1_reachable"].median()
    assert shown.loc[s1.name, "ours (95%)"] == f"{median:.2f} ({boot.low:.2f}–{boot.high:.2f})"
    assert shown.loc[s1.name, "verdict"] == \
        "consistent: the paper's value lies inside our 95% interval (+0.01)"
    contacts = comp.loc["penalised contacts n_c + n_e on the sphere (largest over trials)"]
    assert (contacts["n"], contacts["section"]) == (len(ok), "Sec. 5.2")  # the paper says so in Sec. 5.2
    sweep = read_table(store, "ratio_sweep").set_index("weights_w1_w2_w3")
    assert sweep["argmin_moves"].to_dict() == {"2:1:1": 0, "1:1:2": 1}


def test_prepared_identifications_beside_table3(tmp_path):
    prepared = [{"shape": "sphere", "mass_kg": 0.4, "mu": 0.3, "nodes": 390, "body_id": "b1",
                 "lambda1": 0.3, "lambda2": 0.9, "n_exp": 0.5, "b": 0.6, "k": 0.1, "c": 0.002,
                 "best_cost": 0.01, "n_evaluations": 50_000, "wall_time_s": 3.0}]
    store = make_run(tmp_path, "my_grid", "quasi_static",
                     {"shape": ["sphere"], "mass_kg": [0.4], "mu": [0.3],
                      "planner": ["heuristic", "random"]},
                     seeds=3, paper={}, outputs=quasi_static_outputs, prepared=prepared)
    build_reports(["my_grid"], root=tmp_path)
    ident = read_table(store, "identifications").set_index("parameter")
    assert ident.loc["lambda1", "paper"] == 0.332  # from campaigns/pso_repeatability.yaml
    assert ident.loc["n_exp", "ours_mean"] == 0.5
    assert read_table(store, "success_rates")["planner"].tolist() == ["heuristic", "random"]


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


def test_pso_budgets_split_and_pinned_parameters(tmp_path):
    def outputs(factors, rng):
        conv = factors["budget"] == "converged"
        return {"lambda1": 1.5, "lambda2": rng.uniform(0.3, 1.4), "n_exp": rng.normal(0.5, 0.05),
                "b": rng.uniform(0.2, 1.5), "k": rng.uniform(0.05, 0.3),
                "c": 0.002 if conv else rng.uniform(5e-4, 0.01), "best_cost": rng.uniform(0, 1),
                "n_evaluations": 50_000 if conv else 120, "at_bound": "lambda1",  # its upper bound
                **{f"at_bound_{p}": p == "lambda1" for p in ("lambda1", "lambda2", "n", "b", "k", "c")}}

    store = make_run(tmp_path, "pso_repeatability", "pso_repeatability",
                     {"shape": ["sphere"], "budget": ["repeatability", "converged"]}, seeds=6,
                     paper=None, outputs=outputs)
    build_reports(["pso_repeatability"], root=tmp_path)
    ok = ok_records(store)
    rep, conv = ok[ok["budget"] == "repeatability"], ok[ok["budget"] == "converged"]
    cv = read_table(store, "cv").set_index("parameter")
    assert cv.loc["n_exp", "n"] == len(rep)
    assert cv.loc["n_exp", "cv_pct"] == pytest.approx(100 * sps.variation(rep["n_exp"], ddof=1))
    assert cv.loc["lambda1", "cv_pct"] == 0.0
    t3 = read_table(store, "table3").set_index("parameter")
    assert t3.loc["c", "ours_mean"] == pytest.approx(0.002) and t3.loc["c", "n"] == len(conv)
    md = (store.path / "report" / "report.md").read_text()
    assert "Pinned in every run (CV 0, a bound of the search box): λ1 at 1.5" in md  # the label, not the id
    assert cv.loc["lambda1", "why"] == "every value is the same: a zero spread has no interval"
    assert "| lambda1 | 60.0 | 0.0 (every value is the same" not in md  # no interval shown
    assert "restarts at the paper's 8 × 15 budget" in md
    # issue 13: an identified value on a search bound is said so wherever it is shown
    assert (cv.loc["lambda1", "at_bound"], cv.loc["n_exp", "at_bound"]) == (len(rep), 0)
    assert t3.loc["lambda1", "at_bound"] == len(conv)
    assert f"Ended on a PSO search bound (`at_bound`): λ1 in {len(rep)} of {len(rep)} runs" in md
