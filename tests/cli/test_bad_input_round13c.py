"""Bad input, round 13: what its left-overs left. An output file named only by a format suffix, for
every option naming a file to write, and the overrides of a numeric factor's level or a factor's
level deleted by its bare name; later, a number in an override written with an underscore. Each
refusal: exit 2, one sentence naming what is wrong, where, and what to write, nothing stored
changed (``refused``)."""

from __future__ import annotations

import pytest
from cli_checks import invoke, mesh_study, refused

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


@pytest.mark.parametrize("typed", ["factors.nodes.0=0144", "nodes.0=0144"])
def test_a_numeric_factors_level_with_a_leading_zero_is_not_told_to_quote_it(tmp_path, typed):
    # a level of nodes was looked up as the factor "nodes.0", none, and told to "quote it ('0144')
    # to mean text", which nodes refuses: its levels are whole numbers
    refused(tmp_path, ["show", "smoke", typed, "--root", tmp_path],
            f"override {typed!r}: 0144 has a leading zero, which Hydra reads as the text '0144', "
            "not the number 144; write 144.")


def test_a_text_factors_level_with_a_leading_zero_may_be_quoted(tmp_path):
    refused(tmp_path, ["show", "smoke", "shape.0=0144", "--root", tmp_path],
            "override 'shape.0=0144': 0144 has a leading zero, which Hydra reads as the text "
            "'0144', not the number 144; write 144, or quote it ('0144') to mean text.")


@pytest.mark.parametrize(("typed", "factor", "level"), [
    ("~shape.0", "shape", "0"),  # said "deletes shape.0, which this study does not have"
    ("~nodes.1", "nodes", "1"),
    ("~factors.shape.0", "shape", "0"),  # said "list indices must be integers or slices, not str."
])
def test_a_factors_level_deleted_by_its_index_is_refused_naming_the_level(tmp_path, typed, factor,
                                                                         level):
    refused(tmp_path, ["show", "smoke", typed, "--root", tmp_path],
            f"override {typed!r} deletes level {level} of the factor {factor} "
            f"(factors.{factor}.{level}), but a level cannot be deleted by its index (Hydra deletes "
            f"no item of a list); give the levels to keep instead, as {factor}=[...].")


def test_a_deleted_level_of_a_factor_the_study_lacks_has_nothing_to_delete(tmp_path):
    refused(tmp_path, ["show", "smoke", "~planner.0", "--root", tmp_path],
            "override '~planner.0' deletes planner.0, which this study does not have, so there is "
            "nothing to delete; leave it out.")


@pytest.mark.parametrize(("typed", "word", "read", "end"), [
    ("seeds=1_0", "1_0", "10", "."),  # ran ten seeds per scene
    ("seeds='1_0'", "1_0", "10", "."),  # quoted, OmegaConf's int() read it so too
    ("nodes=[144,1_750]", "1_750", "1750", "."),
    ("evaluator.alpha=0.1_5", "0.1_5", "0.15", "."),
    ("shape.0=1_0", "1_0", "10", ", or quote it ('1_0') to mean text."),  # a text factor's level
])
def test_a_number_written_with_an_underscore_is_refused_naming_what_it_reads_as(tmp_path, typed, word,
                                                                                read, end):
    # Hydra's grammar (and Python's int) read the underscore as grouping digits: seeds=1_0 ran 10
    # seeds, where a measured cell 1_4 is refused as a typo
    refused(tmp_path, ["show", "smoke", typed, "--root", tmp_path],
            f"override {typed!r}: {word} has an underscore, which is read as grouping digits, the "
            f"number {read}; write the value without it ({read}, if that is what you meant){end}")


@pytest.mark.parametrize("typed", ["description=run_1_0", "description='1_0'"])
def test_an_underscore_in_text_is_no_number(tmp_path, typed):
    done = invoke("show", "smoke", typed, "--root", tmp_path)
    assert done.exit_code == 0, done.output


@pytest.mark.parametrize(("lines", "said"), [
    # YAML 1.1 (PyYAML, OmegaConf) reads an underscore between digits as grouping them: each was
    # taken as the number, as an override's was before check_overrides refused it
    ("seeds: 1_0", "line 5: seeds = 1_0 has an underscore, which YAML reads as grouping digits, the "
     "number 10; write the number without it (10, if that is what you meant), or '1_0' in quotes "
     "to mean text."),
    ("seeds: 1_000", "line 5: seeds = 1_000 has an underscore, which YAML reads as grouping digits, "
     "the number 1000; write the number without it (1000, if that is what you meant), or '1_000' "
     "in quotes to mean text."),
    ("factors:\n  shape: [sphere]\n  nodes: [144, 1_750]", "line 7: factors.nodes[1] = 1_750 has an "
     "underscore, which YAML reads as grouping digits, the number 1750; write the number without "
     "it (1750, if that is what you meant), or '1_750' in quotes to mean text."),
    ("description: -0.1_5", "line 5: description = -0.1_5 has an underscore, which YAML reads as "
     "grouping digits, the number -0.15; write the number without it (-0.15, if that is what you "
     "meant), or '-0.1_5' in quotes to mean text."),  # a text key got "-0.15"
])
def test_a_number_written_with_an_underscore_in_a_study_file_is_refused(results, user_dir, lines,
                                                                        said):
    path = mesh_study(user_dir, f"{lines}\n")
    for command in ("show", "run"):
        refused(results, [command, path, "--root", results], f"{path}, {said}")


@pytest.mark.parametrize("line", ["description: '1_0'", "description: run_1_0"])
def test_an_underscore_in_text_in_a_study_file_is_no_number(results, user_dir, line):
    path = mesh_study(user_dir, f"{line}\nfactors:\n  shape: [sphere]\n  nodes: [144]\n")
    done = invoke("show", path, "--root", results)
    assert done.exit_code == 0, done.output


@pytest.mark.parametrize(("args", "said"), [
    # Typer (pydantic) read each as Python's float() and int() do: 0.15, 10, 5.0, 10
    (["plan", "ball.obj", "--mass-kg", "0.1_5"], "--mass-kg 0.1_5 has an underscore, which is read "
     "as grouping digits, the number 0.15; write the number without it (0.15, if that is what you "
     "meant)."),
    (["plan", "ball.obj", "--mass-kg", "0.1", "--mu", "1_0"], "--mu 1_0 has an underscore, which is "
     "read as grouping digits, the number 10.0; write the number without it (10.0, if that is what "
     "you meant)."),
    (["plan", "ball.obj", "--mass-kg", "0.1", "--fingertip-radius-mm=5_0"], "--fingertip-radius-mm "
     "5_0 has an underscore, which is read as grouping digits, the number 50.0; write the number "
     "without it (50.0, if that is what you meant)."),
    (["report", "--jobs", "1_0"], "--jobs 1_0 has an underscore, which is read as grouping digits, "
     "the number 10; write the number without it (10, if that is what you meant)."),
    # what Typer cannot read is named as before
    (["plan", "ball.obj", "--mass-kg", "1__0"], "--mass-kg '1__0' is not a number; see graspcampaign "
     "plan --help."),
    (["report", "--jobs", "1.5"], "--jobs '1.5' is not a whole number; see graspcampaign report --help."),
])
def test_a_numeric_option_written_with_an_underscore_is_refused_naming_what_it_reads_as(tmp_path, args,
                                                                                       said):
    # the mesh is never looked for: the option is refused as the command line is read
    where = ["--root", tmp_path] if args[0] == "report" else []
    refused(tmp_path, [*args, *where], said)
