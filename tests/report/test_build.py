"""build_reports: section registry, output formats, index and headline pages, rounding, words.

Small runs are written here through ``RunStore`` and a manifest from ``campaign.provenance`` (the
record columns of docs/records.md); reference intervals come from statsmodels.
"""

from __future__ import annotations

import importlib
import json

import numpy as np
import pandas as pd
import pytest
from statsmodels.stats.proportion import proportion_confint
from typer.testing import CliRunner

from graspcampaign.campaign.grid import expand
from graspcampaign.campaign.provenance import new_manifest, write_manifest
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.schema import StudyCfg
from graspcampaign.errors import UserInputError
from graspcampaign.report import table as tbl
from graspcampaign.report.build import SECTIONS, build_reports
from graspcampaign.report.document import check_formats


def write_run(root, name="ablation", kind="quasi_static", n_success=None, error_rows=(),
              paper=None, source="simulation", planners=("heuristic", "random"),
              aborted_rows=None):
    """A run of ``len(planners) * 10`` trials; ``n_success[planner]`` successes each."""
    study = StudyCfg(name=name, kind=kind, seed=3, seeds=10,
                     factors={"shape": ["sphere"], "planner": list(planners)},
                     paper=paper if paper is not None else {"success_pct": {"heuristic": 72.0}})
    n_success = n_success or {"heuristic": 7, "random": 1}
    rows, counts = [], dict.fromkeys(planners, 0)
    for trial in expand(study):
        planner = trial.factors["planner"]
        row = {"trial_id": trial.trial_id, "study": name, "run": "r1", "kind": kind,
               "trial_index": trial.index, "scene_id": trial.scene_id, "status": "ok",
               "error_type": None, "error_message": None, "wall_time_s": 0.01, "worker": "w",
               "host": "h", "source": source, **trial.factors}
        if aborted_rows is not None:  # hardware protocols: an aborted attempt stays "ok"
            row["aborted"] = trial.index in aborted_rows
        if trial.index in error_rows:
            row.update(status="error", error_type="ValueError", error_message="bad")
        elif row.get("aborted"):
            row.update(success=None)
        else:
            success = counts[planner] < n_success.get(planner, 0)
            counts[planner] += success
            row.update(success=success, failure_check="none" if success else "residual",
                       residual_norm_n=0.1 if success else 2.0, delta_max_mm=0.5 + trial.index,
                       exceeds_1mm=0.5 + trial.index > 1)
        rows.append(row)
    store = RunStore(root / name / "r1")
    store.write_shard("records", "a", rows)
    write_manifest(store.manifest_path, new_manifest(study, "r1", len(rows), source))
    return store


def test_every_section_resolves_to_a_callable():
    for kind, target in SECTIONS.items():
        module, attr = target.split(":")
        assert callable(getattr(importlib.import_module(module), attr)), kind
    for kind in ("quasi_static", "pso_repeatability", "wrench_balance", "heuristic_weights"):
        assert kind in SECTIONS


def test_formats_md_csv_json_html(tmp_path):
    store = write_run(tmp_path)
    paths = build_reports(["ablation"], root=tmp_path, formats=["json", "html"])
    out = store.path / "report"
    assert paths == [out / "report.html"]
    assert not (out / "report.md").exists() and not (out / "tables").exists()
    data = json.loads((out / "tables.json").read_text())
    assert data["success_by_planner"][0]["planner"] == "heuristic"
    html = (out / "report.html").read_text()
    assert "<table" in html and "figures/fig16_ablation.png" in html and "Data source" in html
    assert "ablation/r1/report/report.html" in (tmp_path / "index.md").read_text()
    build_reports(["ablation"], root=tmp_path, formats=["md", "csv"])
    assert (out / "report.md").exists() and (out / "tables" / "success_by_planner.csv").exists()


def test_unknown_format_is_bad_input_and_writes_nothing(tmp_path):
    store = write_run(tmp_path)
    with pytest.raises(UserInputError, match="unknown report format 'pdf'; choose from md, csv"):
        build_reports(["ablation"], root=tmp_path, formats=["md", "pdf"])
    assert not (store.path / "report").exists() and not (tmp_path / "index.md").exists()
    assert check_formats("md, CSV,md") == ["md", "csv"]


def test_cli_format_option(tmp_path):
    from graspcampaign.cli.main import app

    write_run(tmp_path)
    runner = CliRunner()
    bad = runner.invoke(app, ["report", "ablation", "--root", str(tmp_path), "--format", "pdf"])
    assert bad.exit_code == 2
    good = runner.invoke(app, ["report", "ablation", "--run", "r1", "--root", str(tmp_path),
                               "--format", "md,json"])
    assert good.exit_code == 0, good.output
    assert (tmp_path / "ablation" / "r1" / "report" / "tables.json").exists()


def test_errored_trials_enter_no_denominator(tmp_path):
    # trials 0-9 are the heuristic's (the seed axis is innermost)
    store = write_run(tmp_path, error_rows=(0, 2))
    build_reports(["ablation"], root=tmp_path)
    table = pd.read_csv(store.path / "report" / "tables" / "success_by_planner.csv")
    row = table.set_index("planner").loc["heuristic"]
    assert (row["n"], row["n_error"], row["successes"]) == (8, 2, 7)
    low, high = proportion_confint(7, 8, method="wilson")  # statsmodels reference
    assert (row["wilson_low_pct"], row["wilson_high_pct"]) == pytest.approx((100 * low, 100 * high))
    md = (store.path / "report" / "report.md").read_text()
    assert "18 trials executed; 2 errored trials counted separately" in md


def test_report_never_runs_a_trial(tmp_path, monkeypatch):
    import graspcampaign.campaign.kind as kind_module
    import graspcampaign.campaign.runner as runner_module

    def forbidden(*args, **kwargs):
        raise AssertionError("the report ran a trial")

    monkeypatch.setattr(runner_module, "run_task", forbidden)
    monkeypatch.setattr(kind_module, "KINDS", {})
    write_run(tmp_path)
    assert build_reports(root=tmp_path)[0].exists()


def test_headline_page_and_index(tmp_path):
    write_run(tmp_path, name="baseline_grid", planners=("heuristic", "antipodal", "random"),
              n_success={"heuristic": 6, "antipodal": 4, "random": 1},
              paper={"success_pct": {"heuristic": 67.6, "antipodal": 40.0, "random": 11.0},
                     "trials_per_planner": 675})
    write_run(tmp_path, name="other", kind="no_section_kind", planners=("heuristic",))
    build_reports(root=tmp_path)
    rows = pd.read_csv(tmp_path / "headline.csv").set_index("headline")
    grid = rows.loc["Baseline grid"]
    assert (grid["n"], grid["ours_pct"], grid["paper_pct"]) == (10, 60.0, 67.6)
    assert grid["ours_baseline"] == "antipodal 40.0%, random 10.0%"
    assert grid["verdict"].startswith("differs from the paper by \u22127.6 pp; paper's value inside")
    assert rows.loc["Heuristic ablation", "verdict"] == "no records yet"
    assert rows.loc["Heuristic ablation", "paper_pct"] == 72.0  # from campaigns/ablation.yaml
    md = (tmp_path / "headline.md").read_text()
    assert "simulation: 10 seeds" in md and "[report](baseline_grid/r1/report/report.md)" in md
    index = (tmp_path / "index.md").read_text()
    assert "[headline.md](headline.md)" in index and "other/r1/report/report.md" in index


def test_virtual_rig_rows_say_so(tmp_path):
    # the Test 2 section needs the full protocol columns; the headline needs only these
    write_run(tmp_path, name="test2_grasp", kind="no_section_kind", source="virtual",
              paper={"proposed_success_pct": 77.8, "proposed_trials": 819,
                     "random_success_pct": 28.0}, aborted_rows={0, 15})
    build_reports(["test2_grasp"], root=tmp_path)
    rows = pd.read_csv(tmp_path / "headline.csv").set_index("headline")
    assert rows.loc["Grasp validation, all", "testbed"].startswith("VIRTUAL RIG")
    # trials 0-9 are the heuristic's (the seed axis is innermost): one aborted, one random one
    assert rows.loc["Grasp validation, all", ["n", "n_aborted", "ours_pct"]].tolist() == \
        [9, 1, pytest.approx(700 / 9)]
    assert "lack the `group` column" in rows.loc["Grasp validation, nominal", "verdict"]


# --------------------------------------------------------------------------------------------
# table helpers: rounding once, words, paired tests
# --------------------------------------------------------------------------------------------


def test_rate_display_rounds_once_from_full_precision():
    records = pd.DataFrame({"status": "ok", "planner": "random", "shape": "sphere",
                            "success": [True] * 17 + [False] * 83})
    pair = tbl.rate_table(records, ["planner"], paper_pct=lambda k: 17.0)
    # Wilson 17/100 = (0.108936, 0.255480): 25.5, not the doubly rounded 25.6 (issue 5)
    assert pair.display["ours % (Wilson 95%)"].iloc[0] == "17.0 (10.9–25.5)"
    assert pair.full["wilson_high_pct"].iloc[0] == pytest.approx(25.5480, abs=1e-4)
    assert pair.full["verdict"].iloc[0].startswith("matches the paper (difference 0.0 pp)")


def test_verdict_words():
    text = tbl.verdict(72.0, 0.506, 0.37, 0.64)
    assert text == ("differs from the paper by \u221221.4 pp; paper's value outside our 95% "
                    "Wilson interval")
    assert tbl.verdict(None, 0.5, 0.4, 0.6) == "the paper reports no value for this row"
    assert "inside the object-bootstrap interval" in tbl.verdict(60.0, 0.5, 0.4, 0.61, 0.3, 0.7)
    assert tbl.format_signed(-0.04) == "0.0 pp" and tbl.format_signed(1.25) == "+1.2 pp"


def test_mcnemar_pairs_occurrences_and_skips_errors():
    # scene s1 has two occurrences per planner; scene s3 misses its baseline (errored)
    records = pd.DataFrame({
        "scene_id": ["s1", "s1", "s1", "s1", "s2", "s2", "s3", "s3"],
        "trial_index": range(8),
        "planner": ["a", "b", "a", "b", "a", "b", "a", "b"],
        "status": ["ok"] * 7 + ["error"],
        "success": [True, False, True, True, False, True, True, None]})
    full = tbl.mcnemar_table(records, "a", ["b"]).full.iloc[0]
    assert (full["pairs"], full["reference_only"], full["compared_only"], full["unpaired"]) == \
        (3, 1, 1, 1)
    assert full["chi2_cc"] == 0.0 and full["p_exact"] == 1.0


def test_design_limit_counts_exceedances():
    d = np.array([0.2, 0.9, 1.0, 1.01, 5.0])
    records = pd.DataFrame({"status": "ok", "planner": "a", "delta_max_mm": d,
                            "success": [True, True, False, True, False]})
    row = tbl.design_limit_table(records, ["planner"]).full.iloc[0]
    assert (row["exceeds_1mm"], row["successes_exceeding"]) == (2, 1)  # 1.0 is not above 1 mm
