"""A run resumed under ``--allow-drift`` to a larger design and run to its end is complete at that
design's size, through the command line: ``status``, the report's provenance header and the index
count the design of the session that last ran it, and the header names the drift; a manifest
stored before sessions recorded their design is read as then (its first design's count)."""

from __future__ import annotations

import json

from cli_checks import SMOKE, invoke, replaced


def _status(root) -> dict:
    result = invoke("status", "smoke", "--json", "--root", root)
    assert result.exit_code == 0, result.output
    return json.loads(result.output)


def _index_trials(root) -> str:
    """The trials column of the smoke run's row on the index page."""
    row = next(line for line in (root / "index.md").read_text().splitlines()
               if line.startswith("| smoke |"))
    return row.strip("|").split("|")[-1].strip()


def test_a_run_resumed_to_a_larger_design_and_run_to_its_end_is_complete(tmp_path):
    root = tmp_path / "results"
    assert invoke("run", "smoke", *SMOKE, "--root", root).exit_code == 0  # 1 trial: sphere, 144
    larger = replaced(SMOKE, "shape=[sphere,ellipsoid]", "nodes=[144,390]")  # 4 trials
    refused = invoke("run", "smoke", *larger, "--root", root)
    assert refused.exit_code == 2 and "--allow-drift" in refused.output
    result = invoke("run", "smoke", *larger, "--allow-drift", "--root", root)
    assert result.exit_code == 0, result.output
    assert "smoke/default: 4 trials, 1 already recorded, 3 ran" in result.output
    info = _status(root)
    assert (info["n_trials"], info["n_recorded"], info["complete"]) == (4, 4, True)
    assert info["finished_at"] is not None
    assert invoke("report", "smoke", "--root", root).exit_code == 0
    page = (root / "smoke" / "default" / "report" / "report.md").read_text()
    assert "- **Trials:** 4 recorded of 4; 4 executed" in page.splitlines()
    assert _index_trials(root) == "4"
    # the header's design and hash are the first session's: the drift names the other config
    sessions = json.loads((root / "smoke" / "default" / "manifest.json").read_text())["sessions"]
    assert sessions[0]["config_hash"] != sessions[1]["config_hash"]
    assert (f"- **Drift:** resumed under another config (`{sessions[1]['config_hash']}`) with "
            "--allow-drift: the design and hash above are the first session's, the trial count the "
            f"design of the session that ran it last (`{sessions[1]['config_hash']}`); the records "
            "hold the trials of each") in page.splitlines()


def test_a_manifest_whose_sessions_name_no_design_is_read_as_before(tmp_path):
    """A manifest stored before sessions recorded their design (``n_trials``, ``recorded``): its
    design is the one it was started with, complete when that many trials are recorded; a drifted
    one, whose later design it does not hold, reads as it did (4 recorded of 1, not complete)."""
    root = tmp_path / "results"
    assert invoke("run", "smoke", *SMOKE, "--root", root).exit_code == 0
    manifest_path = root / "smoke" / "default" / "manifest.json"

    def strip_sessions():
        manifest = json.loads(manifest_path.read_text())
        assert {"n_trials", "recorded"} <= set(manifest["sessions"][-1])  # what this code writes
        for session in manifest["sessions"]:
            session.pop("n_trials", None), session.pop("recorded", None)
        manifest_path.write_text(json.dumps(manifest, indent=2))

    strip_sessions()
    info = _status(root)
    assert (info["n_trials"], info["n_recorded"], info["complete"]) == (1, 1, True)
    larger = replaced(SMOKE, "shape=[sphere,ellipsoid]", "nodes=[144,390]")
    assert invoke("run", "smoke", *larger, "--allow-drift", "--root", root).exit_code == 0
    strip_sessions()
    info = _status(root)
    assert (info["n_trials"], info["n_recorded"], info["complete"]) == (1, 4, False)
    assert invoke("report", "smoke", "--root", root).exit_code == 0
    page = (root / "smoke" / "default" / "report" / "report.md").read_text()
    assert "- **Trials:** 4 recorded of 1; 4 executed" in page.splitlines()
    other = json.loads(manifest_path.read_text())["sessions"][1]["config_hash"]
    assert (f"- **Drift:** resumed under another config (`{other}`) with --allow-drift: the design, "
            "hash and trial count above are the first session's; the records hold the trials of "
            "each") in page.splitlines()
    assert _index_trials(root) == "1"
