"""A campaign killed with SIGKILL mid-run, one shard then damaged, resumes to exactly the records of
an uninterrupted run."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest
from damage import corrupt_value_column

from graspcampaign.campaign.records import RunStore

NODES = "nodes=[144,150,156,162,168,174,180,186]"


def _cmd(tmp_path, run):
    return [sys.executable, "-m", "graspcampaign", "run", "smoke", NODES, "runner.n_jobs=2",
            "runner.batch_size=1", f"output.root={tmp_path}", "--run", run]


def _records(path) -> pd.DataFrame:
    df = RunStore(path).read().to_pandas()
    volatile = [c for c in df.columns if c.endswith("_time_s") or c in ("worker", "host", "run")]
    return df.drop(columns=volatile).sort_values("trial_id").reset_index(drop=True)


@pytest.mark.slow  # three CLI processes with loky workers: `make test-full`; the in-process kill
# (tests/campaign/test_runner.py) keeps resume and quarantine in the fast suite
def test_sigkill_then_resume_equals_uninterrupted_run(tmp_path):
    subprocess.run(_cmd(tmp_path, "full"), check=True, capture_output=True, timeout=300)
    full = _records(tmp_path / "smoke" / "full")
    assert len(full) == 40

    proc = subprocess.Popen(_cmd(tmp_path, "killed"), start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    records = tmp_path / "smoke" / "killed" / "records"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and len(list(records.glob("part-*.parquet"))) < 4:
        time.sleep(0.005)
    os.killpg(proc.pid, signal.SIGKILL)  # the runner and its loky workers, mid-run
    proc.wait()
    n_before = len(RunStore(records.parent).recorded_ids())
    assert 1 < n_before < 40, f"the kill did not land mid-run ({n_before} of 40 recorded)"
    # and a bad sector in one shard's value column: footer and trial_id pages intact
    damaged = sorted(records.glob("part-*.parquet"))[0]
    corrupt_value_column(damaged, "volume_m3")

    resumed = subprocess.run(_cmd(tmp_path, "killed"), capture_output=True, text=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    assert f"{n_before - 1} already recorded, {40 - n_before + 1} ran" in resumed.stdout
    assert f"damaged file {damaged} moved to" in resumed.stderr
    assert (records.parent / "quarantine" / f"records__{damaged.name}").is_file()
    after = _records(records.parent)
    assert after["trial_id"].is_unique
    pd.testing.assert_frame_equal(full, after)
