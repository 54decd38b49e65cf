"""``report`` of a run another process is recording (its lock, ``runner.run_lock``, held) writes its
pages, says so in the provenance header and on stdout, and exits 0; a run nobody holds says
nothing of it. ``status`` says whether the run is in progress. The lock is held from the test as
the lock tests hold it."""

from __future__ import annotations

import json

from cli_checks import SMOKE, invoke

from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_lock


def test_a_report_of_a_run_being_recorded_says_it_is_in_progress(tmp_path):
    root = tmp_path / "results"
    assert invoke("run", "smoke", *SMOKE, "--root", root).exit_code == 0  # 1 trial recorded
    store = RunStore(root / "smoke" / "default")
    manifest = json.loads(store.manifest_path.read_text())
    # as a session of a 4-trial design writes it when it starts (runner.run_study), its 3 to come
    first = manifest["sessions"][0]
    manifest["sessions"].append({**{k: first[k] for k in ("host", "backend", "n_jobs", "config_hash")},
                                 "started_at": first["finished_at"], "n_trials": 4, "finished_at": None})
    manifest["finished_at"] = None
    store.manifest_path.write_text(json.dumps(manifest, indent=2))
    line = "run in progress: 1 of 4 recorded when this report was made"
    page = store.path / "report" / "report.md"
    with run_lock(store, "smoke/default"):
        result = invoke("report", "smoke", "--root", root, "--format", "md,html")
        assert result.exit_code == 0, result.output
        assert f"report: {page} (and .html)\n  {line}\n" in result.stdout
        header = "- **Run in progress:** 1 of 4 recorded when this report was made"
        assert header in page.read_text().splitlines()
        assert ("<dt>Run in progress</dt><dd>1 of 4 recorded when this report was made</dd>"
                in page.with_suffix(".html").read_text())
    result = invoke("report", "smoke", "--root", root)
    assert result.exit_code == 0, result.output
    assert "in progress" not in result.output and "in progress" not in page.read_text()


def test_status_says_whether_another_process_is_recording_the_run(tmp_path):
    # status printed "complete: False" of a run being recorded and of one stopped alike
    root = tmp_path / "results"
    assert invoke("run", "smoke", *SMOKE, "--root", root).exit_code == 0
    store = RunStore(root / "smoke" / "default")
    with run_lock(store, "smoke/default"):
        held = invoke("status", "smoke", "--root", root, "--json")
    free = invoke("status", "smoke", "--root", root)
    assert held.exit_code == 0 and free.exit_code == 0, held.output + free.output
    assert json.loads(held.stdout)["in_progress"] is True
    assert "in_progress: False\n" in free.stdout
