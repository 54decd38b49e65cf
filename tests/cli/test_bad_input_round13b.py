"""Bad input, round 13: its left-overs. Hydra's functions of sweeps in an override, a factor's bare
name with an element index, and a schedule file stem that is only a suffix. Each refusal: exit 2,
one sentence naming what is wrong, where, and what to write, nothing stored changed
(``refused``)."""

from __future__ import annotations

import pytest
from cli_checks import refused

SWEEP_TAIL = ("(one study per value, Hydra's --multirun), which this tool does not run; give a "
              "factor its levels as a list (e.g. mu=[0.3,0.5]), or run the study once per value.")


@pytest.mark.parametrize(("typed", "function"), [
    # sort() and shuffle() of a list return a list, which the bare name wrapped as one level:
    # "factors.shape[0] must be of type str, got ['cube', 'sphere'] (list)."
    ("shape=sort([sphere,cube])", "sort"),
    ("shape=shuffle([sphere,cube])", "shuffle"),
    ("factors.shape=[sphere,shuffle([pear,handle])]", "shuffle"),
    # Hydra's own words: "TypeError while evaluating 'tag(a,[sphere])': mismatch type argument ..."
    ("shape=tag(a,[sphere])", "tag"),
])
def test_a_function_of_hydras_sweeps_is_refused_as_a_sweep_is(tmp_path, typed, function):
    refused(tmp_path, ["show", "smoke", typed, "--root", tmp_path],
            f"override {typed!r} calls {function}(), a function of Hydra's sweeps {SWEEP_TAIL}")


def test_a_quoted_function_name_is_text(tmp_path):
    # 'sort(x)' quoted is a level's name, refused as a shape none of the study's
    refused(tmp_path, ["show", "smoke", "shape=['sort(x)']", "--root", tmp_path],
            "factors.shape[0] has unknown value 'sort(x)'; allowed values: sphere, ellipsoid, "
            "rounded_cube, pear, handle.")


def test_a_factors_bare_name_with_a_level_index_sets_that_level(tmp_path):
    # shape.0=cube was "shape is not a known key of the study config (...); did you mean paper?";
    # it now is factors.shape.0=cube, refused as that override is (cube is no shape)
    said = ("factors.shape[0] has unknown value 'cube'; allowed values: sphere, ellipsoid, "
            "rounded_cube, pear, handle.")
    refused(tmp_path, ["show", "smoke", "shape.0=cube", "--root", tmp_path], said)
    refused(tmp_path, ["show", "smoke", "factors.shape.0=cube", "--root", tmp_path], said)


def test_a_factors_bare_name_with_a_level_index_composes_as_the_full_key():
    from graspcampaign.campaign.compose import compose_study

    # the study's levels (smoke.yaml: sphere, ellipsoid, rounded_cube, pear, handle), level 1 replaced
    assert compose_study("smoke", ["shape.1=rounded_cube", "shape.2=ellipsoid"]).factors["shape"] == [
        "sphere", "rounded_cube", "ellipsoid", "pear", "handle"]


@pytest.mark.parametrize(("typed", "level"), [
    # each was "shape is not a known key of the study config; did you mean paper? known keys: ..."
    ("+shape.0=pear", "shape.0=pear"),
    ("+shape=[pear]", "shape.0=VALUE"),
    ("shape.x=1", "shape.0=VALUE"),
])
def test_a_factors_bare_name_in_another_form_is_refused_with_the_forms_it_takes(tmp_path, typed, level):
    refused(tmp_path, ["show", "smoke", typed, "--root", tmp_path],
            f"override {typed!r} names the factor shape by its bare name in a form it does not "
            f"take; write {level} (one level, as factors.{level}) or shape=[...] (all its levels).")


def test_a_bare_name_with_an_index_of_a_factor_the_study_lacks_says_to_add_it(tmp_path):
    # it was "planner is not a known key of the study config (...); did you mean paper? ..."
    refused(tmp_path, ["show", "smoke", "planner.0=pso", "--root", tmp_path],
            "planner is not a factor of this study (override 'planner.0=pso' rejected; its factors: "
            "nodes, shape); add it with +factors.planner=[heuristic, random].")


@pytest.mark.parametrize("name", [".csv", ".Parquet", ".xlsx"])
def test_a_schedule_stem_that_is_only_a_suffix_is_refused(tmp_path, name):
    # --out <dir>/.csv wrote the hidden files .csv.csv and .csv.parquet
    out = tmp_path / name
    refused(tmp_path, ["schedule", "test2_grasp", "--out", out, "--root", tmp_path / "results"],
            f"--out {out} names only a suffix, no file name (a name beginning with a dot is a "
            f"hidden file's); give a file stem such as {tmp_path / 'schedule'}.")
