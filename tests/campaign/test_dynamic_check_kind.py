"""The dynamic_check kind end to end at small scale: a reduced baseline_grid, then its check.

Outside references: the source study's own records (vertex ids, labels), the planner's geometry
(the centroid planner's horizontal normals, Sec. 6.5) and the validity gate's definition.
"""

from __future__ import annotations

import numpy as np
import pytest

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.kinds import dynamic_check as kind
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study
from graspcampaign.errors import MissingSourceRunError, UserInputError

SOURCE = ("shape=[sphere]", "mass_kg=[0.2]", "mu=[0.5]", "seeds=1", "+params.nodes=144")


def _run(study, root, *overrides, run=None):
    cfg = compose_study(study, ["runner.backend=sequential", "runner.progress=false",
                                f"output.root={root}", *overrides])
    summary = run_study(cfg, run=run)
    return summary, RunStore(summary.path).read().to_pandas()


@pytest.fixture(scope="module")
def checked(tmp_path_factory):
    root = tmp_path_factory.mktemp("dynamic_check")
    _, source = _run("baseline_grid", root, *SOURCE)
    # cut at 0.12 s: the closure (~0.08 s) and the start of the lift-off are simulated
    summary, records = _run("dynamic_check", root, "+params.t_max_s=0.12")
    return root, source, summary, records


def test_dynamic_check_re_runs_every_source_trial_per_preset(checked):
    _, source, summary, records = checked
    assert summary.n_error == 0 and len(records) == 2 * len(source) == 2 * 5  # 4 planners + ferrari_canny
    assert sorted(records["model_preset"].unique()) == ["firm", "table2"]
    for preset, group in records.groupby("model_preset"):
        assert set(group["source_trial_id"]) == set(source["trial_id"]), preset
    merged = records.merge(source, left_on="source_trial_id", right_on="trial_id",
                           suffixes=("", "_source"))
    # the planned contacts of the source records, re-planned from their own streams
    for j in (1, 2, 3):
        np.testing.assert_array_equal(merged[f"vertex_{j}"], merged[f"vertex_{j}_source"])
    for column in ("shape", "mass_kg", "mu", "planner", "seed"):
        np.testing.assert_array_equal(merged[column], merged[f"{column}_source"])
    # centroid contacts are the exact ray hits with horizontal normals (Sec. 6.5), not vertices
    centroid = records[records["planner"] == "centroid"]
    np.testing.assert_allclose(centroid[["contact_normal_z_1", "contact_normal_z_2",
                                         "contact_normal_z_3"]], 0.0, atol=1e-12)
    assert (records["source_study"] == "baseline_grid").all()


def test_dynamic_check_records_both_labels(checked):
    _, source, _, records = checked
    merged = records.merge(source, left_on="source_trial_id", right_on="trial_id",
                           suffixes=("", "_source"))
    radius_mm = 5.0  # conf/model/table2.yaml, the source's fingertip
    # source labels by column name; the gate applied here when the source predates it
    if "success_unbounded_source" in merged.columns:
        np.testing.assert_array_equal(merged["qs_success"], merged["success_source"])
    else:
        assert merged["qs_gate_derived"].all()
        np.testing.assert_array_equal(merged["qs_success_unbounded"], merged["success_source"])
        np.testing.assert_array_equal(merged["qs_valid_geometry"],
                                      merged["delta_max_mm_source"] <= radius_mm)
    np.testing.assert_array_equal(merged["qs_success"],
                                  merged["qs_success_unbounded"] & merged["qs_valid_geometry"])
    np.testing.assert_allclose(merged["qs_delta_max_mm"], merged["delta_max_mm_source"])
    # the dynamic labels and the like-for-like label under the preset, each with its gate
    for prefix in ("", "qs_preset_"):
        np.testing.assert_array_equal(
            records[f"{prefix}success"],
            records[f"{prefix}success_unbounded"] & records[f"{prefix}valid_geometry"])
    np.testing.assert_array_equal(records["valid_geometry"],
                                  records["delta_max_mm"] <= records["fingertip_radius_mm"])
    assert set(records["dynamic_status"]) <= {"stable", "not_settled", "penetration_limit",
                                              "dropped"}
    lifted = records[records["closure_end_s"].notna()]  # contacts close before lift-off
    assert len(lifted) and (lifted["closure_end_s"] > lifted[["touch_1_s", "touch_2_s",
                                                              "touch_3_s"]].max(axis=1)).all()
    firm = records[records["model_preset"] == "firm"]
    assert (firm["n_exp"] == 1.5).all() and (firm["e_object_pa"] == 2455800.0).all()
    assert (records["plan_time_s"] > 0).all() and (records["grasp_time_s"] > 0).all()
    # every planner of one source scene shares a scene id (paired comparisons)
    assert records.groupby("model_preset")["scene_id"].nunique().eq(1).all()


def test_planner_filter_and_resume(checked):
    root, _, _, _ = checked
    summary, records = _run("dynamic_check", root, "+params.t_max_s=0.12",
                            "+factors.planner=[centroid]", "model_preset=[table2]", run="subset")
    assert summary.n_trials == 1 and (records["planner"] == "centroid").all()


def test_replanned_vertices_must_match_the_record(checked):
    root, _, _, _ = checked
    source = kind.load_source(str(root), "baseline_grid", "default")
    row = source.records.iloc[0].copy()
    row["vertex_1"] = row["vertex_1"] + 1
    with pytest.raises(RuntimeError, match=rf"re-planning {row['trial_id']} gave vertices "
                                           r"\[\d+, \d+, \d+\], its record has \[\d+, \d+, \d+\]: "
                                           r"the planner or its config changed since the source "
                                           r"ran$"):
        kind._replan(source, row)


def test_a_relative_source_root_is_read_from_the_working_directory(checked, tmp_path, monkeypatch):
    """A source run was cached by its root as given: asked for under a relative root from a
    directory holding the run, then from one holding none, the second read the first's run
    (test_main::test_list_separates_the_papers_studies_from_the_extensions listed dynamic_check
    with 4 trials, not "after baseline_grid", after another test's list had read its run)."""
    root, source = checked[0], checked[1]
    monkeypatch.chdir(root.parent)
    assert set(kind.load_source(root.name, "baseline_grid", "default").trials) == set(
        source["trial_id"])
    monkeypatch.chdir(tmp_path)
    with pytest.raises(MissingSourceRunError, match=rf"^dynamic_check re-simulates the records of "
                                                    rf"baseline_grid/default, but {root.name}/"
                                                    r"baseline_grid/default holds no run; "):
        kind.load_source(root.name, "baseline_grid", "default")


def test_missing_or_wrong_source_is_bad_input(tmp_path):
    with pytest.raises(UserInputError) as info:
        _run("dynamic_check", tmp_path)
    assert str(info.value) == (
        "dynamic_check re-simulates the records of baseline_grid/default, but "
        f"{tmp_path}/baseline_grid/default holds no run; run `graspcampaign run baseline_grid "
        f"--root {tmp_path}` first (or set params.source_study / params.source_run).")
    assert not any(tmp_path.iterdir())  # nothing written
    _run("smoke", tmp_path, "nodes=[144]")
    with pytest.raises(UserInputError, match=r"^dynamic_check re-simulates quasi-static plans, "
                                             r"but smoke/default is a 'mesh_features' run; "):
        _run("dynamic_check", tmp_path, "params.source_study=smoke")
    with pytest.raises(UserInputError, match=r"^study 'dynamic_check' \(trial kind 'dynamic_check'\) "
                                             r"builds its own trial list from its params and reads "
                                             r"only the factors model_preset, shape, mass_kg, mu and "
                                             r"planner: factors\.nodes would change nothing"):
        _run("dynamic_check", tmp_path, "+factors.nodes=[144]")


def test_a_missing_source_is_made_by_the_command_named_even_off_its_configured_run(tmp_path, monkeypatch):
    """The advice said `graspcampaign run S` whenever the source run was named "default", which
    for a source study whose output.run is another name writes that run and not the one missing."""
    from pathlib import Path

    studies = tmp_path / "mine"
    studies.mkdir()
    text = (Path(__file__).parents[2] / "campaigns" / "baseline_grid.yaml").read_text()
    (studies / "my_grid.yaml").write_text(text.replace("name: baseline_grid", "name: my_grid\n"
                                                       "compare_with: baseline_grid\noutput:\n  run: mine"))
    monkeypatch.setenv("GRASPCAMPAIGN_PATH", str(studies))
    with pytest.raises(UserInputError) as info:
        _run("dynamic_check", tmp_path, "params.source_study=my_grid", "params.source_run=default")
    assert (f"run `graspcampaign run my_grid --run default --root {tmp_path}` first (or set "
            "params.source_study / params.source_run).") in str(info.value)
    assert info.value.source == "my_grid --run default"  # what `list` says to run first



def _source_frame(rows, missing):
    """A source run's ok records as ``load_source`` holds them: an Arrow table (a null where a trial
    has no reading) read into pandas, indexed by trial id; ``missing`` "NaN": the nulls as NaN, as a
    frame reindexed or concatenated in pandas holds them."""
    import pyarrow as pa

    frame = pa.Table.from_pylist(rows).to_pandas()
    if missing == "NaN":
        frame = frame.astype(object).where(frame.notna(), np.nan)
    return frame.set_index("trial_id", drop=False)


@pytest.mark.parametrize("missing", ["None", "NaN"])
def test_a_source_trial_without_a_label_is_unlabelled_not_a_label(missing):
    """``source_labels`` read a source label with ``bool()``: a trial whose file lacked
    ``success_unbounded`` / ``valid_geometry`` (null) was checked as a quasi-static failure (None) or
    success (NaN). Its label is now None and the agreement table counts it in ``unlabelled``."""
    from types import SimpleNamespace

    from graspcampaign.analysis.dynamic_check import agreement_table

    source = SimpleNamespace(study=SimpleNamespace(model=SimpleNamespace(fingertip_radius_m=0.005)))
    # (success, success_unbounded, valid_geometry) of five source trials; None: not recorded
    labels = {"t0": (True, True, True), "t1": (False, None, True), "t2": (False, True, None),
              "t3": (None, None, None), "t4": (False, False, True)}
    rows = _source_frame([{"trial_id": t, "success": s, "success_unbounded": u, "valid_geometry": v,
                           "delta_max_mm": 1.0, "failure_check": "none"}
                          for t, (s, u, v) in labels.items()], missing)
    got = {t: kind.source_labels(source, rows.loc[t]) for t in labels}
    for t, (s, u, v) in labels.items():
        assert (got[t]["qs_success"], got[t]["qs_success_unbounded"], got[t]["qs_valid_geometry"]) == \
            (s, u, v), t
        assert got[t]["qs_gate_derived"] is False
    # the check's records (every dynamic grasp held), as the kind's rows are stored
    import pyarrow as pa

    records = pa.Table.from_pylist([{"status": "ok", "dynamic_status": "stable", "success": True,
                                     "success_unbounded": True, **got[t]} for t in labels]).to_pandas()
    gated = agreement_table(records, "qs_success", "success").iloc[0]
    # by hand: qs_success recorded on t0, t1, t2, t4 (t0 held in both, the other three dynamic only)
    assert (gated["n"], gated["unlabelled"], gated["both_success"], gated["dynamic_only"]) == (4, 1, 1, 3)
    unbounded = agreement_table(records, "qs_success_unbounded", "success_unbounded").iloc[0]
    # by hand: qs_success_unbounded recorded on t0, t2 (True) and t4 (False)
    assert (unbounded["n"], unbounded["unlabelled"], unbounded["both_success"],
            unbounded["dynamic_only"]) == (3, 2, 2, 1)


def test_a_source_before_the_gate_without_a_reading_is_unlabelled():
    """A source written before the validity gate (no ``success_unbounded`` / ``valid_geometry``)
    derives the gate here: a trial without ``success`` or ``delta_max_mm`` gets no label from it."""
    from types import SimpleNamespace

    source = SimpleNamespace(study=SimpleNamespace(model=SimpleNamespace(fingertip_radius_m=0.005)))
    rows = _source_frame([{"trial_id": "a", "success": None, "delta_max_mm": 1.0},
                          {"trial_id": "b", "success": True, "delta_max_mm": None},
                          {"trial_id": "c", "success": True, "delta_max_mm": 6.0}], "None")
    got = [kind.source_labels(source, rows.loc[t]) for t in "abc"]
    assert [(g["qs_success"], g["qs_success_unbounded"], g["qs_valid_geometry"]) for g in got] == [
        (None, None, True), (None, True, None), (False, True, False)]  # c: 6 mm > the 5 mm radius
    assert all(g["qs_gate_derived"] for g in got)
