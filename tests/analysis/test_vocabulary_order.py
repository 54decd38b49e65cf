"""Display order of ``vocabulary.ordered``: a study's own levels the vocabulary lacks (a table's
``all`` scope) lead, then the vocabulary's levels in its order, then anything else by text."""

from __future__ import annotations

from graspcampaign.analysis.vocabulary import VOCABULARIES, ordered


def test_design_levels_the_vocabulary_lacks_come_first():
    planners = list(VOCABULARIES["planner"])
    values = ["zeta", planners[1], "all", planners[0], "alpha"]
    assert ordered("planner", values, first=["all"]) == ["all", planners[0], planners[1], "alpha", "zeta"]
    # a design order does not reorder the vocabulary's own levels
    assert ordered("planner", planners[:2], first=planners[1::-1]) == planners[:2]
