"""One vocabulary for every study: every planner, grip law, model preset and integrator the
campaign can run has a label, a place in the order and its own colour."""

from __future__ import annotations

import pandas as pd

from graspcampaign.analysis import vocabulary as V
from graspcampaign.campaign.schema import FACTOR_SPECS
from graspcampaign.core.planner import PLANNERS


def test_every_planner_has_its_own_label_and_colour():
    assert set(PLANNERS) <= set(V.PLANNERS)
    assert V.label("planner", "ferrari_canny") == "Ferrari\u2013Canny \u03b5"
    colours = [t.colour for t in V.PLANNERS.values()]
    assert len(set(colours)) == len(colours)


def test_no_colour_means_two_things():
    """A colour is in one vocabulary only (or in OTHER_COLOURS, the levels outside them): Test 3's
    impulse block was the force-balance planner's purple, Test 2's shapes and materials one palette."""
    owners: dict[str, set[str]] = {}
    for name, voc in [*((n, v) for n, v in vars(V).items() if n.isupper() and isinstance(v, dict)
                         and v and all(isinstance(t, V.Term) for t in v.values())),
                      ("OTHER_COLOURS", {c: V.Term(c, c, c) for c in V.OTHER_COLOURS})]:
        for term in voc.values():
            if term.colour:
                owners.setdefault(term.colour.lower(), set()).add(name)
    assert {c: n for c, n in owners.items() if len(n) > 1} == {}
    coloured = {"PLANNERS", "BLOCKS", "SHAPES", "MATERIALS", "OUTCOMES", "FINGERS"}
    assert coloured <= set().union(*owners.values())
    assert len(V.OTHER_COLOURS) == len(set(V.OTHER_COLOURS))
    for voc in {id(v): v for v in V.VOCABULARIES.values()}.values():  # and one colour per level
        colours = [t.colour for t in voc.values() if t.colour]
        assert len(set(colours)) == len(colours)


def test_the_factor_levels_of_the_campaign_are_in_the_vocabulary():
    assert tuple(V.GRIP_LAWS) == FACTOR_SPECS["grip_law"]["choices"] == ("paper", "slip", "oracle")
    assert tuple(V.INTEGRATORS) == FACTOR_SPECS["integrator"]["choices"]
    from graspcampaign.campaign.compose import project_dirs

    presets = {p.stem for p in (project_dirs()[0] / "model").glob("*.yaml")}
    assert presets == set(V.MODEL_PRESETS)
    assert V.ordered("grip_law", ["oracle", "paper", "slip"]) == ["paper", "slip", "oracle"]
    from graspcampaign.rig.belief import BELIEF_MODELS

    assert set(V.BELIEF_MODELS) == {*BELIEF_MODELS.values(), "actual"}  # `none`: the actual quantities
    assert all(isinstance(t.label, str) and t.label for voc in V.VOCABULARIES.values() for t in voc.values())


def test_data_source_is_one_rule_over_record_sources_and_the_manifest():
    # the report (its records' column) and RunStore.source (the sources its checked files hold)
    # both call it: virtual as soon as one record says so, else the declared source
    assert V.data_source({"measured", "virtual"}, "measured") == "virtual"
    assert V.data_source(pd.Series(["measured", None]), "measured") == "measured"
    assert V.data_source((), "simulation") == "simulation"
    assert V.data_source((), None) == "simulation"


def test_the_fingers_have_their_own_colours_paul_tols_muted_scheme():
    """Figs. 12-13 drew the fingers in matplotlib's cycle (blue, orange, green), Fig. 30 in green, red and
    purple (its red the slip line's): one colour per finger now, Tol's colour-blind-safe muted indigo,
    wine and purple (P. Tol, "Colour schemes", SRON/EPS/TN/09-002, 2021, scheme "muted")."""
    assert [(t.key, t.label, t.colour.lower()) for t in V.FINGERS.values()] == [
        ("finger1", "finger 1", "#332288"), ("finger2", "finger 2", "#882255"),
        ("finger3", "finger 3", "#aa4499")]
    assert [V.colour("finger", f"finger{j}") for j in (1, 2, 3)] == [t.colour for t in V.FINGERS.values()]
