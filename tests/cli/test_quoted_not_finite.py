"""A quoted text that reads as no finite number ('Infinity', '-inf', 'NaN') given
in a mapping override for a number key (``pso={inertia: 'Infinity'}``). Each is one sentence naming what
is wrong and where, as typed, exit 2, nothing stored changed (``cli_checks.refused``)."""

from __future__ import annotations

import pytest
from cli_checks import HEADER, invoke, refused


@pytest.mark.parametrize(("override", "said"), [
    ("pso={inertia: 'Infinity'}", "Infinity is infinite"),
    ("pso={inertia: '-inf'}", "-inf is infinite"),
    ('pso={inertia: "NaN"}', "NaN is not a number"),
    ("runner={progress_interval_s: 'Infinity'}", "Infinity is infinite"),
    ("evaluator={tau_f_n: 'nan'}", "nan is not a number"),
    ("pso={inertia: 0.5, c1: '-Infinity'}", "-Infinity is infinite"),
    ("factors={mu: [0.3, 'inf']}", "inf is infinite")])
def test_a_quoted_text_for_a_number_in_a_mapping_is_refused_as_typed(tmp_path, override, said):
    """Hydra reads a quoted 'Infinity' as text and the number field's float() as inf: the schema
    refused it as "pso.inertia must be finite, got inf." (not as typed), where the unquoted forms
    (``pso={inertia: Infinity}``) and a quoted one set alone (``pso.inertia='Infinity'``) are refused
    as typed; the mapping's entry is now scanned with its quoted text. factors' list said it as typed
    without the override ("factors.mu[1]: inf is infinite; give a finite number.")."""
    refused(tmp_path, ["show", "baseline_grid", override, "--root", tmp_path],
            f"override {override!r}: {said}; give a finite number.")


@pytest.mark.parametrize(("override", "run"), [("output={run: 'nan'}", "nan"),
                                               ("output={run: 'Infinity'}", "Infinity")])
def test_a_quoted_text_key_in_a_mapping_may_still_read_inf_or_nan(tmp_path, override, run):
    """The quoted text is scanned only in the entry of a key that takes a number: a run may be named nan."""
    done = invoke("show", "smoke", override, "--root", tmp_path)
    assert done.exit_code == 0 and f"run: {tmp_path}/smoke/{run} (0 of" in done.stdout, done.output


@pytest.mark.parametrize(("line", "key", "said"), [
    ("pso: {inertia: 'Infinity'}", "pso.inertia", "Infinity is infinite"),
    ("runner: {progress_interval_s: '-inf'}", "runner.progress_interval_s", "-inf is infinite"),
    ('evaluator: {tau_f_n: "NaN"}', "evaluator.tau_f_n", "NaN is not a number")])
def test_a_quoted_text_for_a_number_in_a_study_file_is_refused_as_typed(tmp_path, line, key, said):
    """A study file's quoted forms were already refused as typed: held so."""
    study = tmp_path / "mine.yaml"
    study.write_text(f"{HEADER}name: mine\nkind: mesh_features\n{line}\nfactors: {{shape: [sphere], "
                     "nodes: [144]}\n")
    refused(tmp_path, ["show", study, "--root", tmp_path / "results"],
            f"{study}, line 5: {key}: {said}; give a finite number.")
