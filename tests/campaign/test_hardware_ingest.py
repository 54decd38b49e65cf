"""Ingest of the ``test2_grasp`` measured records through the command line: the engine's records
exported and ingested under the same ids and source, re-runs and late attempts, files of another
source refused, one test per malformed-file kind (nothing stored changes).
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hardware_checks import REDUCED, TIMING, cli, same

from graspcampaign.campaign.kinds import hardware as H
from graspcampaign.campaign.records import RunStore
from graspcampaign.cli.main import app
from graspcampaign.rig.record_schema import record_columns


def _ingest(root, *files, study="test2_grasp", run="measured"):
    return cli.invoke(app, ["ingest", study, *map(str, files), "--run", run, "--set",
                            f"output.root={root}", *[a for o in REDUCED for a in ("--set", o)]])


def _snapshot(path):
    return sorted((p.relative_to(path).as_posix(), p.stat().st_size, p.stat().st_mtime_ns)
                  for p in path.rglob("*") if p.is_file())


@pytest.fixture(scope="module")
def t2_export(tmp_path_factory, study_run):
    root, summary = study_run("test2_grasp", *REDUCED)  # the run of `runs`, ingested beside it
    records = RunStore(summary.path).read().to_pandas()
    export = H.export_records(records, "test2_grasp")
    folder = tmp_path_factory.mktemp("t2files")
    half = len(export) // 2
    export.iloc[:half].to_csv(folder / "day1.csv", index=False)
    export.iloc[half:].to_parquet(folder / "day2.parquet", index=False)
    result = _ingest(root, folder / "day1.csv")
    assert result.exit_code == 0, result.output
    return root, folder, records, export, RunStore(root / "test2_grasp" / "measured")


def test_ingest_stores_the_engine_records_under_the_same_ids(t2_export):
    root, folder, records, export, store = t2_export
    result = _ingest(root, folder / "day2.parquet", run="all")
    assert result.exit_code == 0, result.output
    result = _ingest(root, folder / "day1.csv", run="all")
    assert result.exit_code == 0, result.output
    got = RunStore(root / "test2_grasp" / "all").read().to_pandas()
    assert len(got) == len(records) and set(got["trial_id"]) == set(records["trial_id"])
    a = records.set_index("trial_id").sort_index()
    b = got.set_index("trial_id").sort_index()
    skip = TIMING | {"status", "error_type", "error_message", "abort_reason", "environment"}
    for col in sorted((set(a.columns) & set(b.columns)) - skip):
        assert same(a[col], b[col]), col
    assert (b["source"] == "virtual").all()  # the files say what they are
    assert record_columns("test2_grasp")[0] == "trial_id" == export.columns[0]


def _listed_source(root, run):
    """The source column of ``run``'s row in the root's index page."""
    from graspcampaign.report.build import build_reports

    assert not build_reports(["test2_grasp"], run=run, root=root, formats=["md"]).failed
    index = (Path(root) / "index.md").read_text()
    return re.search(rf"^\| test2_grasp \| \[{run}\]\([^)]*\) \| ([^|]+) \|", index, re.M)[1]


def test_a_virtual_rigs_exports_are_stored_and_listed_as_virtual(t2_export, tmp_path):
    """The exports say source = virtual in every row: the manifest, the ingest message, status
    and the index say what the records are, never "measured"."""
    root, folder, *_ = t2_export
    result = _ingest(root, folder / "day2.parquet", run="exported")
    assert result.exit_code == 0, result.output
    n = len(pd.read_parquet(folder / "day2.parquet"))
    path = Path(root) / "test2_grasp" / "exported"
    assert result.stdout == (f"{n} virtual-rig records (source = virtual: exports, not rig "
                             f"measurements) stored in {path}\n")
    assert json.loads((path / "manifest.json").read_text())["source"] == "virtual"
    status = cli.invoke(app, ["status", "test2_grasp", "--run", "exported", "--root", str(root)])
    assert "\nsource: virtual\n" in status.stdout, status.output
    assert _listed_source(root, "exported") == "VIRTUAL RIG (synthetic data)"
    # a second file goes into the same run (ingest's, not `run`'s), and a rig's is still refused
    assert _ingest(root, folder / "day1.csv", run="exported").exit_code == 0
    refused = cli.invoke(app, ["run", "test2_grasp", "--root", str(root), "--run", "exported",
                               *REDUCED, "runner.progress=false"])
    assert refused.exit_code == 2 and "holds virtual records (ingested)" in refused.stderr


def test_an_older_ingest_of_exports_is_shown_by_its_records(t2_export, tmp_path):
    """A run stored before the manifest said virtual (manifest: measured, records: virtual)."""
    root, folder, *_ = t2_export
    assert _ingest(root, folder / "day1.csv", run="older").exit_code == 0
    manifest = Path(root) / "test2_grasp" / "older" / "manifest.json"
    manifest.write_text(manifest.read_text().replace('"source": "virtual"', '"source": "measured"'))
    status = cli.invoke(app, ["status", "test2_grasp", "--run", "older", "--root", str(root)])
    assert "\nsource: virtual\n" in status.stdout, status.output
    assert _listed_source(root, "older") == "VIRTUAL RIG (synthetic data)"


def test_an_unforeseen_rerun_gets_its_own_trial(t2_export, tmp_path):
    root, _, records, export, _ = t2_export
    plain = records[~records["rig_fault"].astype(bool) & (records["attempt"] == 1)].iloc[0]
    row = export[export["trial_id"] == plain[H.SHEET_ID]].iloc[0]
    aborted = {c: None for c in export.columns} | {"trial_id": row["trial_id"], "aborted": True,
                                                   "outcome": "aborted", "source": "virtual"}
    rerun = row.to_dict() | {"trial_id": f"{plain['slot_id']}-a2"}
    pd.DataFrame([aborted, rerun]).to_csv(tmp_path / "rerun.csv", index=False)
    result = _ingest(root, tmp_path / "rerun.csv", run="rerun")
    assert result.exit_code == 0, result.output
    got = RunStore(root / "test2_grasp" / "rerun").read().to_pandas().set_index(H.SHEET_ID)
    assert got.loc[rerun["trial_id"], "attempt"] == 2
    assert got.loc[rerun["trial_id"], "trial_id"] not in set(records["trial_id"])
    assert got.loc[row["trial_id"], "trial_id"] == plain["trial_id"]


def test_a_late_second_executed_attempt_of_a_stored_slot_is_refused(t2_export, tmp_path):
    """A re-run of a slot whose executed record an earlier ingest call stored (day1.csv)."""
    root, folder, records, export, store = t2_export
    day1 = set(pd.read_csv(folder / "day1.csv")["trial_id"])
    done = records[records[H.SHEET_ID].isin(day1) & ~records["aborted"].astype(bool)].iloc[0]
    row = export[export["trial_id"] == done[H.SHEET_ID]].iloc[0]
    late = f"{done['slot_id']}-a9"
    pd.DataFrame([row.to_dict() | {"trial_id": late}]).to_csv(tmp_path / "late.csv", index=False)
    before = _snapshot(store.path)
    result = _ingest(root, tmp_path / "late.csv")
    assert result.exit_code == 2, result.output
    assert re.search(rf"^error: late\.csv, row 1, column 'aborted': slot '{done['slot_id']}' "
                     rf"already has an executed record in the run's stored records \(trial "
                     rf"'{done[H.SHEET_ID]}'\)\.$", result.stderr, re.M), result.stderr
    assert _snapshot(store.path) == before
    # the same file into a run without that slot's record is accepted
    assert _ingest(root, tmp_path / "late.csv", run="late").exit_code == 0


def test_records_of_another_source_are_refused_in_a_run(t2_export, tmp_path):
    """The run holds virtual-rig exports (day1.csv): a rig's own file (no source column, so
    measured) is not pooled with them."""
    root, folder, _, export, store = t2_export
    day1 = set(pd.read_csv(folder / "day1.csv")["trial_id"])
    new = export[~export["trial_id"].isin(day1)].iloc[:2].drop(columns="source")
    new.to_csv(tmp_path / "rig.csv", index=False)
    before = _snapshot(store.path)
    result = _ingest(root, tmp_path / "rig.csv")
    assert result.exit_code == 2, result.output
    assert result.stderr == ("error: rig.csv, row 1, column 'source': value 'measured' differs from "
                             "'virtual' in the run's stored records; a run holds the records of one "
                             "source (measured or virtual): ingest the others into another run with "
                             "--run.\n")
    assert _snapshot(store.path) == before
    assert _ingest(root, tmp_path / "rig.csv", run="rig").exit_code == 0


def test_files_of_two_sources_in_one_ingest_are_refused(t2_export, tmp_path):
    """Each file holds one source; the second file, of the other source, is named at its row 1."""
    root, folder, _, export, _ = t2_export
    day1 = set(pd.read_csv(folder / "day1.csv")["trial_id"])
    new = export[~export["trial_id"].isin(day1)]
    new.iloc[:2].to_csv(tmp_path / "exported.csv", index=False)
    new.iloc[2:4].drop(columns="source").to_csv(tmp_path / "rig.csv", index=False)
    result = _ingest(root, tmp_path / "exported.csv", tmp_path / "rig.csv", run="mixed")
    assert result.exit_code == 2, result.output
    assert result.stderr == ("error: rig.csv, row 1, column 'source': value 'measured' differs from "
                             "'virtual' in exported.csv, row 1; a run holds the records of one "
                             "source (measured or virtual): ingest the others into another run with "
                             "--run.\n")
    assert not list(Path(root).rglob("mixed"))


TEMPLATE = (r" \(`graspcampaign schedule <study> --template` writes a sheet with every "
            r"column\)\.")
OUTCOMES = ("stable, success, partial, failure_slip, failure_drop, failure_damage, "
            "failure_contact_loss, aborted")


def _bad(export: pd.DataFrame, kind: str, folder, store):
    """A malformed measured-records file of one failure kind; returns (paths, whole message)."""
    ex = export[~export["aborted"].astype(bool)].reset_index(drop=True)
    df = ex.copy()
    path = folder / f"{kind}.csv"
    at = rf"{kind}\.csv, "
    if kind == "file_type":
        path = folder / "records.txt"
        path.write_text("trial_id\n")
        return [path], (r"records\.txt: unsupported file type '\.txt' "
                        r"\(expected \.csv, \.parquet or \.xlsx\)\.")
    if kind == "missing_file":
        missing = folder / "nowhere.csv"
        return [missing], re.escape(f"{missing} does not exist; give a file of measured records "
                                    "(CSV, XLSX or Parquet).")
    if kind == "corrupt":
        path = folder / "broken.parquet"
        path.write_bytes(b"PAR1 not really parquet")
        return [path], (r"broken\.parquet: the file cannot be read as parquet \(ArrowInvalid\); it "
                        r"is damaged or incomplete \(a copy cut short\?\): copy or save it again\.")
    if kind == "no_rows":
        df = df.iloc[:0]
        msg = at + r"header, column 'trial_id': the file has no data rows\."
    elif kind == "missing_column":
        df = df.drop(columns=["sf_actual"])
        msg = at + r"header: a required column is missing: sf_actual" + TEMPLATE
    elif kind == "missing_columns_all_named":
        df = df.drop(columns=["sf_actual", "outcome", "stable"])
        msg = at + r"header: required columns are missing: outcome, stable, sf_actual" + TEMPLATE
    elif kind == "wrong_unit":
        df = df.rename(columns={"peak_slip_mm": "peak_slip_m"})
        msg = at + r"header: 'peak_slip_m' has unit 'm' where 'peak_slip_mm' \(mm\) is expected" \
            + TEMPLATE
    elif kind == "empty_id":
        df.loc[2, "trial_id"] = ""
        msg = at + r"row 3, column 'trial_id': trial id is empty\."
    elif kind == "unknown_id":
        df.loc[1, "trial_id"] = "t2A-sphere-01-prop-0000000000"
        msg = at + (r"row 2, column 'trial_id': trial id 't2A-sphere-01-prop-0000000000' is not "
                    r"in the schedule\.")
    elif kind == "duplicate":
        df = pd.concat([df, df.iloc[[0]]], ignore_index=True)
        msg = at + (rf"row {len(df)}, column 'trial_id': duplicate trial id '[^']+' \(first seen "
                    r"in row 1\)\.")
    elif kind == "not_boolean":
        df["aborted"] = df["aborted"].astype(object)
        df.loc[0, "aborted"] = "maybe"
        msg = at + (r"row 1, column 'aborted': value 'maybe' is not a boolean \(true/false, yes/no, "
                    r"y/n, t/f, 1/0\)\.")
    elif kind == "not_number":
        df["normal_force_1_n"] = df["normal_force_1_n"].astype(object)
        df.loc[0, "normal_force_1_n"] = "1,5"
        msg = at + (r"row 1, column 'normal_force_1_n': value '1,5' is not a number \(a decimal "
                    r"comma: save the sheet with a decimal point '\.'\)\.")
    elif kind == "not_finite":
        df.loc[0, "g_geo_actual"] = math.inf
        msg = at + r"row 1, column 'g_geo_actual': value 'inf' is not finite\."
    elif kind == "out_of_range":
        df.loc[0, "deformation_1_mm"] = 120.0
        msg = at + (r"row 1, column 'deformation_1_mm': value 120 lies outside \[0, 50\] mm "
                    r"\(wrong units\?\)\.")
    elif kind == "bad_choice":
        df.loc[0, "outcome"] = "wobbled"
        msg = at + rf"row 1, column 'outcome': value 'wobbled' is not one of {OUTCOMES}\."
    elif kind == "unknown_source":
        df.loc[0, "source"] = "bogus"
        msg = at + r"row 1, column 'source': value 'bogus' is not one of measured, virtual\."
    elif kind == "required_empty":
        df.loc[0, "sf_actual"] = None
        msg = at + (r"row 1, column 'sf_actual': value is empty but the trial was executed "
                    r"\(aborted is false\)\.")
    elif kind == "inconsistent":
        i = int(np.flatnonzero(df["outcome"].isin(["stable", "success"]))[0])
        df.loc[i, "success"] = False
        msg = at + (rf"row {i + 1}, column 'success': success is False but outcome is "
                    r"'(stable|success)' \(success means outcome stable or success, §8\.1\)\.")
    elif kind == "missing_flag":
        i = int(np.flatnonzero(df["outcome"] == "failure_drop")[0])
        df.loc[i, "drop_flag"] = False
        msg = at + (rf"row {i + 1}, column 'drop_flag': outcome is 'failure_drop' but drop_flag "
                    r"is false \(every failure class carries its flag, §8\.1\)\.")
    elif kind == "slot_twice":
        extra = df.iloc[[0]].assign(trial_id=lambda d: d["trial_id"] + "-a2")
        df = pd.concat([df, extra], ignore_index=True)
        msg = at + (rf"row {len(df)}, column 'aborted': slot '[^']+' already has an executed "
                    r"record in row 1; only one attempt per slot may be executed\.")
    elif kind == "across_files":
        df.iloc[:3].to_csv(folder / "a.csv", index=False)
        df.iloc[2:5].to_parquet(folder / "b.parquet", index=False)
        return [folder / "a.csv", folder / "b.parquet"], \
            r"b\.parquet, row 1, column 'trial_id': trial '[^']+' is already in a\.csv \(one " \
            r"record per trial\)\."
    elif kind == "already_stored":
        df = export.iloc[:2]
        msg = at + (r"row 1, column 'trial_id': trial '[^']+' is already stored in this run; measured "
                    r"records are never overwritten \(ingest a corrected file into another run with "
                    r"--run\)\.")
    else:
        raise AssertionError(kind)
    df.to_csv(path, index=False)
    return [path], msg


FAILURES = ("file_type", "missing_file", "corrupt", "no_rows", "missing_column",
            "missing_columns_all_named", "wrong_unit", "empty_id", "unknown_id", "duplicate",
            "not_boolean", "not_number", "not_finite", "out_of_range", "bad_choice",
            "unknown_source", "required_empty", "inconsistent", "missing_flag", "slot_twice",
            "across_files", "already_stored")


@pytest.mark.parametrize("kind", FAILURES)
def test_malformed_files_are_rejected_and_nothing_changes(t2_export, kind, tmp_path):
    root, _, _, export, store = t2_export
    before = _snapshot(root)
    files, message = _bad(export, kind, tmp_path, store)
    result = _ingest(root, *files)
    assert result.exit_code == 2, result.output
    assert re.fullmatch(f"error: {message}\n", result.stderr), result.stderr
    assert _snapshot(root) == before
