"""Mutation round 9: what dynamic_check says of a source run it cannot use (docs/decisions.md,
mutation round 9): the command to finish it gives the source's overrides as every command resuming
a run reads them (``provenance.overrides_given``), and a source run name is a run name."""

from __future__ import annotations

import json

import pytest
from cli_checks import BG, refused, unfinished_source


def test_an_unfinished_source_whose_overrides_hold_a_number_is_named_in_one_sentence(tmp_path, monkeypatch):
    """dynamic_check's command to finish its source run read the source's ``overrides`` itself and
    joined a number into it (a TypeError and its traceback); as every command resuming a run, it
    gives them as ``overrides_given`` reads them: none that is not text."""
    root = tmp_path / "results"
    source = unfinished_source(root, monkeypatch)
    manifest = source / "manifest.json"
    manifest.write_text(json.dumps({**json.loads(manifest.read_text()), "overrides": [1, *BG]}))
    refused(root, ["run", "dynamic_check", "runner.backend=sequential", "--root", root],
            f"dynamic_check needs every trial of baseline_grid/default, but 1 of 2 are not recorded "
            f"under {source}; run `graspcampaign run baseline_grid --root {root}` again to finish it.")


@pytest.mark.parametrize(("key", "value"), [
    ("source_run", "''"), ("source_run", "../x"), ("source_run", "x/y"), ("source_run", "."),
    ("source_study", "../smoke"),
])
def test_a_source_named_by_no_run_name_is_refused_as_a_run_name_is(tmp_path, key, value):
    """``params.source_run=''`` named the study's directory as the run and advised ``run
    baseline_grid --run ''``, which `run` refuses (as ``--run ../x``): a source run or study name is
    a name of one path component, as ``--run`` and ``output.run`` are, refused in their words."""
    root = tmp_path / "results"
    shown = value.strip("'")
    refused(root, ["run", "dynamic_check", f"params.{key}={value}", "--root", root],
            f"params.{key} = {shown!r} is not allowed; use ASCII letters (a-z, A-Z), digits, '.', '_' "
            "and '-' (starting with a letter or digit, at most 100), so the run stays inside the results "
            "directory.")
