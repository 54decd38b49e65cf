"""Tests 2-3 schedules: the paper's counts (§8.1, Tables 6-9), ids, run order, units."""

from __future__ import annotations

import re

import numpy as np
import pytest

from graspcampaign.rig import protocol as pr


@pytest.fixture(scope="module")
def t2():
    return pr.test2_schedule(0)


@pytest.fixture(scope="module")
def t3():
    return pr.test3_schedule(0)


def _executed(df):
    return df[~df["rig_fault"]]


def test_test2_counts_equal_the_paper(t2):
    paper = pr.PAPER_COUNTS[pr.STUDY_TEST2]
    assert len(t2) == 1785 == paper["commanded"]
    ex = _executed(t2)
    assert len(ex) == 1755 == paper["executed"]
    assert int(t2["rig_fault"].sum()) == 30 == int((t2["attempt"] == 2).sum())
    assert ex["planner"].value_counts().to_dict() == paper["planners"]
    prop = ex[ex["planner"] == "heuristic"]
    assert prop["group"].value_counts().to_dict() == paper["groups"]
    assert prop["shape"].value_counts().to_dict() == paper["shapes"]  # Table 6 n
    assert ex["object_id"].nunique() == 40
    objects = pr.objects_table()
    assert len(objects) == 40 and objects["material"].nunique() == 4
    assert objects["mass_kg"].max() == 0.6


def test_test2_groups_follow_the_design(t2):
    ex = _executed(t2)
    assert set(ex[ex["group"] == "A"]["shape"]) == {"sphere"}
    e = ex[ex["group"] == "E"]
    assert e["closing_speed_mm_per_s"].value_counts().to_dict() == {10.0: 80, 5.0: 20, 20.0: 20}
    assert e["lift_speed_mm_per_s"].value_counts().to_dict() == {30.0: 80, 10.0: 20, 50.0: 20}
    c = ex[ex["group"] == "C"]
    assert c["friction_level"].value_counts().to_dict() == {"natural": 48, "medium": 48, "low": 48}
    assert set(c["material"]) == {"silicone_soft", "silicone_ref"}
    assert set(ex["pose_err_mm"]) == {0.0, 10.0}
    m = ex[ex["group"] == "M"]
    assert m["object_id"].nunique() == 10
    assert m.groupby("planner").size().to_dict() == dict.fromkeys(pr.PLANNER_LABELS, 90)
    # every matched cell (object, condition, repeat) has all five planners
    cells = m.groupby(["object_id", "condition", "repeat"])["planner"].nunique()
    assert (cells == 5).all() and len(cells) == 90
    d = ex[ex["group"] == "D"]
    assert d.groupby("object_id").size().tolist() == [15] * 7


def test_test3_counts_equal_the_paper(t3):
    paper = pr.PAPER_COUNTS[pr.STUDY_TEST3]
    assert len(t3) == 1245 and len(_executed(t3)) == 1230
    assert int(t3["rig_fault"].sum()) == 15
    ex = _executed(t3)
    assert ex["planner"].value_counts().to_dict() == paper["planners"]
    prop = ex[ex["planner"] == "heuristic"]
    assert prop["block"].value_counts().to_dict() == paper["blocks"]
    natural = prop[prop["probe"] == ""]
    assert natural["block"].value_counts().to_dict() == {"A": 240, "B": 180, "C": 60, "D": 160,
                                                         "E": 100}
    assert len(natural) == 740
    probes = prop[prop["probe"] == "coating"]
    assert probes.groupby(["block", "friction_level"]).size().to_dict() == {
        ("A", "high"): 20, ("A", "low"): 20, ("A", "medium"): 20,
        ("C", "high"): 10, ("C", "low"): 10, ("C", "medium"): 10}
    b = prop[prop["block"] == "B"]
    assert b.groupby(["disturbance_kind", "load_frac_w"]).size().to_dict() == {
        ("down", 0.25): 40, ("down", 0.5): 60, ("down", 0.75): 40, ("up", 0.5): 20,
        ("up", 1.0): 20}
    dd = prop[prop["block"] == "D"]
    assert dd["load_frac_w"].value_counts().sort_index().to_dict() == {
        0.8: 40, 1.0: 40, 1.2: 60, 1.4: 10, 1.8: 10}
    assert set(dd["pulse_duration_ms"]) == {100.0, 200.0}
    e = prop[prop["block"] == "E"]
    assert e.groupby(["frequency_hz", "amplitude_n"]).size().tolist() == [25] * 4
    a = prop[(prop["block"] == "A") & (prop["probe"] == "")]
    assert a["ramp_cap_n"].unique().tolist() == [15.0]
    assert set(a["ramp_rate_n_per_s"]) == {0.2, 0.6, 1.0}


def test_test3_matched_set_pairs_every_planner(t3):
    ex = _executed(t3)
    m = ex[ex["matched"]]
    assert m["object_id"].nunique() == 10
    cells = m.groupby(["object_id", "condition"])["planner"].nunique()
    assert len(cells) == 100 and (cells == 5).all()
    assert (m.groupby("planner").size() == 100).all()


@pytest.mark.parametrize("maker", [pr.test2_schedule, pr.test3_schedule])
def test_ids_are_stable_unique_and_content_derived(maker):
    a, b = maker(0), maker(1)
    assert a["trial_id"].is_unique
    assert set(a["slot_id"]) == set(b["slot_id"])  # the seed changes order, never ids
    assert a["run_order"].tolist() != b["run_order"].tolist() or \
        a["trial_id"].tolist() != b["trial_id"].tolist()
    rerun = a[a["attempt"] == 2]
    assert (rerun["trial_id"] == rerun["slot_id"] + "-a2").all()
    faulted = a[a["rig_fault"]]
    assert set(faulted["slot_id"]) == set(rerun["slot_id"])
    assert maker(0).equals(a)  # deterministic


@pytest.mark.parametrize("maker", [pr.test2_schedule, pr.test3_schedule])
def test_run_order_is_blocked_by_session_and_day(maker):
    df = maker(3)
    assert df["run_order"].tolist() == list(range(1, len(df) + 1))
    assert df.groupby("session")["day"].nunique().max() == 1
    sizes = df[df["attempt"] == 1].groupby("session").size()
    assert sizes.max() <= pr.SESSION_SLOTS
    # matched units stay in one session
    m = df[df["matched"] & (df["attempt"] == 1)]
    key = m["object_id"] + m["condition"] + m["repeat"].astype(str)
    assert m.groupby(key)["session"].nunique().max() == 1
    # a re-run follows its aborted attempt in the same session
    for _, rerun in df[df["attempt"] == 2].iterrows():
        first = df[(df["slot_id"] == rerun["slot_id"]) & (df["attempt"] == 1)].iloc[0]
        assert first["session"] == rerun["session"] and first["run_order"] < rerun["run_order"]
    # within a session the order is shuffled (not the design order)
    assert not df["trial_id"].equals(df.sort_values("trial_id")["trial_id"])


UNITLESS = {"trial_id", "slot_id", "attempt", "rig_fault", "study", "protocol_seed", "run_order",
            "day", "session", "session_position", "group", "block", "disturbance",
            "disturbance_kind", "probe", "object_id", "shape", "object_index", "material",
            "planner", "planner_label", "plan_key", "friction_level", "matched", "condition",
            "repeat"}


@pytest.mark.parametrize("maker", [pr.test2_schedule, pr.test3_schedule])
def test_dimensional_columns_carry_units(maker):
    df = maker(0)
    for col in df.columns:
        if col in UNITLESS:
            continue
        assert re.search(r"_(kg|mm|s|mm_per_s|deg|w|n|n_per_s|nm|nm_per_s|ms|hz)$", col), col


def test_masses_follow_the_envelope_rule():
    from graspcampaign.core import disturbance as d
    from graspcampaign.core.statics import GRAVITY
    from graspcampaign.rig.plan import material_model

    for k, (material, mass) in enumerate(zip(pr.OBJECT_MATERIALS, pr.OBJECT_MASSES_KG,
                                             strict=True), start=1):
        if k in pr.HEAVY_INDICES:
            assert mass == 0.6
            continue
        m = material_model(material)
        creep = float(d.creep_compliance(pr.LIFT_HEIGHT_MM / 30.0 + pr.HOLD_S, m.rho, m.tau))
        cap = float(d.force_at_indentation(m.cap_depth, m.cap_k_n_per_mm_n, m.n, creep))
        envelope = 3 * m.mu_s * d.KAPPA * cap / (d.SF_TARGET * GRAVITY * (1 + d.A_LIFT / GRAVITY))
        fraction = 0.5 if OBJECT_IS_LIGHT[k] else 0.8
        assert mass == pytest.approx(round(fraction * envelope / 0.05) * 0.05)


OBJECT_IS_LIGHT = {1: True, 2: False, 3: False, 5: True, 6: False, 7: False}


def test_bad_seed_is_rejected():
    with pytest.raises(ValueError, match="seed must be a non-negative int"):
        pr.test2_schedule(-1)
    with pytest.raises(ValueError, match="seed must be a non-negative int"):
        pr.test3_schedule(1.5)


def test_proof_loads(t3):
    a = t3[t3["block"] == "A"]
    np.testing.assert_allclose(a["proof_force_n"], a["mass_kg"] * 9.81)
    c = t3[t3["block"] == "C"]
    assert (c["proof_torque_nm"] > 0).all()
    sphere = c[c["shape"] == "sphere"]
    np.testing.assert_allclose(sphere["proof_torque_nm"], sphere["mass_kg"] * 9.81 * 0.05,
                               rtol=0.02)


def test_test3_coatings_do_not_follow_the_reports_display_order(monkeypatch):
    """Block A and C trials take coatings in turn from COATING_LEVELS: a report reordering its
    coatings' display (analysis.vocabulary.COATINGS) must not reorder a rig's schedule."""
    import importlib

    from graspcampaign.analysis import vocabulary
    from graspcampaign.rig import protocol_design

    designed = protocol_design.COATING_LEVELS
    assert set(designed) == set(vocabulary.COATINGS)  # the reports' names for the same coatings
    monkeypatch.setattr(vocabulary, "COATINGS", dict(reversed(vocabulary.COATINGS.items())))
    try:
        assert importlib.reload(protocol_design).COATING_LEVELS == designed
    finally:
        monkeypatch.undo()
        importlib.reload(protocol_design)
