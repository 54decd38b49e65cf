"""A run stored under the legacy config digest (the description inside the hash; docs/decisions.md,
"A study's description is not part of its config hash") read by ``ingest`` and ``status`` through
the command line: accepted when only the description changed, a real change (a seed) refused
with exit 2 and nothing stored changed. The runner's side is in test_runner.py.
"""

from __future__ import annotations

import json
import shutil

import pytest
from hardware_checks import REDUCED, cli
from legacy_hashing import old_digest, old_hashing

from graspcampaign.campaign import provenance
from graspcampaign.campaign.kinds import hardware as H
from graspcampaign.campaign.records import RunStore
from graspcampaign.cli.main import app


def _ingest(root, file, *overrides):
    sets = [a for o in (*REDUCED, *overrides) for a in ("--set", o)]
    return cli.invoke(app, ["ingest", "test2_grasp", str(file), "--run", "legacy", "--root", str(root),
                            *sets])


def _files(root):
    return {p: p.read_bytes() for p in sorted((root / "test2_grasp" / "legacy").rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def legacy(study_run, tmp_path_factory):
    """The first half of a virtual rig's exports ingested by the old hashing (description "stale");
    the second half's file beside it."""
    records = RunStore(study_run("test2_grasp", *REDUCED)[1].path).read().to_pandas()
    export, root = H.export_records(records, "test2_grasp"), tmp_path_factory.mktemp("legacy")
    half = len(export) // 2
    export.iloc[:half].to_csv(root / "day1.csv", index=False)
    export.iloc[half:].to_csv(root / "day2.csv", index=False)
    with old_hashing():
        first = _ingest(root, root / "day1.csv", "description=stale")
    assert first.exit_code == 0, first.output
    manifest = json.loads((root / "test2_grasp" / "legacy" / "manifest.json").read_text())
    assert manifest["config_hash"] == old_digest(manifest["config"]) != provenance.config_digest(
        manifest["config"])  # the premise: a run that only the legacy digest names
    return root, manifest, len(export)


@pytest.fixture
def copy(legacy, tmp_path):
    root, manifest, n = legacy
    shutil.copytree(root, tmp_path / "r")
    return tmp_path / "r", manifest, n


def test_status_accepts_a_run_under_the_legacy_digest(copy):
    root, manifest, n = copy
    result = cli.invoke(app, ["status", "test2_grasp", "--run", "legacy", "--root", str(root), "--json"])
    assert result.exit_code == 0, result.output
    info = json.loads(result.stdout)
    assert (info["config_hash"], info["n_recorded"]) == (manifest["config_hash"], n // 2)


def test_status_refuses_a_changed_config_under_the_legacy_digest(copy):
    # the legacy digest names one config: the manifest's config edited (its seed) matches neither digest
    root, manifest, _ = copy
    path = root / "test2_grasp" / "legacy" / "manifest.json"
    edited = {**manifest["config"], "seed": manifest["config"]["seed"] + 1}
    path.write_text(json.dumps({**manifest, "config": edited}, indent=2))
    result = cli.invoke(app, ["status", "test2_grasp", "--run", "legacy", "--root", str(root)])
    assert result.exit_code == 2, result.output
    assert (f"has a manifest.json that does not match the run (config_hash is {manifest['config_hash']}, "
            f"but its config hashes to {provenance.config_digest(edited)})") in result.stderr


def test_ingest_into_a_run_under_the_legacy_digest_after_a_description_fix(copy):
    root, manifest, n = copy
    result = _ingest(root, root / "day2.csv", "description=fixed")
    assert result.exit_code == 0, result.output
    stored = json.loads((root / "test2_grasp" / "legacy" / "manifest.json").read_text())
    # the run keeps one name for its config: the new session records the legacy digest
    assert {s["config_hash"] for s in stored["sessions"]} == {manifest["config_hash"]}
    assert len(RunStore(root / "test2_grasp" / "legacy").read()) == n


def test_ingest_refuses_a_real_change_to_a_run_under_the_legacy_digest(copy):
    # a changed seed was stored beside the run's config (its session naming another config)
    root, manifest, _ = copy
    seed, before = manifest["config"]["seed"], _files(root)
    result = _ingest(root, root / "day2.csv", "description=fixed", f"seed={seed + 1}")
    assert result.exit_code == 2, result.output
    assert result.stderr == (
        f"error: run test2_grasp/legacy at {root / 'test2_grasp' / 'legacy'} was started with a different "
        f"resolved study config (seed {seed} -> {seed + 1}); records of another config are stored in a "
        "run of their own, so choose another run name (--run NAME).\n")
    assert _files(root) == before


def test_show_says_what_ingest_would_refuse(copy):
    # show's drift note skipped measured runs: it said nothing where ingest refuses; and show of a
    # measured run with records raised IndexError (its records carry no wall time to estimate from)
    root, manifest, _ = copy
    seed = manifest["config"]["seed"]
    refused = _ingest(root, root / "day2.csv", f"seed={seed + 1}")
    shown = cli.invoke(app, ["show", "test2_grasp", *REDUCED, f"seed={seed + 1}", "--run", "legacy",
                             "--root", str(root)])
    same = cli.invoke(app, ["show", "test2_grasp", *REDUCED, "--run", "legacy", "--root", str(root)])
    assert refused.exit_code == 2 and shown.exit_code == 0 == same.exit_code, shown.output
    assert f"note: `ingest` would refuse: {refused.stderr.removeprefix('error: ')}" in shown.stdout
    assert "note:" not in same.stdout
