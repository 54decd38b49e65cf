"""Bad input, round 13: what its left-overs left. An output file named only by a format suffix, for
every option naming a file to write, and the overrides of a numeric factor's level or a factor's
level deleted by its bare name. Each refusal: exit 2, one sentence naming what is wrong, where, and
what to write, nothing stored changed (``refused``)."""

from __future__ import annotations

import pytest
from cli_checks import refused

SUFFIX_ONLY = "names only a suffix, no file name (a name beginning with a dot is a hidden file's)"


@pytest.mark.parametrize("name", [".txt", ".TXT", ".csv"])
def test_a_times_file_named_only_by_a_suffix_is_refused(tmp_path, monkeypatch, name):
    # reproduce --times DIR/.txt appended its lines to the hidden file .txt
    from graspcampaign.cli import main

    monkeypatch.setattr(main, "_study_rows", lambda: [])  # on the old code: no study is run
    times = tmp_path / "logs" / name
    refused(tmp_path, ["reproduce", "--root", tmp_path / "results", "--times", times],
            f"--times {times} {SUFFIX_ONLY}; give a file such as "
            f"{tmp_path / 'logs' / 'reproduce_times.txt'}.")


@pytest.mark.parametrize("name", [".png", ".PNG"])
def test_a_picture_named_only_by_a_suffix_is_refused(tmp_path, sphere, name):
    # plan --png DIR/.png said it "does not end in .png" and suggested DIR/.png.png
    png = tmp_path / name
    refused(tmp_path, ["plan", sphere, "--mass-kg", "0.2", "--png", png],
            f"--png {png} {SUFFIX_ONLY}; give a file path ending in .png, such as "
            f"{tmp_path / 'plan.png'}.")
