"""Every command on a measured run: a virtual rig's records exported without their ``source`` column
(a rig's own file, so ``source = measured``) and ingested under the reduced overrides of the tests,
into a results root of its own.

Imported helpers by name (``from hardware_checks import ...``), as pytest puts this directory on the path.
"""

from __future__ import annotations

import json
import re

import pandas as pd
import pytest
from hardware_checks import REDUCED, cli

from graspcampaign.campaign.kinds import hardware as H
from graspcampaign.campaign.records import RunStore
from graspcampaign.cli.main import app
from graspcampaign.rig import test1 as T

SETS = [a for o in REDUCED for a in ("--set", o)]
T1_REDUCED = ["params.materials=[gel]", "params.specimens=[1,11]", "params.environments=[normal_lab]",
              "params.pso_restarts=3", "params.pso_particles=12", "params.pso_iterations=40",
              "params.pso_max_reruns=2"]


@pytest.fixture(scope="module")
def t2_measured(study_run, tmp_path_factory):
    """The first half of a reduced virtual test2_grasp run, ingested as measured under its own root."""
    _, summary = study_run("test2_grasp", *REDUCED)
    export = H.export_records(RunStore(summary.path).read().to_pandas(), "test2_grasp")
    root = tmp_path_factory.mktemp("measured")
    export.iloc[: len(export) // 2].drop(columns="source").to_csv(root / "day1.csv", index=False)
    result = cli.invoke(app, ["ingest", "test2_grasp", str(root / "day1.csv"), *SETS, "--root", str(root)])
    assert result.exit_code == 0, result.output
    return root, len(export) // 2


def test_a_measured_run_under_overrides_is_marked_reduced_as_a_run_is(t2_measured):
    # ingest kept no overrides in the manifest: the report and the headline presented a reduced
    # measured run (a sixteenth of the protocol's sheet) as the study's design
    root, _ = t2_measured
    result = cli.invoke(app, ["report", "test2_grasp", "--run", "measured", "--root", str(root)])
    assert result.exit_code == 0, result.output
    measured = (root / "test2_grasp/measured/report/report.md").read_text().splitlines()
    sizes = [int(re.search(r"= (\d+) trials", cli.invoke(app, ["show", "test2_grasp", *o]).stdout)[1])
             for o in ([], REDUCED)]  # the study file's sheet, and the reduced one
    assert sizes[1] < sizes[0]
    assert (f"- **Reduced/modified run:** overrides `params.fraction=0.06`; {sizes[1]} of the study's "
            f"{sizes[0]} trials") in measured
    assert "> **Data source:** measured on hardware (ingested records)" in measured
    headline = pd.read_csv(root / "headline.csv").dropna(subset=["run"])
    assert len(headline) and headline["testbed"].str.startswith("measured on hardware †").all()


def test_show_of_a_measured_run_estimates_no_run_time(t2_measured):
    # show estimated the compute time of the trials not yet measured, which `run` refuses to add
    root, ingested = t2_measured
    shown = cli.invoke(app, ["show", "test2_grasp", *REDUCED, "--run", "measured", "--root", str(root)])
    assert shown.exit_code == 0, shown.output
    n_trials = json.loads((root / "test2_grasp/measured/manifest.json").read_text())["n_trials"]
    assert (f"estimated time: none: `run` adds no trials to an ingested run; its {n_trials - ingested} "
            "trials not recorded come from `ingest`") in shown.stdout.splitlines()
    refused = cli.invoke(app, ["run", "test2_grasp", *REDUCED, "--run", "measured", "--root", str(root)])
    assert refused.exit_code == 2 and "never adds simulated or virtual trials" in refused.stderr


def test_a_measured_bench_report_says_nothing_of_the_virtual_bench(tmp_path):
    # the finding ended on where the virtual bench differs by construction, and Table 4's caption
    # called E the virtual bench's drawn modulus, on a run of rig measurements (E is empty there)
    schedule = T.test1_schedule(701, materials=["gel"], specimens=[1, 11], environments=["normal_lab"])
    waves = T.run_virtual_bench(schedule, 701, keep_waveforms=True).waveforms
    first = sorted(schedule.groupby("block").head(2)["event_id"])
    waves[waves["event_id"].isin(first)].drop(columns="source").to_csv(tmp_path / "rig.csv", index=False)
    sets = [a for o in T1_REDUCED for a in ("--set", o)]
    result = cli.invoke(app, ["ingest", "test1_bench", str(tmp_path / "rig.csv"), *sets,
                              "--root", str(tmp_path)])
    assert result.exit_code == 0, result.output
    result = cli.invoke(app, ["report", "test1_bench", "--run", "measured", "--root", str(tmp_path)])
    assert result.exit_code == 0, result.output
    report = tmp_path / "test1_bench/measured/report"
    text = (report / "report.md").read_text()
    assert "virtual bench" not in text.lower() and "> **Data source:** measured on hardware" in text
    table4 = pd.read_csv(report / "tables/table4.csv")
    assert table4.loc[table4["row"] == "ours", ["modulus_kpa", "modulus_sd_kpa"]].isna().all().all()
    assert "Our E is empty: the bench measures no modulus." in text
