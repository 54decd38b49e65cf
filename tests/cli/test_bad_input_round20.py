"""Bad input, round 20: new users' wrong inputs (docs/decisions.md, "Bad input, round 20", lists
every one tried). Each is one sentence naming what is wrong and where, exit 2, nothing stored
changed (``cli_checks.refused``).
"""

from __future__ import annotations

import pytest
from cli_checks import HEADER, T2, filled_records, invoke, refused

#: the factors of the one-trial mesh_features study the study-file tests write
FACTORS = "factors: {shape: [sphere], nodes: [144]}\n"


@pytest.mark.parametrize(("line", "said"), [
    ('"seeds ": 2', "the key 'seeds ' ends with a space, which no setting's name has; write 'seeds'"),
    ('" seeds": 2', "the key ' seeds' begins with a space, which no setting's name has; write 'seeds'"),
    ('runner: {"n_jobs ": 2}',
     "the key 'n_jobs ' ends with a space, which no setting's name has; write 'n_jobs'"),
    ('"": 2', "the key '' is empty, and no setting is named so; write the name of the setting"),
    ('"  ": 2', "the key '  ' is only spaces, and no setting is named so; write the name of the "
                "setting")])
def test_a_study_file_key_empty_or_with_a_space_at_an_end_is_named_as_written(tmp_path, line, said):
    """Quoted, YAML keeps the space: it was "seeds  is not a known key of the study config; did
    you mean seeds?", the space unseen, and an empty key was "mine.yaml:  is not a known key"."""
    study = tmp_path / "mine.yaml"
    study.write_text(f"{HEADER}name: mine\nkind: mesh_features\n{line}\n{FACTORS}")
    refused(tmp_path, ["show", study, "--root", tmp_path / "results"], f"{study}, line 5: {said}.")


#: why two study names may not differ only in case, as each refusal says it
ONE_DIRECTORY = ("runs are stored and reported by their study's name, and on a file system that "
                 "ignores case (macOS, Windows, a USB stick) the directories {0}/ and {1}/ are one")


def test_a_study_renamed_to_its_own_name_in_other_case_is_refused(tmp_path):
    """It ran, stored as results/SMOKE/ beside results/smoke/: one directory on macOS."""
    refused(tmp_path, ["show", "smoke", "name=SMOKE", "--root", tmp_path],
            f"override 'name=SMOKE' differs only in case from the study's own name smoke: "
            f"{ONE_DIRECTORY.format('SMOKE', 'smoke')}, so this run would be taken for one of "
            "smoke's; leave the override out, or give a name that differs in more than case.")


def test_a_study_renamed_after_another_study_but_for_case_is_refused(tmp_path):
    """``name=baseline_grid`` was refused (round 14), ``name=Baseline_Grid`` ran."""
    refused(tmp_path, ["show", "smoke", "name=Baseline_Grid", "--root", tmp_path],
            "override 'name=Baseline_Grid' names the study Baseline_Grid, which differs only in "
            "case from the study baseline_grid (campaigns/baseline_grid.yaml): "
            f"{ONE_DIRECTORY.format('Baseline_Grid', 'baseline_grid')}, so this run of smoke would "
            "be taken for one of baseline_grid's; give a name that differs in more than case from "
            "every study's (graspcampaign list shows them).")


def test_a_study_file_of_ones_own_named_as_a_tool_study_but_for_case_is_refused(user_dir, tmp_path):
    """Smoke.yaml beside the tool's smoke was listed, shown and run (results/Smoke/ beside
    results/smoke/); now it is listed as broken, the tool's smoke still runnable."""
    study = user_dir / "Smoke.yaml"
    study.write_text(f"{HEADER}name: Smoke\nkind: mesh_features\n{FACTORS}")
    said = (f"{study}, line 3: name: Smoke differs only in case from the study smoke "
            f"(campaigns/smoke.yaml): {ONE_DIRECTORY.format('Smoke', 'smoke')}; rename the study "
            "(its file and its name:) to one that differs in more than case.")
    for named in ("Smoke", study):
        refused(tmp_path, ["show", named, "--root", tmp_path], said)
    listed = invoke("list", "--names")
    assert listed.exit_code == 0 and listed.stderr == f"warning: study Smoke is broken: {said}\n"
    shown = invoke("show", "smoke", "--root", tmp_path)
    assert shown.exit_code == 0 and shown.stderr == "", shown.output


@pytest.mark.parametrize("command", [["run", "smoke"], ["report"], ["status", "smoke"]])
def test_a_root_that_is_the_tools_configs_place_is_refused(home, command):
    """A source checkout (or a GRASPCAMPAIGN_HOME) given as the results root took the runs among
    its files, and `report` of it then wrote one line for each of its files (66 for the checkout:
    "the report of tests/test_api.py could not be written: run tests/test_api.py at ... is a file,
    not a run directory ...")."""
    refused(home, [*command, "--root", home],
            f"--root {home}: it holds conf/config.yaml and campaigns/, the tool's configs (a source "
            "checkout or a GRASPCAMPAIGN_HOME), so runs stored there would lie among its files; give "
            f"a folder for the results instead, such as {home / 'results'}.")


@pytest.mark.parametrize(("inside", "what"), [("campaigns", "study files"),
                                              ("conf/model", "config groups")])
def test_a_root_among_the_tools_config_files_is_refused(home, inside, what):
    place = home / inside.split("/")[0]
    said = "" if inside == place.name else "inside "
    refused(home, ["run", "smoke", "--root", home / inside],
            f"--root {home / inside}: it is {said}{place}, the tool's {what}, so runs stored there "
            f"would lie among them; give a folder for the results instead, such as "
            f"{home / 'results'}.")


def test_list_extensions_without_names_is_refused(tmp_path):
    """It printed the table of every study, as if it were not given."""
    refused(tmp_path, ["list", "--extensions"],
            "--extensions chooses which names --names prints (graspcampaign list --names "
            "--extensions: the studies the paper does not run); the table lists every study, each "
            "marked paper or extension in its 'of' column, so give --names with it or leave it out.")


@pytest.mark.parametrize("study", ["test2_grasp", "test3_disturbance"])
def test_a_trial_id_in_other_case_is_named_as_the_schedules(tmp_path, study):
    """As Test 1's event ids are (round 17); it was "... is not in the schedule", nothing more."""
    sheet = filled_records(tmp_path, study, rows=slice(0, 1))
    typed = sheet.loc[0, "trial_id"].upper()
    sheet.assign(trial_id=typed).to_csv(tmp_path / "measured.csv", index=False)
    root = tmp_path / "results"
    refused(root, ["ingest", study, tmp_path / "measured.csv", *T2, "--root", root],
            f"measured.csv, row 1, column 'trial_id': trial id '{typed}' is not in the schedule "
            f"(trial ids are case-sensitive: '{sheet.loc[0, 'trial_id']}'?).")


@pytest.mark.parametrize("command", ["status", "report", "show", "run"])
def test_a_study_and_run_given_as_the_results_directory_spells_them_are_told_apart(results, command):
    """``status smoke/default`` was "study 'smoke/default' is a path; give the study's name (the
    value of name: in the study file; default if the file is named after it) ...", naming the run
    as the study; ``run smoke/default`` was "study file smoke/default does not exist"."""
    refused(results, [command, "smoke/default", "--root", results],
            "study 'smoke/default' names a study and a run, as the results directory spells them; "
            "give the study's name and the run apart: smoke --run default.")


#: how a refused override of a config group says what to write instead
CHOOSE = "choose one of its options ({0}=OPTION; options: {1})"
MODELS, RUNNERS = "firm, nominal, table2", "dask, local"


@pytest.mark.parametrize(("override", "said"), [
    ("model=null", f"gives the config group model null, which is no option; "
                   f"{CHOOSE.format('model', MODELS)}."),
    ("runner=NULL", f"gives the config group runner null, which is no option; "
                    f"{CHOOSE.format('runner', RUNNERS)}."),
    ("+model=firm", "adds the config group model, which every study has already (conf/config.yaml "
                    f"chooses its option); {CHOOSE.format('model', MODELS)} without the '+': "
                    "model=firm."),
    ("++runner=dask", "adds the config group runner, which every study has already "
                      f"(conf/config.yaml chooses its option); {CHOOSE.format('runner', RUNNERS)} "
                      "without the '++': runner=dask."),
    ("model=${seed}", "chooses the option of config group model by ${seed}, a key of the study, but "
                      "a group's option is chosen before the study is composed; "
                      f"{CHOOSE.format('model', MODELS)}.")])
def test_an_override_of_a_config_group_hydra_would_misread_is_refused_in_words(tmp_path, override,
                                                                               said):
    """Each was Hydra's own: "Config group override must be a string or a list. Got NoneType.",
    "Multiple values for model. To override a value use 'override model: firm'.", "force-add of
    config groups is not supported: '++runner=dask'.", "_dummy_ refers to ${seed}, which is not a
    key of the study config." (a key of Hydra's own)."""
    refused(tmp_path, ["show", "baseline_grid", override, "--root", tmp_path],
            f"override {override!r} {said}")


def test_compare_with_given_on_the_command_line_is_named_as_the_override(tmp_path):
    """Both named the study file alone, which does not set compare_with: "campaigns/
    baseline_grid.yaml: compare_with = 'nosuch' is not a study ..." and "/…/campaigns/
    baseline_grid.yaml: compare_with = smoke is a study of trial kind mesh_features, ..."."""
    refused(tmp_path, ["show", "baseline_grid", "compare_with=nosuch", "--root", tmp_path],
            "campaigns/baseline_grid.yaml with override compare_with=nosuch: compare_with = 'nosuch' "
            "is not a study with paper values; allowed: ablation, baseline_grid, dynamic_check, "
            "friction_mass, gravity_settle, heuristic_weights, mesh_resolution, pso_repeatability, "
            "sensitivity, shapes, smoke, surrogate, test1_bench, test2_grasp, test3_disturbance, "
            "wrench_balance.")
    refused(tmp_path, ["show", "baseline_grid", "compare_with=smoke", "--root", tmp_path],
            "override 'compare_with=smoke': compare_with = smoke is a study of trial kind "
            "mesh_features, and this study's kind is quasi_static: it would be reported with smoke's "
            "report, which reads mesh_features records; compare with a study of kind quasi_static "
            "(ablation, baseline_grid, shapes) or leave compare_with out.")


@pytest.mark.parametrize(("override", "said"), [
    ("mass_kg=[0.2,false]", "factors.mass_kg[1] must be of type float, got false (a boolean)."),
    ("shape=[true]", "factors.shape[0] must be of type str, got true (a boolean).")])
def test_true_or_false_among_a_factors_levels_is_named_as_typed(tmp_path, override, said):
    """Round 19 mended it for a single value; a level of a list was still "got False (bool)",
    Python's spelling, which the user never typed."""
    refused(tmp_path, ["show", "baseline_grid", override, "--root", tmp_path], said)


def test_true_among_a_study_files_levels_is_named_as_written(tmp_path):
    study = tmp_path / "mine.yaml"
    study.write_text(f"{HEADER}name: mine\nkind: mesh_features\n"
                     "factors: {shape: [sphere], nodes: [true]}\n")
    refused(tmp_path, ["show", study, "--root", tmp_path / "results"],
            f"{study}, line 5: factors.nodes[0] must be of type int, got true (a boolean).")
