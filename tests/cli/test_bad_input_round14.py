"""Bad input, round 14: a new researcher's first hour. A study file that says where its runs go
(``output.root``), a run renamed after another study, a study compared with (or hiding) one of
another trial kind, a zip group of one factor, a name of non-ASCII letters, Ctrl-C outside a run.
Each refusal: exit 2, one sentence naming what is wrong, where, and what to write, nothing stored
changed (``refused``)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from cli_checks import HEADER, SMOKE, invoke, mesh_study, refused, snapshot

import graspcampaign as gc

#: a one-trial mesh study (sphere, 144 nodes) run in this process
ONE = "seed: 0\nseeds: 1\nfactors: {shape: [sphere], nodes: [144]}\nrunner: {backend: sequential}\n"


def test_status_and_report_find_the_run_where_its_study_file_stores_it(tmp_path, user_dir, monkeypatch):
    # the study file's output.run was read and its output.root was not: status and report looked
    # under results/ and said "run `graspcampaign run mine` first", which had just been done
    monkeypatch.chdir(tmp_path)
    mesh_study(user_dir, ONE + "output: {root: elsewhere, run: r1}\n")
    assert invoke("run", "mine").exit_code == 0
    status = invoke("status", "mine", "--json")
    assert status.exit_code == 0, status.output
    assert json.loads(status.stdout)["path"] == "elsewhere/mine/r1"
    report = invoke("report", "mine")
    assert report.exit_code == 0, report.output
    assert report.stdout.splitlines()[0] == "report: elsewhere/mine/r1/report/report.md"
    assert gc.load_records("mine")["status"].tolist() == ["ok"]
    # --root still names another root, and the command said to make a run missing there makes it
    # there (`graspcampaign run mine` stores it under the file's output.root)
    refused(tmp_path, ["status", "mine", "--root", "results"],
            "no run at results/mine/r1; run `graspcampaign run mine --root results` first.")
    assert not (tmp_path / "results").exists()


def test_a_report_of_studies_stored_under_different_roots_asks_for_one(tmp_path, user_dir, monkeypatch):
    monkeypatch.chdir(tmp_path)
    mesh_study(user_dir, ONE + "output: {root: elsewhere}\n")
    assert invoke("run", "smoke", "shape=[sphere]", "nodes=[144]", "runner.backend=sequential").exit_code == 0
    assert invoke("run", "mine").exit_code == 0
    refused(tmp_path, ["report", "smoke", "mine"],
            "the studies named are stored under different results roots (their output.root: smoke "
            "under results, mine under elsewhere), and one report writes one root's index; report "
            "them one root at a time, with --root.")


@pytest.mark.parametrize("command", ["show", "run"])
def test_a_run_renamed_after_another_study_is_refused_naming_that_study(tmp_path, command):
    # baseline_grid renamed smoke was stored as results/smoke/default, among smoke's runs, and
    # `report smoke` then read its quasi-static records with smoke's report (exit 1, an item failed)
    refused(tmp_path, [command, "baseline_grid", "name=smoke", "--root", tmp_path],
            "override 'name=smoke' names the study smoke (campaigns/smoke.yaml): runs are stored "
            "and reported by their study's name, so this run of baseline_grid would be taken for "
            "one of smoke's; give a name no study has (graspcampaign list shows them).")


def test_a_run_renamed_after_a_study_of_ones_own_is_refused_and_a_new_name_runs(tmp_path, user_dir):
    mesh_study(user_dir, ONE)
    refused(tmp_path, ["show", "smoke", "name=mine", "--root", tmp_path],
            f"override 'name=mine' names the study mine ({user_dir / 'mine.yaml'}): runs are stored "
            "and reported by their study's name, so this run of smoke would be taken for one of "
            "mine's; give a name no study has (graspcampaign list shows them).")
    # a name of its own, or the study's own name, is taken
    for name in ("smoke_again", "smoke"):
        assert invoke("show", "smoke", f"name={name}", "--root", tmp_path).exit_code == 0
    assert invoke("show", "mine", "name=mine", "--root", tmp_path).exit_code == 0


def _interrupt(*args, **kwargs):
    raise KeyboardInterrupt


@pytest.mark.parametrize("command", [["report", "smoke"], ["run", "smoke", "--report"]])
def test_ctrl_c_while_reports_are_written_says_what_it_leaves(results, monkeypatch, command):
    # it exited 130 saying nothing: Typer turns a KeyboardInterrupt into a silent exit 130, so the
    # "interrupted" of main() was never printed
    from graspcampaign.report import build

    before = _pages(results)
    monkeypatch.setattr(build, "report_run", _interrupt)
    result = invoke(*command, *(SMOKE if command[0] == "run" else []), "--root", results)
    assert result.exit_code == 130
    assert result.stderr == ("interrupted: each report file written so far is whole (written in "
                             "full, then put in place) and the rest are not written; run the "
                             "command again to write them.\n")
    assert _pages(results) == before  # (`run` adds its session to the run's manifest)


def _pages(root):
    """What a report writes under ``root``: each run's report/ and the root's pages."""
    return {k: v for k, v in snapshot(root).items() if "/report" in k or "/" not in k}


def test_ctrl_c_in_any_other_command_is_said(results, monkeypatch):
    from graspcampaign.campaign import status

    monkeypatch.setattr(status, "run_status", _interrupt)
    result = invoke("status", "smoke", "--root", results)
    assert (result.exit_code, result.stderr, result.stdout) == (130, "interrupted (Ctrl-C).\n", "")


@pytest.mark.parametrize("name", ["étude", "mesh_ü"])
def test_a_name_with_a_letter_beyond_ascii_is_told_the_letters_are_ascii(tmp_path, name):
    # "use letters, digits, ..." refused é, which is a letter, without saying which letters it meant
    refused(tmp_path, ["show", "smoke", "--run", name, "--root", tmp_path],
            f"--run = {name!r} is not allowed; use ASCII letters (a-z, A-Z), digits, '.', '_' and "
            "'-' (starting with a letter or digit, at most 100), so the run stays inside the "
            "results directory.")


@pytest.mark.parametrize(("zipped", "said"), [
    # an empty group and a group of one were taken ("zipped: " with nothing after it)
    ("[[]]", "zip[0] names no factor; a zip group advances two or more factors together, level "
     "by level (e.g. zip: [[shape, nodes]]), or leave zip out."),
    ("[[shape]]", "zip[0] names only shape; a zip group advances two or more factors together, "
     "level by level (e.g. zip: [[shape, nodes]]), or leave zip out."),
    # a factor named twice in one group was said to be "already zipped"
    ("[[shape, nodes, shape]]", "zip[0] names shape twice; give each factor once."),
])
def test_a_zip_group_of_fewer_than_two_factors_is_refused(tmp_path, user_dir, zipped, said):
    path = mesh_study(user_dir, "seed: 0\nseeds: 1\nfactors: {shape: [sphere, pear], nodes: [144, 390]}\n"
                                f"zip: {zipped}\n")
    refused(tmp_path, ["show", "mine", "--root", tmp_path], f"{path}, line 8: {said}")


def test_comparing_with_a_study_of_another_trial_kind_is_refused(tmp_path, user_dir):
    # a quasi-static study compared with smoke was reported with smoke's report: its mesh tables
    # empty (no such columns) and "sharp vertices on the sphere: 0, matches as printed" of a run
    # that built no mesh feature at all
    path = user_dir / "mine.yaml"
    path.write_text(HEADER + "name: mine\nkind: quasi_static\ncompare_with: smoke\nseed: 0\nseeds: 1\n"
                    "factors: {shape: [sphere], mass_kg: [0.4], mu: [0.3], planner: [heuristic]}\n"
                    "paper: {sphere_sharp_vertices: 0, sphere_sharp_edges: 0}\n")
    refused(tmp_path, ["run", "mine", "--root", tmp_path],
            f"{path}, line 5: compare_with = smoke is a study of trial kind mesh_features, and this "
            "study's kind is quasi_static: it would be reported with smoke's report, which reads "
            "mesh_features records; compare with a study of kind quasi_static (ablation, "
            "baseline_grid, shapes) or leave compare_with out.")


def test_a_file_hiding_a_tool_study_of_another_kind_is_refused(tmp_path, user_dir):
    # with baseline_grid's paper block copied (as the message of a missing block advises) a
    # mesh_features file named baseline_grid ran, to be reported with baseline_grid's report
    paper = (Path(__file__).parents[2] / "campaigns" / "baseline_grid.yaml").read_text().split("paper:")[1]
    path = user_dir / "baseline_grid.yaml"
    path.write_text(HEADER + "name: baseline_grid\nkind: mesh_features\n" + ONE + "paper:" + paper)
    refused(tmp_path, ["show", "baseline_grid", "--root", tmp_path],
            f"{path}: this file takes the name of the tool's study baseline_grid "
            "(campaigns/baseline_grid.yaml), of trial kind quasi_static, which it hides, and its kind "
            "is mesh_features: it would be reported with baseline_grid's report, which reads "
            "quasi_static records; give your study a name of its own.")


@pytest.mark.parametrize("command", ["show", "run"])
def test_an_empty_output_root_in_a_study_file_is_refused_with_its_line(tmp_path, user_dir, monkeypatch,
                                                                      command):
    # show took it (the run "at mine/r1" in the current directory); run refused it without the file
    monkeypatch.chdir(tmp_path)
    path = mesh_study(user_dir, ONE + "output: {root: '', run: r1}\n")
    refused(tmp_path, [command, "mine"],
            f"{path}, line 9: output.root is empty; give the results directory (for example "
            "results): an empty root would mean the current directory.")


def test_show_refuses_an_output_root_run_refuses(tmp_path):
    # a file, or a run's directory, given as output.root: show printed a run under it
    (tmp_path / "notes.txt").write_text("mine")
    for command in ("show", "run"):
        refused(tmp_path, [command, "smoke", f"output.root={tmp_path / 'notes.txt'}"],
                f"output.root {tmp_path / 'notes.txt'}: is a file, not a directory.")


def test_an_alias_of_no_anchor_is_named_as_one(tmp_path, user_dir):
    # *nope (no &nope anywhere) was said to repeat "a value given elsewhere"
    path = mesh_study(user_dir, "seed: 0\nseeds: 1\nfactors: {shape: *nope, nodes: [144]}\n")
    refused(tmp_path, ["show", "mine", "--root", tmp_path],
            f"{path}, line 7: the alias *nope names no anchor (&nope) before it, and aliases are "
            "not read (expanded, a few can make billions of values); write the value out.")
