"""A run stopped between two tasks as SIGKILL stops it (:func:`kill_after`)."""

from __future__ import annotations


class Killed(BaseException):
    """Stands in for SIGKILL: the run stops between two tasks, nothing after the loop runs (a
    BaseException, so no ``except Exception`` on its way out takes it for a failed trial)."""


def kill_after(monkeypatch, n_tasks: int) -> None:
    """Make the run raise :class:`Killed` once ``n_tasks`` tasks are stored (their progress told)."""
    from graspcampaign.campaign import runner

    calls = []

    def advance(self, n, failed):
        calls.append(n)
        if len(calls) == n_tasks:
            raise Killed

    monkeypatch.setattr(runner._Progress, "advance", advance)
