"""Bad input, round 19: an empty mapping given to a config group or a study's section on the
command line (``model={}``), numbers that overflow to inf or are NaN in an override or a study
file (``seeds=1e400``), and new users' wrong inputs. Each is one sentence naming what is wrong and
where, exit 2, nothing stored changed (``cli_checks.refused``).

(A study folder the report may not list, and a complete run it may not write, are in
tests/cli/test_unreadable_places.py, which runs them as a user permission bits stop.)
"""

from __future__ import annotations

import pytest
from cli_checks import HEADER, invoke, refused

#: what an empty mapping's sentence says after naming the override
MERGED = "an empty mapping, which changes nothing (it is merged into the study's {key}); "


@pytest.mark.parametrize(("override", "choose"), [
    ("model={}", "choose one of its options (model=OPTION; options: firm, nominal, table2) or "),
    ("pso={ }", "choose one of its options (pso=OPTION; options: converged, repeatability) or "),
    ("params={}", ""), ("+paper={}", ""), ("factors={}", "")])
def test_an_empty_mapping_for_a_group_or_a_section_is_refused_naming_it(tmp_path, override, choose):
    """Each was taken, and changed nothing: the study ran as if it were not given."""
    key = override.lstrip("+").partition("=")[0]
    refused(tmp_path, ["show", "baseline_grid", override, "--root", tmp_path],
            f"override {override!r} gives {key} {MERGED.format(key=key)}{choose}set one of its keys "
            f"({key}.KEY=VALUE), or leave the override out.")


def test_a_mapping_that_sets_a_key_of_a_group_is_still_taken(tmp_path):
    done = invoke("show", "baseline_grid", "model={lambda1: 2}", "--root", tmp_path)
    assert done.exit_code == 0 and done.stderr == "", done.output


@pytest.mark.parametrize(("override", "said"), [
    ("seeds=1e400", "1e400 overflows to inf (no float is that large)"),
    ("seeds='1e400'", "1e400 overflows to inf (no float is that large)"),
    ("mu=[0.3,1E400]", "1E400 overflows to inf (no float is that large)"),
    ("pso.inertia=-1e4_00", "-1e4_00 overflows to -inf (no float is that large)"),
    ("mass_kg=[nan]", "nan is not a number"), ("runner.progress_interval_s=-Inf", "-Inf is infinite"),
    ("factors={mu: [0.3, 2e308]}", "2e308 overflows to inf (no float is that large)"),
    ("pso={inertia: NaN}", "NaN is not a number"),
    ("pso={inertia: Infinity}", "Infinity is infinite"),
    ("factors={mu: [0.3, infinity]}", "infinity is infinite"),
    ("runner={address: nan, progress_interval_s: inf}", "inf is infinite"),
    ("factors={shape: [nan], mu: [0.3, 2e308]}", "2e308 overflows to inf (no float is that large)")])
def test_a_number_that_is_no_finite_number_is_refused_as_typed(tmp_path, override, said):
    """Each was "seeds must be a whole number, got inf." or "factors.mu[1] must be finite, got
    inf.": not the value typed. A mapping's ``Infinity``, text to Hydra but inf to a number field, was
    that again after a mapping's scan kept to its floats; a mapping that gives a text key nan (a run's
    address, a shape) named that nan, not the number no finite number (rev40b)."""
    refused(tmp_path, ["show", "baseline_grid", override, "--root", tmp_path],
            f"override {override!r}: {said}; give a finite number.")


@pytest.mark.parametrize(("override", "run"), [("output.run=nan", "nan"), ("output={run: nan}", "nan"),
                                               ("output={run: Infinity}", "Infinity")])
def test_a_text_key_may_be_named_inf_or_nan(tmp_path, override, run):
    """In a mapping too: ``output={run: nan}`` was refused as "nan is not a number" (every float of a
    mapping was scanned, whatever its key takes)."""
    done = invoke("show", "smoke", override, "--root", tmp_path)
    assert done.exit_code == 0 and f"run: {tmp_path}/smoke/{run} (0 of" in done.stdout, done.output


@pytest.mark.parametrize(("line", "key", "said"), [
    ("seeds: 1e400", "seeds", "1e400 overflows to inf (no float is that large)"),
    ("runner: {progress_interval_s: 1.0e400}", "runner.progress_interval_s",
     "1.0e400 overflows to inf (no float is that large)"),
    ("runner: {progress_interval_s: nan}", "runner.progress_interval_s", "nan is not a number"),
    ("factors: {shape: [sphere], nodes: [1e999]}", "factors.nodes[0]",
     "1e999 overflows to inf (no float is that large)")])
def test_a_study_file_number_that_is_no_finite_number_is_refused_as_typed(tmp_path, line, key, said):
    """YAML reads 1e400 as text: "seeds must be of type int, got '1e400' (str)."."""
    study = tmp_path / "mine.yaml"
    factors = "" if line.startswith("factors") else "factors: {shape: [sphere], nodes: [144]}\n"
    study.write_text(f"{HEADER}name: mine\nkind: mesh_features\n{line}\n{factors}")
    refused(tmp_path, ["show", study, "--root", tmp_path / "results"],
            f"{study}, line 5: {key}: {said}; give a finite number.")


def test_one_phrase_of_the_package_says_permission_denied():
    """There were four ("… (permission denied; chmod or chown it, or run the command as its
    owner)", "… (permission denied); chmod or chown it, or run as its owner.", "… permission
    denied (its permissions … keep this user out); give this user access …", "cannot write there
    (Permission denied); make it writable …"): core.words.PERMISSION_DENIED is now the only text
    that says it."""
    import ast
    from pathlib import Path

    import graspcampaign

    package = Path(graspcampaign.__file__).parent
    saying = sorted(f"{path.relative_to(package)}:{node.lineno}" for path in package.rglob("*.py")
                    for node in ast.walk(ast.parse(path.read_text()))
                    if isinstance(node, ast.Constant) and isinstance(node.value, str)
                    and "permission denied" in node.value.lower())
    assert [where.partition(":")[0] for where in saying] == ["core/words.py"], saying


@pytest.mark.parametrize(("option", "typed", "said"), [
    ("--mass-kg", "1e400", "1e400 overflows to inf (no float is that large)"),
    ("--mass-kg", "nan", "nan is not a number"), ("--mu", "Infinity", "Infinity is infinite"),
    ("--fingertip-radius-mm", "-1e999", "-1e999 overflows to -inf (no float is that large)")])
def test_a_numeric_option_that_is_no_finite_number_is_refused_as_typed(sphere, tmp_path, option, typed,
                                                                       said):
    """Each was "--mass-kg inf is out of range; allowed: …" (nan too: no number is out of range)."""
    args = ["plan", sphere, "--mass-kg", "0.1"]
    args = args[:2] + [option, typed] if option == "--mass-kg" else args + [option, typed]
    refused(tmp_path, args, f"{option} {said}; give a finite number.")


def test_an_override_of_a_number_written_infinity_is_refused_as_typed(tmp_path):
    """Hydra reads it as text, and the float field's float() as inf: "must be finite, got inf"."""
    refused(tmp_path, ["show", "baseline_grid", "pso.inertia=infinity", "--root", tmp_path],
            "override 'pso.inertia=infinity': infinity is infinite; give a finite number.")


def test_a_study_file_whose_name_is_no_study_name_is_told_to_be_renamed(tmp_path):
    """It was told "write name: my study or rename the file to mine.yaml", and name: my study is
    refused ("name = 'my study' is not allowed; use ASCII letters …")."""
    study = tmp_path / "my study.yaml"
    study.write_text(f"{HEADER}name: mine\nkind: mesh_features\n"
                     "factors: {shape: [sphere], nodes: [144]}\n")
    refused(tmp_path, ["show", study, "--root", tmp_path / "results"],
            f"{study}, line 3: name: mine is not the file's name 'my study', which is no study name "
            "(ASCII letters, digits, '.', '_' and '-', starting with a letter or digit); a study is "
            "listed, run and reported by its file name, so rename the file to mine.yaml.")


@pytest.mark.parametrize(("override", "message"), [
    ("seeds=true", "seeds must be a whole number, got true."),
    ("pso.inertia=false", "pso.inertia must be a number, got false.")])
def test_true_or_false_for_a_number_is_echoed_as_typed(tmp_path, override, message):
    """It was "got True.", Python's spelling, which the user never typed."""
    refused(tmp_path, ["show", "baseline_grid", override, "--root", tmp_path], message)
