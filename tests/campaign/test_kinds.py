"""The simulation trial kinds end to end, on reduced versions of the real study files."""

from __future__ import annotations

import numpy as np
import pytest

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study

REQUIRED = ["trial_id", "study", "planner", "shape", "mass_kg", "mu", "seed", "status", "success",
            "failure_check", "residual_norm_n", "torque_norm_nm", "slip_margin_n", "eta",
            "delta_max_mm", "h_total", "s1", "s2", "s3", "n_sharp_vertex", "n_sharp_edge",
            "wall_time_s"]


def _run(study, tmp_path, *overrides):
    cfg = compose_study(study, ["runner.backend=sequential", f"output.root={tmp_path}", *overrides])
    summary = run_study(cfg)
    store = RunStore(summary.path)
    return summary, store, store.read().to_pandas()


def test_reduced_baseline_grid_end_to_end(tmp_path):
    summary, store, df = _run("baseline_grid", tmp_path, "shape=[sphere,handle]", "mass_kg=[0.4]",
                              "mu=[0.3]", "seeds=2")
    assert summary.n_error == 0 and len(df) == 2 * 4 * 2
    assert set(REQUIRED) <= set(df.columns)
    # every planner of one scene draw sees the same object, mass, friction and seed
    scenes = df.groupby("scene_id")
    assert (scenes["planner"].nunique() == 4).all()
    assert (scenes[["shape", "mass_kg", "mu", "seed"]].nunique() == 1).all().all()
    # one identification per soft body, reused by every trial of that body
    prepared = store.read("prepared").to_pandas()
    assert len(prepared) == 2 and summary.n_prepared == 2
    for _, body in prepared.iterrows():
        used = df.loc[df["shape"] == body["shape"], "lambda1"]
        assert np.allclose(used, body["lambda1"])
    assert run_study(compose_study("baseline_grid", [
        "runner.backend=sequential", f"output.root={tmp_path}", "shape=[sphere,handle]",
        "mass_kg=[0.4]", "mu=[0.3]", "seeds=2"])).n_prepared == 0
    # Sec. 6.5: centroid's normals are horizontal, so delta never leaves its 0.5 mm seed
    centroid = df[df["planner"] == "centroid"]
    assert not centroid["success"].any()
    np.testing.assert_allclose(centroid[["delta_1_mm", "delta_2_mm", "delta_3_mm"]], 0.5)
    np.testing.assert_allclose(centroid[["contact_normal_z_1", "contact_normal_z_2",
                                         "contact_normal_z_3"]], 0.0, atol=1e-12)
    assert (df["exceeds_1mm"] == (df["delta_max_mm"] > 1.0)).all()


def test_no_pso_is_judged_under_the_body_parameters(tmp_path):
    _, _, df = _run("ablation", tmp_path, "shape=[sphere]", "seeds=1", "+factors.planner=[no_pso]")
    row = df.iloc[0]
    assert row["believed_n_exp"] == 1.5 and row["n_exp"] != 1.5  # nominal belief, identified truth


def test_uniform_weight_scaling_never_moves_the_argmin(tmp_path):
    _, _, df = _run("heuristic_weights", tmp_path, "seeds=3")
    assert (df.groupby("seed")["argmin_key"].nunique() == 1).all()
    # H scales with the weights: H(0.5) = H(1)/2 and H(2) = 2 H(1) on the same triple
    for _, group in df.groupby("seed"):
        h = group.set_index("weight_scale")["h_total"]
        assert h[0.5] == pytest.approx(h[1.0] / 2) and h[2.0] == pytest.approx(2 * h[1.0])
    assert df["s1_reachable"].iloc[0] == pytest.approx(0.25, abs=0.02)  # Sec. 5.2, nearest vertices


def test_wrench_balance_reaches_the_grip_command(tmp_path):
    summary, store, df = _run("wrench_balance", tmp_path, "mu=[0.3]")
    trace = store.read("tables/iterations").to_pandas()
    assert len(trace) == 100
    assert trace["normal_force_1_n"].iloc[-1] == pytest.approx(65.0)
    assert np.all(np.diff(trace["normal_force_1_n"]) >= 0)


def test_pso_repeatability_trace_and_bounds(tmp_path):
    from graspcampaign.core.identify import PAPER_BOUNDS

    summary, store, df = _run("pso_repeatability", tmp_path, "seeds=2", "budget=[repeatability]")
    trace = store.read("tables/pso_trace").to_pandas()
    assert len(trace) == 2 * 15 and trace.groupby("trial_id")["n_evaluations"].max().eq(120).all()
    for _, t in trace.groupby("trial_id"):
        assert np.all(np.diff(t.sort_values("iteration")["best_cost"]) <= 0)
    for name, column in (("lambda1", "lambda1"), ("n", "n_exp"), ("b", "b"), ("c", "c")):
        low, high = PAPER_BOUNDS[name]
        assert df[column].between(low, high).all()


def test_gravity_settle_records_trace_and_shape(tmp_path):
    summary, store, df = _run("gravity_settle", tmp_path, "nodes=[144]", "+params.settle_t_max_s=0.3")
    row = df.iloc[0]
    assert 0.0 < row["squash_ratio"] <= 1.0
    trace = store.read("tables/settle").to_pandas()
    assert trace["time_s"].is_monotonic_increasing and len(trace) > 10
    shape = store.read("tables/shape").to_pandas()
    assert len(shape) == 144


def test_dynamic_grasp_records_traces_and_like_for_like(tmp_path):
    summary, store, df = _run("friction_mass", tmp_path, "nodes=[144]", "mu=[0.3]", "mass_kg=[0.2]",
                              "+params.t_max_s=0.05")
    row = df.iloc[0]
    assert row["dynamic_status"] in ("stable", "not_settled", "penetration_limit", "dropped")
    assert row["lp_status"] in ("feasible", "infeasible", "undetermined")
    assert isinstance(row["qs_success"], (bool, np.bool_))
    steps = store.read("tables/steps").to_pandas()
    assert set(steps["trial_id"]) == {row["trial_id"]}
    assert {"residual_z_n", "total_penetration_m", "normal_force_3_n"} <= set(steps.columns)
    assert steps["time_s"].is_monotonic_increasing
