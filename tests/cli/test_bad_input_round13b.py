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
