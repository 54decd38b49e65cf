"""Bad input on the paths least tried: runner options that would be ignored, measured-record files
given twice or far beyond any schedule, and decimal commas. Each is refused in one sentence with
exit 2 and nothing stored changed (``refused``)."""

from __future__ import annotations

import csv

import pandas as pd
import pytest
from cli_checks import SMOKE, invoke, refused, replaced


@pytest.mark.parametrize("backend", ["loky", "sequential"])
def test_a_dask_address_without_the_dask_backend_is_refused(results, backend):
    # the old code ran the trials on this machine and never said the address went unused
    for command in ("show", "run"):
        refused(results, [command, "smoke", *replaced(SMOKE, f"runner.backend={backend}"),
                          "runner.address=tcp://127.0.0.1:8786", "--run", "elsewhere", "--root",
                          results],
                f"runner.address = 'tcp://127.0.0.1:8786' names a Dask scheduler, but "
                f"runner.backend = {backend} runs the trials on this machine and would ignore it: "
                "add runner.backend=dask, or drop runner.address.")


def test_a_file_of_measured_records_given_twice_is_named(results, tmp_path):
    # the old code read the file twice and said its first trial 'is already in good.csv'
    sheet = tmp_path / "day1.csv"
    sheet.write_text("trial_id\nt2A-sphere-01-prop-0000000000\n")
    (tmp_path / "link.csv").symlink_to(sheet)
    for again, message in ((sheet, f"{sheet} is given twice"),
                           (tmp_path / "link.csv", f"{tmp_path / 'link.csv'} is {sheet} again")):
        refused(results, ["ingest", "test2_grasp", sheet, again, "--root", results],
                f"{message}; give each file of measured records once.")


@pytest.mark.parametrize("study", ["test2_grasp", "test3_disturbance"])
def test_a_records_file_far_beyond_any_sheet_is_refused_unread(results, tmp_path, study):
    # the old code read it whole: a 200 MiB file took a minute and 3 GiB before its refusal
    huge = tmp_path / "export.csv"
    with huge.open("wb") as out:  # sparse: 33 MiB on the file system, none of it written
        out.truncate(33 * 2**20)
    refused(results, ["ingest", study, huge, "--root", results],
            "export.csv: the file is 33 MiB, and a file of trial records is at most 32 MiB (the "
            "whole Test 2 sheet with its commanded columns is 2 MiB); check it is the right file.",
            seconds=10)


def test_a_records_file_just_over_the_limit_is_not_said_to_be_at_it(results, tmp_path):
    # the old code rounded a size in MiB to the nearest one: 32 MiB and one byte read "the file is
    # 32 MiB, and ... at most 32 MiB", as the GiB sizes of Test 1's limit no longer do
    huge = tmp_path / "export.csv"
    with huge.open("wb") as out:
        out.truncate(32 * 2**20 + 1)
    refused(results, ["ingest", "test2_grasp", huge, "--root", results],
            "export.csv: the file is 32.1 MiB, and a file of trial records is at most 32 MiB (the "
            "whole Test 2 sheet with its commanded columns is 2 MiB); check it is the right file.",
            seconds=10)


def test_a_decimal_comma_in_a_quoted_cell_is_named(results, tmp_path):
    # a spreadsheet's regional export with every cell quoted passes the separator check; the old
    # code said only "value '0,16' is not a number"
    sheet = tmp_path / "sheet"
    made = invoke("schedule", "test2_grasp", "params.fraction=0.06", "--template", "--out", sheet)
    assert made.exit_code == 0, made.output
    row = pd.read_csv(tmp_path / "sheet-template.csv").iloc[[0]].assign(
        aborted=False, outcome="stable", success=True, stable=True, slip_flag=False,
        drop_flag=False, damage_flag=False, contact_loss_flag=False, peak_slip_mm=0.16)
    row.to_csv(tmp_path / "rig.csv", index=False, decimal=",", quoting=csv.QUOTE_ALL)
    refused(results, ["ingest", "test2_grasp", tmp_path / "rig.csv", "--set", "params.fraction=0.06",
                      "--root", results],
            "rig.csv, row 1, column 'peak_slip_mm': value '0,16' is not a number (a decimal comma: "
            "save the sheet with a decimal point '.').")


def test_plan_says_a_dense_mesh_is_slow(tmp_path, monkeypatch):
    # the old code said nothing: a 5.2 M-face scan planned for 162 s in 7 GB without a word
    import trimesh

    from graspcampaign.rig import plan

    mesh = tmp_path / "scan.stl"
    trimesh.creation.icosphere(subdivisions=3, radius=30.0).export(mesh)  # 1280 faces, in mm
    monkeypatch.setattr(plan, "DENSE_FACES", 1000)  # the real limit: a minute of planning
    done = invoke("plan", mesh, "--mass-kg", "0.1", "--png", tmp_path / "scan.png", "--json")
    assert done.exit_code == 0, done.output
    assert done.stderr == (
        "warning: mesh 'scan.stl' has 1280 faces: planning on it takes half a minute or more per "
        "million faces and gigabytes of memory (every step scales with the faces); a copy "
        f"decimated to under 100 faces plans in seconds (the paper's objects have {plan.N_NODES} "
        "vertices)\n")
    monkeypatch.setattr(plan, "DENSE_FACES", 1280)
    assert invoke("plan", mesh, "--mass-kg", "0.1", "--png", tmp_path / "scan.png").stderr == ""
