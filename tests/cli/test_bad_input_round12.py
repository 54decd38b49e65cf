"""Bad input, round 12: what session 33 saw and left. A near miss of a config key named alike
wherever it is typed, ... Each refusal: exit 2, one sentence naming what is wrong and where,
nothing stored changed (``refused``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from cli_checks import EVENT, SMOKE, T1, bench_press, invoke, mesh_study, refused

KEYS = ("name, kind, description, seed, seeds, repeats, factors, zip, method_factors, params, paper, "
        "compare_with, extension, model, evaluator, features, pso, runner, output")


@pytest.mark.parametrize(("override", "said"), [
    # a top-level key was quoted ('seed'), a dotted one not (runner.progress)
    ("seedz=1", "seedz is neither a known key of the study config nor a factor of this study "
     "(factors: nodes, shape); did you mean seed? override rejected."),
    ("+seedz=1", f"seedz is not a known key of the study config (override '+seedz=1' rejected); "
     f"did you mean seed? known keys: {KEYS}."),
    ("runer.n_jobs=1", f"runer is not a known key of the study config (override 'runer.n_jobs=1' "
     f"rejected); did you mean runner? known keys: {KEYS}."),
])
def test_a_near_miss_of_a_config_key_is_named_as_typed_at_any_depth(results, override, said):
    refused(results, ["show", "smoke", override, "--root", results], said)


def test_deleting_a_key_the_study_does_not_set_says_what_deleting_would_do(results):
    # it said the schema's default "would take" compare_with's place "without a word", of a
    # study whose compare_with already was that default
    refused(results, ["show", "smoke", "~compare_with", "--root", results],
            "override '~compare_with' deletes compare_with, a key every study has: it would only "
            "put back the schema's default (\"\"), which a study that does not set compare_with "
            "already holds; set the value you want instead (compare_with=...).")


@pytest.fixture
def home_dir(tmp_path, monkeypatch):
    """A home directory (``HOME``) and a current directory apart from it."""
    home, here = tmp_path / "home", tmp_path / "here"
    home.mkdir()
    here.mkdir()
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.chdir(here)
    return home


def test_a_quoted_tilde_in_a_path_option_is_the_home_directory(home_dir):
    # each made a directory named '~' in the current directory
    done = invoke("run", "smoke", *SMOKE, "--root", "~/runs")
    assert done.exit_code == 0, done.output
    assert (home_dir / "runs" / "smoke" / "default" / "manifest.json").is_file()
    for args in (["status", "smoke", "--root", "~/runs"], ["report", "smoke", "--root", "~/runs"],
                 ["schedule", "test2_grasp", "--out", "~/day1"]):
        done = invoke(*args)
        assert done.exit_code == 0, done.output
    assert (home_dir / "runs" / "smoke" / "default" / "report" / "report.md").is_file()
    assert (home_dir / "day1.csv").is_file()
    assert list(Path.cwd().iterdir()) == []


@pytest.mark.parametrize(("args", "said"), [
    (["show", "smoke", "--root", "~nosuchuser/runs"], "--root ~nosuchuser/runs starts with "
     "~nosuchuser, a home directory that cannot be found; give its path in full."),
    (["schedule", "test2_grasp", "--out", "~nosuchuser/day1"], "--out ~nosuchuser/day1 starts "
     "with ~nosuchuser, a home directory that cannot be found; give its path in full."),
    (["plan", "~nosuchuser/ball.obj", "--mass-kg", "0.1"], "mesh ~nosuchuser/ball.obj starts with "
     "~nosuchuser, a home directory that cannot be found; give its path in full."),
])
def test_a_path_option_in_the_home_of_no_user_is_refused(home_dir, args, said):
    refused(home_dir, args, said)
    assert list(Path.cwd().iterdir()) == []


def _study(folder: Path, seeds: str, nodes: str = "[144]") -> Path:
    return mesh_study(folder, f"seeds: {seeds}\nfactors:\n  shape: [sphere]\n  nodes: {nodes}\n")


@pytest.mark.parametrize(("seeds", "nodes", "said"), [
    # each was run as octal: 8 seeds, 100 nodes, with nothing said
    ("010", "[144]", "line 5: seeds = 010 has a leading zero, which YAML reads as octal 8; write 10 "
     "or 8."),
    ("-010", "[144]", "line 5: seeds = -010 has a leading zero, which YAML reads as octal -8; write "
     "-10 or -8."),
    ("2", "[144, 0144]", "line 8: factors.nodes[1] = 0144 has a leading zero, which YAML reads as "
     "octal 100; write 144 or 100."),
    ("2", "\n    - 144\n    - 0_620", "line 10: factors.nodes[1] = 0_620 has a leading zero, which "
     "YAML reads as octal 400; write 620 or 400."),
])
def test_an_integer_with_a_leading_zero_in_a_study_file_is_refused(results, user_dir, seeds, nodes,
                                                                    said):
    path = _study(user_dir, seeds, nodes)
    for command in ("show", "run"):
        refused(results, [command, path, "--root", results], f"{path}, {said}")


@pytest.mark.parametrize(("seeds", "nodes", "said"), [
    # each was run as base 60 (1:30 is 1 * 60 + 30) with nothing said
    ("1:30", "[144]", "line 5: seeds = 1:30 has a colon, which YAML reads as a base-60 (sexagesimal) "
     "number, 90; write 90, or '1:30' in quotes to mean text."),
    ("2", "[144, 1:30:00]", "line 8: factors.nodes[1] = 1:30:00 has colons, which YAML reads as a "
     "base-60 (sexagesimal) number, 5400; write 5400, or '1:30:00' in quotes to mean text."),
    ("2", "\n    - 144\n    - -1:30.5", "line 10: factors.nodes[1] = -1:30.5 has a colon, which YAML "
     "reads as a base-60 (sexagesimal) number, -90.5; write -90.5, or '-1:30.5' in quotes to mean "
     "text."),
])
def test_a_number_with_a_colon_in_a_study_file_is_refused(results, user_dir, seeds, nodes, said):
    path = _study(user_dir, seeds, nodes)
    for command in ("show", "run"):
        refused(results, [command, path, "--root", results], f"{path}, {said}")


@pytest.mark.parametrize(("lines", "said"), [
    # each said "got False (bool)" (or True, or null) of a word the file does not hold
    ("factors:\n  shape: [NO]\n  nodes: [144]", "line 6: factors.shape[0] must be of type str, got "
     "NO, which YAML reads as false; quote it: 'NO'."),
    ("factors:\n  shape: [sphere, yes]\n  nodes: [144]", "line 6: factors.shape[1] must be of type "
     "str, got yes, which YAML reads as true; quote it: 'yes'."),
    ("output:\n  run: Off", "line 6: output.run must be of type str, got Off, which YAML reads as "
     "false; quote it: 'Off'."),
    ("description: no", "line 5: description must be of type str, got no, which YAML reads as false; "
     "quote it: 'no'."),
    # a number wanted: quotes would not help
    ("factors:\n  shape: [sphere]\n  nodes: [on]", "line 7: factors.nodes[0] must be of type int, "
     "got on, which YAML reads as true."),
    ("output:\n  root: ~", "line 6: output.root must be of type str, got ~, which YAML reads as "
     "null; quote it: '~'."),  # it said "got null"
    # written as YAML's own words, they are named as before
    ("compare_with: false", "line 5: compare_with must be of type str, got false (a boolean)."),
    ("output:\n  run: null", "line 6: output.run must be of type str, got null."),
])
def test_a_word_yaml_reads_as_true_or_false_is_named_as_written(results, user_dir, lines, said):
    path = mesh_study(user_dir, f"{lines}\n")
    refused(results, ["show", path, "--root", results], f"{path}, {said}")


@pytest.mark.parametrize(("file", "override", "n_seeds"), [
    ("07", None, 7),  # octal 7 is 7
    ("0x10", None, 16), ("0b11", None, 3),  # each means what it says (1_000 is refused since)
    ("1", "seeds='10'", 10),  # text, which OmegaConf reads as an int setting's number
])
def test_an_integer_read_as_written_is_taken(results, user_dir, file, override, n_seeds):
    path = _study(user_dir, file)
    done = invoke("show", path, *([override] if override else []), "--root", results)
    assert done.exit_code == 0, done.output
    assert f"seeds per scene: {n_seeds} " in done.output


@pytest.mark.parametrize(("override", "zero", "number", "advice"), [
    ("seeds=010", "010", 10, "."),  # it was taken as 10
    ("factors.nodes=[0144]", "0144", 144, "."),  # these said "must be of type int, got '0144' (str)"
    ("nodes=[144,0144]", "0144", 144, "."),
    ("seed=-0_7", "-0_7", -7, "."),
    # quoting is advice only where a key takes text (a number key turns '010' into 10)
    ("output.run=007", "007", 7, ", or quote it ('007') to mean text."),
])
def test_an_override_with_a_leading_zero_is_refused(results, override, zero, number, advice):
    refused(results, ["show", "smoke", override, "--root", results], f"override {override!r}: "
            f"{zero} has a leading zero, which Hydra reads as the text '{zero}', not the number "
            f"{number}; write {number}{advice}")


def test_an_override_quoted_with_a_leading_zero_is_text(results):
    done = invoke("show", "smoke", "output.run='007'", "--root", results)
    assert done.exit_code == 0, done.output
    assert f"{Path(results) / 'smoke' / '007'} " in done.output


@pytest.mark.parametrize(("study", "schedule", "typo", "hint"), [
    # each was accepted: a protocol's trial keys were not declared, so they went unchecked
    ("test1_bench", "test1", "materal", "did you mean 'material'? "),
    ("test2_grasp", "test2", "plannr", "did you mean 'planner'? "),
    ("test3_disturbance", "test3", "nosuch", ""),
])
def test_a_method_factor_no_protocol_trial_holds_is_refused(results, study, schedule, typo, hint):
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.rig import protocol, test1

    if schedule == "test1":
        columns = set(test1.test1_schedule(0).columns)
    else:  # a Tests 2-3 trial keeps the sheet's id as rig_trial_id, and not the study's name
        sheet = getattr(protocol, f"{schedule}_schedule")(0)
        columns = {"rig_trial_id" if c == "trial_id" else c for c in sheet.columns} - {"study"}
    named = sorted({*compose_study(study, []).factors, *columns} - {"seed"})
    refused(results, ["show", study, f"method_factors=[{typo}]", "--root", results],
            f"method_factors names {typo!r}, which is no factor and no key of a trial of kind "
            f"{study!r}, so it would change nothing but the config hash; {hint}a method factor "
            "names a factor or trial key whose levels share one scene's random draws (this "
            f"study's: {', '.join(named)}).")


def test_a_method_factor_a_protocol_trial_holds_is_taken(results):
    done = invoke("show", "test3_disturbance", "method_factors=[planner,condition]", "--root",
                  results)
    assert done.exit_code == 0, done.output


@pytest.mark.parametrize(("flipped", "row", "peak", "said"), [
    # each was stored, its fits flagged fit_failed
    ("displacement_mm", 151, f"is at -0.65 mm where its normal force peaks ({2.0 * 0.65 ** 1.5:g} N)",
     "indentation (into the specimen)"),
    ("normal_force_n", 151, f"peaks at {-2.0 * 0.65 ** 1.5:g} N", "compression (the fingertip pressing)"),
])
def test_a_test1_channel_recorded_with_the_other_sign_is_refused(results, tmp_path, flipped, row,
                                                                 peak, said):
    waves = bench_press()
    waves[flipped] = -waves[flipped]
    waves.to_csv(tmp_path / "waves.csv", index=False)
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results],
            f"waves.csv, row {row}, column '{flipped}': event '{EVENT}' {peak}, below "
            f"zero: {said} is positive here; flip the column's sign.")


def test_a_force_negative_throughout_is_refused(results, tmp_path):
    waves = bench_press().assign(normal_force_n=-0.3)
    waves.to_csv(tmp_path / "waves.csv", index=False)
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results],
            f"waves.csv, row 1, column 'normal_force_n': event '{EVENT}' peaks at -0.3 N, below "
            "zero: compression (the fingertip pressing) is positive here; flip the column's sign.")


@pytest.mark.parametrize("approach_mm", [0.1, 1.0])
def test_a_press_with_its_adhesion_pull_off_is_stored(results, tmp_path, approach_mm):
    # 1.0: logged from further off the specimen than the 0.75 mm commanded depth, so the
    # displacement's largest sample is the approach (-1 mm); a first sign rule refused it
    depth = (0.75 + approach_mm) * np.sin(np.linspace(0.0, np.pi, 301)) - approach_mm
    bench_press().assign(displacement_mm=depth).to_csv(tmp_path / "waves.csv", index=False)
    done = invoke("ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results)
    assert done.exit_code == 0, done.output


def test_a_tilde_in_output_root_is_the_home_directory(home_dir, user_dir):
    # each made a directory named '~' in the current directory
    done = invoke("run", "smoke", *SMOKE, 'output.root="~/runs"')
    assert done.exit_code == 0, done.output
    assert (home_dir / "runs" / "smoke" / "default" / "manifest.json").is_file()
    path = mesh_study(user_dir, "output:\n  root: ~/mine\nfactors:\n  shape: [sphere]\n  nodes: [144]\n")
    done = invoke("run", path)
    assert done.exit_code == 0, done.output
    assert (home_dir / "mine" / "mine" / "default" / "manifest.json").is_file()
    assert list(Path.cwd().iterdir()) == []


def test_output_root_in_the_home_of_no_user_is_refused(home_dir, user_dir):
    refused(home_dir, ["show", "smoke", 'output.root="~nosuchuser/runs"'], "output.root = "
            "~nosuchuser/runs starts with ~nosuchuser, a home directory that cannot be found; give "
            "its path in full.")
    path = mesh_study(user_dir, "output:\n  root: ~nosuchuser/r\n")
    refused(home_dir, ["show", path], f"{path}, line 6: output.root = ~nosuchuser/r starts with "
            "~nosuchuser, a home directory that cannot be found; give its path in full.")


def test_a_kind_parameter_refused_by_its_own_check_names_its_key_once(results):
    # the params' ConfigError went through the OmegaConf sentence, which put the prefix before
    # the key it already had: "params.params.materials[0]: params.materials[0] has unknown value"
    refused(results, ["show", "test1_bench", "params.materials=[no]", "--root", results],
            "params.materials[0] has unknown value 'no'; allowed values: gel, silicone_soft, "
            "bio_foam, silicone_ref.")


def test_quoting_advice_keeps_an_interpolation_whole(results):
    # the word to quote stopped at the interpolation's '{' and ',': 'quote it: output.root="~$"{…}'
    refused(results, ["show", "smoke", "output.root=~${oc.env:X,y}", "--root", results],
            "cannot parse override 'output.root=~${oc.env:X,y}': '~' (character 13) is not allowed "
            "in an unquoted value (only ASCII letters, digits, spaces and _-+.$%*@?|/\\ are); quote "
            'it: output.root="~${oc.env:X,y}", typed in single quotes on the shell.')
