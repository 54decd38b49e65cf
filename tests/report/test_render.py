"""report/render.py: a part an item cannot do without is asked for through ``Run.stored``, which says
in one sentence which run lacks which table and what to do; before, dynamic (twice), wrench, sensitivity
and surrogate each raised their own wording ("the run has no `steps` table", "... no PSO
identifications (prepared/)", ...), some without the run or a remedy."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pyarrow as pa
import pytest

from graspcampaign.report.render import Run
from graspcampaign.report.studies import dynamic, sensitivity, surrogate, wrench


class NoParts:
    """A run's store holding no part at all (a run recorded before its kind stored them), under a
    results root of its own."""

    path = Path("/data/runs/study/r1")

    def read(self, part: str) -> pa.Table:
        return pa.table({})


def bare(study: str) -> Run:
    records = pd.DataFrame({"trial_id": ["t0"], "status": ["ok"], "mu": [0.3], "panel": ["mu_mass"]})
    return Run(records, {"study": study, "run": "r1", "config": {"factors": {}}, "overrides": ["seeds=2"]},
               store=NoParts())


#: the commands name the run's root and the overrides it was started with: `run` refuses a run's
#: own command without them ("started with another config"), and another root is another run
TRIALS = ("the study stores it while the run's trials run and this run stored none; run `graspcampaign run "
          "{study} seeds=2 --run NEW --root /data/runs` to record a new run.")


@pytest.mark.parametrize(("study", "name", "read", "todo"), [
    ("gravity_settle", "tables/shape", lambda run: dynamic._trial(run, "shape", "t0"), TRIALS),
    ("friction_mass", "tables/steps", dynamic.ends, TRIALS),
    ("wrench_balance", "tables/iterations", wrench._traces, TRIALS),
    ("sensitivity", "prepared", sensitivity._identified(True, "median"), TRIALS),
    ("surrogate", "summary/surrogate_regression", lambda run: surrogate._read(run, "regression", "r2"),
     "the study writes it once every trial is recorded; run `graspcampaign run {study} seeds=2 --run r1 "
     "--root /data/runs` again to complete the run."),
])
def test_a_part_an_item_needs_and_the_run_lacks_is_named_in_one_sentence(study, name, read, todo):
    with pytest.raises(ValueError) as raised:
        read(bare(study))
    assert str(raised.value) == f"run {study}/r1 has no `{name}` table: {todo.format(study=study)}"


def test_a_stored_part_is_read_once_and_returned():
    frame, reads = pd.DataFrame({"trial_id": ["t0"], "x": [1.0]}), []

    class One(NoParts):
        def read(self, part: str) -> pa.Table:
            reads.append(part)
            return pa.Table.from_pandas(frame)

    run = Run(frame, {"study": "s", "run": "r1"}, store=One())
    pd.testing.assert_frame_equal(run.stored("tables/x"), frame)
    pd.testing.assert_frame_equal(run.stored("tables/x"), frame)
    assert reads == ["tables/x"]


def test_a_file_that_cannot_be_read_is_not_said_to_be_written():
    """``reason`` says "cannot write FILE" of a full disk only (no space is missing to read): a
    statistic whose file is missing, or unreadable, was said to be one that "cannot write" it."""
    import errno

    from graspcampaign.report.render import reason

    missing = FileNotFoundError(errno.ENOENT, "No such file or directory", "/data/runs/a/manifest.json")
    assert reason(missing) == "/data/runs/a/manifest.json: no such file or directory"
    denied = PermissionError(errno.EACCES, "Permission denied", "/data/report/report.md")
    assert reason(denied) == ("/data/report/report.md: permission denied (its permissions, or those "
                              "of the directory holding it, keep this user out); give this user "
                              "access (chmod, chown), or run the command as the user who owns it")
    full = OSError(errno.ENOSPC, "No space left on device", "/data/report/report.md")
    assert reason(full) == ("cannot write /data/report/report.md: no space left on device; free some "
                            "space there and run the command again")
