"""The keys of a paper dict are checked when a study is composed: a key that is no level of the
factor or param it is keyed by, or no word of its vocabulary, is refused naming the study file, the
key and the allowed ones. Before, a misspelt key (``"1"`` for the weight scale ``1.0``, a planner
in a nested dict, a coating or an impulse level the protocol does not have) passed, and the report
silently said "not reported" for that level. ``show`` prints an empty paper dict as ``{}`` (it
printed a trailing ", ")."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_checks import invoke, refused

CAMPAIGNS = Path(__file__).parents[2] / "campaigns"


def copy(folder: Path, study: str, old: str, new: str) -> Path:
    """A user's copy ``my_<study>.yaml`` of a tool study (comparing with it), ``old`` replaced."""
    text = (CAMPAIGNS / f"{study}.yaml").read_text()
    assert text.count(old) == 1
    path = folder / f"my_{study}.yaml"
    path.write_text(text.replace(f"name: {study}", f"name: my_{study}\ncompare_with: {study}")
                    .replace(old, new))
    return path


@pytest.mark.parametrize("study, old, new, message", [
    ("heuristic_weights", '"1.0": 0.833', '"1": 0.833',
     "paper.h_at_scale.1 is not a level of factors.weight_scale; allowed: 1.0, 0.5, 2.0."),
    ("mesh_resolution", '"1750": 72.0', '"1570": 72.0', "paper.runtime_ms.1570 is not a level of "
     "params.resolutions; allowed: 144, 250, 356, 390, 600, 900, 1300, 1750."),
    ("baseline_grid", "rounded_cube: {heuristic: 56.0", "rounded_cube: {heuristc: 56.0",
     "paper.success_by_shape_pct.rounded_cube.heuristc is not a known planner; allowed: heuristic, "
     "no_s1, no_s2, no_s3, no_pc, no_pe, antipodal, centroid, no_pso, force_balance, random, "
     "ferrari_canny, reference."),
    ("surrogate", "auc: {mlp:", "auc: {MLP:",
     "paper.auc.MLP is not a known model; allowed: pso_call, mlp, random_forest."),
    # keyed by the levels the protocols fix (analysis.vocabulary, which rig/ builds its sheets from)
    ("test1_bench", '"30": 0.05', '"35": 0.05',
     "paper.oblique_margin_n.35 is not a known press_angle; allowed: 0, 15, 30, 45."),
    ("test3_disturbance", "coating: {high:", "coating: {hgh:",
     "paper.coating.hgh is not a known coating; allowed: high, medium, low."),
    ("test3_disturbance", "down_0.5: 82.0", "down_0.3: 82.0", "paper.vertical_levels_pct.down_0.3 is not a "
     "known vertical_load; allowed: down_0.25, down_0.5, down_0.75, up_0.5, up_1.0."),
    ("test3_disturbance", '"0.8": 98.0', '"0.9": 98.0', "paper.impulse_retained_pct.0.9 is not a known "
     "impulse_load; allowed: 0.8, 1.0, 1.2, 1.4, 1.8."),
    ("test3_disturbance", '"1.8": 100.0', '"1.6": 100.0', "paper.impulse_drop_pct.1.6 is not a known "
     "impulse_load; allowed: 0.8, 1.0, 1.2, 1.4, 1.8."),
    ("friction_mass", "finger3: 12.0", "finger_3: 12.0", "paper.finger_forces_internal_units.finger_3 is "
     "not a known finger; allowed: finger1, finger2, finger3."),
])
def test_a_paper_key_outside_its_levels_is_refused(user_dir, tmp_path, study, old, new, message):
    path = copy(user_dir, study, old, new)
    for command in ("show", "run"):
        refused(tmp_path, [command, path.stem, "--root", tmp_path / "results"], f"{path}: {message}")


def test_a_reduced_design_keeps_the_papers_other_levels(user_dir, tmp_path):
    # the paper's 1750-node runtime stays valid when a run leaves that resolution out
    shown = invoke("show", "mesh_resolution", "params.resolutions=[144,390]", "--root", tmp_path)
    assert shown.exit_code == 0, shown.output


def test_show_prints_an_empty_paper_dict_as_such(user_dir, tmp_path):
    path = copy(user_dir, "ablation", "success_pct: {heuristic: 72.0, no_s1: 72.0, no_s2: 72.0, no_s3: 72.0, "
                "no_pc: 72.0, no_pe: 72.0,\n                random: 6.0, centroid: 0.0}", "success_pct: {}")
    shown = invoke("show", path.stem, "--root", tmp_path)
    assert shown.exit_code == 0, shown.output
    assert ("paper: figure=Fig. 16, trials_per_variant=50, interval_half_width_pp=12.0, success_pct={}\n"
            in shown.stdout)
