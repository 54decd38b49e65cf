"""Bad input, round 12 (a fresh adversary): what stored wrong data, lost records or printed a
traceback. Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored
changed (``refused``; for Tests 2-3 on a run that already holds records, ``stored``)."""

from __future__ import annotations

import pandas as pd
import pytest
from cli_checks import T2, filled_records, invoke, refused


def test_a_number_with_an_underscore_in_a_measured_cell_is_refused(stored, tmp_path):
    # the old code stored sf_actual '1_4' as 14.0 (Python's float reads '_' as digit grouping)
    frame = filled_records(tmp_path, rows=slice(2, 4)).astype({"sf_actual": object})
    frame.loc[1, "sf_actual"] = "1_4"
    frame.to_csv(tmp_path / "day2.csv", index=False)
    refused(stored, ["ingest", "test2_grasp", tmp_path / "day2.csv", *T2, "--root", stored],
            "day2.csv, row 2, column 'sf_actual': value '1_4' is not a number.")


def test_records_on_a_second_sheet_of_a_workbook_are_named_not_left_unread(stored, tmp_path):
    # the old code stored the first sheet's two trials and said nothing of the second sheet's
    book = tmp_path / "days.xlsx"
    with pd.ExcelWriter(book) as writer:
        filled_records(tmp_path, rows=slice(2, 4)).to_excel(writer, sheet_name="day2", index=False)
        filled_records(tmp_path, rows=slice(4, 6)).to_excel(writer, sheet_name="day3", index=False)
    refused(stored, ["ingest", "test2_grasp", book, *T2, "--root", stored],
            "days.xlsx, header: sheet 'day3' holds records too (every required column, rows "
            "below it), but ingest reads only the workbook's first sheet, so they would not be "
            "stored: save each sheet as a CSV file and ingest the files together, or move the "
            "rows to the first sheet (`graspcampaign schedule <study> --template` writes a sheet "
            "with every column).")
    with pd.ExcelWriter(book) as writer:  # a blank template kept behind the records holds none
        filled_records(tmp_path, rows=slice(2, 4)).to_excel(writer, sheet_name="day2", index=False)
        filled_records(tmp_path, rows=slice(0, 0)).to_excel(writer, sheet_name="blank", index=False)
    done = invoke("ingest", "test2_grasp", book, *T2, "--root", stored)
    assert done.exit_code == 0, done.output


def test_negative_zero_is_the_level_zero_so_listing_both_is_refused(tmp_path):
    # the old code took 0.0 and -0.0 for two levels (their reprs differ): two trials of one scene
    for command in ("show", "run"):
        refused(tmp_path, [command, "wrench_balance", "factors.mu=[0.0,-0.0]", "--root", tmp_path],
                "factors.mu lists the level 0.0 twice (factors.mu[0] and factors.mu[1]); give each "
                "level once.")


NAME_SAID = ("a name in it is 300 bytes long, more than the 255 a file system takes for one file "
             "or directory name; give a shorter one.")


def _cut(path) -> str:
    """``path`` as a message shows a value over 200 characters: its first 60 and its length."""
    text = str(path)
    return f"{text[:60]}... ({len(text)} characters)"


@pytest.mark.parametrize("command", [["run", "smoke"], ["status", "smoke"], ["report"]])
def test_a_results_root_with_a_name_over_255_bytes_is_refused_before_any_work(tmp_path, command):
    # the old code ended in a traceback (OSError: [Errno 36] File name too long)
    root = tmp_path / ("b" * 300)
    refused(tmp_path, [*command, "--root", root], f"--root {_cut(root)}: {NAME_SAID}")


def test_an_output_file_with_a_name_over_255_bytes_is_refused_before_any_work(tmp_path, sphere):
    # the old code: schedule and plan ended in a traceback; reproduce ran every study (hours at
    # paper scale) and would have failed appending its first time
    out = tmp_path / ("b" * 296)  # with .txt or .png: 300 bytes
    refused(tmp_path, ["schedule", "test2_grasp", "--out", f"{out}bbbb", "--root", tmp_path],
            f"--out {_cut(f'{out}bbbb')}: {NAME_SAID}")
    refused(tmp_path, ["reproduce", "--times", f"{out}.txt", "--root", tmp_path],
            f"--times {_cut(f'{out}.txt')}: {NAME_SAID}")
    refused(tmp_path, ["plan", sphere, "--mass-kg", "0.1", "--png", f"{out}.png"],
            f"--png {_cut(f'{out}.png')}: {NAME_SAID}")  # named as --out and --times are (round 18)


@pytest.mark.parametrize(("override", "said"), [
    # the old code said "got None" of a mapping merged into a factor's list of levels
    ("factors.mu={a:1}", "factors.mu takes a list of levels, e.g. factors.mu=[0.3,0.5] (or the "
     "bare mu=0.3), got a mapping."),
    # it said "must be a list." naming nothing given
    ("zip={a:1}", "zip must be a list, got a mapping."),
])
def test_a_mapping_where_a_list_belongs_is_named_a_mapping_not_none(tmp_path, override, said):
    refused(tmp_path, ["show", "wrench_balance", override, "--root", tmp_path], said)


@pytest.mark.parametrize(("override", "said"), [
    # each said "<section> is neither a known key of the study config nor a factor of this
    # study ...; did you mean '<section>'?": the section itself, which is known
    ("runner={nosuch:1}", "runner.nosuch is not a known key of runner (override "
     "'runner={nosuch:1}' rejected); known keys: backend, n_jobs, address, batch_size, "
     "target_task_s, progress, progress_interval_s, connect_timeout_s."),
    ("paper={figure:x,a:1}", "paper.a is not set by this study (override 'paper={figure:x,a:1}' "
     "rejected); add it with a leading '+' (+paper.a=...), and the study's paper schema checks "
     "it."),
    ("factors={mu:[0.1],nosuch:[1]}", "factors.nosuch is not a known factor (override "
     "'factors={mu:[0.1],nosuch:[1]}' rejected); known factors: b, budget, damping_law, dt_s, "
     "grip_law, integrator, lambda1, lambda2, mass_kg, model_preset, mu, n_cand, n_exp, n_max, "
     "nodes, planner, pso_seed, shape, variant, w1, w2, w3, weight_scale."),
])
def test_an_unknown_key_inside_a_sections_mapping_is_named_not_the_section(tmp_path, override,
                                                                           said):
    refused(tmp_path, ["show", "wrench_balance", override, "--root", tmp_path], said)


def test_an_ascii_stl_cut_short_is_named_as_one_not_empty(tmp_path, sphere):
    # the old code said "is empty: it has no faces" of a file holding 80 whole facets
    import trimesh

    text = trimesh.load(sphere).export(file_type="stl_ascii")
    cut = tmp_path / "cut.stl"
    cut.write_text(text[:text.rindex("endsolid")])  # every facet, no closing line
    lines = text[:text.rindex("endsolid")].rstrip().splitlines()
    refused(tmp_path, ["plan", cut, "--mass-kg", "0.1"],
            f"mesh 'cut.stl' is cut short: an ASCII STL ends with an 'endsolid' line, and this "
            f"one ends on line {len(lines)} ('endfacet'); copy or export it again.")


@pytest.mark.parametrize(("command", "selection", "said"), [
    # schedule ended in a traceback (KeyError: "['plan_time_s'] not found in axis"); run stored a
    # run of 0 trials; ingest then had no sheet to check records against
    (["schedule", "test2_grasp"], ["params.fraction=1e-320"], "params.fraction=1e-320 selects"),
    (["run", "test2_grasp"], ["params.fraction=1e-9"], "params.fraction=1e-09 selects"),
    (["show", "test2_grasp"], ["params.objects=[sphere-01]", "params.groups=[C]"],
     "params.objects=[sphere-01], params.groups=[C] select"),
])
def test_a_protocol_selection_that_keeps_no_trial_is_refused(tmp_path, command, selection, said):
    kind = command[1]
    refused(tmp_path, [*command, *selection, "--root", tmp_path],
            f"{said} no trial of the {kind} sheet; select more (empty lists and fraction 1.0 are "
            "the full protocol).")


@pytest.mark.parametrize(("study", "override", "said"), [
    # the old code said "params.params.groups[0]: params.groups[0] has unknown value 'a'; ..."
    ("test2_grasp", "params.groups=[a]", "params.groups[0] has unknown value 'a'; did you mean "
     "'A'? allowed values: A, B, C, D, E, M, X."),
    ("test3_disturbance", "params.blocks=[z]", "params.blocks[0] has unknown value 'z'; allowed "
     "values: A, B, C, D, E."),
])
def test_a_kind_parameters_own_check_is_said_once_with_its_key(tmp_path, study, override, said):
    refused(tmp_path, ["show", study, override, "--root", tmp_path], said)


def test_an_interpolation_resolving_to_no_number_says_to_what(tmp_path, monkeypatch):
    # the old code said "... cannot be resolved: While dereferencing interpolation
    # '${oc.env:GC_ROUND12}': Value 'twelve' of type 'str' could not be converted to Integer."
    monkeypatch.setenv("GC_ROUND12", "twelve")
    refused(tmp_path, ["show", "smoke", "seed=${oc.env:GC_ROUND12}", "--root", tmp_path],
            "seed = '${oc.env:GC_ROUND12}' resolves to 'twelve', not a whole number.")
    refused(tmp_path, ["show", "smoke", "evaluator.alpha=${oc.env:GC_ROUND12}", "--root", tmp_path],
            "evaluator.alpha = '${oc.env:GC_ROUND12}' resolves to 'twelve', not a number.")
