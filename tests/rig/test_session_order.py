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


def test_each_day_holds_a_morning_then_an_afternoon_session(schedule):
    """Two sessions per day (protocol_design.SESSION_SLOTS): in run order the first session is the
    morning of day 1, and each day has its morning before its afternoon, the last day maybe only
    its morning; a session's name carries the day of its rows."""
    ordered = schedule.sort_values("run_order")
    sessions = ordered.drop_duplicates("session")[["session", "day"]]
    assert sessions["session"].iloc[0] == "d01-am" and sessions["day"].iloc[0] == 1
    halves = sessions.groupby("day", sort=False)["session"].agg(lambda s: [n[-2:] for n in s])
    assert halves.index.tolist() == list(range(1, len(halves) + 1))
    assert all(h == ["am", "pm"] for h in halves.iloc[:-1]) and halves.iloc[-1] in (["am"], ["am", "pm"])
    assert (ordered["session"].str[1:3].astype(int) == ordered["day"]).all()
