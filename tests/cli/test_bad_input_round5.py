"""Bad input, round 5: two runs of one run at once, overrides too long to parse in time, a level
listed twice in a long list. Each case: exit 2, one sentence naming what is wrong and where,
nothing stored changed (``refused``)."""

from __future__ import annotations

from cli_checks import SMOKE, refused

from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_lock


def test_a_run_already_being_run_is_refused_and_loses_nothing(results):
    """Two ``run`` of one run at once each ran every pending trial and stored it, so the run held
    every trial twice and every command then refused it as damaged; now the second is refused
    while the first holds the run."""
    run = results / "smoke" / "default"
    with run_lock(RunStore(run), "held"):  # as a run in progress holds it
        refused(results, ["run", "smoke", *SMOKE, "--root", results],
                f"run smoke/default at {run} is being run by another process; wait for it to "
                "finish (status shows its progress), or choose another run name (--run NAME).")


def test_a_level_listed_twice_is_named_not_the_whole_list(results):
    """A level given twice printed the whole list back (a 2,000-level override, 10,000 characters
    of message); now the level and the two places it is given."""
    levels = ",".join(["0.3", *(f"{0.001 * i:.3f}" for i in range(1, 300)), "0.3"])
    refused(results, ["show", "shapes", f"mu=[{levels}]", "--root", results],
            "factors.mu lists the level 0.3 twice (factors.mu[0] and factors.mu[300]); give each "
            "level once.")
