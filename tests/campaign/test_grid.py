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


def test_a_stored_run_keeps_its_trial_ids_and_streams():
    """The first three trials of the reference surrogate run (stored by commit 1787481, read back
    with ``pd.read_parquet`` from its records): a resumed run must find these ids and draw these
    scenarios, or it stores every trial again with other values."""
    from graspcampaign.campaign.kinds.surrogate import SurrogateParams, draw_scenario

    study = StudyCfg(name="surrogate", kind="surrogate", seed=901, seeds=3)
    stored = [("s0-d97715e2e2", "706cec465c", "pear", 0.637330, 0.223947, 0.104242),
              ("s1-127df95f04", "0a39ff8522", "pear", 0.716880, 0.054717, 1.612672),
              ("s2-4f6059e6fc", "ab5824136c", "handle", 0.207317, 0.223349, 0.320075)]
    for trial, (trial_id, scene_id, shape, mass, mu, b) in zip(expand(study), stored, strict=True):
        assert (trial.trial_id, trial.scene_id) == (trial_id, scene_id)
        drawn = draw_scenario(SurrogateParams(), trial.rng(study.seed))
        assert drawn["shape"] == shape
        np.testing.assert_allclose([drawn["mass_kg"], drawn["mu"], drawn["msd_b"]], [mass, mu, b],
                                   atol=5e-7)


def test_a_renamed_method_factor_still_shares_the_scene():
    """A method factor is left out of the scene under the name ids are hashed by: renamed (``b``,
    hashed as its first name) it still leaves every level of it facing one draw."""
    trials = expand(_study(factors={"shape": ["sphere"], "b": [0.1, 0.5]}, method_factors=["b"],
                           seeds=1))
    assert len(trials) == 2 and trials[0].scene_id == trials[1].scene_id
    np.testing.assert_array_equal(trials[0].rng(3).random(4), trials[1].rng(3).random(4))


def test_a_stored_protocol_run_keeps_its_trial_ids():
    """A protocol's rows carry no seed: its trials take seed 0, as the reference test2_grasp run
    (commit 1787481, ``params.fraction=0.08``) stored them; its first three ids and scenes."""
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.kind import get_kind
    from graspcampaign.campaign.runner import kind_params, study_trials

    study = compose_study("test2_grasp", ["params.fraction=0.08"])
    kind = get_kind(study.kind)
    trials = study_trials(study, kind, kind_params(study, kind))[:3]
    assert [(t.trial_id, t.scene_id) for t in trials] == [
        ("t2A-sphere-06-prop-f6071de919_t2A-sphere-06-prop-51f4759af3", "64d93d2075"),
        ("t2C-ellipsoid-03-prop-0b3171aa9a_t2C-ellipsoid-0-d7c68f5e1b", "eb966f0da2"),
        ("t2M-sphere-01-fb-febaf3d67e_t2M-sphere-01-fb-feb-490ced6c7e", "4946aeac97")]
