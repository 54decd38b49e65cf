"""Bad input, round 6: an ingest into a run another process holds, deleting a key (``~key``) that
cannot or need not be deleted, a
list override too long for Hydra's parser, a million worker processes, a
workbook named .csv and a CSV named .xlsx, a header given twice.
Each case: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

import os

import pandas as pd
import pytest
from cli_checks import SMOKE, refused, replaced

from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_lock

NEEDED = "which every study needs; set it instead"
NOTHING = "which this study does not have, so there is nothing to delete; leave it out"
DELETIONS = {
    # Hydra said "ContactModelCfg (DictConfig) does not support deletion." / "RunnerCfg ..."
    "~model.lambda1": f"override '~model.lambda1' deletes model.lambda1, {NEEDED} (model.lambda1=...).",
    "~runner.n_jobs": f"override '~runner.n_jobs' deletes runner.n_jobs, {NEEDED} (runner.n_jobs=...).",
    # Hydra said "Could not delete from config. 'nosuch' does not exist."
    "~nosuch": f"override '~nosuch' deletes nosuch, {NOTHING}.",
    "~model.nosuch": f"override '~model.nosuch' deletes model.nosuch, {NOTHING}.",
    "~mu": f"override '~mu' deletes mu, {NOTHING}, or write ~factors.mu to delete the factor mu.",
}


@pytest.mark.parametrize("override", sorted(DELETIONS))
def test_a_deletion_hydra_words_badly_is_one_sentence(results, override):
    refused(results, ["show", "baseline_grid", override, "--root", results], DELETIONS[override])


def test_an_ingest_into_a_run_being_run_is_refused_and_loses_nothing(results, tmp_path):
    """An ingest read the run's records, and wrote a shard and the manifest, while a run or another
    ingest of the run was writing them too; now it waits for none and is refused, as a second run is."""
    sheet = tmp_path / "day1.csv"
    sheet.write_text("trial_id\nt2A-sphere-01-prop-0000000000\n")
    run = results / "test2_grasp" / "measured"
    run.mkdir(parents=True)
    with run_lock(RunStore(run), "held"):  # as a run or ingest in progress holds it
        refused(results, ["ingest", "test2_grasp", sheet, "--root", results],
                f"run test2_grasp/measured at {run} is being run by another process; wait for it "
                "to finish (status shows its progress), or choose another run name (--run NAME).")


def test_a_list_override_too_long_to_parse_in_time_is_refused_unparsed(results):
    """Hydra's parser is quadratic in a list's items: 20,000 levels took over two minutes before
    anything was said; now refused before it parses them, within a few seconds."""
    levels = ",".join(f"{0.00001 * i:.5f}" for i in range(1, 20_001))
    refused(results, ["show", "shapes", f"mu=[{levels}]", "--root", results],
            f"override 'mu=[{levels[:56]}... ({len(levels) + 5} characters)' holds 20,000 "
            "comma-separated values, more than an override can hold (2,000); give them in a study "
            "file instead (a copy of the study run by its path, e.g. graspcampaign run "
            "./my_study.yaml; README, Your own studies).", seconds=10)


def test_a_million_workers_are_refused_before_any_starts(results):
    """``runner.n_jobs=1000000`` had joblib start that many worker processes; now more than four
    per core of this machine are refused at compose, before a worker or a file is made."""
    cores = os.cpu_count()
    for command in ("show", "run"):  # show first: on the old code its assertion stops the test
        refused(results, [command, "smoke", *replaced(SMOKE, "runner.backend=loky"), "runner.n_jobs=1000000",
                          "--root", results],
                f"runner.n_jobs = 1000000 would start 1,000,000 worker processes, more than 4 per "
                f"core of this machine ({cores} cores); trials compute, so more workers than cores "
                f"only share them, each holding its own memory: give at most {4 * cores}, or -1 for "
                "one per core.")


@pytest.mark.parametrize(("name", "write", "message"), [
    # it said "the file is not UTF-8 text (byte 0xc7); save it as CSV UTF-8."
    ("day1.csv", lambda frame, path: frame.to_excel(path, index=False),
     "day1.csv: the file is an Excel workbook (xlsx), not CSV text as its name says; rename it to "
     "day1.xlsx."),
    ("day1.csv", lambda frame, path: frame.to_parquet(path, index=False),
     "day1.csv: the file is a Parquet table, not CSV text as its name says; rename it to "
     "day1.parquet."),
    # it said "the file cannot be read as xlsx (ValueError)."
    ("day1.xlsx", lambda frame, path: frame.to_csv(path, index=False),
     "day1.xlsx: the file is not an Excel workbook (xlsx): it does not begin as one does; if it is "
     "CSV text, rename it to day1.csv."),
])
def test_a_file_named_as_another_type_is_named_with_the_type_it_holds(results, tmp_path, name,
                                                                      write, message):
    path = tmp_path / name
    write(pd.DataFrame({"trial_id": ["t2A-sphere-01-prop-0000000000"], "aborted": [True]}), path)
    refused(results, ["ingest", "test2_grasp", path, "--root", results], message)


def test_a_header_given_again_as_a_row_is_named(results, tmp_path):
    # it said "day1.csv, row 1, column 'aborted': value 'aborted' is not a boolean (...)"
    sheet = tmp_path / "day1.csv"
    sheet.write_text("trial_id,aborted\ntrial_id,aborted\nt2A-sphere-01-prop-0000000000,true\n")
    refused(results, ["ingest", "test2_grasp", sheet, "--root", results],
            "day1.csv, row 1: the row repeats the header (two sheets pasted one after the other?); "
            "delete it.")
