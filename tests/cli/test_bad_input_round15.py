"""Bad input, round 15: rough edges of the last rounds (a mesh unit refused without its option and
report formats separated by spaces are tested beside their kin in ``test_rough_edges``). A study
file ending in upper-case .YAML, a run named as another but for case, a foreign file's trace rows
dropped in silence, preparations lost from a run whose PSO settings drifted. Each refusal: exit 2,
one sentence naming what is wrong, where, and what to write, nothing stored changed
(``refused``)."""

from __future__ import annotations

import shutil

import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from cli_checks import (
    BG,
    BG_QUOTED,
    SMOKE,
    grid_run,
    invoke,
    mesh_study,
    refused,
    replaced,
    resume_grid,
    resumed,
)

from graspcampaign.campaign.records import RunStore, _write_atomic

#: a one-trial mesh study (sphere, 144 nodes) run in this process
ONE = "seed: 0\nseeds: 1\nfactors: {shape: [sphere], nodes: [144]}\nrunner: {backend: sequential}\n"

MISCASED = ("is not read: a study file's name ends in .yaml or .yml in lower case, as the study search "
            "path and Hydra's look for it (the case of a file name matters on Linux);")


@pytest.mark.parametrize("suffix", [".YAML", ".Yml"])
def test_a_study_file_ending_in_upper_case_is_told_the_case_matters(tmp_path, user_dir, suffix):
    # "must end in .yaml or .yml" to a file ending in .YAML; on GRASPCAMPAIGN_PATH it was passed
    # over, and its study said to be unknown among the others
    path = mesh_study(user_dir, ONE).rename(user_dir / f"mine{suffix}")
    lower = f"mine{suffix.lower()}"
    refused(tmp_path, ["show", path, "--root", tmp_path],
            f"study file {path} {MISCASED} rename it {lower}.")
    refused(tmp_path, ["show", "mine", "--root", tmp_path],
            f"unknown study 'mine': the file {path} {MISCASED} rename it {lower}.")
    # status and report take a study's name: a path is told so, whatever its suffix's case
    refused(tmp_path, ["status", path.name, "--root", tmp_path],
            f"study '{path.name}' is a path; give the study's name (the value of name: in the "
            "study file; mine if the file is named after it), under which its runs are stored.")
    path.rename(user_dir / lower)
    assert invoke("show", "mine", "--root", tmp_path).exit_code == 0


def test_a_new_run_named_as_another_but_for_case_is_refused_naming_it(results):
    # --run Default made results/smoke/Default beside results/smoke/default: one directory on
    # macOS, Windows or a USB stick, where the second run's trials joined the first's records
    smoke = results / "smoke"
    refused(results, ["run", "smoke", *SMOKE, "--run", "Default", "--root", results],
            f"run smoke/Default at {smoke / 'Default'}: its name differs only in case from "
            f"{smoke / 'default'}, which is there already, and on a file system that ignores case "
            "(macOS, Windows, a USB stick) the two are one directory; to add to that run, give --run "
            "default; for a new one, give a run name that differs in more than case.")
    # the run itself resumes, and a name that differs in more than case is a run of its own
    for run in ("default", "Default2"):
        assert invoke("run", "smoke", *SMOKE, "--run", run, "--root", results).exit_code == 0


def test_an_ingest_into_a_run_named_as_a_folder_there_but_for_case_is_refused(results, tmp_path):
    # ingest makes runs too (its default run, measured); a folder that is no run is named as such
    (results / "test2_grasp" / "Measured").mkdir(parents=True)
    (sheet := tmp_path / "rig.csv").write_text("trial_id\n")
    where = results / "test2_grasp"
    refused(results, ["ingest", "test2_grasp", sheet, "--root", results],
            f"run test2_grasp/measured at {where / 'measured'}: its name differs only in case from "
            f"{where / 'Measured'}, which is there already, and on a file system that ignores case "
            "(macOS, Windows, a USB stick) the two are one directory; give a run name that differs "
            "in more than case.")


def test_ctrl_c_before_a_command_starts_is_said_as_within_one(monkeypatch, capsys):
    # main()'s own handler is not dead under Typer 0.29: Typer's try begins after it builds the
    # click command (get_command) and answers a completion request, so a Ctrl-C there reaches
    # main(), which said "interrupted" where every command says "interrupted (Ctrl-C)."
    import typer.main

    from graspcampaign.cli.main import main

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(typer.main, "get_command", interrupted)
    monkeypatch.setattr("sys.argv", ["graspcampaign", "list"])
    with pytest.raises(BaseException) as stopped:  # noqa: PT011  (without the handler, the Ctrl-C itself)
        main()
    assert stopped.type is SystemExit, "main() let the Ctrl-C through (a traceback)"
    assert (stopped.value.code, *capsys.readouterr()) == (130, "", "interrupted (Ctrl-C).\n")


def test_a_trace_file_of_trials_outside_the_design_is_moved_aside_as_a_records_file_is(results):
    # its rows were dropped on resume as a killed run's leftovers (traces of trials with no
    # record): the file rewritten to nothing, i.e. deleted, and not a word said, where a records
    # file of such trials is moved to quarantine/ with a warning
    (own,) = (grid_run(results) / "tables" / "candidates").glob("*.parquet")
    outside = "sphere_0.2_0.3_heuristic_s0-0123456789"
    table = pq.read_table(own)
    foreign = own.with_name("part-eeeeeeeeee.parquet")
    _write_atomic(table.set_column(0, "trial_id", pa.array([outside] * table.num_rows))
                  .replace_schema_metadata(None), foreign)  # as the tool writes a file
    kept = foreign.read_bytes()
    repaired, target = resumed(results, foreign, f"traces of 1 trial not in the study's design ({outside})")
    assert "2 trials, 2 already recorded, 0 ran" in repaired.stdout
    assert target.read_bytes() == kept
    assert [p.name for p in own.parent.iterdir()] == [own.name]


def test_preparations_lost_are_not_computed_again_under_other_pso_settings(results):
    # resumed with --allow-drift after prepared/ was lost, the run computed the body's PSO
    # identification again with the new pso.n_particles, while its recorded trials used the old
    run = grid_run(results)
    (body,) = RunStore(run).read("prepared", ["body_id"]).column("body_id").to_pylist()
    shutil.rmtree(run / "prepared")
    drifted = ["run", "baseline_grid", *replaced(BG, "pso.n_particles=3"), "--allow-drift", "--root", results]
    lost = (f"run baseline_grid/default at {run} has lost 1 preparation its recorded trials used "
            f"(first body {body}), which this session cannot compute again as they were: ")
    new = "start a new run for this config (output.run=NAME or --run NAME)."
    refused(results, drifted, f"{lost}they were computed with the settings the run was started with "
                              f"(pso.n_particles 2 -> 3); resume it as started (graspcampaign run "
                              f"baseline_grid {BG_QUOTED} --run default --root {results}) to compute "
                              f"them again as they were, or {new}")
    # the advice works: resumed as started, the preparation is computed as it was, and then the
    # drift runs; a drift of the design alone computes it as it was too
    assert resume_grid(results).stderr == (
        f"warning: run baseline_grid/default at {run} has no prepared directory, which holds the "
        "preparations of the 1 body its recorded trials used; it is computed again\n")
    assert invoke(*drifted).exit_code == 0
    shutil.rmtree(run / "prepared")
    # which of the run's two configs computed it is not kept
    refused(results, drifted, f"{lost}its sessions ran more than one config, and which computed each "
                              f"is not kept; {new}")


def test_preparations_lost_are_computed_again_in_a_drift_of_the_design_alone(results):
    run = grid_run(results)
    shutil.rmtree(run / "prepared")
    alone = invoke("run", "baseline_grid", *replaced(BG, "planner=[heuristic]"), "--allow-drift",
                   "--root", results)
    assert alone.exit_code == 0, alone.output
    assert "1 trial, 1 already recorded, 0 ran" in alone.stdout
    assert (run / "prepared").is_dir()


def test_show_reads_a_source_runs_design_under_its_own_root(results, tmp_path, monkeypatch):
    # the catalog kept dynamic_check's design size by its config hash, which leaves output.root
    # out: once a show under one root had read its source run, show under an empty root found
    # that run's design (test_rough_edges::test_show_describes_a_study_whose_source_run_is_missing
    # failed so, after another test's show, through the test suite's shared catalog)
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(tmp_path / "cache"))
    (empty := tmp_path / "empty").mkdir()
    known = invoke("show", "dynamic_check", "--root", results)
    assert known.exit_code == 0, known.output
    assert known.stdout.splitlines()[6].startswith("design: the protocol's schedule = ")
    waiting = invoke("show", "dynamic_check", "--root", empty)
    assert waiting.exit_code == 0, waiting.output
    assert waiting.stdout.splitlines()[6].startswith(
        "design: not known until its source run is recorded: dynamic_check re-simulates the "
        f"records of baseline_grid/default, but {empty}/baseline_grid/default holds no run; ")


def test_a_tool_study_given_another_kind_by_override_blames_the_override(tmp_path):
    """``smoke kind=surrogate`` was told that smoke's own file 'takes the name of the tool's study
    smoke, which it hides', and to rename it: the override changed the kind, not a file."""
    refused(tmp_path, ["show", "smoke", "kind=surrogate", "--root", tmp_path],
            "kind = surrogate: smoke is a study of trial kind mesh_features, and it would be reported "
            "with smoke's report, which reads mesh_features records; give a study of another kind a "
            "study file of its own.")
