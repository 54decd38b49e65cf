"""Bad input, round 21: the leftovers of round 20 and new users' wrong inputs (docs/decisions.md,
"Bad input, round 21 (rough42)", lists every one tried). Each is one sentence naming what is wrong
and where, exit 2, nothing stored changed (``cli_checks.refused``).
"""

from __future__ import annotations

import pytest
from cli_checks import HEADER, T2, filled_records, immutable, refused


@pytest.mark.parametrize(("override", "said"), [
    ("runner.n_jobs=1e3", "runner.n_jobs must be a whole number, got 1e3."),
    ("seeds=1E3", "seeds must be a whole number, got 1E3."),
    ("seeds=2.50", "seeds must be a whole number, got 2.50."),
    ("seeds=[1e3]", "seeds must be a whole number, got [1e3].")])
def test_a_number_given_for_a_whole_number_is_echoed_as_typed(tmp_path, override, said):
    """It was echoed as Hydra read it: "got 1000.0", "got 2.5", "got [1000.0]" (round 20 left
    ``runner.n_jobs=1e3`` alone)."""
    refused(tmp_path, ["show", "smoke", override, "--root", tmp_path], said)


@pytest.mark.parametrize("override", ["+compare_with=smoke", "+seeds=3", "+runner.n_jobs=2"])
def test_adding_a_key_every_study_has_names_the_override(tmp_path, override):
    """Hydra's "Could not append to config. An item is already at 'compare_with'" was said as
    "compare_with already exists; override it without the leading '+'.", the override unnamed."""
    key = override[1:].partition("=")[0]
    refused(tmp_path, ["show", "smoke", override, "--root", tmp_path],
            f"override {override!r} adds {key}, which every study has already; set it without the "
            f"leading '+': {override[1:]}.")


def test_compare_with_forced_on_the_command_line_is_named_as_typed(tmp_path):
    """``++compare_with=`` reaches the kind check as compose finds it (``override.group``), not by
    a key test of the study check's own."""
    refused(tmp_path, ["show", "test2_grasp", "++compare_with=smoke", "--root", tmp_path],
            "override '++compare_with=smoke': compare_with = smoke is a study of trial kind "
            "mesh_features, and this study's kind is test2_grasp: it would be reported with smoke's "
            "report, which reads mesh_features records; compare with a study of kind test2_grasp "
            "(test2_grasp) or leave compare_with out.")


@pytest.mark.parametrize(("override", "written"), [
    ("seeds=３", "seeds=3"), ("runner.n_jobs=３", "runner.n_jobs=3"), ("mu=[０.３]", "mu=[0.3]")])
def test_a_full_width_digit_in_an_override_is_named_with_what_to_write(tmp_path, override, written):
    at = next(i for i, char in enumerate(override) if not char.isascii())
    refused(tmp_path, ["show", "baseline_grid", override, "--root", tmp_path],
            f"cannot parse override {override!r}: {override[at]!r} (character {at + 1}) looks like "
            f"'{written[at]}' but is not ASCII; write {written!r}.")


@pytest.mark.parametrize(("override", "said"), [
    ("mu=[5]", "factors.mu[0] = 5.0 is out of range; allowed: >= 0 and <= 3 (dry friction of soft "
               "materials stays below 3)."),
    ("seed=-1", "seed = -1 is out of range; allowed: >= 0 and <= 4294967295 (a 32-bit word, the "
                "seeds numpy's RandomState takes).")])
def test_a_bound_prints_as_plans_plausible_range_prints_it(tmp_path, override, said):
    """A float bound printed "<= 3.0", where ``plan`` and the whole-number bounds print "<= 3"."""
    refused(tmp_path, ["show", "baseline_grid", override, "--root", tmp_path], said)


@pytest.mark.parametrize("command", [["run", "smoke", "nodes=[144]", "shape=[sphere]"],
                                     ["ingest", "test2_grasp", "day1.csv", *T2]])
def test_a_new_run_in_a_study_folder_that_cannot_be_written_is_refused(tmp_path, command):
    """A study folder made immutable (a read-only share): making the run's directory ended in a
    traceback (PermissionError: [Errno 1] Operation not permitted)."""
    filled_records(tmp_path).to_csv(tmp_path / "day1.csv", index=False)
    study = tmp_path / "results" / command[1]
    study.mkdir(parents=True)
    args = [tmp_path / arg if arg == "day1.csv" else arg for arg in command]
    with immutable(study):
        refused(tmp_path / "results", [*args, "--run", "new", "--root", tmp_path / "results"],
                f"run {command[1]}/new at {study / 'new'}: {study}: cannot write there (Operation not "
                "permitted); make it writable for this user, or run the command as the user who "
                "owns the run.")


@pytest.mark.parametrize(("override", "reason"), [("mu=(0.3,0.5)", "unexpected '('"),
                                                  ("mu={0.3}", "cannot read '{0.3}'")])
def test_a_bare_factor_value_that_cannot_be_parsed_is_quoted_as_typed(tmp_path, override, reason):
    """The reason was Hydra's for the rewritten factors.mu=[(0.3,0.5)]: "cannot read '[('", a
    bracket the user never typed."""
    refused(tmp_path, ["show", "baseline_grid", override, "--root", tmp_path],
            f"cannot parse override {override!r}: {reason}; write KEY=VALUE, a list as [a,b], and "
            "quote a value holding other characters.")


def test_a_column_name_holding_a_character_that_does_not_print_is_shown_escaped(stored, tmp_path):
    """A NUL or a zero-width space pasted into a header cell was printed as it is: "a required
    column is missing: stable; a column is not part of the sheet: 'stable' (did you mean
    'stable'?)", the two names alike to the eye."""
    sheet = filled_records(tmp_path, rows=slice(2, 4))
    columns = list(sheet.columns)
    sheet.rename(columns={"stable": "sta\x00ble", "outcome": "out\u200bcome"}).to_csv(
        tmp_path / "day2.csv", index=False)
    refused(stored, ["ingest", "test2_grasp", tmp_path / "day2.csv", *T2, "--root", stored],
            "day2.csv, header: required columns are missing: outcome, stable; columns are not part of "
            "the sheet: 'out\\u200bcome' (did you mean 'outcome'?), 'sta\\x00ble' (did you mean "
            f"'stable'?); its columns are {', '.join(columns)} (`graspcampaign schedule <study> "
            "--template` writes a sheet with every column).")


def test_a_study_compared_with_a_misspelt_study_is_told_the_near_one(user_dir, tmp_path):
    """``compare_with: Smoke`` listed the 16 studies with paper values, smoke among them, where
    every other unknown name says "did you mean"."""
    study = user_dir / "mine.yaml"
    study.write_text(f"{HEADER}name: mine\nkind: mesh_features\ncompare_with: Smoke\n"
                     "factors: {shape: [sphere], nodes: [144]}\n")
    refused(tmp_path, ["show", "mine", "--root", tmp_path],
            f"{study}: compare_with = 'Smoke' is not a study with paper values; did you mean 'smoke'? "
            "allowed: ablation, baseline_grid, dynamic_check, friction_mass, gravity_settle, "
            "heuristic_weights, mesh_resolution, pso_repeatability, sensitivity, shapes, smoke, "
            "surrogate, test1_bench, test2_grasp, test3_disturbance, wrench_balance.")


@pytest.mark.parametrize(("option", "value", "said"), [
    ("--root", " results", "begins with a space, which would be part of the name; write 'results' "
                           "(its full path, for a name that does begin with one)"),
    ("--root", "results ", "ends with a space, which would be part of the name; write 'results'"),
    ("--root", "  ", "is only spaces; give a path"),
    ("--out", "sheet ", "ends with a space, which would be part of the name; write 'sheet'")])
def test_a_path_to_write_with_a_space_at_an_end_is_refused(tmp_path, monkeypatch, option, value, said):
    """Pasted with the space beside it, ``--root ' results'`` made a folder named " results" beside
    results/ and stored the run there; ``status`` then said "no run at  results/..."."""
    monkeypatch.chdir(tmp_path)
    command = ["run", "smoke", "nodes=[144]", "shape=[sphere]"] if option == "--root" else \
        ["schedule", "test2_grasp", *T2[1:]]
    refused(tmp_path, [*command, option, value], f"{option} {value!r} {said}.")
