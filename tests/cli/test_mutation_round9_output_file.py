"""Mutation round 9: ``app.file_path`` reads a value of ``/`` alone as the root directory it is, not
as a name ending in a separator (docs/decisions.md, mutation round 9)."""

from __future__ import annotations

import pytest
from cli_checks import refused


@pytest.mark.parametrize("root", ["/", "//"])
def test_the_root_directory_as_an_output_file_is_refused_as_a_directory(tmp_path, root):
    """``--out /`` strips to no name at all: it is the root directory (an existing one), refused as
    any existing directory is, and the file suggested is in it."""
    refused(tmp_path, ["schedule", "test2_grasp", "--out", root, "--root", tmp_path / "results"],
            f"--out {root} is a directory; give a file stem such as {root}schedule.")
    refused(tmp_path, ["reproduce", "--times", root],
            f"--times {root} is a directory; give a file such as {root}reproduce_times.txt.")
