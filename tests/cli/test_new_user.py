"""What a new user meets following README.md: the commands it shows, in its order, keep working
together (each case once failed or pointed to the wrong next step)."""

from __future__ import annotations

import re

import pandas as pd
import yaml
from cli_checks import invoke, refused

from graspcampaign.campaign.studyfile import project_dirs


def test_schedule_by_default_writes_where_report_finds_no_run(results):
    """README: `schedule <study> --template`, then `report`. The sheets' default place was the
    study's folder, where `report` of every run takes each file for a run that cannot be read: it
    exited 2 naming schedule.csv and the headline page gained a row per sheet file."""
    made = invoke("schedule", "test2_grasp", "params.fraction=0.05", "--template", "--root", results)
    assert made.exit_code == 0, made.output
    folder = results / "test2_grasp" / "schedule"
    assert made.stdout.splitlines()[1] == (f"measured-records template -> {folder}/sheet-template.csv "
                                           f"(columns and units: {folder}/sheet-template-columns.csv)")
    assert sorted(p.name for p in folder.iterdir()) == [
        "sheet-template-columns.csv", "sheet-template.csv", "sheet.csv", "sheet.parquet"]
    reported = invoke("report", "--root", results)
    assert reported.exit_code == 0, reported.output
    assert reported.stderr == ""
    assert "cannot be read" not in (results / "headline.md").read_text()


def test_a_protocols_measured_run_not_yet_ingested_points_to_ingest(results):
    """README: `ingest <study> FILE…` stores the run `measured`. Before it, `status` advised `run
    <study> --run measured`, which fills that run with virtual-rig trials, and `ingest` then refuses
    it as a simulation run; a simulation study's run of that name is still made by `run`."""
    refused(results, ["status", "test3_disturbance", "--run", "measured", "--root", results],
            f"no run at {results}/test3_disturbance/measured; store the rig's measured records "
            f"with `graspcampaign ingest test3_disturbance FILE… --root {results}` first.")
    refused(results, ["status", "smoke", "--run", "measured", "--root", results],
            f"no run at {results}/smoke/measured; run `graspcampaign run smoke --run measured "
            f"--root {results}` first.")


def test_show_prints_a_long_paper_block_on_lines_of_about_100_characters():
    """`show test2_grasp` printed its paper block as one line of 3,000 characters. Now it is
    broken between pairs; every key of the study file's block is still there."""
    shown = invoke("show", "test2_grasp")
    assert shown.exit_code == 0, shown.output
    block = shown.stdout[shown.stdout.index("\npaper: ") + 1:].splitlines()
    assert len(block) > 20 and max(map(len, block)) <= 100
    assert all(line.startswith("  ") for line in block[1:])
    paper = yaml.safe_load((project_dirs()[1] / "test2_grasp.yaml").read_text())["paper"]
    keys = re.findall(r"(?:^paper: |, |^  )([\w.]+)=", "\n".join(block), flags=re.MULTILINE)
    assert sorted(keys) == sorted(pd.json_normalize(paper).columns)
