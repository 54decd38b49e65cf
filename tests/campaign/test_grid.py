"""Trial expansion: counts, zip, ids, shared scene streams."""

from __future__ import annotations

import numpy as np

from graspcampaign.campaign.grid import expand, n_trials
from graspcampaign.campaign.schema import StudyCfg


def _study(**kw):
    base = dict(name="g", kind="test_pi", seeds=3,
                factors={"shape": ["sphere", "pear"], "mass_kg": [0.2, 0.4, 0.6],
                         "planner": ["heuristic", "random"]})
    base.update(kw)
    return StudyCfg(**base)


def test_cartesian_count_and_order():
    study = _study()
    trials = expand(study)
    assert len(trials) == n_trials(study) == 2 * 3 * 2 * 3
    assert [t.index for t in trials] == list(range(len(trials)))
    # file order, seed innermost
    assert trials[0].factors == {"shape": "sphere", "mass_kg": 0.2, "planner": "heuristic",
                                 "seed": 0, "repeat": 0}
    assert trials[1].factors["seed"] == 1


def test_zip_advances_factors_together():
    study = _study(factors={"mass_kg": [0.2, 0.4], "mu": [0.1, 0.3], "shape": ["sphere"]},
                   zip=[["mass_kg", "mu"]], seeds=1)
    pairs = [(t.factors["mass_kg"], t.factors["mu"]) for t in expand(study)]
    assert pairs == [(0.2, 0.1), (0.4, 0.3)]


def test_repeats_axis():
    study = _study(repeats=4, seeds=1)
    assert n_trials(study) == 2 * 3 * 2 * 4
    assert {t.factors["repeat"] for t in expand(study)} == {0, 1, 2, 3}


def test_ids_are_stable_unique_and_content_derived():
    a, b = expand(_study()), expand(_study())
    assert [t.trial_id for t in a] == [t.trial_id for t in b]
    assert len({t.trial_id for t in a}) == len(a)
    # adding a level does not change the ids of existing trials
    bigger = expand(_study(factors={"shape": ["sphere", "pear", "handle"],
                                    "mass_kg": [0.2, 0.4, 0.6], "planner": ["heuristic", "random"]}))
    assert {t.trial_id for t in a} <= {t.trial_id for t in bigger}


def test_planners_share_scene_streams_and_seeds_differ():
    trials = expand(_study())
    by_scene = {}
    for t in trials:
        by_scene.setdefault(t.scene_id, []).append(t)
    assert all(len(group) == 2 for group in by_scene.values())  # heuristic and random
    for group in by_scene.values():
        draws = [t.rng(7).random(4) for t in group]
        np.testing.assert_array_equal(draws[0], draws[1])
    seeds = [t for t in trials if t.factors["planner"] == "heuristic"
             and t.factors["shape"] == "sphere" and t.factors["mass_kg"] == 0.2]
    assert len({t.rng(7).random() for t in seeds}) == 3
    assert trials[0].rng(7).random() != trials[0].rng(8).random()
