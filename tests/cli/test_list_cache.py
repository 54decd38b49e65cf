"""``list``'s cached design size of a study whose design is read from another run's records."""

from __future__ import annotations

import json
import shutil

import pyarrow.parquet as pq
from cli_checks import grid_run, invoke, resume_grid

from graspcampaign.campaign import catalog
from graspcampaign.campaign.studyfile import project_dirs


def test_a_listed_design_read_from_a_source_run_follows_that_runs_manifest(results, tmp_path,
                                                                             monkeypatch):
    """dynamic_check's row is cached under its study files and its source run's manifest: listed
    before baseline_grid/default is stored it is "after baseline_grid"; once the run is stored
    (its manifest none, then the run's), the row is computed again from the run, not answered
    "after baseline_grid" from the cache (mutant C2 of mutation round 7 survived every test)."""
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(tmp_path / "cache"))
    monkeypatch.chdir(results.parent)  # output.root "results": this copy of the finished root
    study_file = project_dirs()[1] / "dynamic_check.yaml"
    source = grid_run(results)
    aside = source.rename(tmp_path / "aside")
    before = catalog.study_row(study_file)
    assert (before["trials"], before["runnable"]) == ("?", "after baseline_grid")
    aside.rename(source)
    ok = pq.read_table(source / "records", columns=["status"]).column("status").to_pylist()
    after = catalog.study_row(study_file)
    # its two model presets (campaigns/dynamic_check.yaml) times the source run's executed trials
    assert (after["trials"], after["runnable"]) == (2 * ok.count("ok"), "yes")


def test_a_source_runs_sessions_that_record_nothing_add_no_cached_design(results, tmp_path,
                                                                         monkeypatch):
    """dynamic_check's design size (``show``) and row (``list``) were cached under the source
    run's whole manifest, so each session of baseline_grid/default, even a resume that ran
    nothing, added an entry of each to the catalog. They follow what the design follows: the
    run's config hash, its recorded count and the sessions that recorded trials; a session that
    recorded them again (its records lost) is a new entry."""
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(tmp_path / "cache"))
    monkeypatch.chdir(results.parent)  # output.root "results": this copy of the finished root
    study_file = project_dirs()[1] / "dynamic_check.yaml"

    def entries() -> tuple[int, int]:
        held = json.loads((tmp_path / "cache" / "catalog.json").read_text())
        return len(held.get("designs", {})), len(held.get("listed", {}))

    def shown() -> tuple[str, dict]:
        result = invoke("show", "dynamic_check", "--root", results)
        assert result.exit_code == 0, result.output
        return result.stdout, catalog.study_row(study_file)

    first = shown()
    assert entries() == (1, 1)
    assert "0 ran" in resume_grid(results).stdout  # a session more in the manifest
    assert json.loads((grid_run(results) / "manifest.json").read_text())["sessions"][-1]["ran"] == 0
    assert shown() == first
    assert entries() == (1, 1)
    shutil.rmtree(grid_run(results) / "records")
    assert "0 ran" not in resume_grid(results).stdout
    shown()
    assert entries() == (2, 2)
