"""Bad input, round 11: what round 10 saw and left. A method factor no trial holds, a seed or a
task size past what the tools behind them take, an empty paper value, a path to read holding a
line break, a mesh saved as UTF-16, a row of only commas, the booleans a template promises.
Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import trimesh
from cli_checks import invoke, mesh_study, refused

T2 = ["--set", "params.fraction=0.06"]
T1 = ["--set", "params.materials=[gel]", "--set", "params.specimens=[1]", "--set",
      "params.environments=[normal_lab]"]


@pytest.mark.parametrize(("override", "name", "hint"), [
    # each was accepted: show printed the study, run ran it under a new config hash
    ("method_factors=[nosuch]", "nosuch", ""),
    ("method_factors=[planner,plannr]", "plannr", "did you mean 'planner'? "),
    # dynamic_check's own trial key, which a quasi_static trial does not hold
    ("method_factors=[planner,source_trial_id]", "source_trial_id", ""),
])
def test_a_method_factor_no_trial_holds_is_refused(results, override, name, hint):
    for command in ("show", "run"):
        refused(results, [command, "baseline_grid", override, "--root", results],
                f"method_factors names {name!r}, which is no factor and no key of a trial of kind "
                "'quasi_static', so it would change nothing but the config hash; "
                f"{hint}a method factor names a factor or trial key whose levels share one scene's "
                "random draws (this study's: mass_kg, mu, planner, shape).")


def test_a_method_factor_in_a_study_file_is_named_with_its_line(results, user_dir):
    path = mesh_study(user_dir, "method_factors: [nosuch]\nfactors:\n  shape: [sphere]\n  nodes: [144]\n")
    refused(results, ["show", path, "--root", results],
            f"{path}, line 5: method_factors names 'nosuch', which is no factor and no key of a "
            "trial of kind 'mesh_features', so it would change nothing but the config hash; a "
            "method factor names a factor or trial key whose levels share one scene's random "
            "draws (this study's: nodes, shape).")


@pytest.mark.parametrize(("override", "said"), [
    # accepted: schedule test2_grasp then failed with a traceback (OverflowError: Python int too
    # large to convert to C long); 2**32 fails the surrogate's scikit-learn models
    ("seed=12345678901234567890123", "seed = 12345678901234567890123 is out of range; allowed: "
     ">= 0 and <= 4294967295 (a 32-bit word, the seeds numpy's RandomState takes)."),
    ("seed=4294967296", "seed = 4294967296 is out of range; allowed: >= 0 and <= 4294967295 (a "
     "32-bit word, the seeds numpy's RandomState takes)."),
    # accepted: one task of every trial
    ("runner.batch_size=100000000000000000000", "runner.batch_size = 100000000000000000000 is out "
     "of range; allowed: >= 0 and <= 1000000 (a study holds at most 1,000,000 trials, "
     "docs/decisions.md)."),
    # accepted: show printed "paper: figure=, ..." and the run stored it
    ("paper.figure=", "campaigns/baseline_grid.yaml with override paper.figure=: paper.figure is "
     "empty; write the text the paper prints there."),
])
def test_a_seed_a_task_size_or_a_paper_text_past_what_it_takes_is_refused(results, override,
                                                                          said):
    for command in ("show", "run"):
        refused(results, [command, "baseline_grid", override, "--root", results], said)


def test_the_largest_seed_numpy_takes_is_accepted(results):
    import numpy as np
    from sklearn.utils import check_random_state

    check_random_state(2**32 - 1)  # the bound is numpy's, not ours
    with pytest.raises(ValueError, match="2\\*\\*32 - 1"):
        np.random.RandomState(2**32)
    done = invoke("show", "baseline_grid", f"seed={2**32 - 1}", "--root", results)
    assert done.exit_code == 0, done.output


@pytest.mark.parametrize(("args", "said"), [
    # each printed the path as it is, its line break splitting the sentence over two lines
    (["show", "{path}", "--root", "{root}"], "study file {path!r} does not exist; give a YAML file."),
    (["plan", "{path}", "--mass-kg", "0.1"],
     "{path!r} does not exist; give a mesh file (STL, OBJ or PLY)."),
    (["ingest", "test2_grasp", "{path}", "--root", "{root}"],
     "{path!r} does not exist; give a file of measured records (CSV, XLSX or Parquet)."),
])
def test_a_path_to_read_holding_a_line_break_is_named_quoted(results, tmp_path, args, said):
    suffix = {"show": ".yaml", "plan": ".obj", "ingest": ".csv"}[args[0]]
    path = str(tmp_path / f"no\nsuch{suffix}")
    refused(results, [arg.format(path=path, root=results) for arg in args], said.format(path=path))


@pytest.mark.parametrize(("file_type", "suffix", "encoding"), [
    # an OBJ was "is not an OBJ file: OBJ is text, but the file holds binary data", an ASCII STL
    # "its header declares 3,145,760 triangles ... as a binary STL", a PLY "cannot be read as PLY
    # (Not a ply file!)"
    ("obj", ".obj", "utf-16"), ("obj", ".obj", "utf-16-le"), ("stl_ascii", ".stl", "utf-16"),
    ("ply", ".ply", "utf-16"),
])
def test_a_text_mesh_saved_as_utf16_is_named_as_one(tmp_path, file_type, suffix, encoding):
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=40.0)
    text = sphere.export(file_type=file_type, encoding="ascii") if file_type == "ply" else \
        sphere.export(file_type=file_type)
    path = tmp_path / f"ball{suffix}"
    path.write_bytes((text.decode() if isinstance(text, bytes) else text).encode(encoding))
    refused(tmp_path, ["plan", path, "--mass-kg", "0.1"],
            f"mesh 'ball{suffix}' is UTF-16 text, not UTF-8; save it as UTF-8 (or ASCII) text.")


def _filled_sheet(tmp_path, rows: int = 2) -> pd.DataFrame:
    """The first ``rows`` rows of test2_grasp's measured-records template, filled in."""
    made = invoke("schedule", "test2_grasp", "params.fraction=0.06", "--template", "--out",
                  tmp_path / "sheet")
    assert made.exit_code == 0, made.output
    return pd.read_csv(tmp_path / "sheet-template.csv").iloc[:rows].assign(
        aborted=False, outcome="stable", success=True, stable=True, slip_flag=False,
        drop_flag=False, damage_flag=False, contact_loss_flag=False, peak_slip_mm=0.16,
        sf_actual=1.5, g_geo_actual=0.5).drop(columns=["abort_reason", "environment", "source"])


def test_a_row_of_only_commas_in_a_measured_csv_is_named_as_an_empty_row(results, tmp_path):
    # "day1.csv, row 2, column 'trial_id': trial id is empty."
    sheet = tmp_path / "day1.csv"
    lines = _filled_sheet(tmp_path).to_csv(index=False).splitlines(keepends=True)
    sheet.write_text("".join([*lines[:2], "," * (lines[0].count(",")) + "\n", *lines[2:]]))
    refused(results, ["ingest", "test2_grasp", sheet, *T2, "--root", results],
            "day1.csv, row 2 is empty; delete it.")


def test_a_row_of_only_commas_in_a_waveform_file_is_named_as_an_empty_row(results, tmp_path):
    # "waves.csv, row 3, column 'event_id': event id is empty."
    waves = pd.DataFrame({"event_id": "t1-49ea66f7c6ce", "time_s": np.arange(4) * 1e-2,
                          "displacement_mm": 0.5, "normal_force_n": 1.0,
                          "tangential_force_n": 0.0, "tangential_displacement_mm": 0.0})
    lines = waves.to_csv(index=False).splitlines(keepends=True)
    (tmp_path / "waves.csv").write_text("".join([*lines[:3], ",,,,,\n", *lines[3:]]))
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results],
            "waves.csv, row 3 is empty; delete it.")


def test_the_template_lists_every_boolean_word_ingest_reads(results, tmp_path):
    # the columns sheet said "true/false" while ingest also read yes/no, y/n, t/f and 1/0
    made = invoke("schedule", "test2_grasp", "params.fraction=0.06", "--template", "--out",
                  tmp_path / "sheet")
    assert made.exit_code == 0, made.output
    columns = pd.read_csv(next(tmp_path.glob("sheet-*columns*.csv")), dtype=str)
    allowed = set(columns.loc[columns["type"] == "bool", "allowed"])
    assert allowed == {"true/false, yes/no, y/n, t/f, 1/0"}
    words = [w for pair in allowed.pop().split(", ") for w in pair.split("/")]
    sheet = tmp_path / "day1.csv"
    table = _filled_sheet(tmp_path, rows=len(words))
    # every word the template names, in either case, is stored as the side of its pair it is
    truth = [i % 2 == 0 for i in range(len(words))]
    table = table.assign(slip_flag=[w.upper() if i % 3 else w for i, w in enumerate(words)])
    table.to_csv(sheet, index=False)
    done = invoke("ingest", "test2_grasp", sheet, *T2, "--root", results)
    assert done.exit_code == 0, done.output
    stored = pd.read_parquet(results / "test2_grasp" / "measured" / "records")
    stored = stored.set_index("rig_trial_id").loc[table["trial_id"]]
    assert stored["slip_flag"].tolist() == truth


RUNNER_KEYS = ("backend, n_jobs, address, batch_size, target_task_s, progress, progress_interval_s, "
               "connect_timeout_s")


@pytest.mark.parametrize(("word", "meant"), [
    # each drew "did you mean runner.progress?" (cores) or a name no one meant
    ("cores", "n_jobs"), ("workers", "n_jobs"), ("jobs", "n_jobs"), ("Threads", "n_jobs"),
    ("progres", "progress"),  # a typo is still answered by spelling
])
def test_a_word_of_another_tool_for_a_runner_key_is_answered_with_the_key(results, word, meant):
    refused(results, ["show", "smoke", f"+runner.{word}=2", "--root", results],
            f"runner.{word} is not a known key of runner (override '+runner.{word}=2' rejected); "
            f"did you mean runner.{meant}? known keys: {RUNNER_KEYS}.")
