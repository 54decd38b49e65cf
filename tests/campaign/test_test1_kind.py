"""The ``test1_bench`` kind on the engine: design, per-event records, finalize, schedule, ingest.

A reduced study (gel, specimens 1 and 11, normal-lab: 284 events, every block and every held-out
split) is run once per module through ``run_study``; its records are checked against the
in-process path (:func:`graspcampaign.rig.test1.run_virtual_bench`), which no engine code touches.
Ingest goes through the command line (``graspcampaign ingest``), one test per failure kind.
"""

from __future__ import annotations

import hashlib
import json
import re

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.kind import get_kind
from graspcampaign.campaign.kinds import test1 as K
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import kind_params, run_study, study_trials
from graspcampaign.cli.main import app
from graspcampaign.rig import test1 as T
from graspcampaign.rig.test1_fits import META_COLUMNS
from graspcampaign.rig.virtual import RigParams

SEED = 701  # campaigns/test1_bench.yaml
REDUCED = ["params.materials=[gel]", "params.specimens=[1,11]",
           "params.environments=[normal_lab]", "params.pso_restarts=3",
           "params.pso_particles=12", "params.pso_iterations=40", "params.pso_max_reruns=2"]
cli = CliRunner()


def _study(root, *extra, backend="sequential"):
    return compose_study("test1_bench", [f"runner.backend={backend}", "runner.progress=false",
                                         f"output.root={root}", *REDUCED, *extra])


@pytest.fixture(scope="module")
def engine(tmp_path_factory):
    root = tmp_path_factory.mktemp("t1")
    study = _study(root)
    summary = run_study(study)
    store = RunStore(summary.path)
    schedule = T.test1_schedule(SEED, materials=["gel"], specimens=[1, 11],
                                environments=["normal_lab"])
    ref = T.run_virtual_bench(schedule, SEED, keep_waveforms=True)
    return root, study, summary, store, store.read().to_pandas(), schedule, ref


def _fit_columns(ref_fits: pd.DataFrame) -> list[str]:
    return [c for c in ref_fits.columns if c not in META_COLUMNS and c != "source"]


def _assert_same_fits(records: pd.DataFrame, ref_fits: pd.DataFrame) -> None:
    """Same fitted values per event (None and NaN both mean 'not fitted in this block')."""
    ours = records.set_index("event_id").sort_index()
    ref = ref_fits.set_index("event_id").loc[ours.index]
    for c in _fit_columns(ref_fits):
        a, b = ours[c].astype(object), ref[c].astype(object)
        a, b = a.where(a.notna(), None), b.where(b.notna(), None)
        assert a.tolist() == b.tolist(), c


# ---------------------------------------------------------------------------- design


def test_design_is_the_schedule_one_trial_per_event(engine):
    _, study, summary, store, records, schedule, _ = engine
    assert summary.n_trials == len(schedule) == 284 and summary.n_error == 0
    kind = get_kind("test1_bench")
    trials = study_trials(study, kind, kind_params(study, kind))
    assert [t.factors["event_id"] for t in trials] == schedule["event_id"].tolist()
    for col in schedule.columns.drop("event_id"):  # records carry the whole commanded event
        pd.testing.assert_series_equal(
            records.set_index("event_id")[col].loc[schedule["event_id"]].reset_index(drop=True),
            schedule[col], check_names=False, check_dtype=False)
    assert (records["source"] == "virtual").all() and (records["kind"] == "test1_bench").all()
    # the indenter radius the records carry is the one the PSO fits converted lambda2 to C with
    # (C = 4 pi R lambda2, Eq. 14) and the one the virtual rig's contact model uses (Tests 2-3)
    runs = store.read("summary/pso_runs").to_pandas()
    fitted_mm = 1e3 * runs["c_n_s_per_m"] / (4 * np.pi * runs["lambda2"])
    assert records["indenter_radius_mm"].to_numpy() == pytest.approx(fitted_mm.iloc[0], rel=1e-12)
    assert fitted_mm.to_numpy() == pytest.approx(1e3 * RigParams().fingertip_radius, rel=1e-12)


def test_full_protocol_design_counts_and_retained_traces():
    study = compose_study("test1_bench")
    kind = get_kind("test1_bench")
    params = kind_params(study, kind)
    rows = K.design(study, params)
    assert len(rows) == 19168  # §7.1 completed events = planned events
    kept = [r for r in rows if K.retained(r, params)]
    assert len(kept) == 62  # the paper's workbook keeps 62 full traces
    blocks = pd.Series([r["block"] for r in kept]).value_counts()
    assert set(blocks.index) == set(T.BLOCKS)
    assert all(isinstance(v, (str, int, float)) for r in rows[:50] for v in r.values())


def test_params_are_validated_before_anything_runs(tmp_path):
    result = cli.invoke(app, ["run", "test1_bench", "params.materials=[rubber]",
                              f"output.root={tmp_path}"])
    assert result.exit_code == 2
    assert re.search(r"params\.materials\[0\] has unknown value 'rubber'; allowed values: gel",
                     result.stderr)
    assert not any(tmp_path.iterdir())
    result = cli.invoke(app, ["show", "test1_bench", "params.specimens=[1,13]"])
    assert result.exit_code == 2 and "params.specimens[1] = 13 is out of range" in result.stderr


def test_schedule_command_writes_the_commanded_sheet(tmp_path):
    result = cli.invoke(app, ["schedule", "test1_bench", *REDUCED, f"output.root={tmp_path}"])
    assert result.exit_code == 0, result.output
    sheet = pd.read_parquet(tmp_path / "test1_bench" / "schedule" / "sheet.parquet")
    ref = T.test1_schedule(SEED, materials=["gel"], specimens=[1, 11], environments=["normal_lab"])
    pd.testing.assert_frame_equal(sheet, ref)
    assert len(pd.read_csv(tmp_path / "test1_bench" / "schedule" / "sheet.csv")) == 284


# ------------------------------------------------------------------- engine = in-process


def test_engine_records_equal_the_in_process_fits(engine):
    *_, records, _, ref = engine
    assert (records["event_status"] == "completed").all()
    _assert_same_fits(records, ref.fits)


def test_attempt_log_equals_the_in_process_attempts(engine):
    _, _, _, store, records, _, ref = engine
    attempts = store.read("tables/attempts").to_pandas().sort_values(["event_id", "attempt"])
    want = ref.attempts.sort_values(["event_id", "attempt"])
    assert attempts["event_id"].tolist() == want["event_id"].tolist()
    assert attempts["attempt_status"].tolist() == want["status"].tolist()
    assert attempts["n_samples"].tolist() == want["n_samples"].tolist()
    per_event = records.set_index("event_id")
    counts = want.groupby("event_id").size()
    assert (per_event.loc[counts.index, "n_attempts"] == counts).all()


def test_retained_traces_are_the_in_process_waveforms(engine):
    _, _, _, store, records, _, ref = engine
    waves = store.read("tables/waveforms").to_pandas()
    kept = set(records.loc[records["trace_kept"].astype(bool), "event_id"])
    assert set(waves["event_id"]) == kept and len(kept) == 15  # one material: 15 events
    want = ref.waveforms[ref.waveforms["event_id"].isin(kept)]
    got = waves.sort_values(["event_id", "time_s"]).reset_index(drop=True)
    want = want.sort_values(["event_id", "time_s"]).reset_index(drop=True)
    for c in T.WAVEFORM_COLUMNS:
        assert got[c].tolist() == want[c].tolist(), c


def test_finalize_stores_the_study_level_tables(engine):
    _, _, _, store, records, schedule, ref = engine
    names = ("truths", "damage_depth", "pso_runs", "table5", "pso_transfer", "transfer")
    tables = {n: store.read(f"summary/{n}").to_pandas() for n in names}
    assert all(len(t) for t in tables.values())
    runs = tables["pso_runs"]
    assert runs["converged"].sum() >= 3 and len(runs) <= 3 + 2
    assert set(tables["table5"]["parameter"]) == {"lambda1", "lambda2", "n", "b", "k", "c"}
    # the damage depth and transfer errors are the in-process summaries of the same fits
    pd.testing.assert_frame_equal(tables["damage_depth"], T.damage_depths(ref.fits),
                                  check_dtype=False)
    want = T.transfer_errors(ref.fits, ref.waveforms)
    got = tables["transfer"].sort_values(["event_id", "quantity"]).reset_index(drop=True)
    want = want.sort_values(["event_id", "quantity"]).reset_index(drop=True)
    np.testing.assert_allclose(got["error_pct"], want["error_pct"], rtol=1e-12)
    assert set(tables["transfer"]["split"]) == set(T.SPLITS)
    # the truth per specimen is the virtual bench's
    pd.testing.assert_frame_equal(tables["truths"], ref.truths, check_dtype=False)


# ------------------------------------------------------------------------------- ingest


def _ingest(root, *files, extra=()):
    return cli.invoke(app, ["ingest", "test1_bench", *map(str, files), "--set",
                            f"output.root={root}", *[a for o in REDUCED for a in ("--set", o)],
                            *extra])


@pytest.fixture(scope="module")
def ingested(engine, tmp_path_factory):
    """The virtual waveforms of 6 events of every block (and cyclic cycle) written to CSV (half)
    and Parquet (half), ingested: every fit path, at a tenth of the cost of all 284 events."""
    root, *_, schedule, ref = engine
    folder = tmp_path_factory.mktemp("files")
    ids = sorted(schedule.groupby("block").head(6)["event_id"])
    first = ref.waveforms[ref.waveforms["event_id"].isin(ids[: len(ids) // 2])]
    second = ref.waveforms[ref.waveforms["event_id"].isin(ids[len(ids) // 2:])]
    first.to_csv(folder / "day1.csv", index=False)
    second.to_parquet(folder / "day2.parquet", index=False)
    result = _ingest(root, folder / "day1.csv", folder / "day2.parquet")
    assert result.exit_code == 0, result.output
    return root, folder, RunStore(root / "test1_bench" / "measured")


def test_ingest_gives_the_same_fits_as_the_in_process_path(engine, ingested):
    *_, records, _, ref = engine
    _, _, store = ingested
    measured = store.read().to_pandas()
    assert len(records) == 284 and len(measured) == 30
    assert sorted(measured["block"].unique()) == sorted(T.BLOCKS)
    _assert_same_fits(measured, ref.fits)
    assert (measured["indenter_radius_mm"] == records["indenter_radius_mm"].iloc[0]).all()  # the engine's
    # keyed by the engine's trial ids of the same planned events
    ids = records.set_index("event_id")["trial_id"]
    assert (measured.set_index("event_id")["trial_id"] == ids.loc[measured["event_id"]]
            .to_numpy()).all()
    # virtual-bench exports say so: never relabelled as hardware data
    assert (measured["source"] == "virtual").all() and (measured["status"] == "ok").all()
    assert json.loads(store.manifest_path.read_text())["source"] == "virtual"  # and so does the run


def _snapshot(root):
    return {p.relative_to(root).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(root.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def good_event(engine):
    *_, ref = engine
    wav = ref.waveforms
    eid = wav["event_id"].iloc[0]
    return wav[wav["event_id"] == eid].iloc[:40].reset_index(drop=True)


def _bad_unknown_event(df):
    df.loc[12, "event_id"] = "t1-000000000000"
    return df


def _bad_duplicate(df):
    return pd.concat([df.iloc[:30], df.iloc[[29]], df.iloc[30:]], ignore_index=True)


TEMPLATE = r" \(`graspcampaign schedule test1_bench --template` writes a sheet with every column\)\."
ATTEMPT = r"is not an attempt number \(an integer 1 to 99 counting the tries of the event\)\."
FAILURES = {
    "missing_column": (lambda d: d.drop(columns=["normal_force_n"]),
                       r"bad\.csv, header: a required column is missing: normal_force_n" + TEMPLATE),
    "missing_columns_all_named": (
        lambda d: d.drop(columns=["normal_force_n", "event_id", "tangential_displacement_mm"]),
        r"bad\.csv, header: required columns are missing: event_id, normal_force_n, "
        r"tangential_displacement_mm" + TEMPLATE),
    "wrong_unit_column": (lambda d: d.rename(columns={"displacement_mm": "displacement_m"}),
                          r"bad\.csv, header: 'displacement_m' has unit 'm' where "
                          r"'displacement_mm' \(mm\) is expected" + TEMPLATE),
    "attempt_not_an_integer": (lambda d: d.astype({"attempt": object}).assign(
        attempt=lambda x: x["attempt"].where(x.index != 2, "second")),
        r"bad\.csv, row 3, column 'attempt': value 'second' " + ATTEMPT),
    "attempt_negative": (lambda d: d.assign(attempt=-4),
                         r"bad\.csv, row 1, column 'attempt': value -4 " + ATTEMPT),
    "attempt_zero": (lambda d: d.assign(attempt=0), r"bad\.csv, row 1, column 'attempt': value 0 "
                                                    + ATTEMPT),
    "unknown_source": (lambda d: d.assign(source="bogus"),
                       r"bad\.csv, row 1, column 'source': value 'bogus' is not one of measured, "
                       r"virtual\."),
    "values_in_wrong_units": (lambda d: d.assign(normal_force_n=d["normal_force_n"] * 1e3),
                              r"bad\.csv, row \d+, column 'normal_force_n': value .* lies outside "
                              r"the 10 N load-cell range \(wrong units\?\)\."),
    "not_a_number": (lambda d: d.astype({"time_s": object}).assign(
        time_s=lambda x: x["time_s"].where(x.index != 3, "abc")),
        r"bad\.csv, row 4, column 'time_s': value 'abc' is not a number of "
        r"seconds\."),
    "not_finite": (lambda d: d.assign(tangential_force_n=d["tangential_force_n"].where(
        d.index != 7, np.inf)), r"bad\.csv, row 8, column 'tangential_force_n': value inf is "
                                r"not finite\."),
    "empty_value": (lambda d: d.assign(displacement_mm=d["displacement_mm"].where(
        d.index != 5, np.nan)), r"bad\.csv, row 6, column 'displacement_mm': value nan \(an "
                                r"empty cell or NaN\) is not finite\."),
    "time_not_increasing": (lambda d: d.assign(time_s=d["time_s"].where(
        d.index != 10, (d["time_s"].iloc[8] + d["time_s"].iloc[9]) / 2)),
        r"bad\.csv, row 11, column 'time_s': time .* does not increase within event "
        r"'t1-[0-9a-f]{12}' \(previous sample .* s\)\."),
    "unknown_event": (_bad_unknown_event, r"bad\.csv, row 13, column 'event_id': event id "
                                          r"'t1-000000000000' is not in the schedule\."),
    "empty_event_id": (lambda d: d.assign(event_id=d["event_id"].where(d.index != 2, "")),
                       r"bad\.csv, row 3, column 'event_id': event id is empty\."),
    "duplicate_sample": (_bad_duplicate, r"bad\.csv, row 31, column 'time_s': duplicate sample "
                                         r"of event .* \(first seen in row 30\)\."),
    "displacement_in_metres": (  # the tester's file: accepted with K = 17.9 instead of 0.548
        lambda d: d.assign(displacement_mm=d["displacement_mm"] / 1e3, tangential_displacement_mm=
                           d["tangential_displacement_mm"] / 1e3),
        r"bad\.csv, row \d+, column '(tangential_)?displacement_mm': event 't1-[0-9a-f]{12}' peaks "
        r"at .* mm where the schedule commands a (depth|stroke) of .* mm \(ratio 0\.00\d+, outside "
        r"1/3 to 3: wrong units\?\)\."),
}


@pytest.mark.parametrize("failure", sorted(FAILURES))
def test_malformed_file_is_rejected_and_nothing_changes(ingested, good_event, tmp_path, failure):
    root, _, _ = ingested
    make, message = FAILURES[failure]
    path = tmp_path / "bad.csv"
    make(good_event.copy()).to_csv(path, index=False)
    before = _snapshot(root)
    result = _ingest(root, path)
    assert result.exit_code == 2, result.output
    assert re.fullmatch(r"error: " + message + r"\n", result.stderr), result.stderr
    assert result.stderr.count("\n") == 1  # one sentence, no traceback
    assert _snapshot(root) == before


def test_unsupported_file_type_is_rejected(ingested, good_event, tmp_path):
    root, _, _ = ingested
    path = tmp_path / "bad.json"
    good_event.to_json(path)
    before = _snapshot(root)
    result = _ingest(root, path)
    assert result.exit_code == 2
    assert result.stderr == ("error: bad.json: unsupported file type '.json' "
                             "(expected .csv, .parquet or .xlsx).\n")
    assert _snapshot(root) == before


def test_an_event_in_two_files_is_rejected(good_event, tmp_path):
    root = tmp_path / "fresh"  # a new run: the event is stored nowhere yet
    good_event.to_csv(tmp_path / "a.csv", index=False)
    good_event.to_csv(tmp_path / "b.csv", index=False)
    result = _ingest(root, tmp_path / "a.csv", tmp_path / "b.csv")
    assert result.exit_code == 2
    assert re.fullmatch(r"error: b\.csv, row 1, column 'event_id': event 't1-[0-9a-f]{12}' is "
                        r"already in a\.csv \(one file per event\)\.\n", result.stderr)
    assert not root.exists() or _snapshot(root) == {}


def test_reingesting_a_stored_event_is_refused(ingested, good_event, tmp_path):
    root, folder, _ = ingested
    before = _snapshot(root)
    result = _ingest(root, folder / "day1.csv")
    assert result.exit_code == 2
    message = (r"error: day1\.csv, row 1, column 'event_id': event 't1-[0-9a-f]{12}' is already stored "
               r"in this run; measured records are never overwritten \(ingest a corrected file into "
               r"another run with --run\)\.\n")
    assert re.fullmatch(message, result.stderr), result.stderr
    assert _snapshot(root) == before


def test_a_file_without_source_is_labelled_measured(engine, good_event, tmp_path):
    _, study, *_ = engine
    # a rig's own file carries no source column: its fits are measured data
    path = tmp_path / "rig.csv"
    good_event.drop(columns=["source"]).to_csv(path, index=False)
    kind = get_kind("test1_bench")
    rows = K.ingest(study, kind_params(study, kind), [str(path)])
    assert len(rows) == 1 and rows[0]["source"] == "measured"


@pytest.mark.slow
def test_finalize_does_not_depend_on_the_worker_count(engine):
    # two workers: PSO runs as tasks, transfer errors in a thread meanwhile; same tables
    _, study, _, _, records, _, _ = engine
    params = kind_params(study, get_kind(study.kind))
    one = K.finalize(study, params, records)
    two = K.finalize(_study(study.output.root, "runner.n_jobs=2", backend="loky"),
                     params, records)
    assert list(one) == list(two)
    for name in one:
        pd.testing.assert_frame_equal(pd.DataFrame(one[name]), pd.DataFrame(two[name]))
