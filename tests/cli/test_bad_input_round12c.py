"""Bad input, round 12, what its adversary noticed and left: missing-value words and spreadsheet
errors in measured cells, hidden sheets and rows, long paths echoed, a Hydra ``defaults:`` list or a
date in a study file, a PLY whose header and body disagree. Each refusal: exit 2, one sentence
naming what is wrong and where, nothing stored changed (``refused``; on a run that already holds
records, ``stored``)."""

from __future__ import annotations

import pandas as pd
import pytest
from cli_checks import T1, T2, bench_press, filled_records, invoke, refused

#: how ingest and the template name the cells that say "not measured" (written out here)
NOT_MEASURED = "empty or NA, N/A, NaN, null, none (any case)"


def _one_cell(tmp_path, column: str, value, suffix: str = ".csv"):
    """Two trials of the Test 2 template, filled in, with ``value`` in the second row's ``column``."""
    frame = filled_records(tmp_path, rows=slice(2, 4)).astype({column: object})
    frame.loc[1, column] = value
    path = tmp_path / f"day2{suffix}"
    frame.to_csv(path, index=False) if suffix == ".csv" else frame.to_excel(path, index=False)
    return path


@pytest.mark.parametrize("suffix", [".csv", ".xlsx"])
@pytest.mark.parametrize("word", ["NA", "n/a", "N/A", "null"])
def test_a_required_cell_saying_not_measured_is_named_by_its_word(stored, tmp_path, word, suffix):
    # the old code said "value is empty" of NA and null, and "value 'n/a' is not a number" of n/a
    # in a CSV (in a workbook pandas read it as empty)
    sheet = _one_cell(tmp_path, "sf_actual", word, suffix)
    refused(stored, ["ingest", "test2_grasp", sheet, *T2, "--root", stored],
            f"day2{suffix}, row 2, column 'sf_actual': value '{word}' means not measured, but the "
            "trial was executed (aborted is false).")


@pytest.mark.parametrize("word", ["n/a", "N/A", "none"])
def test_each_not_measured_word_is_read_as_an_empty_cell(stored, tmp_path, word):
    # the old code refused n/a and N/A in a CSV, which it read as missing in a workbook
    sheet = _one_cell(tmp_path, "peak_slip_mm", word)
    done = invoke("ingest", "test2_grasp", sheet, *T2, "--root", stored)
    assert done.exit_code == 0, done.output
    kept = pd.read_parquet(stored / "test2_grasp" / "measured" / "records").set_index("rig_trial_id")
    assert pd.isna(kept.loc[pd.read_csv(sheet)["trial_id"][1], "peak_slip_mm"])


@pytest.mark.parametrize("mark", ["-", "?"])
def test_a_dash_in_a_number_cell_is_refused_saying_how_to_write_not_measured(stored, tmp_path, mark):
    sheet = _one_cell(tmp_path, "peak_slip_mm", mark)
    refused(stored, ["ingest", "test2_grasp", sheet, *T2, "--root", stored],
            f"day2.csv, row 2, column 'peak_slip_mm': value '{mark}' is not a number; a cell not "
            f"measured is {NOT_MEASURED}.")


def test_the_template_says_which_words_mean_not_measured(tmp_path):
    done = invoke("schedule", "test2_grasp", *T2[1:], "--template", "--out", tmp_path / "sheet")
    assert done.exit_code == 0, done.output
    columns = pd.read_csv(tmp_path / "sheet-template-columns.csv").set_index("column")
    assert columns.loc["peak_slip_mm", "required"] == (
        f"column required, cells may be {NOT_MEASURED}: not measured")


@pytest.mark.parametrize("suffix", [".csv", ".xlsx"])
@pytest.mark.parametrize(("column", "error"), [("sf_actual", "#DIV/0!"), ("peak_slip_mm", "#N/A"),
                                               ("stable", "#VALUE!"), ("peak_slip_mm", "#REF!")])
def test_a_spreadsheet_error_in_a_cell_is_named_as_one(stored, tmp_path, column, error, suffix):
    # the old code said "value is empty" of an error cell in a workbook (pandas reads one as
    # empty), and stored it as not measured in a column that may be empty; a CSV export's text
    # was "value '#DIV/0!' is not a number"
    sheet = _one_cell(tmp_path, column, error, suffix)
    if suffix == ".xlsx":  # openpyxl writes these words as error cells (t="e"), as Excel does
        from openpyxl import load_workbook

        cell = load_workbook(sheet)["Sheet1"].cell(3, list(pd.read_csv(
            tmp_path / "sheet-template.csv").columns).index(column) + 1)
        assert (cell.data_type, cell.value) == ("e", error)
    refused(stored, ["ingest", "test2_grasp", sheet, *T2, "--root", stored],
            f"day2{suffix}, row 2, column '{column}': the cell holds the spreadsheet error "
            f"{error}; fix the formula or clear the cell.")


def _hidden(tmp_path, rows=(), sheet_hidden: bool = False):
    """day2.xlsx: a hidden helper sheet first (``sheet_hidden``), then two trials with the sheet
    rows ``rows`` hidden, as a spreadsheet program hides or filters them out."""
    from openpyxl import load_workbook

    book_path = tmp_path / "day2.xlsx"
    with pd.ExcelWriter(book_path) as writer:
        if sheet_hidden:
            pd.DataFrame({"material": ["gel"]}).to_excel(writer, sheet_name="lookup", index=False)
        filled_records(tmp_path, rows=slice(2, 5)).to_excel(writer, sheet_name="day2", index=False)
    book = load_workbook(book_path)
    if sheet_hidden:
        book["lookup"].sheet_state = "hidden"
    for row in rows:
        book["day2"].row_dimensions[row].hidden = True
    book.save(book_path)
    return book_path


def test_a_hidden_first_sheet_is_named_not_read_silently(stored, tmp_path):
    # the old code read the hidden sheet, the one a user does not see, and said not a word of
    # its being hidden
    refused(stored, ["ingest", "test2_grasp", _hidden(tmp_path, sheet_hidden=True), *T2,
                     "--root", stored],
            "day2.xlsx: ingest reads the workbook's first sheet, and it, 'lookup', is hidden (a "
            "sheet someone set aside?); unhide it if it holds the records, or move the sheet that "
            "does to the front.")


@pytest.mark.parametrize(("rows", "said"), [((3,), "row 2 is"), ((2, 4), "row 1, row 3 are")])
def test_hidden_rows_of_a_workbook_are_named_not_stored(stored, tmp_path, rows, said):
    # the old code stored the hidden rows with the others, without a word
    refused(stored, ["ingest", "test2_grasp", _hidden(tmp_path, rows), *T2, "--root", stored],
            f"day2.xlsx: {said} hidden in the sheet (hidden or filtered out: left out of the "
            "records?); delete the hidden rows to leave them out, or unhide them to ingest them.")
    done = invoke("ingest", "test2_grasp", _hidden(tmp_path, (9,)), *T2, "--root", stored)
    assert done.exit_code == 0, done.output  # a hidden row below the table holds no record


def _cut(path) -> str:
    """``path`` as a message shows a value over 200 characters: its first 60 and its length."""
    text = str(path)
    return f"{text[:60]}... ({len(text)} characters)"


def test_a_long_output_path_is_echoed_shortened(tmp_path):
    # the old code echoed both paths in full (330 and 324 characters) in the one sentence
    deep = tmp_path.joinpath(*["d" * 50] * 6)
    refused(tmp_path, ["schedule", "test2_grasp", *T2[1:], "--out", deep / "sheet", "--root",
                       tmp_path],
            f"--out {_cut(deep / 'sheet')}: directory {_cut(deep)} does not exist.")
    (tmp_path / "afile").write_text("")
    times = tmp_path.joinpath("afile", *["t" * 50] * 6).with_suffix(".txt")
    refused(tmp_path, ["reproduce", "--times", times, "--root", tmp_path],
            f"--times {_cut(times)}: {tmp_path / 'afile'} is a file, not a directory.")


STUDY = "# @package _global_\nname: mine\nkind: quasi_static\n{line}\nseeds: 1\nfactors:\n  shape: [sphere]\n"


@pytest.mark.parametrize(("line", "said"), [
    # the old code said "defaults is not a known key of the study config; known keys: ...", of
    # Hydra's own list, which a Hydra user writes on purpose
    ("defaults:\n  - _self_\n  - evaluator: default",
     "defaults is not a key of a study file: the presets of the groups (model, evaluator, "
     "features, pso, runner, output) are chosen by the defaults list of conf/config.yaml, which "
     "every study is merged over; set a group's keys under its name in the study file "
     "(evaluator: {n_cand: 300}), or choose another preset on the command line (model=firm)."),
    # it said "got datetime.date(2024, 1, 1) (date)": Python's repr, not what was written
    ("seed: 2024-01-01", "seed must be of type int, got 2024-01-01 (a date)."),
])
def test_a_study_file_says_defaults_and_dates_in_its_own_words(tmp_path, line, said):
    study = tmp_path / "mine.yaml"
    study.write_text(STUDY.format(line=line))
    refused(tmp_path, ["show", study, "--root", tmp_path], f"{study}, line 4: {said}")


@pytest.mark.parametrize("declared", ["binary_big_endian", "binary_little_endian"])
def test_a_ply_whose_header_says_binary_over_a_text_body_is_named(tmp_path, sphere, declared):
    # the old code said trimesh's "PLY is unexpected length!"
    import trimesh

    text = trimesh.load(sphere).export(file_type="ply", encoding="ascii").decode()
    assert "format ascii 1.0" in text
    mesh = tmp_path / "mesh.ply"
    mesh.write_text(text.replace("format ascii 1.0", f"format {declared} 1.0"))
    refused(tmp_path, ["plan", mesh, "--mass-kg", "0.1"],
            f"mesh 'mesh.ply' says 'format {declared} 1.0' in its header, but what follows the "
            "header is text (lines of numbers), which an ASCII PLY holds (format ascii 1.0); "
            "correct that line or export the mesh again.")


@pytest.mark.parametrize("suffix", [".csv", ".xlsx"])
def test_a_waveform_sample_is_read_alike_from_a_csv_and_a_workbook(results, tmp_path, suffix):
    # a workbook read pandas' missing-value words ('NA' was "value nan (an empty cell or NaN) is
    # not finite"), a CSV only the empty cell: a sample is measured, no word stands for one
    waves = bench_press().astype({"displacement_mm": object})
    waves.loc[10, "displacement_mm"] = "NA"
    path = tmp_path / f"waves{suffix}"
    waves.to_csv(path, index=False) if suffix == ".csv" else waves.to_excel(path, index=False)
    refused(results, ["ingest", "test1_bench", path, *T1, "--root", results],
            f"waves{suffix}, row 11, column 'displacement_mm': value 'NA' is not a number.")
