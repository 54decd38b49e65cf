"""Damaged and mismatched manifests: exit 2, the whole one-sentence message, nothing stored
changed, whichever command reads the run.

A damaged or missing ``manifest.json``; a manifest that describes another run than the one
stored; a file in place of the run directory; a run refused before it starts; ``run`` and
``ingest`` never writing into each other's runs. Every case damages its own copy of the finished
runs (``results`` in conftest.py).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pyarrow.parquet as pq
import pytest
from cli_checks import BG, SMOKE, grid_run, invoke, refused, replaced


# -- 2. a damaged manifest ----------------------------------------------------------------------------
def _json_error(text: str) -> str:
    try:
        json.loads(text)
    except json.JSONDecodeError as exc:
        return f"not valid JSON: {exc.msg} (line {exc.lineno}, column {exc.colno})"
    raise AssertionError(text)


def _manifest(results: Path) -> dict:
    return json.loads((grid_run(results) / "manifest.json").read_text())


def refused_by_every_command(results, message: str) -> None:
    """status, show, report and run of the damaged baseline_grid run each refuse with ``message``."""
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["report", "baseline_grid"], ["run", "baseline_grid", *BG]):
        refused(results, [*args, "--root", results], message)


MANIFESTS = {
    "truncated": (lambda m: json.dumps(m, indent=2)[:300], None),
    "garbled": (lambda m: json.dumps(m).encode()[:40] + b"\xff\xfe" + json.dumps(m).encode()[42:],
                "not UTF-8 text: byte 40 is 0xff"),
    "zero_bytes": (lambda m: b"", "it is empty"),
    "a_list": (lambda m: "[1, 2]", "it holds a JSON list, not an object of the run's fields"),
    "n_trials_many": (lambda m: json.dumps({**m, "n_trials": "many"}),
                      'n_trials is "many", not a whole number of trials'),
    "config_hash_null": (lambda m: json.dumps({**m, "config_hash": None}),
                         "config_hash is null, not a hash"),
    "no_sessions": (lambda m: json.dumps({k: v for k, v in m.items() if k != "sessions"}),
                    "it has no sessions field"),
    # a run that counts its records or is finished was written by a session: none listed is damage
    "empty_sessions": (lambda m: json.dumps({**m, "sessions": []}),
                       "sessions is [], but a run with n_recorded or finished_at has had at least "
                       "one session"),
    # a byte order mark is skipped; a byte that is not UTF-8 is still named where it is in the file
    "garbled_after_bom": (lambda m: b"\xef\xbb\xbf" + json.dumps(m).encode()[:40] + b"\xff"
                          + json.dumps(m).encode()[41:], "not UTF-8 text: byte 43 is 0xff"),
    # status once reported such a run's source as null, then as "simulation" (the report's
    # fallback): neither, the run is refused as every command refuses it (docs/decisions.md)
    "no_source": (lambda m: json.dumps({k: v for k, v in m.items() if k != "source"}),
                  "it has no source field"),
}


@pytest.mark.parametrize("case", sorted(MANIFESTS))
def test_a_damaged_manifest_is_refused_by_every_command(results, case):
    make, why = MANIFESTS[case]
    text = make(_manifest(results))
    path = grid_run(results) / "manifest.json"
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text)
    why = why or _json_error(text)
    message = (f"run baseline_grid/default at {grid_run(results)} has a damaged manifest.json ({why}); "
               "its records cannot be checked without it, so restore the file from a backup or "
               "move the run directory aside and run the study again.")
    refused_by_every_command(results, message)


def test_a_manifest_with_a_byte_order_mark_reads_as_the_same_manifest(results):
    """A manifest re-saved by an editor that adds a UTF-8 byte order mark holds the same fields:
    every command reads it as before (it was refused in Python's words, "Unexpected UTF-8 BOM
    (decode using utf-8-sig)")."""
    path = grid_run(results) / "manifest.json"
    before = invoke("status", "baseline_grid", "--root", results)
    path.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    after = invoke("status", "baseline_grid", "--root", results)
    assert before.exit_code == after.exit_code == 0, after.output
    assert after.stdout == before.stdout and after.stderr == ""
    assert invoke("report", "baseline_grid", "--root", results).exit_code == 0


def test_an_unfinished_run_of_a_version_that_listed_sessions_at_their_end_is_read(results):
    """Versions before the integrity checks stored a new run's manifest with no session until its
    first session ended: such a run, interrupted (no n_recorded, not finished), is no damage."""
    path = grid_run(results) / "manifest.json"
    manifest = json.loads(path.read_text())
    del manifest["n_recorded"]
    path.write_text(json.dumps({**manifest, "sessions": [], "finished_at": None}, indent=2))
    shown = invoke("status", "baseline_grid", "--root", results)
    assert shown.exit_code == 0 and shown.stderr == "", shown.output


# -- 3 (and 2, 4). stored files not what the manifest says, or none; a run refused before it starts
def test_records_without_a_manifest_are_refused_alike_by_every_command(results):
    (grid_run(results) / "manifest.json").unlink()
    message = (f"run baseline_grid/default at {grid_run(results)} has stored files but no "
               "manifest.json, so what they hold cannot be checked; restore the file from a "
               "backup, or move the run directory aside and run the study again.")
    refused_by_every_command(results, message)


def test_a_run_refused_before_it_starts_writes_nothing(results, monkeypatch):
    import contextlib

    from graspcampaign.campaign import runner as runner_module
    from graspcampaign.errors import UserInputError

    @contextlib.contextmanager
    def unreachable(study):  # what an unreachable Dask scheduler does, without the wait
        raise UserInputError("runner.address = 'tcp://127.0.0.1:9': no Dask scheduler answered.")
        yield

    monkeypatch.setattr(runner_module, "_executor", unreachable)
    message = "runner.address = 'tcp://127.0.0.1:9': no Dask scheduler answered."
    refused(results, ["run", "smoke", *SMOKE, "--run", "fresh", "--root", results], message)
    refused(results, ["run", "baseline_grid", *BG, "--root", results], message)
    assert not (results / "smoke" / "fresh").exists()


def test_a_run_this_user_may_not_write_is_refused_before_its_backend_starts(results, monkeypatch):
    """The write check ran in the run's lock, before a Dask cluster was started or its scheduler awaited;
    moved after the manifest is read (round 19), it ran after the backend had started: an unwritable
    run with an unreachable scheduler was refused for the scheduler, after its wait."""
    import contextlib

    from graspcampaign.campaign import runner as runner_module
    from graspcampaign.core.words import PERMISSION_DENIED
    from graspcampaign.errors import UserInputError

    @contextlib.contextmanager
    def unreachable(study):  # what an unreachable Dask scheduler does, without the wait
        raise UserInputError("runner.address = 'tcp://127.0.0.1:9': no Dask scheduler answered.")
        yield

    monkeypatch.setattr(runner_module, "_executor", unreachable)
    run = results / "smoke" / "fresh"
    monkeypatch.setattr(runner_module, "write_denied",  # root may write anywhere: another user's run
                        lambda where: f"cannot be written by this user: {PERMISSION_DENIED}"
                        if Path(where) == run else None)
    refused(results, ["run", "smoke", *SMOKE, "--run", "fresh", "--root", results],
            f"run smoke/fresh at {run}: {run}: cannot be written by this user: {PERMISSION_DENIED}.")
    assert not run.exists()


def _config_edited(m: dict) -> dict:
    config = json.loads(json.dumps(m["config"]))
    config["factors"]["mu"] = [0.4]
    return {**m, "config": config}


_RESTORE = "restore the file from a backup"
#: manifest edits that make it describe another run than the one stored, and why that is seen
MISMATCHES = {
    "source_measured": (lambda m: {**m, "source": "measured"},
                        "source is 'measured', but trial kind quasi_static makes simulation records",
                        _RESTORE),
    "study_renamed": (lambda m: {**m, "study": "shapes"},
                      "study is 'shapes', but the run is stored as baseline_grid/default",
                      f"{_RESTORE}, or put a moved run directory back as shapes/default"),
    "run_renamed": (lambda m: {**m, "run": "other"},
                    "run is 'other', but the run is stored as baseline_grid/default",
                    f"{_RESTORE}, or put a moved run directory back as baseline_grid/other"),
    "kind_changed": (lambda m: {**m, "kind": "mesh_features"},
                     "kind is 'mesh_features', but its config says 'quasi_static'", _RESTORE),
    "fewer_trials": (lambda m: {**m, "n_trials": 1},
                     "n_trials is 1, but it stores 2 trials of its one config", _RESTORE),
    "more_trials": (lambda m: {**m, "n_trials": 5},
                    "n_trials is 5, but the finished run stores 2 trials of its one config",
                    _RESTORE),
    "config_edited": (_config_edited, None, _RESTORE),
}


@pytest.mark.parametrize("case", sorted(MISMATCHES))
def test_a_manifest_that_does_not_describe_its_run_is_refused_by_every_command(results, case):
    edit, why, advice = MISMATCHES[case]
    path = grid_run(results) / "manifest.json"
    manifest = json.loads(path.read_text())
    path.write_text(json.dumps(edit(manifest), indent=2))
    if why is None:  # the hash of the edited config, as composing that config gives it
        from graspcampaign.campaign.compose import compose_study
        from graspcampaign.campaign.provenance import config_hash

        edited = config_hash(compose_study("baseline_grid", replaced(BG, "mu=[0.4]")))
        why = f"config_hash is {manifest['config_hash']}, but its config hashes to {edited}"
    message = (f"run baseline_grid/default at {grid_run(results)} has a manifest.json that does not "
               f"match the run ({why}); {advice}.")
    refused_by_every_command(results, message)


def test_a_session_that_names_no_config_is_not_held_to_the_runs_one_config(results):
    """A session of an earlier ``ingest`` named no config: it may have run another design, so the
    manifest's n_trials is not the count of a run under one config (integrity, as status counts)."""
    path = grid_run(results) / "manifest.json"
    manifest = json.loads(path.read_text())
    earlier = {k: v for k, v in manifest["sessions"][0].items() if k != "config_hash"}
    path.write_text(json.dumps({**manifest, "n_trials": 5,
                                "sessions": [*manifest["sessions"], earlier]}, indent=2))
    status = invoke("status", "baseline_grid", "--json", "--root", results)
    assert status.exit_code == 0, status.output
    assert json.loads(status.stdout)["n_recorded"] == len(pq.read_table(
        grid_run(results) / "records", columns=["trial_id"]))


def test_a_file_in_place_of_the_run_directory_is_refused_by_every_command(results):
    shutil.rmtree(grid_run(results))
    grid_run(results).write_text("not a run")
    message = (f"run baseline_grid/default at {grid_run(results)} is a file, not a run directory; "
               "move it aside or choose another run name (--run NAME).")
    refused_by_every_command(results, message)


def test_run_never_writes_into_measured_records_nor_ingest_into_simulated_ones(results, tmp_path):
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.provenance import new_manifest, write_manifest

    # a protocol's runs as `ingest` (measured) and `run` (the virtual rig) start them
    study = compose_study("test2_grasp", [f"output.root={results}"])
    for run, source in (("measured", "measured"), ("default", "virtual")):
        write_manifest(results / "test2_grasp" / run / "manifest.json",
                       new_manifest(study, run, 10, source))
    refused(results, ["run", "test2_grasp", "--run", "measured", "--root", results],
            f"run test2_grasp/measured at {results / 'test2_grasp' / 'measured'} holds measured "
            "records (ingested); `run` never adds simulated or virtual trials to them, so choose "
            "another run name (--run NAME).")
    sheet = tmp_path / "m.csv"
    sheet.write_text("trial_id\n")
    refused(results, ["ingest", "test2_grasp", sheet, "--run", "default", "--root", results],
            f"run test2_grasp/default at {results / 'test2_grasp' / 'default'} holds virtual "
            "records (from `graspcampaign run`); measured records are stored in a run of their "
            "own, so choose another run name (--run NAME; default measured).")
