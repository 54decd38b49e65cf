"""Bad input, round 7: deleting a whole config group (``~runner``), an option or an override key
given twice, an empty output path, a filled-in measured-records template written over, a mesh
saved under another format's suffix.
Each case: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest
import trimesh
from cli_checks import invoke, refused

CONF = Path(__file__).parents[2] / "conf"  # the project's config groups, one folder each


@pytest.mark.parametrize("override", ["~runner", "~model=table2", "~runner=default"])
def test_deleting_a_config_group_is_refused_naming_its_options(results, override):
    """``~runner`` exited 0 (Hydra drops the group's file and the schema's values stand in) and
    ``~runner=default`` said "Could not delete 'runner=default'. No match in the defaults list."."""
    group = override[1:].partition("=")[0]
    options = ", ".join(sorted(path.stem for path in (CONF / group).glob("*.yaml")))
    refused(results, ["show", "smoke", override, "--root", results],
            f"override {override!r} deletes the config group {group}, which every study needs; set "
            f"one of its options instead ({group}=OPTION; options: {options}).")


@pytest.mark.parametrize(("args", "message"), [
    (["show", "smoke", "--root", "{root}", "--root", "{root}/elsewhere"],
     "option --root is given twice (--root {root}, then --root {root}/elsewhere); give it once."),
    (["run", "smoke", "shape=[sphere]", "nodes=[144]", "--report", "--root", "{root}", "--no-report"],
     "option --report is given twice (--report, then --no-report); give it once."),
    (["plan", "{root}/smoke.stl", "--mass-kg", "0.1", "--mass-kg=0.2"],
     "option --mass-kg is given twice (--mass-kg 0.1, then --mass-kg=0.2); give it once."),
    (["list", "--names", "--names"], "option --names is given twice (--names, then --names); give "
                                     "it once."),
])
def test_an_option_given_twice_is_refused_not_the_last_kept(results, args, message):
    """click kept the last silently: a run went to the second --root, a plan took the second mass."""
    refused(results, [arg.format(root=results) for arg in args], message.format(root=results))


@pytest.mark.parametrize(("args", "message"), [
    # it said "--out . is a directory; give a file stem such as schedule."
    (["schedule", "test2_grasp", "--out", ""], "--out is empty; give a file stem such as schedule."),
    # it said "--times . is a directory; give a file such as reproduce_times.txt."
    (["reproduce", "--times", ""], "--times is empty; give a file such as reproduce_times.txt."),
])
def test_an_empty_output_path_is_named_empty_not_the_current_directory(results, args, message):
    refused(results, [*args, "--root", results], message)


def test_a_filled_in_template_or_another_sheet_is_not_written_over(results):
    """``schedule --template`` wrote the empty template over the one a lab had filled in, and a
    sheet of other settings over the sheet being run, saying nothing."""
    command = ["schedule", "test3_disturbance", "params.fraction=0.05", "--template", "--out",
               results / "day1", "--root", results]
    assert invoke(*command).exit_code == 0
    assert invoke(*command).exit_code == 0  # the same sheets again: nothing lost, written again
    template = results / "day1-template.csv"
    filled = pd.read_csv(template, keep_default_na=False, dtype=str)
    filled.loc[0, "aborted"] = "false"
    filled.to_csv(template, index=False)
    refused(results, command, f"--out {results / 'day1'}: day1-template.csv already exists and "
            "differs from the sheet this command writes (filled in, or made with other settings?); "
            "move it away or give another --out, so that it is not written over.")
    refused(results, ["schedule", "test3_disturbance", "params.fraction=0.1", "--out",
                      results / "day1", "--root", results],
            f"--out {results / 'day1'}: day1.csv already exists and differs from the sheet this "
            "command writes (filled in, or made with other settings?); move it away or give "
            "another --out, so that it is not written over.")


@pytest.mark.parametrize(("overrides", "key"), [
    (["runner.n_jobs=1", "runner.n_jobs=2"], "runner.n_jobs"),
    (["model=firm", "model=nominal"], "model"),
    (["nodes=[144]", "factors.nodes=[390]"], "factors.nodes"),  # a factor by either of its names
])
def test_an_override_naming_a_key_again_is_refused_not_the_last_kept(results, overrides, key):
    """Hydra applied both and kept the last: ``show`` and ``run`` exited 0 with the second value."""
    first, second = overrides
    refused(results, ["show", "smoke", *overrides, "--root", results],
            f"overrides {first!r} and {second!r} both name {key}; give it once (Hydra would keep "
            "the last silently).")


@pytest.mark.parametrize(("overrides", "said"), [
    (["factors={nodes:[144],nodes:[390]}"], "override 'factors={nodes:[144],nodes:[390]}' names "
                                            "factors.nodes twice"),
    (["model={lambda1:1,'x':'a,b',lambda1:2}"], "override \"model={lambda1:1,'x':'a,b',lambda1:2}\" "
                                                "names model.lambda1 twice"),
    (["factors={nodes:[144]}", "nodes=[390]"], "overrides 'factors={nodes:[144]}' and 'nodes=[390]' "
                                               "both name nodes"),
])
def test_a_key_repeated_inside_a_mapping_value_is_refused(results, overrides, said):
    """Hydra's parser kept the last of a key repeated inside ``{...}`` (and the mapping's key beside
    the bare factor): ``show`` exited 0 with ``nodes [1]: 390``."""
    refused(results, ["show", "smoke", *overrides, "--root", results],
            f"{said}; give it once (Hydra would keep the last silently).")


def test_a_mapping_value_with_distinct_keys_composes(results):
    shown = invoke("show", "smoke", "factors={nodes:[144],shape:[sphere]}", "model={lambda1:1.5,n_exp:0.5}",
                   "--root", results)
    assert shown.exit_code == 0, shown.output
    assert "nodes [1]: 144" in shown.stdout and "shape [1]: sphere" in shown.stdout


@pytest.mark.parametrize(("name", "file_type", "message"), [
    # it said "cannot be read as PLY (Not a ply file!)."
    ("sphere.ply", "obj", "is not a PLY file: it looks like an OBJ file (text with vertex lines "
                          "'v x y z'); rename it to .obj."),
    # these two said "... bytes are neither a binary STL (84 bytes plus 50 per triangle) nor an
    # ASCII STL (text starting with 'solid')."
    ("sphere.stl", "obj", "is not an STL file: it looks like an OBJ file (text with vertex lines "
                          "'v x y z'); rename it to .obj."),
    ("sphere.stl", "ply", "is not an STL file: it looks like a PLY file (its first line is 'ply'); "
                          "rename it to .ply."),
])
def test_a_mesh_saved_under_another_formats_suffix_is_named_by_the_format_it_holds(
        tmp_path, name, file_type, message):
    path = tmp_path / name
    exported = trimesh.creation.icosphere(subdivisions=2, radius=40.0).export(file_type=file_type)
    path.write_bytes(exported.encode() if isinstance(exported, str) else exported)  # OBJ is text
    refused(tmp_path, ["plan", path, "--mass-kg", "0.1"], f"mesh {name!r} {message}")
