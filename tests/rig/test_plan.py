"""Planner predictions and the ``plan MESH`` computation (§8.1, §9.1; SPEC §2.10, §7)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from graspcampaign.core import disturbance as d
from graspcampaign.core.mesh import SHAPES, MeshError, make_object
from graspcampaign.core.statics import GRAVITY
from graspcampaign.rig import belief as rb
from graspcampaign.rig import plan as rp
from graspcampaign.rig import protocol


@pytest.fixture(scope="module")
def stl_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("meshes")
    paths = {}
    for shape in SHAPES:
        mesh = make_object(shape, 390)
        mesh.apply_scale(1000.0)  # the file is in millimetres
        paths[shape] = folder / f"{shape}.stl"
        mesh.export(paths[shape])
    return paths


@pytest.mark.parametrize("shape", list(SHAPES))
def test_plan_on_each_shape_predicts_the_shared_budget_limits(stl_files, shape, tmp_path):
    png = tmp_path / f"{shape}.png"
    out = rp.plan_mesh(stl_files[shape], mass_kg=0.1, material="silicone_ref", png_path=png)
    w = 0.1 * GRAVITY
    sf = out["sf_predicted"]
    assert out["weight_n"] == pytest.approx(w)
    if sf >= 1.0:
        assert out["f_lat_n"] == pytest.approx(w * math.sqrt(sf**2 - 1.0))  # F_lat = W sqrt(SF^2-1)
        assert out["f_down_n"] == pytest.approx(w * (sf - 1.0))
        assert out["torque_nm"] == pytest.approx(w * math.sqrt(sf**2 - 1.0) * out["r_eff_mm"] / 1e3)
    else:
        assert out["f_lat_n"] == out["f_down_n"] == out["torque_nm"] == 0.0
    assert sf == pytest.approx(d.safety_factor(out["mu_s"], out["grip_force_n"], out["g_geo"], 0.1))
    assert len(out["contacts"]) == 3
    assert set(out["first_finger"].values()) <= {0, 1, 2, 3}
    assert set(out["h"]) == {"h_tilde", "s1", "s2", "s3", "pc_mag", "pe_mag"}
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    json.dumps(out)  # the CLI prints it with --json


def test_plan_mesh_states_the_residual_check_apart_from_the_stability_verdict(stl_files):
    out = rp.plan_mesh(stl_files["sphere"], mass_kg=0.05)
    assert out["predicted_stable"] and out["residual_n"] > 0.0886  # the verdict is not the residual's
    assert out["sf_predicted"] > 1.0 and out["unloaded_fingers"] == []  # §9.5: why it is stable
    assert out["tau_f_n"] == 0.0886  # §8.1
    assert out["predicted_stable_residual"] is False


def test_plan_warns_once_of_a_coarse_mesh_with_a_remedy_outside_python(tmp_path, caplog):
    import trimesh

    from graspcampaign.core.feature import CoarseMeshWarning

    box = trimesh.creation.box(extents=(40.0, 30.0, 20.0))  # 8 vertices, in mm
    box.export(tmp_path / "box.stl")
    with pytest.warns(CoarseMeshWarning) as caught:
        rp.plan_mesh(tmp_path / "box.stl", mass_kg=0.1)
    assert len(caught) == 1 and not caplog.records
    message = str(caught[0].message)
    assert message.startswith("mesh 'box.stl' has only 8 vertices and the planner places fingers")
    assert message.endswith("remesh or subdivide it finer for a better plan (the paper's objects "
                            "have 390 vertices)")
    assert "FeatureThresholds" not in message
    assert caught[0].filename == __file__  # points at the caller of plan_mesh


def test_plan_with_mu_overrides_the_material(stl_files):
    out = rp.plan_mesh(stl_files["sphere"], mass_kg=0.05, mu=0.9)
    assert out["mu_s"] == 0.9 and out["material"] == rp.DEFAULT_PLAN_MATERIAL
    assert out["png"] is None


MASS = ("below 0.1 g an object weighs less than the rig's 1 mN force resolution, and a "
        "three-finger hand lifts at most ~10 kg")


@pytest.mark.parametrize("kwargs, message", [
    ({"mass_kg": 0.0}, f"mass_kg = 0.0 is out of range; allowed: >= 0.0001 and <= 10 kg ({MASS})."),
    ({"mass_kg": 50.0}, f"mass_kg = 50.0 is out of range; allowed: >= 0.0001 and <= 10 kg ({MASS})."),
    # 1e-300 kg passed (> 0) and planned a grasp of zero forces
    ({"mass_kg": 1e-300}, f"mass_kg = 1e-300 is out of range; allowed: >= 0.0001 and <= 10 kg "
                          f"({MASS})."),
    ({"mass_kg": "heavy"}, "mass_kg must be a number, got 'heavy'."),
    ({"mass_kg": 0.1, "mu": -0.2}, "mu = -0.2 is out of range; allowed: >= 0 and <= 3 (dry friction "
                                   "of soft materials stays below 3)."),
    ({"mass_kg": 0.1, "mu": 50}, "mu = 50 is out of range; allowed: >= 0 and <= 3 (dry friction of "
                                 "soft materials stays below 3)."),
    ({"mass_kg": 0.1, "fingertip_radius_mm": 80},
     "fingertip_radius_mm = 80 is out of range; allowed: >= 1 and <= 50 mm (below 1 mm the "
     "evaluator's 0.5 mm seed penetration sinks half a fingertip's radius, and robot pads stay "
     "below 50 mm)."),
    ({"mass_kg": 0.1, "material": "steel"},
     "material = 'steel' is not a Table 4 material family; use one of gel, silicone_soft, "
     "bio_foam, silicone_ref."),
])
def test_plan_rejects_bad_values(stl_files, kwargs, message):
    with pytest.raises(ValueError) as info:
        rp.plan_mesh(stl_files["sphere"], **kwargs)
    assert str(info.value) == message


def test_plan_rejects_bad_meshes(tmp_path):
    mesh = make_object("sphere", 200)
    mesh.update_faces(np.arange(len(mesh.faces)) > 3)  # punch a hole
    path = tmp_path / "open.stl"
    mesh.export(path)
    with pytest.raises(MeshError, match="not watertight"):
        rp.plan_mesh(path, mass_kg=0.1)
    with pytest.raises(MeshError, match="does not exist"):
        rp.plan_mesh(tmp_path / "missing.stl", mass_kg=0.1)
    with pytest.raises(MeshError, match="'mesh' is not watertight"):  # a Trimesh: the same checks
        rp.plan_mesh(mesh, mass_kg=0.1)


def test_plan_of_a_trimesh_is_the_plan_of_its_file(stl_files):
    """A Trimesh given directly is checked and centred as a file's mesh is: moved and wound inward,
    it plans the grasp the file does (the contacts in the centred frame)."""
    import trimesh

    from graspcampaign.core.mesh import load_mesh

    mesh = load_mesh(stl_files["sphere"], unit="mm")
    moved = mesh.copy()
    moved.apply_translation([0.3, -0.2, 0.1])
    moved.invert()
    assert isinstance(moved, trimesh.Trimesh) and moved.volume < 0
    ours, file = rp.plan_mesh(moved, mass_kg=0.05), rp.plan_mesh(stl_files["sphere"], mass_kg=0.05)
    np.testing.assert_allclose([c["point_mm"] for c in ours["contacts"]],
                               [c["point_mm"] for c in file["contacts"]], atol=2e-3)  # rounded to µm
    assert ours["sf_predicted"] == pytest.approx(file["sf_predicted"], rel=1e-9)


# ------------------------------------------------------------------ predictions
@pytest.fixture(scope="module")
def t2_rows():
    return protocol.test2_schedule(0).to_dict("records")


def test_predictions_follow_their_definitions(t2_rows):
    rows = [r for r in t2_rows if not r["rig_fault"]]
    for row in rows[:40] + [r for r in rows if r["planner"] != "heuristic"][:40]:
        p = rp.predict_trial(row)
        # §9.5 for Test 2: the commanded load is the lifted weight, the margin SF_predicted
        assert p["retention_margin_pred"] == pytest.approx(p["sf_predicted"])
        assert p["predicted_stable"] == (p["sf_predicted"] > 1.0) == p["retention_pred"]
        assert p["predicted_stable_residual"] == (p["residual_pred_n"] <= 0.0886)  # §8.1
        assert p["grip_force_n"] <= p["grip_cap_n"] + 1e-12
        assert p["grip_capped"] == (p["grip_cap_n"] < p["grip_needed_n"])
        assert p["sf_predicted"] == pytest.approx(d.safety_factor(
            p["mu_s_believed"], p["grip_force_n"], p["g_geo_believed"], row["mass_kg"]))
        if not p["grip_capped"]:
            assert p["sf_predicted"] == pytest.approx(d.SF_TARGET)
        assert p["belief_error"] == "paper"
        assert p["belief_model"] == rb.BELIEF_MODELS[row["planner"]]
        if p["sf_predicted"] >= 1:
            w = row["mass_kg"] * GRAVITY
            assert p["f_lat_pred_n"] == pytest.approx(w * math.sqrt(p["sf_predicted"] ** 2 - 1))
        if row["planner"] != "heuristic":
            assert p["believed_n_exp"] == 1.5 and p["creep_believed"] == 1.0


def test_each_planner_sizes_its_grip_from_its_own_belief(t2_rows):
    # The same object, mass and surface: the believed G_geo and mu_s set the grip of an uncapped
    # plan, F = SF_target W (1 + a/g) / (3 mu_s G kappa) (§8.1, inverted).
    row = next(r for r in t2_rows if r["planner"] == "force_balance" and not r["rig_fault"])
    p = rp.predict_trial(row)
    normals = np.array([[p[f"normal_{j}_{a}"] for a in "xyz"] for j in (1, 2, 3)])
    points = np.array([[p[f"contact_{j}_{a}_mm"] for a in "xyz"] for j in (1, 2, 3)]) * 1e-3
    planar = rb.planar_normals(normals, points, np.zeros(3))
    assert p["g_geo_believed"] == pytest.approx(d.geometric_efficiency(planar, rb.NOMINAL_MU_S))
    if not p["grip_capped"]:
        w = row["mass_kg"] * GRAVITY * (1 + d.A_LIFT / GRAVITY)
        assert p["grip_force_n"] == pytest.approx(
            d.SF_TARGET * w / (3 * rb.NOMINAL_MU_S * p["g_geo_believed"] * d.KAPPA))


def test_plans_are_shared_per_object_and_planner(t2_rows):
    by_key = {}
    for row in t2_rows:
        if row["planner"] in ("heuristic", "random") and len(by_key) < 40:
            by_key.setdefault(row["plan_key"], []).append(row)
    shared = next(rows for key, rows in by_key.items() if len(rows) > 1)
    a, b = (rp.predict_trial(r) for r in shared[:2])
    assert [a[f"vertex_{j}"] for j in (1, 2, 3)] == [b[f"vertex_{j}"] for j in (1, 2, 3)]
    randoms = [r for r in t2_rows if r["planner"] == "random" and r["object_id"] == "sphere-01"]
    vertex_sets = {tuple(rp.predict_trial(r)[f"vertex_{j}"] for j in (1, 2, 3)) for r in randoms}
    assert len(vertex_sets) > 1


def test_test3_retention_flag(tmp_path):
    rows = protocol.test3_schedule(0)
    row = rows[(rows["block"] == "A") & (rows["planner"] == "heuristic")].iloc[0].to_dict()
    p = rp.predict_trial(row)
    expected = p["f_lat_pred_n"] / row["proof_force_n"] if p["sf_predicted"] >= 1 else \
        p["sf_predicted"]
    assert p["retention_margin_pred"] == pytest.approx(expected)
    # §9.5: the certification flag is the believed retention margin under the commanded load
    assert p["retention_pred"] == p["predicted_stable"] == (expected > 1)
    assert p["threshold_pred_n"] == p["f_lat_pred_n"]


def test_plan_picture_force_labels_neither_overlap_nor_leave_the_figure(tmp_path, monkeypatch):
    """A new user's plan had fingers 1 and 3 close together in the view: their labels "1: 0.33 N" and
    "3: 0.25 N", drawn at the arrow tails, overlapped. Every force label drawn (measured by the
    renderer while the PNG is written) lies inside the figure and apart from the others."""
    import re

    import matplotlib.text

    drawn, draw = [], matplotlib.text.Text.draw

    def record(text, renderer):
        draw(text, renderer)
        if re.search(r"\d: \d+\.\d+ N$", text.get_text()):
            drawn.append((text.get_window_extent(renderer), text.figure.bbox))

    monkeypatch.setattr(matplotlib.text.Text, "draw", record)
    mesh = make_object("sphere", 390)
    outward = np.array([[0.0, -0.3, 1.0], [0.7, 0.7, 0.1], [0.05, -0.25, 1.0]])
    outward /= np.linalg.norm(outward, axis=1, keepdims=True)
    points = outward * np.abs(mesh.vertices).max()  # fingers 1 and 3 near the top, 2 at the right
    rp.plot_plan(mesh, points, outward, [0.33, 1.0, 0.25], tmp_path / "plan.png")
    assert len(drawn) == 3
    for box, figure in drawn:
        assert figure.x0 <= box.x0 and box.x1 <= figure.x1 and figure.y0 <= box.y0 and box.y1 <= figure.y1
    for i, (box, _) in enumerate(drawn):
        assert not any(box.overlaps(other) for other, _ in drawn[i + 1:])


def test_the_time_under_grip_is_the_lift_plus_the_hold():
    """The creep the planner believes is read at the time under grip: lifting 50 mm at 25 mm/s
    takes 2 s, then the 10 s hold: 12 s by hand (defaults: 50 / 30 s + the 3 s hold)."""
    from graspcampaign.rig.plan_predict import grip_time_s

    assert grip_time_s({"lift_speed_mm_per_s": 25.0, "hold_s": 10.0}) == pytest.approx(12.0)
    assert grip_time_s({}) == pytest.approx(50.0 / 30.0 + 3.0)
