"""``report`` over a root whose entries where runs would be are not all runs: only a root of
several such entries, every one a file, is "no results root" (tests/cli/test_bad_input_round8.py);
one stray file, or a damaged run directory beside a file, is a results root whose entries are each
named with why they cannot be reported.
"""

from __future__ import annotations

from cli_checks import invoke, snapshot

NOT_A_RUN = ("is a file, not a run directory; move it aside or choose another run name "
             "(--run NAME)")


def test_one_stray_file_is_named_as_the_entry_it_is(tmp_path):
    (tmp_path / "smoke").mkdir()
    (tmp_path / "smoke" / "notes.txt").write_text("x")
    before = snapshot(tmp_path)
    done = invoke("report", "--root", tmp_path)
    assert done.exit_code == 2 and done.stdout == ""
    assert done.stderr == (f"error: the report of smoke/notes.txt could not be written: run "
                           f"smoke/notes.txt at {tmp_path / 'smoke' / 'notes.txt'} {NOT_A_RUN}\n")
    assert snapshot(tmp_path) == before


def test_a_damaged_run_directory_beside_a_file_is_a_results_root(tmp_path):
    """A run whose manifest is damaged is a run directory: the root holds runs, each entry named."""
    (tmp_path / "smoke" / "default").mkdir(parents=True)
    (tmp_path / "smoke" / "default" / "manifest.json").write_text("{")
    (tmp_path / "smoke" / "notes.txt").write_text("x")
    done = invoke("report", "--root", tmp_path)
    assert done.exit_code == 2 and "no results root" not in done.stderr
    lines = done.stderr.splitlines()
    assert [line.split(":")[1].strip() for line in lines] == [
        "the report of smoke/default could not be written",
        "the report of smoke/notes.txt could not be written"]
    assert "has a damaged manifest.json (not valid JSON" in lines[0] and lines[1].endswith(NOT_A_RUN)
