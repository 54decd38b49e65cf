"""Bad input, round 22: the rough edges round 21 left (docs/decisions.md, "Unread factors, an
unwritable report folder, and round 21's other leftovers (fact42)"). Each is one sentence naming what
is wrong and where, exit 2, nothing stored changed (``cli_checks.refused``).
"""

from __future__ import annotations

import os

import pytest
from cli_checks import immutable, invoke, mesh_study, refused, snapshot

from graspcampaign.campaign.kind import KINDS, get_kind


@pytest.mark.parametrize(("factors", "said"), [
    # smoke's kind builds meshes: mu was an axis, each trial run twice but for an unused column
    ("{shape: [sphere], nodes: [144], mu: [0.3, 0.5]}",
     "factor 'mu' is not read by the mesh_features kind (it reads shape, nodes); remove it or "
     "choose a kind that varies it."),
    ("{shape: [sphere], nodes: [144], planner: [random]}",
     "factor 'planner' is not read by the mesh_features kind (it reads shape, nodes); remove it or "
     "choose a kind that varies it.")])
def test_a_factor_the_kind_never_reads_in_a_study_file_is_refused(results, user_dir, factors, said):
    path = mesh_study(user_dir, f"seeds: 1\nfactors: {factors}\n")
    for command in ("show", "run"):
        refused(results, [command, path, "--root", results], f"{path}, line 6: {said}")


@pytest.mark.parametrize(("study", "override", "reads"), [
    ("smoke", "+factors.mu=[0.3]", "mesh_features kind (it reads shape, nodes)"),
    ("gravity_settle", "+factors.mu=[0.3]",
     "gravity_settle kind (it reads shape, mass_kg, nodes, integrator)"),
    ("wrench_balance", "+factors.planner=[random]",
     "wrench_balance kind (it reads shape, mass_kg, mu, nodes)"),
    ("surrogate", "+factors.mu=[0.3]", "surrogate kind (it reads no factor)")])
def test_a_factor_the_kind_never_reads_in_an_override_is_refused(results, study, override, reads):
    name = override.split(".")[1].split("=")[0]
    refused(results, ["show", study, override, "--root", results],
            f"factor {name!r} is not read by the {reads}; remove it or choose a kind that varies it.")


def test_every_shipped_cartesian_kind_declares_the_factors_it_reads():
    """``optional_factors=None`` (undeclared, as a kind registered by a test) skips the check: no
    shipped kind may leave it so, or its studies take any factor as an axis again."""
    undeclared = [name for name, target in KINDS.items() if target is not None
                  and get_kind(name).design is None and get_kind(name).optional_factors is None]
    assert undeclared == []


def test_a_whole_number_typed_with_a_trailing_point_is_echoed_readably(results):
    """``seeds=3.`` was echoed "got 3.." (the value as typed, then the sentence's full stop)."""
    refused(results, ["show", "smoke", "seeds=3.", "--root", results],
            "seeds must be a whole number, got 3. (with a decimal point).")


def test_a_schedule_out_stem_that_is_a_special_file_is_refused(results, tmp_path):
    """``--out`` names a stem (<stem>.csv and <stem>.parquet are written beside it): a stem that is
    itself a device or a named pipe is refused before any work, so no <device>.csv is written in
    /dev. A named pipe in a tmp folder stands for the device: nothing under /dev is touched."""
    pipe = tmp_path / "pipe"
    os.mkfifo(pipe)
    refused(tmp_path, ["schedule", "test2_grasp", "--out", pipe, "--root", results],
            f"--out {pipe}: is a named pipe (FIFO), not a regular file.")


def test_a_run_whose_report_folder_cannot_be_written_is_named_and_the_others_reported(results):
    """A report/ made immutable (a read-only share) was found only when report.md was written, after
    its figures: exit 1 and "report.md: operation not permitted"; it is now checked first, bad
    input (exit 2) naming the folder, and the other run is reported all the same."""
    folder = results / "smoke" / "default" / "report"
    before = snapshot(folder.parent)
    with immutable(folder):
        result = invoke("report", "--root", results)
        assert snapshot(folder.parent) == before
    assert result.exit_code == 2, result.output
    assert result.stderr == (
        f"error: the report of smoke/default could not be written: its report folder {folder}: "
        "cannot write there (Operation not permitted); make it writable for this user, or run the "
        "command as the user who owns the run\n")
    assert f"report: {results / 'baseline_grid' / 'default' / 'report' / 'report.md'}\n" in result.stdout


@pytest.mark.parametrize(("study", "override", "said"), [
    # the override's advice, "add it with +factors.mu=[0.3, 0.5]", led to a second refusal: the kind
    # never reads mu (a Cartesian kind's optional factors; a designed kind reads its design's only)
    ("smoke", "mu=[0.3]",
     "mu is not a factor of this study (override 'mu=[0.3]' rejected; its factors: nodes, shape), and the "
     "mesh_features kind does not read it (it reads shape, nodes)."),
    ("test3_disturbance", "mu=[0.3]",
     "mu is not a factor of this study (override 'mu=[0.3]' rejected; its factors: none), and the "
     "test3_disturbance kind does not read it (it reads no factor).")])
def test_an_override_is_not_advised_to_add_a_factor_the_kind_never_reads(tmp_path, study, override, said):
    refused(tmp_path, ["show", study, override, "--root", tmp_path], said)


def test_the_advice_to_add_a_factor_is_one_the_study_takes(tmp_path):
    """A factor the kind reads is advised with an example that composes: grip_law's was the placeholder
    [a, b], itself refused (grip_law takes paper, slip, oracle); the advice is followed here."""
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.errors import ConfigError

    with pytest.raises(ConfigError) as refusal:
        compose_study("baseline_grid", ["grip_law=[slip]", f"output.root={tmp_path}"])
    advice = str(refusal.value).rsplit("add it with ", 1)[1].rstrip(".")
    assert advice == "+factors.grip_law=[paper, slip]"
    study = compose_study("baseline_grid", [advice, f"output.root={tmp_path}"])
    assert study.factors["grip_law"] == ["paper", "slip"]
