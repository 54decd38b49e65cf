"""Bad input, round 16: a hardware researcher's first afternoon. A workbook cell formatted as a
date holding a number past 9999-12-31, Excel's lock file given (or left) beside a workbook, a bad
``plan --material``, a run named as another but for case in ``show``, ``status`` and ``report``,
and a study file's path given to ``status``. Each refusal: exit 2, one sentence naming what is
wrong, where, and what to write, nothing stored changed (``refused``)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest
from cli_checks import SMOKE, T2, filled_records, invoke, refused

MATERIALS = "use one of gel, silicone_soft, bio_foam, silicone_ref."


def _dated(frame: pd.DataFrame, path: Path, cell: str, serial: float) -> Path:
    """``frame`` as a workbook whose ``cell`` holds ``serial`` formatted as a date."""
    from openpyxl import load_workbook

    frame.to_excel(path, index=False)
    book = load_workbook(path)
    book.active[cell] = serial
    book.active[cell].number_format = "yyyy-mm-dd"
    book.save(path)
    return path


def test_a_date_cell_past_year_9999_is_refused_naming_the_cell(results, tmp_path):
    # 3,000,000 days after 1900 is past 9999-12-31: openpyxl warned and read the error #VALUE!,
    # which pandas leaves empty, so row 2's peak slip was stored as not measured
    book = _dated(filled_records(tmp_path), tmp_path / "day1.xlsx", "J3", 3_000_000)
    refused(results, ["ingest", "test2_grasp", book, *T2, "--root", results],
            "day1.xlsx, row 2, column 'peak_slip_mm': the cell (J3) is formatted as a date, but "
            "its value 3000000 is outside the dates a workbook holds (up to 9999-12-31), so it "
            "would be read as empty; give the cell a number format, or fix its value.")


def test_a_date_cell_within_the_calendar_is_named_as_a_date(results, tmp_path):
    # the neighbouring case, unchanged: a date the calendar holds is read as one and refused
    book = _dated(filled_records(tmp_path), tmp_path / "day1.xlsx", "J3", 45_000)
    refused(results, ["ingest", "test2_grasp", book, *T2, "--root", results],
            "day1.xlsx, row 2, column 'peak_slip_mm': value 2023-03-15 00:00:00 is a date/time, "
            "not a number.")


def test_excels_lock_file_given_as_records_is_named_as_one(results, tmp_path):
    # `ingest test2_grasp *.xlsx` beside an open workbook: it said "not an Excel workbook (xlsx)
    # ...; if it is CSV text, rename it to ~$day1.csv"
    lock = tmp_path / "~$day1.xlsx"
    lock.write_bytes(b"\x0bresearcher" + b"\x00" * 150)
    refused(results, ["ingest", "test2_grasp", lock, *T2, "--root", results],
            "~$day1.xlsx: the file is the lock file Excel keeps beside a workbook open in it, not "
            "records; ingest the workbook itself, saved and closed.")


@pytest.mark.parametrize(("name", "lock"), [
    ("day1.xlsx", "~$day1.xlsx"),  # Excel, a short name
    ("my results.xlsx", "~$ results.xlsx"),  # Excel, a longer name: its first two characters go
    ("day1.csv", ".~lock.day1.csv#"),  # LibreOffice
])
def test_a_file_open_in_a_spreadsheet_program_is_refused(results, tmp_path, name, lock):
    # it was stored as saved, whatever the program showed unsaved
    frame = filled_records(tmp_path)
    path = tmp_path / name
    frame.to_csv(path, index=False) if name.endswith(".csv") else frame.to_excel(path, index=False)
    (tmp_path / lock).write_bytes(b"\x0bresearcher")
    refused(results, ["ingest", "test2_grasp", path, *T2, "--root", results],
            f"{name}: the file is open in a spreadsheet program (its lock file {lock} is beside "
            "it), so what is saved may not be what it shows; save and close it, then ingest again "
            f"(delete {lock} if no program has it open).")
    (tmp_path / lock).unlink()  # closed: the same file is stored
    assert invoke("ingest", "test2_grasp", path, *T2, "--root", results).exit_code == 0


@pytest.mark.parametrize(("material", "meant"), [
    ("unobtainium", ""), ("Gel", "did you mean 'gel'? "), ("", ""),
])
def test_plan_names_the_material_option(tmp_path, sphere, material, meant):
    # it said "unknown material 'unobtainium'; ...", naming no option
    refused(tmp_path, ["plan", sphere, "--mass-kg", "0.1", "--material", material, "--png",
                       tmp_path / "p.png"],
            f"--material {material!r} is not a Table 4 material family; {meant}{MATERIALS}")


def test_show_of_a_run_named_as_another_but_for_case_says_run_would_refuse_it(results):
    # show said "run: …/Default (0 of 10 recorded)" of a run `run` refuses to make
    smoke = results / "smoke"
    shown = invoke("show", "smoke", *SMOKE, "--run", "Default", "--root", results)
    assert shown.exit_code == 0, shown.output
    assert (f"note: `run` and `ingest` would refuse: run smoke/Default at {smoke / 'Default'}: its "
            f"name differs only in case from {smoke / 'default'}, which is there already, and on a "
            "file system that ignores case (macOS, Windows, a USB stick) the two are one directory; "
            "to add to that run, give --run default; for a new one, give a run name that differs "
            "in more than case.\n") in shown.stdout
    assert "note:" not in invoke("show", "smoke", *SMOKE, "--run", "Default2", "--root",
                                 results).stdout


@pytest.mark.parametrize("command", ["status", "report"])
def test_status_and_report_of_a_case_twin_do_not_advise_a_refused_run(results, command):
    # they said "did you mean --run default? run `graspcampaign run smoke --run Default ...`
    # first.", a command that `run` refuses
    said = (f"no run at {results / 'smoke' / 'Default'}; " if command == "status" else
            f"no run 'Default' of study 'smoke' under {results}; ")
    refused(results, [command, "smoke", "--run", "Default", "--root", results],
            f"{said}did you mean --run default? a run named Default cannot be made beside default "
            "(on a file system that ignores case the two are one directory).")


def test_status_given_a_study_files_path_names_its_name_key(results, user_dir):
    # it said "(mine, the name: of a study file)"
    path = user_dir / "mine.yaml"
    path.write_text("# @package _global_\n# schema: StudyCfg\nname: mine\nkind: mesh_features\n")
    refused(results, ["status", path, "--root", results],
            f"study {str(path)!r} is a path; give the study's name (mine, the value of name: in the "
            "study file), under which its runs are stored.")
    refused(results, ["status", "elsewhere/theirs.yaml", "--root", results],
            "study 'elsewhere/theirs.yaml' is a path; give the study's name (the value of name: in "
            "the study file; theirs if the file is named after it), under which its runs are "
            "stored.")
