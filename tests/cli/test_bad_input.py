"""Bad input, class by class: exit 2, the whole one-sentence message, nothing under results/ changed.

Each class is tried through every command that reads it (``show`` and ``run`` compose a study;
``status``, ``report`` and ``ingest`` take run names). Study files of a user's own live on the
config search path (``GRASPCAMPAIGN_PATH``) or are given as paths; broken group files need a
``GRASPCAMPAIGN_HOME`` of their own.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_checks import HEADER, invoke, refused, snapshot

from graspcampaign.campaign import studyfile

PROJECT = Path(studyfile.project_dirs()[0]).parent
SMOKE = ["shape=[sphere]", "nodes=[144]", "runner.backend=sequential"]


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """A results root holding one finished smoke run (so 'nothing changed' has something to keep)."""
    root = tmp_path_factory.mktemp("bad_input") / "results"
    done = invoke("run", "smoke", *SMOKE, "--root", root)
    assert done.exit_code == 0, done.output
    return root


def _commands(case: str, first: str) -> tuple[str, ...]:
    """``run`` for every case (it is the command that could write); ``show`` for the first case
    of a class too (it composes the same way, and must refuse the same way)."""
    return ("show", "run") if case == first else ("run",)


GOOD_BODY = "name: mine\nkind: mesh_features\nfactors:\n  shape: [sphere]\n  nodes: [144]\n"

# study file class -> (file text, the message after "<path>")
STUDY_FILES = {
    "tab_indented": (HEADER + "name: mine\nkind: mesh_features\nfactors:\n\tshape: [sphere]\n",
                     ", line 6: a tab character where YAML allows only spaces for indentation."),
    "unclosed_list": (HEADER + "name: mine\nkind: mesh_features\nfactors:\n  shape: [sphere,\n",
                      ", line 6: this is not valid YAML (while parsing a flow node: expected the "
                      "node content, but found '<stream end>')."),
    "bad_mapping": (HEADER + "name: mine\nkind: mesh_features\n  seeds: 2\n",
                    ", line 5: this is not valid YAML (mapping values are not allowed here)."),
    "key_twice": (HEADER + "name: mine\nkind: mesh_features\nname: yours\n",
                  ", line 5: this is not valid YAML (key 'name' is given twice (first on line 3))."),
    "empty": ("", " is empty; a study file needs at least the keys name and kind."),
    "comments_only": (HEADER, " is empty; a study file needs at least the keys name and kind."),
    "a_list": (HEADER + "- name: mine\n", " must be a mapping of keys (name: ..., kind: ...), not "
                                          "a list."),
    "no_kind": (HEADER + "name: mine\n", " has no kind key; a study file needs at least the keys "
                                         "name and kind."),
    # aliases of aliases expand to billions of values (it hung); nesting beyond Python's
    # recursion limit (it was a RecursionError traceback, exit 1)
    "alias_bomb": (HEADER + GOOD_BODY + "params:\n  a: &a [x, x, x, x, x, x, x, x, x]\n"
                   + "".join(f"  {c}: &{c} [{', '.join([f'*{p}'] * 9)}]\n"
                             for p, c in zip("abcdefgh", "bcdefghi", strict=True)),
                   ", line 10: the alias *a repeats a value given elsewhere, and aliases are not "
                   "read (expanded, a few can make billions of values); write the value out."),
    "nested_too_deep": (HEADER + GOOD_BODY + "params:\n  x: " + "[" * 3000 + "]" * 3000 + "\n",
                        ": its lists or mappings are nested too deeply to read (over 100 levels "
                        "within each other); a config nests a few."),
    # within PyYAML's reach but not OmegaConf's: "maximum recursion depth exceeded", without the file
    "nested_150_deep": (HEADER + GOOD_BODY + "params:\n  x: " + "[" * 150 + "]" * 150 + "\n",
                        ": its lists or mappings are nested too deeply to read (over 100 levels "
                        "within each other); a config nests a few."),
    # a merge key read as PyYAML's "could not determine a constructor for the tag ...merge", and
    # a null key as "None is not a known key" without its line
    "merge_key": (HEADER + GOOD_BODY + "model:\n  <<: {lambda1: 1.0}\n",
                  ", line 9: the merge key << repeats keys given elsewhere, and merge keys are not "
                  "read (as aliases are not: expanded, a few can make billions of values); write "
                  "the keys out."),
    "merge_key_of_an_alias": (HEADER + "base: &b {seeds: 1}\n" + GOOD_BODY + "  <<: *b\n",
                              ", line 9: the merge key << repeats keys given elsewhere, and merge "
                              "keys are not read (as aliases are not: expanded, a few can make "
                              "billions of values); write the keys out."),
    "null_key": (HEADER + GOOD_BODY + "~: 1\n",
                 ", line 8: the key ~ is YAML's null, not a name; write the name of the setting."),
    "null_factor": (HEADER + GOOD_BODY + "  null: [1]\n", ", line 8: the key null is YAML's null, "
                                                          "not a name; write the name of the setting."),
    # 50 MB kept show busy for minutes (PyYAML reads ~1 MB/s, twice per command): refused unread
    "too_large": (HEADER + GOOD_BODY + "description: >\n" + "  lorem ipsum\n" * (2**20 // 14),
                  " is 1.1 MiB; a study or config-group file is at most 1 MiB (the shipped ones "
                  "are under 5 KB, and each command reads YAML at about a second per MB, twice, "
                  "docs/decisions.md)."),
    "no_package_header": ("# schema: StudyCfg\n" + GOOD_BODY,
                          " does not start with the comment line '# @package _global_', which "
                          "every study file needs (see campaigns/smoke.yaml)."),
}


@pytest.mark.parametrize("case", sorted(STUDY_FILES))
@pytest.mark.parametrize("how", ["name", "path"])
def test_broken_study_file(results, user_dir, case, how):
    text, tail = STUDY_FILES[case]
    path = user_dir / "mine.yaml"
    path.write_text(text)
    for command in _commands(case, "tab_indented"):
        refused(results, [command, "mine" if how == "name" else path, "--root", results],
                f"{path}{tail}")


# keys and values inside a study file: the schema names them, with the file and line
STUDY_VALUES = {
    "unknown_key": ("colour: red\n", "{path}, line 8: colour is not a known key of the study config; known "
                                     "keys: name, kind, description, seed, seeds, repeats, factors, "
                                     "zip, method_factors, params, paper, compare_with, extension, "
                                     "model, "
                                     "evaluator, features, pso, runner, output."),
    "unknown_group_key": ("model:\n  lambda3: 0.2\n",
                          "{path}, line 9: model.lambda3 is not a known key of model; "
                          "did you mean model.lambda1 or model.lambda2? known keys: lambda1, "
                          "lambda2, n_exp, "
                          "fingertip_radius_m, e_finger_pa, e_object_pa, nu_finger, nu_object, "
                          "damping_law, alpha_hc_s_per_m."),
    "impossible_friction": ("factors:\n  mu: [0.3, 50]\n",
                            "{path}, line 6: factors.mu[1] = 50.0 is out of range; allowed: >= "
                            "0 and <= 3 (dry friction of soft materials stays below 3)."),
    "negative_mass": ("factors:\n  mass_kg: [-0.2]\n",
                      "{path}, line 6: factors.mass_kg[0] = -0.2 is out of range; allowed: >= "
                      "0.0001 and <= 10 (below 0.1 g an object weighs less than the rig's 1 mN "
                      "force resolution, and a three-finger hand lifts at most ~10 kg)."),
    "run_escaping_results": ("output:\n  run: ../../elsewhere\n",
                             "{path}, line 9: output.run = '../../elsewhere' is not allowed; use "
                             "ASCII letters (a-z, A-Z), digits, '.', '_' and '-' (starting with a "
                             "letter or digit, at most 100), so the run stays inside the results "
                             "directory."),
    # OmegaConf's 'KeyError raised while resolving interpolation: "Environment variable ..."'
    "unset_environment_variable": ("description: ${oc.env:GRASPCAMPAIGN_NO_SUCH_VARIABLE}\n",
                                   "{path}, line 8: description = "
                                   "'${{oc.env:GRASPCAMPAIGN_NO_SUCH_VARIABLE}}' cannot be resolved: "
                                   "environment variable GRASPCAMPAIGN_NO_SUCH_VARIABLE is not set "
                                   "(set it, or give a default: "
                                   "${{oc.env:GRASPCAMPAIGN_NO_SUCH_VARIABLE,VALUE}})."),
    "name_escaping_results": ("name: ../mine\n",
                              "{path}, line 7: name = '../mine' is not allowed; use ASCII letters "
                              "(a-z, A-Z), digits, '.', '_' and '-' (starting with a letter or "
                              "digit, at most 100), so the run stays inside the results directory."),
}


@pytest.mark.parametrize("case", sorted(STUDY_VALUES))
def test_bad_value_in_a_study_file(results, user_dir, case):
    extra, message = STUDY_VALUES[case]
    body = GOOD_BODY.replace("name: mine\n", "") if extra.startswith("name:") else GOOD_BODY
    if extra.startswith("factors:"):
        body = "name: mine\nkind: mesh_features\n"
    path = user_dir / "mine.yaml"
    path.write_text(HEADER + body + extra)
    for command in _commands(case, "impossible_friction"):
        refused(results, [command, "mine", "--root", results], message.format(path=path))


GROUP_FILES = {
    "model/table2.yaml": ("# schema: ContactModelCfg\nlambda1: [0.3,\n", [],
                          ", line 2: this is not valid YAML (while parsing a flow node: expected "
                          "the node content, but found '<stream end>')."),
    "model/nominal.yaml": ("# schema: ContactModelCfg\nlambda1: 1.0\n\tlambda2: 1.0\n",
                           ["model=nominal"], ", line 3: a tab character where YAML allows only "
                                              "spaces for indentation."),
}


@pytest.mark.parametrize("name", sorted(GROUP_FILES))
def test_broken_group_file_is_named_with_its_line(results, home, name):
    text, overrides, tail = GROUP_FILES[name]
    (home / "conf" / name).write_text(text)
    for command in _commands(name, "model/table2.yaml"):
        refused(results, [command, "smoke", *overrides, "--root", results],
                f"{home / 'conf' / name}{tail}")


def test_one_broken_study_file_does_not_break_list(user_dir):
    (user_dir / "broken.yaml").write_text(HEADER + "name: broken\nkind: [oops\n")
    (user_dir / "mine.yaml").write_text(HEADER + GOOD_BODY)
    message = (f"{user_dir / 'broken.yaml'}, line 4: this is not valid YAML (while parsing a flow "
               "sequence: expected ',' or ']', but got '<stream end>').")
    result = invoke("list")
    assert result.exit_code == 0, result.output
    assert result.stderr == f"warning: study broken is broken: {message}\n"
    lines = {line.split("│")[1].strip(): line for line in result.stdout.splitlines()
             if line.count("│") > 4}
    assert "broken" in lines["broken"].split("│")[4]
    assert lines["mine"].split("│")[3].strip() == "1"  # its own trial count
    assert "baseline_grid" in lines and lines["baseline_grid"].split("│")[3].strip() == "3375"
    names = invoke("list", "--names")
    assert "broken" not in names.stdout.split() and "mine" in names.stdout.split()


PLUS = {
    "+sedes=3": "sedes is not a known key of the study config (override '+sedes=3' rejected); did you "
                "mean seeds? known keys: "
                "name, kind, description, seed, seeds, repeats, factors, zip, method_factors, "
                "params, paper, compare_with, extension, model, evaluator, features, pso, runner, output.",
    "+model.foo=1": "model.foo is not a known key of model (override '+model.foo=1' "
                    "rejected); known keys: lambda1, lambda2, n_exp, fingertip_radius_m, "
                    "e_finger_pa, e_object_pa, nu_finger, nu_object, damping_law, alpha_hc_s_per_m.",
    # another tool's word for n_jobs, answered by meaning (n_jobs' said_as; difflib's nearest
    # was runner.progress, ratio 0.62)
    "+runner.cores=4": "runner.cores is not a known key of runner (override '+runner.cores=4' "
                       "rejected); did you mean runner.n_jobs? known keys: backend, n_jobs, "
                       "address, batch_size, target_task_s, progress, progress_interval_s, "
                       "connect_timeout_s.",
    "model=nosuch": "model=nosuch is not an option of config group model; available options: "
                    "firm, nominal, table2.",
}


@pytest.mark.parametrize("override", sorted(PLUS))
def test_unknown_keys_added_with_plus_and_unknown_options(results, override):
    for command in _commands(override, "+sedes=3"):
        refused(results, [command, "smoke", override, "--root", results], PLUS[override])


RUN_NAME = ("is not allowed; use ASCII letters (a-z, A-Z), digits, '.', '_' and '-' (starting "
            "with a letter or digit, at most 100), so the run stays inside the results directory.")


@pytest.mark.parametrize("name", ["../../elsewhere", "a/b", "..", ".hidden", "/abs"])
def test_run_names_never_leave_the_results_root(results, tmp_path, name):
    message = f"--run = {name!r} {RUN_NAME}"
    commands = [["run", "smoke", *SMOKE], ["status", "smoke"], ["report", "smoke"]]
    if name == "../../elsewhere":
        commands.append(["show", "smoke"])
    for args in commands:
        refused(results, [*args, "--run", name, "--root", results], message)
    records = tmp_path / "m.csv"
    records.write_text("trial_id\n")
    refused(results, ["ingest", "test2_grasp", records, "--run", name, "--root", results], message)
    refused(results, ["run", "smoke", *SMOKE, f"output.run={name}", "--root", results],
            f"output.run = {name!r} {RUN_NAME}")


def test_schedule_out_into_a_path_whose_parent_is_a_file(results, tmp_path):
    blocker = tmp_path / "notes.txt"
    blocker.write_text("a file, not a folder")
    refused(results, ["reproduce", "--times", blocker / "times.txt", "--root", results],
            f"--times {blocker / 'times.txt'}: {blocker} is a file, not a directory.")
    refused(results, ["schedule", "test2_grasp", "--out", blocker / "sheet", "--root", results],
            f"--out {blocker / 'sheet'}: {blocker} is a file, not a directory.")
    refused(results, ["schedule", "test2_grasp", "--out", blocker / "deeper" / "sheet", "--root",
                      results], f"--out {blocker / 'deeper' / 'sheet'}: {blocker} is a file, not "
                                 "a directory.")
    refused(results, ["schedule", "test2_grasp", "--out", tmp_path, "--root", results],
            f"--out {tmp_path} is a directory; give a file stem such as {tmp_path / 'schedule'}.")
    missing = tmp_path / "no_such_dir" / "deeper"  # as plan --png: a mistyped directory grows no tree
    refused(results, ["schedule", "test2_grasp", "--out", missing / "x", "--root", results],
            f"--out {missing / 'x'}: directory {missing} does not exist.")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


UNREACHABLE = ("runner.address = 'tcp://127.0.0.1:9': no Dask scheduler answered within 1 s "
               "(OSError); start one (dask scheduler) or drop runner.address to run on a local "
               "cluster.")


def test_a_malformed_dask_address_is_refused_before_anything_runs(results):
    for command in ("show", "run"):
        refused(results, [command, "smoke", "runner.backend=dask", "runner.address=localhost",
                          "--root", results],
                "runner.address = 'localhost' is not a Dask scheduler address; expected e.g. "
                "tcp://host:8786.")


def test_an_unreachable_dask_scheduler_is_one_sentence(monkeypatch):
    from graspcampaign.campaign import scheduler
    from graspcampaign.campaign.runner import _connect
    from graspcampaign.errors import UserInputError

    # the client's own failure, past a probe that let it through (the probe: tests below)
    monkeypatch.setattr(scheduler, "check_scheduler", lambda address, timeout_s: None)

    class Unreachable:  # what distributed.Client does when nothing answers in time
        def __init__(self, address, timeout):
            raise OSError(f"Timed out trying to connect to {address} after {timeout} s")

    with pytest.raises(UserInputError) as info:
        _connect(Unreachable, "tcp://127.0.0.1:9", 1.0)
    assert str(info.value) == UNREACHABLE


@pytest.mark.slow  # imports distributed and waits for the connection timeout: `make test-full`
def test_unreachable_dask_scheduler_fails_fast_in_one_sentence(results):
    pytest.importorskip("distributed")
    # port 9 (discard) on the loopback: nothing listens
    refused(results, ["run", "smoke", "shape=[sphere]", "nodes=[144]", "runner.backend=dask",
                      "runner.connect_timeout_s=1", "runner.address=tcp://127.0.0.1:9", "--root",
                       results], UNREACHABLE)


IMPOSSIBLE = {
    "mu=50": "factors.mu[0] = 50.0 is out of range; allowed: >= 0 and <= 3 (dry friction of "
             "soft materials stays below 3).",
    "mu=[0.3,-0.1]": "factors.mu[1] = -0.1 is out of range; allowed: >= 0 and <= 3 (dry "
                     "friction of soft materials stays below 3).",
    "mass_kg=-1": "factors.mass_kg[0] = -1.0 is out of range; allowed: >= 0.0001 and <= 10 "
                  "(below 0.1 g an object weighs less than the rig's 1 mN force resolution, and a "
                  "three-finger hand lifts at most ~10 kg).",
    "mass_kg=40": "factors.mass_kg[0] = 40.0 is out of range; allowed: >= 0.0001 and <= 10 "
                  "(below 0.1 g an object weighs less than the rig's 1 mN force resolution, and a "
                  "three-finger hand lifts at most ~10 kg).",
    "model.lambda1=100": "model.lambda1 = 100.0 is out of range; allowed: > 0 and <= 15 (the "
                         "identification scale factors stay within 10x their PSO bounds).",
    "model.n_exp=0": "model.n_exp = 0.0 is out of range; allowed: > 0 and <= 3 (contact force "
                     "exponents of soft bodies lie between ~0.4 and ~2).",
    "model.fingertip_radius_m=0.5": "model.fingertip_radius_m = 0.5 is out of range; allowed: >= "
                                    "0.001 and <= 0.05 (below 1 mm the evaluator's 0.5 mm seed "
                                    "penetration sinks half a fingertip's radius, and robot pads "
                                    "stay below 50 mm).",
}


@pytest.mark.parametrize("override", sorted(IMPOSSIBLE))
def test_physically_impossible_values_are_refused_with_the_range(results, override):
    for command in _commands(override, "mu=50"):
        refused(results, [command, "shapes", override, "--root", results], IMPOSSIBLE[override])


NODES_ALLOWED = (">= 12 and <= 20000 (a closed mesh needs 12 nodes, and one finer than 20,000 "
                 "resolves nothing a 5 mm fingertip feels)")
SIM_TIME_ALLOWED = ("> 0 and <= 60 (a grasp closes, lifts and holds within seconds; 60 s is "
                    "~2x10^6 RK4 steps)")


@pytest.mark.parametrize(("study", "override", "allowed"), [
    ("gravity_settle", "+params.settle_t_max_s=-1.0", SIM_TIME_ALLOWED),
    ("gravity_settle", "+params.implicit_dt_s=0.0", "> 0"),
    ("friction_mass", "+params.t_max_s=0.0", SIM_TIME_ALLOWED),
    ("friction_mass", "+params.grip_speed_m_per_s=-0.02", "> 0"),
    ("shapes", "+params.nodes=5", NODES_ALLOWED), ("shapes", "+params.candidate_sample=-3", ">= 0")])
def test_a_kind_parameter_out_of_range_is_refused_before_the_run_starts(results, study, override, allowed):
    # a negative settle time ran RK4 to an "ok" record and failed the implicit trial with a bare
    # ZeroDivisionError; a zero grasp time failed every trial at run time instead of at load;
    # params.nodes=5 wrote the run's manifest, then failed with "n_nodes must be at least 12", so
    # the corrected command was refused as config drift; a negative candidate sample ran
    refused(results, ["run", study, override, "--root", results],
            f"{override.removeprefix('+').replace('=', ' = ')} is out of range; allowed: {allowed}.")


MASS_ALLOWED = (">= 0.0001 and <= 10 (below 0.1 g an object weighs less than the rig's 1 mN force "
                "resolution, and a three-finger hand lifts at most ~10 kg)")


@pytest.mark.parametrize("command", ["show", "run"])
@pytest.mark.parametrize(("study", "override", "value", "allowed"), [
    ("mesh_resolution", "params.resolutions=[10]", "params.resolutions[0] = 10", NODES_ALLOWED),
    ("mesh_resolution", "params.resolutions=[100000]", "params.resolutions[0] = 100000",
     NODES_ALLOWED),
    ("mesh_resolution", "params.budget_nodes=[144,5]", "params.budget_nodes[1] = 5", NODES_ALLOWED),
    ("friction_mass", "nodes=[100000]", "factors.nodes[0] = 100000", NODES_ALLOWED),
    ("friction_mass", "+params.t_max_s=1e9", "params.t_max_s = 1000000000.0", SIM_TIME_ALLOWED),
    ("surrogate", "params.mu_range=[0.05,9]", "params.mu_range[1] = 9.0",
     ">= 0 and <= 3 (dry friction of soft materials stays below 3)"),
    ("sensitivity", "params.mu_range=[0.05,9]", "params.mu_range[1] = 9.0",
     ">= 0 and <= 3 (dry friction of soft materials stays below 3)"),
    ("surrogate", "params.mass_range_kg=[0.1,50]", "params.mass_range_kg[1] = 50.0", MASS_ALLOWED),
    ("sensitivity", "params.mass_range_kg=[0.1,50]", "params.mass_range_kg[1] = 50.0", MASS_ALLOWED)])
def test_kind_param_lists_and_time_budgets_are_bounded_as_their_factors(
        results, command, study, override, value, allowed):
    # show accepted these and run failed after running (MeshError: n_nodes must be at least 12), or
    # ran a 100,000-node mesh, 10^9 simulated seconds, or a friction of 9; each list item now takes
    # the bound of the factor it stands for (nodes, mu), the time budget a 60 s bound
    refused(results, [command, study, override, "--root", results],
            f"{value} is out of range; allowed: {allowed}.")


def test_status_of_an_unknown_study_does_not_suggest_running_it(results):
    from graspcampaign.campaign.studyfile import list_studies

    refused(results, ["status", "nosuch", "--root", results],
            f"unknown study 'nosuch': not on the config search path and no records under "
            f"{results}; available studies: {', '.join(list_studies())}.")
    # the command it suggests makes the run asked about: it named neither --root nor --run
    refused(results, ["status", "baseline_grid", "--root", results],
            f"no run at {results / 'baseline_grid' / 'default'}; run `graspcampaign run "
            f"baseline_grid --root {results}` first.")
    refused(results, ["status", "smoke", "--run", "b", "--root", results],
            f"no run at {results / 'smoke' / 'b'}; run `graspcampaign run smoke --run b --root "
            f"{results}` first.")


def test_a_misspelt_study_name_suggests_the_nearest(results):
    from graspcampaign.campaign.studyfile import list_studies

    known = ", ".join(list_studies())
    for command in ("status", "report"):
        refused(results, [command, "baselin_grid", "--root", results],
                f"unknown study 'baselin_grid': not on the config search path and no records "
                f"under {results}; did you mean 'baseline_grid'? available studies: {known}.")
    result = invoke("run", "baselin_grid", "--root", results)
    assert result.exit_code == 2
    assert result.stderr.startswith("error: unknown study 'baselin_grid'; did you mean "
                                    f"'baseline_grid'? available studies: {known} (searched: ")


@pytest.mark.parametrize(("args", "message"), [
    (["report", "--jobs", "two"], "--jobs 'two' is not a whole number; see graspcampaign report --help."),
    (["report", "--jobs", "1.5"], "--jobs '1.5' is not a whole number; see graspcampaign report --help."),
    (["run", "smoke", "--set", "seeds=1"], "no such option: --set (Possible options: --report); see "
                                           "graspcampaign run --help."),
    (["status"], "missing argument 'study'; see graspcampaign status --help."),
    (["schedule", "test2_grasp", "--out"], "option '--out' requires an argument; see graspcampaign "
                                           "schedule --help."),
    (["nosuch"], "no such command 'nosuch'; see graspcampaign --help."),
])
def test_a_command_line_that_cannot_be_parsed_is_one_sentence(results, args, message):
    """Typer's own errors (a typed option's bad value, an unknown option, a missing argument) are
    one sentence and exit 2, as the tool's are, not a box of usage lines."""
    refused(results, [*args, "--root", results] if args[0] == "report" else args, message)


@pytest.mark.parametrize("jobs", [0, -2])
def test_report_jobs_must_be_a_process_count(results, jobs):
    before = snapshot(results)
    result = invoke("report", "--root", results, "--jobs", jobs)
    assert result.exit_code == 2
    assert result.output == (f"error: --jobs {jobs}: give a number of processes (1 or more), or -1 "
                             "for one per core.\n")
    assert snapshot(results) == before


NOT_UTF8 = {"binary": (b"\xff\xfe\x00binary", "line 1: the file is not UTF-8 text (byte 0xff)"),
            "latin-1": ((HEADER + GOOD_BODY + "description: caf\u00e9\n").encode("latin-1"),
                        "line 8: the file is not UTF-8 text (byte 0xe9)")}


@pytest.mark.parametrize("case", sorted(NOT_UTF8))
def test_a_study_file_that_is_not_utf8_names_its_line_and_byte(results, user_dir, case):
    """It said '<path> cannot be read as a text file (UnicodeDecodeError).'"""
    data, where = NOT_UTF8[case]
    path = user_dir / "mine.yaml"
    path.write_bytes(data)
    for study in ("mine", path):
        refused(results, ["show", study, "--root", results], f"{path}, {where}; save it as UTF-8.")


def test_status_and_report_given_a_study_files_path_ask_for_its_name(results):
    """``run`` and ``show`` take a study file's path; what is stored is under the study's name. It
    said "study = 'campaigns/smoke.yaml' is not allowed; use letters, digits, ..."."""
    path = PROJECT / "campaigns" / "smoke.yaml"
    for command in ("status", "report"):
        refused(results, [command, path, "--root", results],
                f"study {str(path)!r} is a path; give the study's name (smoke, the value of name: in "
                "the study file), under which its runs are stored.")
