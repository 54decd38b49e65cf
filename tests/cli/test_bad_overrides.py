"""Override messages: each bad override gets one sentence naming it as typed, exit 2, nothing
stored changed (``results``: a copy of finished runs, tests/cli/conftest.py). Pattern of
``test_bad_configs.py``."""

from __future__ import annotations

import pytest
from cli_checks import invoke, refused

PARSE_HINT = "write KEY=VALUE, a list as [a,b], and quote a value holding other characters."
SWEEP = ("is a sweep (one study per value, Hydra's --multirun), which this tool does not run; give a "
         "factor its levels as a list (e.g. mu=[0.3,0.5]), or run the study once per value.")

# -- override messages ------------------------------------------------------------------------------
OVERRIDES = {
    "=3": "override '=3' has no key before '='; write KEY=VALUE, e.g. seeds=3 or mu=[0.3,0.5].",
    "evaluator.nosuch=1": "evaluator.nosuch is not a known key of evaluator (override "
                          "'evaluator.nosuch=1' rejected); known keys: seed_depth_m, n_max, alpha, "
                          "eps, tau_f_n, tau_t_nm, n_cand, residual_check, grip_law, "
                          "grip_safety_factor, grip_cap_depth_m, oracle_cone_facets, fc_cone_edges.",
    # a config group takes a preset's name: Hydra's own sentence named neither key nor presets
    "evaluator=3": "evaluator=3 is not an option of config group evaluator; available options: "
                   "default.",
    # a paper value set on the command line is named beside the file (it blamed the file alone)
    "+paper.nosuch=1": "campaigns/baseline_grid.yaml with override +paper.nosuch=1: paper.nosuch is "
                       "not a known key; allowed: figure, trials_per_planner, success_pct, "
                       "success_by_shape_pct.",
    "paper.figure=3": "campaigns/baseline_grid.yaml with override paper.figure=3: paper.figure must be "
                      "text; got 3.",
    # a section replaced by a scalar says what the section takes (it printed OmegaConf's "paper:
    # Cannot assign str to Dict[str, Any].")
    "paper=x": "paper must be a mapping of keys, got 'x'.",
    # a name below a list (it printed Python's "invalid literal for int() with base 10: 'x'.")
    "factors.mu.x=1": "factors.mu is a list, so factors.mu.x is not an item of it (override "
                      "'factors.mu.x=1' rejected); an item is named by its index, e.g. factors.mu.0.",
    # a key below an unknown one names the first unknown part in its section (it said only "not a
    # known key of the study config")
    "evaluator.tau.x=1": "evaluator.tau is not a known key of evaluator (override 'evaluator.tau.x=1' "
                         "rejected); did you mean evaluator.tau_f_n? known keys: seed_depth_m, "
                         "n_max, alpha, eps, tau_f_n, tau_t_nm, n_cand, residual_check, grip_law, "
                         "grip_safety_factor, grip_cap_depth_m, oracle_cone_facets, fc_cone_edges.",
    "nosuch.a=1": "nosuch is not a known key of the study config (override 'nosuch.a=1' rejected); known "
                  "keys: name, kind, description, seed, seeds, repeats, factors, zip, method_factors, "
                  "params, paper, compare_with, extension, model, evaluator, features, pso, runner, "
                  "output.",
    "paper.rates.x=1": "paper.rates.x is not set by this study (override 'paper.rates.x=1' rejected); add "
                       "it with a leading '+' (+paper.rates.x=...), and the study's paper schema checks "
                       "it.",
    # a name below a single value: it said "evaluator.alpha must be a number, got {}."
    "evaluator.alpha.x=1": "evaluator.alpha takes one value, so evaluator.alpha.x names nothing in it "
                           "(override 'evaluator.alpha.x=1' rejected); set it as evaluator.alpha=VALUE.",
    # a name below a factor's level: it blamed the study file's factors line beside the override
    # ("campaigns/baseline_grid.yaml, line 15: factors.mu.0.x is not a known key of the study config")
    "factors.mu.0.x=1": "factors.mu.0 takes one value, so factors.mu.0.x names nothing in it (override "
                        "'factors.mu.0.x=1' rejected); set it as factors.mu.0=VALUE.",
    "seed.x=1": "seed takes one value, so seed.x names nothing in it (override 'seed.x=1' rejected); set "
                "it as seed=VALUE.",
    "runner.nosuch=3": "runner.nosuch is not a known key of runner (override 'runner.nosuch=3' "
                       "rejected); known keys: backend, n_jobs, address, batch_size, target_task_s, "
                       "progress, progress_interval_s, connect_timeout_s.",
    "factors.nosuch=[1,2]": "factors.nosuch is not a known factor (override 'factors.nosuch=[1,2]' "
                            "rejected); known factors: b, budget, damping_law, dt_s, "
                            "grip_law, integrator, lambda1, lambda2, mass_kg, model_preset, mu, "
                            "n_cand, n_exp, n_max, nodes, planner, pso_seed, shape, variant, w1, w2, "
                            "w3, weight_scale.",
    "factors.mu=50": "factors.mu takes a list of levels, e.g. factors.mu=[0.3,0.5] (or the bare "
                     "mu=0.3), got 50.",
    "mu=" + "x" * 100_000: "factors.mu[0] must be of type float, got '" + "x" * 60
                           + "... (100000 characters)' (str).",
    # Hydra's lexer stops at a character its unquoted values or keys do not take (its grammar,
    # hydra/grammar/OverrideLexer.g4): the message names it and the fix
    "shape=[sphère]": "cannot parse override 'shape=[sphère]': 'è' (character 11) is not allowed in "
                      "an unquoted value (only ASCII letters, digits, spaces and _-+.$%*@?|/\\ "
                      "are); quote it: shape=[\"sphère\"], typed in single quotes on the shell.",
    # a character that looks like ASCII is named with the ASCII it looks like (quoting keeps it)
    "shape=[pear,sph\u00a0ere]": "cannot parse override 'shape=[pear,sph\\xa0ere]': U+00A0 "
                                 "(no-break space) (character 16) looks like a space but is not "
                                 "ASCII; write 'shape=[pear,sph ere]'.",
    "seeds =2": "cannot parse override 'seeds =2': its key has ' ' at character 6, but a key takes "
                "only ASCII letters, digits, '_', '-', '.' and '/'; write 'seeds=2'.",
    # Hydra's parser gives no reason in its first line ("Error parsing override 'a==b'"), and named
    # the rewritten 'factors.shape=[sphere]]' rather than the override as typed
    "a==b": f"cannot parse override 'a==b': unexpected '='; {PARSE_HINT}",
    "shape=[sphere]]": f"cannot parse override 'shape=[sphere]]': unexpected ']'; {PARSE_HINT}",
    # a newline was "LexerNoViableAltException: seeds=1."
    "seeds=1\nseeds=2": "cannot parse override 'seeds=1\\nseeds=2': U+000A (a control character) "
                         "(character 8) is not allowed in an override; remove it.",
    # a sweep is many studies: it was "tags: Unexpected type annotation: Set[str].", "Ambiguous
    # value for argument 'seeds=1,2'." or "... requires --multirun", an option this tool lacks
    "shape=choice(sphere,pear)": f"override 'shape=choice(sphere,pear)' {SWEEP}",
    "seeds=1,2": f"override 'seeds=1,2' {SWEEP}",
    "seeds=range(1,3)": f"override 'seeds=range(1,3)' {SWEEP}",
    # deleting a key every study needs: it said "name = '???' is not allowed; ..."
    "~name": "override '~name' deletes name, which every study needs; set it instead (name=...).",
    # an empty group option: it said "In 'config': Could not find 'model/'."
    "model=": "model= names no option of config group model; available options: firm, nominal, table2.",
    # a list given to a config group: Hydra merged every preset, the later winning
    **{f"{group}=[{options}]": f"{group}=[{options}] is a list, and a study composes one option of "
                              f"config group {group}; available options: {listed}."
       for group, options, listed in [("model", "nominal,table2", "firm, nominal, table2"),
                                      ("evaluator", "default", "default"),
                                      ("features", "paper,paper", "paper"),
                                      ("pso", "converged,repeatability", "converged, repeatability"),
                                      ("runner", "local,dask", "dask, local"),
                                      ("output", "default", "default")]},
    # Hydra's parser recursed beyond Python's limit: "maximum recursion depth exceeded while ..."
    "shape=" + "[" * 500 + "]" * 500: "override 'shape=" + "[" * 54 + "... (1006 characters)': its "
                                      "lists or mappings are nested too deeply to read (over 100 "
                                      "levels within each other); a config nests a few.",
    # OmegaConf's 'KeyError raised while resolving interpolation: ...' and 'Unsupported
    # interpolation type nosuch', naming no value
    "name=${oc.env:GRASPCAMPAIGN_NO_SUCH_VARIABLE}":
        "name = '${oc.env:GRASPCAMPAIGN_NO_SUCH_VARIABLE}' cannot be resolved: environment variable "
        "GRASPCAMPAIGN_NO_SUCH_VARIABLE is not set (set it, or give a default: "
        "${oc.env:GRASPCAMPAIGN_NO_SUCH_VARIABLE,VALUE}).",
    "description=${nosuch:x}": "description = '${nosuch:x}' cannot be resolved: OmegaConf has no "
                               "resolver named nosuch.",
    # a key too long for a file name: it said "[Errno 36] File name too long: '<hydra's path>/aaa..."
    "a" * 300 + "=1": "a" * 60 + "... (300 characters) is neither a known key of the study config nor "
                      "a factor of this study (factors: mass_kg, mu, planner, shape); override rejected.",
}


@pytest.mark.parametrize("override", sorted(OVERRIDES), ids=lambda o: o[:24])
def test_override_messages_name_the_override_in_plain_words(results, override):
    both = ("=3", "evaluator.nosuch=1", "factors.mu.0.x=1")
    for command in ("show", "run") if override in both else ("show",):
        refused(results, [command, "baseline_grid", override, "--root", results], OVERRIDES[override])


def test_the_quoted_form_an_override_message_suggests_is_read(results):
    """The fix the message gives parses: the value then meets the factor's own check."""
    refused(results, ["show", "baseline_grid", 'shape=["sphère"]', "--root", results],
            "factors.shape[0] has unknown value 'sphère'; did you mean 'sphere'? allowed values: "
            "sphere, ellipsoid, "
            "rounded_cube, pear, handle.")


def test_the_level_a_one_value_message_names_is_set_as_it_says(results):
    """``set it as factors.mu.0=VALUE`` (the message for factors.mu.0.x=1) sets mu's first level."""
    from graspcampaign.campaign.compose import compose_study

    levels = [0.2, *compose_study("baseline_grid").factors["mu"][1:]]
    shown = invoke("show", "baseline_grid", "factors.mu.0=0.2", "--root", results)
    assert shown.exit_code == 0, shown.output
    assert f"  mu [{len(levels)}]: {', '.join(map(str, levels))}\n" in shown.stdout
