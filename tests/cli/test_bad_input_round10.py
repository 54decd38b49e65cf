"""Bad input, round 10: study files with YAML's rarer forms (a complex key, a language tag),
overrides deleting a study's own keys or naming a character after a dot, paths that loop or hold
a line break, text meshes and measured files saved in another text form (a byte-order mark,
UTF-16, a title above the header). Merged workbook cells: test_bad_ingest_round10.py.
Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

import io
import json
from pathlib import Path

import pandas as pd
import pytest
import trimesh
from cli_checks import HEADER, SMOKE, invoke, refused

BODY = "name: mine\nkind: mesh_features\nfactors:\n  shape: [sphere]\n  nodes: [144]\n"


@pytest.mark.parametrize(("extra", "tail"), [
    # a traceback (TypeError: unhashable type: 'list'), of show, run and list alike
    ("? [a, b]\n: 1\n", "line 8: the key [a, b] is a list, not a name; write the name of the setting."),
    ("? {a: 1}\n: 1\n", "line 8: the key {a: 1} is a mapping, not a name; write the name of the setting."),
    # "this is not valid YAML (could not determine a constructor for the tag 'tag:yaml.org,...')"
    ("params: !!python/object/apply:os.system [echo]\n",
     "line 8: the tag !!python/object/apply:os.system is not read; a study or group file holds "
     "plain values (numbers, text, true/false, lists, mappings), so remove it."),
])
def test_a_complex_key_or_a_language_tag_in_a_study_file_is_named_with_its_line(results, user_dir,
                                                                              extra, tail):
    path = user_dir / "mine.yaml"
    path.write_text(HEADER + BODY + extra)
    for command in ("show", "run"):
        refused(results, [command, path, "--root", results], f"{path}, {tail}")


@pytest.mark.parametrize(("override", "default"), [
    # each was accepted: baseline_grid then showed (and ran) 1 seed, not its 15; study seed 0, not 605
    ("~seeds", "1"), ("~seed", "0"), ("~method_factors", '["planner", "variant"]'),
    ("~extension", "false"),
    # it said "trial kind 'quasi_static' needs the factors shape, mass_kg, mu and planner ..."
    ("~factors", "{}"),
])
def test_deleting_a_key_the_study_sets_is_refused_naming_the_default_that_would_stand_in(
        results, override, default):
    key = override[1:]
    for command in ("show", "run"):
        refused(results, [command, "baseline_grid", override, "--root", results],
                f"override '{override}' deletes {key}, a key every study has: it would only put "
                f"back the schema's default ({default}), which a study that does not set {key} "
                f"already holds; set the value you want instead ({key}=...).")


KEY_CHARACTERS = "but a key takes only ASCII letters, digits, '_', '-', '.' and '/'"


@pytest.mark.parametrize(("override", "said"), [
    # each named the dot before it: "its key has '.' at character 9" (Hydra's caret marks where its
    # token began)
    ("+factors.μ=[0.3]", f"its key has 'μ' at character 10, {KEY_CHARACTERS}."),
    ("factors.μ=[0.3]", f"its key has 'μ' at character 9, {KEY_CHARACTERS}."),
])
def test_a_character_no_key_holds_after_a_dot_is_named_itself(results, override, said):
    refused(results, ["show", "smoke", override, "--root", results],
            f"cannot parse override {override!r}: {said}")


LOOP = "is a symbolic link in a loop (it leads back to itself)"


@pytest.mark.parametrize(("args", "place", "said"), [
    # each said "is not a directory" (or, for --png, "directory ... does not exist")
    (["status", "smoke", "--root"], "{loop}", f"--root {{loop}}: {LOOP}."),
    (["report", "--root"], "{loop}", f"--root {{loop}}: {LOOP}."),
    (["run", "smoke", *SMOKE, "--root"], "{loop}/results", f"--root {{loop}}/results: {{loop}} {LOOP}."),
    (["schedule", "test2_grasp", "--out"], "{loop}/sheet", f"--out {{loop}}/sheet: {{loop}} {LOOP}."),
    (["plan", "{sphere}", "--mass-kg", "0.1", "--png"], "{loop}/p.png",
     f"--png {{loop}}/p.png: {{loop}} {LOOP}."),
])
def test_a_place_to_read_or_write_through_a_loop_of_links_is_named_as_one(tmp_path, args, place,
                                                                          said):
    (tmp_path / "a").symlink_to("b")
    (tmp_path / "b").symlink_to("a")
    sphere = tmp_path / "sphere.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=40.0).export(sphere)
    names = {"loop": tmp_path / "a", "sphere": sphere}
    refused(tmp_path, [arg.format(**names) for arg in args] + [place.format(**names)],
            said.format(**names))


@pytest.mark.parametrize("file_type", ["obj", "stl_ascii", "ply"])
def test_a_text_mesh_saved_with_a_byte_order_mark_plans_as_without_one(tmp_path, file_type):
    # an OBJ whose first line is a vertex was "has a face (line 6) that refers to vertex 4, but the
    # file has only 3 vertices", an ASCII STL "is not an STL file: ... neither a binary STL nor an
    # ASCII STL (text starting with 'solid')"
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=40.0)
    text = sphere.export(file_type=file_type, encoding="ascii") if file_type == "ply" else \
        sphere.export(file_type=file_type)
    text = text if isinstance(text, bytes) else text.encode()
    text = b"".join(line for line in text.splitlines(keepends=True) if not line.startswith(b"#"))
    suffix = ".stl" if file_type == "stl_ascii" else f".{file_type}"
    plain, marked = tmp_path / "plain" / f"ball{suffix}", tmp_path / "marked" / f"ball{suffix}"
    for path, data in ((plain, text), (marked, b"\xef\xbb\xbf" + text)):
        path.parent.mkdir()
        path.write_bytes(data)
    done = [invoke("plan", path, "--mass-kg", "0.1", "--png", tmp_path / f"{path.parent.name}.png",
                   "--json") for path in (plain, marked)]
    assert [d.exit_code for d in done] == [0, 0], done[1].output
    plans = [{k: v for k, v in json.loads(d.stdout).items() if k != "png"} for d in done]
    assert plans[1] == plans[0]


def _filled_sheet(tmp_path: Path) -> str:
    """Two rows of test2_grasp's measured-records template, filled in, as CSV text."""
    made = invoke("schedule", "test2_grasp", "params.fraction=0.06", "--template", "--out",
                  tmp_path / "sheet")
    assert made.exit_code == 0, made.output
    rows = pd.read_csv(tmp_path / "sheet-template.csv").iloc[:2].assign(
        aborted=False, outcome="stable", success=True, stable=True, slip_flag=False,
        drop_flag=False, damage_flag=False, contact_loss_flag=False, peak_slip_mm=0.16,
        sf_actual=1.5, g_geo_actual=0.5)
    return rows.drop(columns=["abort_reason", "environment", "source"]).to_csv(index=False)


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-le"])
def test_a_file_saved_as_utf16_is_named_as_one(results, user_dir, tmp_path, encoding):
    # a CSV was "the file is not UTF-8 text (byte 0xff)" with its byte-order mark, and without one
    # "row 4: 1 cells where the header has 22 columns"; a study file "... (byte 0xff)"
    sheet = tmp_path / "day1.csv"
    sheet.write_bytes(_filled_sheet(tmp_path).encode(encoding))
    refused(results, ["ingest", "test2_grasp", sheet, "--set", "params.fraction=0.06", "--root",
                      results], "day1.csv: the file is UTF-16 text, not UTF-8; save it as CSV UTF-8.")
    study = user_dir / "mine.yaml"
    study.write_bytes((HEADER + BODY).encode(encoding))
    refused(results, ["show", study, "--root", results],
            f"{study}: the file is UTF-16 text, not UTF-8; save it as UTF-8.")


@pytest.mark.parametrize(("above", "lines"), [
    # it said "row 1: 22 cells where the header has 1 columns (a cell with a comma needs quotes; ...)"
    ("Test 2, day 1\n", "the first line has 1 cell where the rows below it have 22 cells (a title "
                        "or note line above the header?)"),
    ("# rig B\nby: me\n", "the first 2 lines have 1 cell each where the rows below them have 22 "
                          "cells (title or note lines above the header?)"),
])
def test_a_title_above_the_header_of_a_csv_is_named_as_one(results, tmp_path, above, lines):
    sheet = tmp_path / "day1.csv"
    sheet.write_text(above.replace(", ", " ") + _filled_sheet(tmp_path))
    refused(results, ["ingest", "test2_grasp", sheet, "--set", "params.fraction=0.06", "--root",
                      results],
            f"day1.csv, header: {lines}; the header must be the first line: delete the lines above "
            "it.")


def test_a_row_of_one_cell_is_counted_in_the_singular(results, tmp_path):
    # "row 2: 1 cells where the header has 22 columns"
    sheet = tmp_path / "day1.csv"
    sheet.write_text(_filled_sheet(tmp_path) + "t2A-sphere-06-prop-f6071de919\n" + "x," * 21 + "x\n")
    refused(results, ["ingest", "test2_grasp", sheet, "--set", "params.fraction=0.06", "--root",
                      results],
            "day1.csv, row 3: 1 cell where the header has 22 columns (a cell with a comma needs "
            "quotes; a truncated file loses its last row's cells).")


@pytest.mark.parametrize(("args", "option", "place", "code"), [
    # run made a results root named 'res\nults' and wrote its run there; schedule wrote 'she\net.csv'
    (["run", "smoke", *SMOKE], "--root", "res\nults", "U+000A"),
    (["schedule", "test2_grasp", "--out"], "--out", "she\net", "U+000A"),
    (["plan", "{sphere}", "--mass-kg", "0.1", "--png"], "--png", "p\tq.png", "U+0009"),
])
def test_a_path_to_write_holding_a_line_break_or_a_tab_is_refused(tmp_path, args, option, place,
                                                                  code):
    sphere = tmp_path / "sphere.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=40.0).export(sphere)
    given = str(tmp_path / place)
    words = [arg.format(sphere=sphere) for arg in args] + ([option] if option == "--root" else [])
    refused(tmp_path, [*words, given], f"{option} {given!r}: {code} (a control character) is not "
                                       "allowed in a path given here; remove it.")


@pytest.mark.parametrize("override", ["description=[a]", "compare_with={a:1}"])
def test_a_list_or_a_mapping_where_text_belongs_is_named_in_plain_words(results, override):
    # it said "description: Cannot convert 'list' to string: '['a']'." (OmegaConf's words)
    key, _, _ = override.partition("=")
    got = "['a']" if key == "description" else "{'a': 1}"
    refused(results, ["show", "baseline_grid", override, "--root", results],
            f"{key} must be a value of type str, got {got}.")


def test_one_measured_record_stored_is_said_in_the_singular(results, tmp_path):
    # "1 measured records stored in ..."
    sheet = tmp_path / "day1.csv"
    sheet.write_text("".join(_filled_sheet(tmp_path).splitlines(keepends=True)[:2]))
    done = invoke("ingest", "test2_grasp", sheet, "--set", "params.fraction=0.06", "--root", results)
    assert done.exit_code == 0, done.output
    assert done.stdout == f"1 measured record stored in {results / 'test2_grasp' / 'measured'}\n"


@pytest.mark.parametrize("suffix", [".xlsx", ".csv"])
def test_a_title_row_as_wide_as_the_table_is_named_by_the_row_holding_the_names(results, tmp_path,
                                                                                suffix):
    # it said "required columns are missing: trial_id, aborted, ...; columns are not part of the
    # sheet: 'Test 2, day 1', 'Unnamed: 1', ..."
    sheet = tmp_path / f"day1{suffix}"
    table = pd.read_csv(io.StringIO(_filled_sheet(tmp_path)), dtype=str)
    rows = [["Test 2 day 1"] + [None] * (table.shape[1] - 1), list(table.columns),
            *table.to_numpy().tolist()]
    if suffix == ".xlsx":
        pd.DataFrame(rows).to_excel(sheet, index=False, header=False)
    else:
        pd.DataFrame(rows).to_csv(sheet, index=False, header=False)
    refused(results, ["ingest", "test2_grasp", sheet, "--set", "params.fraction=0.06", "--root",
                      results],
            f"day1{suffix}, header: row 1 holds the column names, so what is above it (a title or "
            "a note?) was read as the header; the header must be the first row, so delete the "
            "rows above it (`graspcampaign schedule <study> --template` writes a sheet with every "
            "column).")
