"""Planner predictions and the ``plan MESH`` computation (§8.1, §9.1; SPEC §2.10, §7)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from graspcampaign.core import bench
from graspcampaign.core import disturbance as d
from graspcampaign.core.mesh import SHAPES, MeshError, make_object
from graspcampaign.core.statics import GRAVITY
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


def test_plan_with_mu_overrides_the_material(stl_files):
    out = rp.plan_mesh(stl_files["sphere"], mass_kg=0.05, mu=0.9)
    assert out["mu_s"] == 0.9 and out["material"] == rp.DEFAULT_PLAN_MATERIAL
    assert out["png"] is None


@pytest.mark.parametrize("kwargs, message", [
    ({"mass_kg": 0.0}, "mass_kg = 0.0 is out of range; allowed: > 0 and <= 10 kg (a mass must be "
                       "positive and a three-finger hand lifts at most ~10 kg)."),
    ({"mass_kg": 50.0}, "mass_kg = 50.0 is out of range; allowed: > 0 and <= 10 kg (a mass must be "
                        "positive and a three-finger hand lifts at most ~10 kg)."),
    ({"mass_kg": "heavy"}, "mass_kg must be a number, got 'heavy'."),
    ({"mass_kg": 0.1, "mu": -0.2}, "mu = -0.2 is out of range; allowed: >= 0 and <= 3 (dry friction "
                                   "of soft materials stays below 3)."),
    ({"mass_kg": 0.1, "mu": 50}, "mu = 50 is out of range; allowed: >= 0 and <= 3 (dry friction of "
                                 "soft materials stays below 3)."),
    ({"mass_kg": 0.1, "fingertip_radius_mm": 80},
     "fingertip_radius_mm = 80 is out of range; allowed: > 0 and <= 50 mm (a fingertip is a few "
     "millimetres to a few centimetres in radius)."),
    ({"mass_kg": 0.1, "material": "steel"},
     "unknown material 'steel': use one of gel, silicone_soft, bio_foam, silicone_ref"),
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


# ------------------------------------------------------------------ materials
def test_material_contact_params_reproduce_table4():
    for name, fam in bench.FAMILIES.items():
        m = rp.material_model(name)
        cp = m.contact_params()
        assert cp.k_n_per_mm_n == pytest.approx(fam.k_n_per_mm_n)  # Eq. 14 back to Table 4 K
        assert cp.c_n_s_per_m == pytest.approx(fam.c)
        assert m.cap_depth < m.damage_depth and m.cap_k_n_per_mm_n < m.k_n_per_mm_n


def test_material_contact_params_at_another_fingertip_radius():
    # K scales with sqrt(R) once (Eq. 14), in material_model; contact_params must not scale again
    fam = bench.FAMILIES["gel"]
    m = rp.material_model("gel", "natural", 8e-3)
    cp = m.contact_params(8e-3)
    assert m.k_n_per_mm_n == pytest.approx(fam.k_n_per_mm_n * math.sqrt(8.0 / 5.0))
    assert cp.k_n_per_mm_n == pytest.approx(m.k_n_per_mm_n)
    assert cp.lambda1 == pytest.approx(rp.material_model("gel").contact_params().lambda1)
    assert cp.c_n_s_per_m == pytest.approx(fam.c * 8.0 / 5.0)


def test_damage_depth_closed_form():
    # gel: stabilised softening 0.10 (d/2 mm)^2 reaches 1 - 0.85 at d = 2 mm sqrt(1.5)
    gel = bench.FAMILIES["gel"]
    assert rp.family_damage_depth(gel) == pytest.approx(2e-3 * math.sqrt(0.15 / 0.10))
    # reference silicone: permanent set 0.08 mm (d/2 mm)^1.5 reaches 0.5 mm first
    ref = bench.FAMILIES["silicone_ref"]
    assert rp.family_damage_depth(ref) == pytest.approx(2e-3 * (0.5 / 0.08) ** (2 / 3))


def test_coatings():
    low = rp.material_model("gel", "low")
    assert low.mu_s == rp.COATING_MU_S["low"]
    assert low.mu_k / low.mu_s == pytest.approx(bench.FAMILIES["gel"].mu_k / bench.FAMILIES["gel"].mu_s)
    with pytest.raises(ValueError, match="unknown friction level 'oily'"):
        rp.material_model("gel", "oily")


# ------------------------------------------------------------------ predictions
@pytest.fixture(scope="module")
def t2_rows():
    return protocol.test2_schedule(0).to_dict("records")


def test_predictions_follow_their_definitions(t2_rows):
    for row in t2_rows[:60]:
        p = rp.predict_trial(row)
        assert p["predicted_stable"] == (p["residual_pred_n"] <= 0.0886)
        assert p["grip_force_n"] <= p["grip_cap_n"] + 1e-12
        assert p["grip_capped"] == (p["grip_cap_n"] < p["grip_needed_n"])
        assert p["sf_predicted"] == pytest.approx(d.safety_factor(
            p["mu_s_believed"], p["grip_force_n"], p["g_geo_predicted"], row["mass_kg"]))
        normals = np.array([[p[f"normal_{j}_{a}"] for a in "xyz"] for j in (1, 2, 3)])
        assert p["g_geo_predicted"] == pytest.approx(d.geometric_efficiency(normals))
        if p["sf_predicted"] >= 1:
            w = row["mass_kg"] * GRAVITY
            assert p["f_lat_pred_n"] == pytest.approx(w * math.sqrt(p["sf_predicted"] ** 2 - 1))
        if row["planner"] == "no_pso":
            assert p["n_believed"] == 1.5


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
    assert p["retention_pred"] == (expected > 1)
    assert p["threshold_pred_n"] == p["f_lat_pred_n"]
