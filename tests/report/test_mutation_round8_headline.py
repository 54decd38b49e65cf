"""Mutation round 8: the Table 1 page's rows and the spec's rate and gate items, checked by
consequences counted by hand (docs/decisions.md, mutation round 8)."""

from __future__ import annotations

import pandas as pd

from graspcampaign.analysis.vocabulary import label
from graspcampaign.campaign.paper import study_paper
from graspcampaign.campaign.records import RunStore
from graspcampaign.report.document import Document, Text
from graspcampaign.report.headline import TABLE1, _run_row, runs_of
from graspcampaign.report.render import Run, render
from graspcampaign.report.spec import Finding, GateRemoved, Rates, ReportSpec

ROW = {h.label: h for h in TABLE1}


def records(planners: dict[str, list], errored: tuple[str, ...] = ()) -> pd.DataFrame:
    """Trials of each planner with these successes; every trial of ``errored`` planners errored."""
    rows = [{"status": "error" if p in errored else "ok", "planner": p, "success": None if p in errored
             else s, "aborted": False} for p, outcomes in planners.items() for s in outcomes]
    return pd.DataFrame(rows)


def row_of(headline: str, frame: pd.DataFrame, tmp_path, config: dict | None = None) -> dict:
    h = ROW[headline]
    manifest = {"run": "r1", "config": config or {"factors": {"shape": ["sphere", "pear"]}}}
    return _run_row(h, RunStore(tmp_path / h.study / "r1"), tmp_path,
                    (manifest, study_paper(h.study), frame, "simulation"))


def test_the_no_pso_planner_is_a_baseline_of_ours_as_of_the_papers_table_7(tmp_path):
    """The paper's Table 7 lists no-PSO among the proposed planner's baselines (46.7%); our row of the
    same run lists it too, though its name begins as an ablation variant's ("no_")."""
    frame = records({"heuristic": [True, True, False, False], "no_pso": [True, False, False, False]})
    row = row_of("Grasp validation, all", frame, tmp_path)
    assert f"{label('planner', 'no_pso')} 46.7%" in row["paper_baselines"]
    assert row["ours_baselines"] == f"{label('planner', 'no_pso')} 25.0%"  # 1 of 4


def test_a_baseline_whose_every_trial_errored_is_no_rate(tmp_path):
    """random's 2 trials errored: no executed trial, no rate to list beside antipodal's 1 of 2."""
    frame = records({"heuristic": [True, False], "antipodal": [True, False], "random": [True, True]},
                    errored=("random",))
    row = row_of("Baseline grid", frame, tmp_path)
    assert row["ours_baselines"] == "antipodal 50.0%"
    assert (row["n"], row["rate_pct"]) == (2, 50.0)


def test_a_quasi_static_run_recorded_before_grip_law_is_algorithm_2s(tmp_path):
    """Records without the grip_law column were judged by the evaluator's law, Algorithm 2 unless
    configured: the row counts them (2 trials, 1 success), it does not call the column missing."""
    frame = records({"heuristic": [True, False], "random": [False, False]})
    assert "grip_law" not in frame
    row = row_of("Baseline grid", frame, tmp_path)
    assert (row["n"], row["rate_pct"], row["why"]) == (2, 50.0, "")
    configured = {"factors": {"shape": ["sphere"]}, "evaluator": {"grip_law": "oracle"}}
    row = row_of("Baseline grid", frame, tmp_path, configured)
    assert row["why"].startswith("no trial of the proposed planner")


def test_one_seed_is_not_named_in_the_testbed(tmp_path):
    frame = records({"heuristic": [True]})
    one = row_of("Baseline grid", frame, tmp_path, {"seeds": 1, "factors": {"shape": ["sphere", "pear"]}})
    ten = row_of("Baseline grid", frame, tmp_path, {"seeds": 10, "factors": {"shape": ["sphere", "pear"]}})
    assert (one["testbed"], ten["testbed"]) == ("simulation: 2 shapes", "simulation: 2 shapes × 10 seeds")


def test_a_file_in_place_of_a_run_is_listed_an_empty_folder_is_not(tmp_path):
    """The pages must not silently drop a run that cannot be read: a file where a run belongs is
    one; an empty folder (no manifest, no records) and a hidden file are none."""
    (tmp_path / "r1").mkdir()
    (tmp_path / "r1" / "manifest.json").write_text("{}")
    (tmp_path / "r2").write_text("not a run")
    (tmp_path / "r3").mkdir()
    (tmp_path / ".notes").write_text("")
    (tmp_path / "r4" / "records").mkdir(parents=True)
    assert [p.name for p in runs_of(tmp_path)] == ["r1", "r2", "r4"]


def test_the_aborted_column_appears_only_when_an_attempt_was_aborted():
    ok = pd.DataFrame({"status": "ok", "planner": "heuristic", "shape": "sphere", "success": [True, False],
                       "aborted": False})
    spec = ReportSpec("s", [Rates("rates", "Rates", ["planner"], bootstrap=False)])
    heads = []
    for frame in (ok, ok.assign(aborted=[False, True], success=[True, None])):
        doc = render(spec, Run(frame, {}), Document("t", "simulation", []))
        heads.append([c.label for c in doc.blocks[0].cols])
    assert "aborted" not in heads[0] and "aborted" in heads[1]


def test_a_gate_over_no_success_says_it_removed_none():
    """No trial succeeded without the gate: "removed none", not "removed 0 of 0 successes"; 2 of
    the 5 trials had a contact deeper than r (valid_geometry False), counted by hand."""
    frame = pd.DataFrame({"status": "ok", "planner": "heuristic", "shape": "sphere",
                          "success": [False] * 5, "success_unbounded": [False] * 5,
                          "valid_geometry": [True, True, True, False, False]})
    doc = render(ReportSpec("s", [GateRemoved(["planner"]), Finding(lambda run: "Found.")]), Run(frame, {}),
                 Document("t", "simulation", []))
    finding = [b.markdown for b in doc.blocks if isinstance(b, Text) and b.kind == "finding"]
    assert finding[0].startswith("Found. The validity gate removed none (no trial succeeded without it): "
                                 "2 of 5 executed trials")
