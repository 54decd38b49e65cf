"""Run order of the Tests 2-3 sheets: sessions filled to SESSION_SLOTS, positions 1..n inside each.

Invariants of the blocking, read off the schedules: a session closes only when the next unit no
longer fits (so the fullest holds exactly ``SESSION_SLOTS``), and the position of a trial in its
session, re-runs included, counts 1, 2, ... in run order.
"""

from __future__ import annotations

import pytest

from graspcampaign.rig import protocol as pr

LARGEST_UNIT = 5
"""A matched-set unit holds the five planners of one (object, condition, repeat); others hold one slot."""


@pytest.fixture(scope="module", params=[pr.test2_schedule, pr.test3_schedule])
def schedule(request):
    return request.param(2)


def test_sessions_are_filled_until_the_next_unit_does_not_fit(schedule):
    first = schedule[schedule["attempt"] == 1]
    sessions = first.groupby("session", sort=False).size()  # in run order
    assert sessions.max() == pr.SESSION_SLOTS
    # each closed session lacked room for the next unit only: fewer free slots than a unit holds
    assert (pr.SESSION_SLOTS - sessions.iloc[:-1] < LARGEST_UNIT).all()


def test_session_positions_count_one_to_n_in_run_order(schedule):
    for session, rows in schedule.sort_values("run_order").groupby("session", sort=False):
        assert rows["session_position"].tolist() == list(range(1, len(rows) + 1)), session
