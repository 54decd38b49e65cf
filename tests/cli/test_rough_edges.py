"""The rough edges the previous session's closing note left (branch left): an output option ending
in a path separator, ...

Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

import pytest
import trimesh
from cli_checks import refused


@pytest.fixture
def sphere(tmp_path):
    """A valid mesh file to plan on (40 mm sphere)."""
    path = tmp_path / "sphere.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=40.0).export(path)
    return path


@pytest.mark.parametrize(("args", "option", "instead"), [
    # schedule --out day1/ wrote day1.csv and day1.parquet beside the directory meant
    (["schedule", "test2_grasp"], "--out", "a file stem such as {dir}/schedule"),
    # plan said the path "does not end in .png", reproduce wrote its times to a file named day1
    (["plan", "{mesh}", "--mass-kg", "0.1"], "--png", "a file path ending in .png, such as "
                                                      "{dir}/plan.png"),
    (["reproduce"], "--times", "a file such as {dir}/reproduce_times.txt"),
])
@pytest.mark.parametrize("exists", [False, True])
def test_an_output_path_ending_in_a_slash_is_refused_as_the_directory_it_names(
        tmp_path, sphere, args, option, instead, exists):
    folder = tmp_path / "day1"
    if exists:
        folder.mkdir()
    given = [a.format(mesh=sphere) for a in args]
    refused(tmp_path, [*given, option, f"{folder}/",
                       *(["--root", tmp_path / "results"] if args[0] != "plan" else [])],
            f"{option} {folder}/ ends in '/', so it names a directory; give "
            f"{instead.format(dir=folder)}.")
