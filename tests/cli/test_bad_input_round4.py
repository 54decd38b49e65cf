"""Bad input, round 4: the inputs least tried (damaged run directories, report options, the
notebook API). Each case: exit 2 (or the API's exception), one sentence naming what is wrong and
where, nothing stored changed."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from cli_checks import BG, grid_run, invoke, refused, resume_advice, snapshot
from statsmodels.stats.proportion import proportion_confint

import graspcampaign
import graspcampaign as gc
from graspcampaign.errors import ConfigError, UserInputError

#: this checkout's package first on a child interpreter's path
SRC = {**os.environ, "PYTHONPATH": str(Path(graspcampaign.__file__).parents[1])}


def test_gc_stats_works_after_import_graspcampaign_alone_and_stays_lazy():
    """README's notebook user writes ``gc.stats.wilson_interval`` after ``import graspcampaign as
    gc`` (an AttributeError before); ``import graspcampaign`` alone still imports no scipy."""
    code = ("import sys, graspcampaign as gc\n"
            "lazy = 'scipy' not in sys.modules and 'graspcampaign.stats' not in sys.modules\n"
            "ci = gc.stats.wilson_interval(3, 10)\n"
            "print(lazy, repr(ci.low), repr(ci.high))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                          env=SRC)
    lazy, low, high = done.stdout.split()
    assert lazy == "True"
    assert (float(low), float(high)) == pytest.approx(proportion_confint(3, 10, method="wilson"),
                                                      abs=1e-12)


def test_a_file_in_place_of_a_run_directory_is_named_by_report_of_every_run(results):
    """``report`` of every run once skipped such a file in silence (exit 0) and rewrote the
    headline and index pages without the run, as if it had no records; now it fails as for a run
    without its manifest: exit 2 naming the file, the pages left as they were, the others
    reported."""
    pages = {p: p.read_bytes() for p in results.glob("*.*")}
    shutil.rmtree(grid_run(results))
    grid_run(results).write_text("not a run")
    (results / "smoke" / ".DS_Store").write_text("hidden: not a run")
    done = invoke("report", "--root", results)
    why = (f"run baseline_grid/default at {grid_run(results)} is a file, not a run directory; move "
           "it aside or choose another run name (--run NAME)")
    assert done.exit_code == 2, done.output
    assert done.stderr == ("warning: the headline and index pages were left as they were: run "
                           f"baseline_grid/default cannot be read ({why})\n"
                           f"error: the report of baseline_grid/default could not be written: {why}\n")
    assert done.stdout == f"report: {results}/smoke/default/report/report.md\n"
    assert {p: p.read_bytes() for p in results.glob("*.*")} == pages


#: a records file damaged as a disk or a copy damages it -> why, in plain words (pyarrow's were
#: "Parquet file size is 0 bytes", "Parquet magic bytes not found in footer. Either the file is
#: corrupted or this is not a parquet file." and "Couldn't deserialize thrift: don't know what
#: type: ")
CUT = "it does not end with a Parquet footer: cut short, or not a Parquet file"
DAMAGED = {
    "zero_bytes": (lambda data: b"", "it is empty"),
    "cut_mid_file": (lambda data: data[: len(data) // 2], CUT),
    "its_footer_cut": (lambda data: data[:-4], CUT),
    "bytes_appended": (lambda data: data + b"more", CUT),
    "its_head_cut": (lambda data: data[100:],
                     "its Parquet structure cannot be decoded: damaged, or not a Parquet file"),
}


@pytest.mark.parametrize("case", sorted(DAMAGED))
def test_a_damaged_records_file_is_named_in_plain_words(results, case):
    damage, why = DAMAGED[case]
    (records,) = (grid_run(results) / "records").glob("*.parquet")
    records.write_bytes(damage(records.read_bytes()))
    refused(results, ["status", "baseline_grid", "--root", results],
            f"run baseline_grid/default at {grid_run(results)} has a damaged file "
            f"records/{records.name} ({why}); {resume_advice(results)}")


def test_a_run_name_that_is_no_text_is_refused_before_the_run_writes(tmp_path):
    """``run_study(study, run=3)`` once ran the trials and stored run 3 as a number in the
    manifest, which every command then refused as damaged ("run is 3, not a name")."""
    study = gc.compose_study("smoke", ["shape=[sphere]", "nodes=[144]", "runner.backend=sequential",
                                       f"output.root={tmp_path / 'results'}"])
    with pytest.raises(ConfigError, match=r"^--run = 3 is not a name: give it as text \(a str\)\.$"):
        gc.run_study(study, run=3)
    assert not (tmp_path / "results").exists()


@pytest.mark.parametrize(("call", "error", "message"), [
    (lambda root: gc.compose_study("smoke", "nodes=[144]"), ConfigError,
     "overrides = 'nodes=[144]' is not a list of KEY=VALUE texts; give one, e.g. ['seeds=2']."),
    (lambda root: gc.compose_study("smoke", [5]), ConfigError,
     "overrides = [5] is not a list of KEY=VALUE texts; give one, e.g. ['seeds=2']."),
    (lambda root: gc.compose_study(5), ConfigError,
     "study = 5 is not a study's name or file path: give it as text."),
    (lambda root: gc.load_records(None, root=root), ConfigError,
     "study = None is not a name: give it as text (a str)."),
    (lambda root: gc.load_records("smoke", 3, root=root), ConfigError,
     "run = 3 is not a name: give it as text (a str)."),
    # root=None is the study's configured root (output.root), as run_study stores it
    (lambda root: gc.load_records("smoke", root=3), UserInputError,
     "root = 3 is not a path: give the results directory as text or a Path."),
], ids=["overrides_a_string", "override_a_number", "study_a_number", "load_study_none",
        "load_run_a_number", "load_root_a_number"])
def test_the_notebook_api_names_an_argument_of_the_wrong_type(results, call, error, message):
    """A notebook's wrong-typed argument: one sentence naming it (was a TypeError or
    AttributeError from deep inside, or a string's characters read as overrides)."""
    before = snapshot(results)
    with pytest.raises(error) as raised:
        call(results)
    assert str(raised.value) == message
    assert snapshot(results) == before


def test_a_file_in_place_of_a_study_directory_is_named_not_run_for_ever(results):
    """status said "no run ...; run it first", show counted 0 recorded, and run then failed with
    "cannot write .../manifest.json: not a directory; ... run the command again", for ever."""
    study = grid_run(results).parent
    shutil.rmtree(study)
    study.write_text("not a study")
    message = (f"run baseline_grid/default at {grid_run(results)} cannot be stored: {study} is a "
               "file, not the study's directory; move it aside.")
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["run", "baseline_grid", *BG]):
        refused(results, [*args, "--root", results], message)


@pytest.mark.parametrize("lookup", [
    lambda frame: frame.pivot(index="a", columns="a", values="success"),  # mcnemar's pairing
    lambda frame: frame[["success"]],
    lambda frame: frame.loc[:, ["a", "success"]],
    lambda frame: frame["success"],
], ids=["pivot", "list", "loc", "one"])
def test_a_column_the_records_lack_is_named_by_its_name_alone(lookup):
    """A report item over records without ``success`` said "the records have no `The following
    'values' labels are not columns of the DataFrame: ['success']` column"."""
    import pandas as pd

    from graspcampaign.report.render import reason

    with pytest.raises(KeyError) as raised:
        lookup(pd.DataFrame({"a": [1, 2]}))
    assert reason(raised.value) == "the records have no `success` column"


@pytest.mark.parametrize(("override", "meant"), [
    # a typo of a key the study sets was told to add it with '+', which would run with the typo unread
    ("params.fractoin=0.1", "did you mean params.fraction? A key it does not set is added "),
    ("paper.table7x=1", "did you mean paper.table7? A key it does not set is added "),
    ("params.nosuchthing=0.1", "add it "),  # nothing near: the '+' advice alone
])
def test_a_mistyped_params_or_paper_key_names_the_key_the_study_sets(tmp_path, override, meant):
    key, checker = override.split("=")[0], "its trial kind's" if override.startswith("params") \
        else "the study's paper"
    refused(tmp_path, ["run", "test2_grasp", override, "--root", tmp_path],
            f"{key} is not set by this study (override {override!r} rejected); {meant}with a leading "
            f"'+' (+{key}=...), and {checker} schema checks it.")
