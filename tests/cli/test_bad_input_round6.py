"""Bad input, round 6: deleting a key (``~key``) that cannot or need not be deleted, ...
Each case: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

import pytest
from cli_checks import refused

NEEDED = "which every study needs; set it instead"
NOTHING = "which this study does not have, so there is nothing to delete; leave it out"
DELETIONS = {
    # Hydra said "ContactModelCfg (DictConfig) does not support deletion." / "RunnerCfg ..."
    "~model.lambda1": f"override '~model.lambda1' deletes model.lambda1, {NEEDED} (model.lambda1=...).",
    "~runner.n_jobs": f"override '~runner.n_jobs' deletes runner.n_jobs, {NEEDED} (runner.n_jobs=...).",
    # Hydra said "Could not delete from config. 'nosuch' does not exist."
    "~nosuch": f"override '~nosuch' deletes nosuch, {NOTHING}.",
    "~model.nosuch": f"override '~model.nosuch' deletes model.nosuch, {NOTHING}.",
    "~mu": f"override '~mu' deletes mu, {NOTHING}, or write ~factors.mu to delete the factor mu.",
}


@pytest.mark.parametrize("override", sorted(DELETIONS))
def test_a_deletion_hydra_words_badly_is_one_sentence(results, override):
    refused(results, ["show", "baseline_grid", override, "--root", results], DELETIONS[override])
