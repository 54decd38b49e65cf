"""sensitivity's factor ``b`` was ``b_n_s_per_m``, a unit its values never held (the MSD nodal damping
in the simulator's internal units, §11's PSO bound [0.1, 2.0]). A factor's name is in the study
config (``method_factors``), in its config hash and in the hash of each trial's id and random
stream, so a run stored before the rename must still read, report, count and resume as one
stored now, and an override by the former name is told the current one.

A run "stored before the rename" is made here as the code before it made it (commit 85bd998): the
kind's design rows and records carry ``b_n_s_per_m``, the study's ``method_factors`` names it, and
trial ids are hashed by the names as given (``grid.FIRST_NAMES`` empty).
"""

from __future__ import annotations

import dataclasses
import json

import pandas as pd
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from graspcampaign.api import load_records
from graspcampaign.campaign import grid
from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.kind import RUNTIME_KINDS, get_kind
from graspcampaign.campaign.kinds.sensitivity import PANEL_AXES
from graspcampaign.campaign.runner import kind_params, run_study, study_trials
from graspcampaign.campaign.status import run_status
from graspcampaign.cli.main import app
from graspcampaign.report.build import build_reports

FORMER, CURRENT = "b_n_s_per_m", "b"
#: Two levels per axis, one seed (12 trials), a token PSO for panel (a), one trial a shard.
REDUCED = ["params.levels=2", "seeds=1", "pso.n_particles=2", "pso.n_iterations=2",
           "runner.batch_size=1"]
#: Panel n_b's trial ids as the code before the rename stored them (the reference records of
#: `params.levels=2 seeds=1`, /tmp/golden/records, written by commit 85bd998): (n, b) -> id.
STORED_IDS = {(0.1, 0.1): "n_b_sphere_heuristic_0.4_0.3_0.1_0.1_s0-7be7c555c4",
              (1.0, 0.1): "n_b_sphere_heuristic_0.4_0.3_1_0.1_s0-73666640e8",
              (0.1, 2.0): "n_b_sphere_heuristic_0.4_0.3_0.1_2_s0-77e45588c0",
              (1.0, 2.0): "n_b_sphere_heuristic_0.4_0.3_1_2_s0-56094e2d5c"}
STORED_SCENE = "3be8d6f4a7"  # the four share one scene: n and b are method factors
#: Columns that differ between two runs of one study whatever they store (when, where, how long).
TIMED = ["wall_time_s", "worker", "host", "plan_time_s", "context_time_s", "runtime_ms"]


def _cfg(root, *overrides):
    return compose_study("sensitivity", ["runner.backend=sequential", "runner.progress=false",
                                         f"output.root={root}", *REDUCED, *overrides])


def _as_before(stop_at: tuple[float, float] | None = None):
    """The sensitivity kind as the code before the rename ran it: its design's n_b rows and so its
    records name b ``b_n_s_per_m``; interrupted (Ctrl-C) at the n_b trial (n, b) ``stop_at``."""
    kind = get_kind("sensitivity")

    def design(study, params):
        return [{(FORMER if k == CURRENT else k): v for k, v in row.items()}
                for row in kind.design(study, params)]

    def run(inp, rng):
        f = inp.trial.factors
        if stop_at is not None and (f.get("n_exp"), f.get(FORMER)) == stop_at:
            raise KeyboardInterrupt
        return kind.run(inp, rng)

    return dataclasses.replace(kind, design=design, run=run)


def _run_before(root, stop_at=None):
    """Store the reduced study as the code before the rename stored it."""
    cfg = _cfg(root)
    cfg.method_factors = [FORMER if m == CURRENT else m for m in cfg.method_factors]
    with pytest.MonkeyPatch.context() as patch:
        patch.setitem(RUNTIME_KINDS, "sensitivity", _as_before(stop_at))
        patch.setattr(grid, "FIRST_NAMES", {})  # ids hashed by the names as given
        return run_study(cfg)


def _stored_names(root) -> set[str]:
    folder = root / "sensitivity" / "default" / "records"
    return set().union(*(pq.read_schema(p).names for p in folder.glob("*.parquet")))


def _records(root) -> pd.DataFrame:
    df = load_records("sensitivity", root=root)
    return df.drop(columns=TIMED).sort_values("trial_id").reset_index(drop=True)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The reduced study stored now, stored before the rename, and stored before it until
    interrupted at the n_b trial (1, 2), then resumed now (same code version: no --allow-drift)."""
    roots = {name: tmp_path_factory.mktemp(name) for name in ("now", "before", "mixed")}
    run_study(_cfg(roots["now"]))
    _run_before(roots["before"])
    with pytest.raises(KeyboardInterrupt):
        _run_before(roots["mixed"], stop_at=(1.0, 2.0))
    resumed = run_study(_cfg(roots["mixed"]))
    return roots, resumed


def test_the_factor_is_b_and_its_trials_keep_the_ids_stored_before():
    study = _cfg("results")
    assert PANEL_AXES["n_b"] == ("n_exp", CURRENT) and CURRENT in study.method_factors
    kind = get_kind("sensitivity")
    n_b = [t for t in study_trials(study, kind, kind_params(study, kind)) if t.factors["panel"] == "n_b"]
    assert all(FORMER not in t.factors for t in n_b)
    assert {(t.factors["n_exp"], t.factors[CURRENT]): t.trial_id for t in n_b} == STORED_IDS
    assert {t.scene_id for t in n_b} == {STORED_SCENE}


def test_a_run_stored_before_reads_as_one_stored_now(runs):
    roots, _ = runs
    assert FORMER in _stored_names(roots["before"]) and CURRENT not in _stored_names(roots["before"])
    assert CURRENT in _stored_names(roots["now"]) and FORMER not in _stored_names(roots["now"])
    before, now = _records(roots["before"]), _records(roots["now"])
    assert before.columns.tolist() == now.columns.tolist() and FORMER not in before
    pd.testing.assert_frame_equal(before, now)  # the same trial ids, scenes and outcomes
    assert sorted(now.loc[now["panel"] == "n_b", "trial_id"]) == sorted(STORED_IDS.values())


def test_a_run_stored_before_is_reported_as_one_stored_now(runs):
    roots, _ = runs
    tables = {}
    for name in ("now", "before"):
        assert build_reports(["sensitivity"], root=roots[name], formats=["csv"]).failed == []
        folder = roots[name] / "sensitivity" / "default" / "report" / "tables"
        tables[name] = {p.name: pd.read_csv(p) for p in sorted(folder.glob("*.csv"))}
    assert tables["before"].keys() == tables["now"].keys() and "sensitivity_claims.csv" in tables["now"]
    for name, table in tables["now"].items():
        before = tables["before"][name]
        if "quantity" in table:  # the runtime rows are timings: differ run to run
            before, table = (t[~t["quantity"].str.contains("runtime")] for t in (before, table))
        timed = [c for c in table if "runtime" in c]
        pd.testing.assert_frame_equal(before.drop(columns=timed), table.drop(columns=timed), obj=name)


def test_status_and_show_count_a_run_stored_before_as_complete(runs):
    roots, _ = runs
    status = run_status(roots["before"], "sensitivity")
    assert (status["n_recorded"], status["n_ok"], status["complete"]) == (12, 12, True)
    manifest = json.loads((roots["before"] / "sensitivity" / "default" / "manifest.json").read_text())
    assert FORMER in manifest["config"]["method_factors"]  # the premise: the config names the former
    # show, for the design as configured now: every trial recorded, and `run` would not refuse
    result = CliRunner().invoke(app, ["show", "sensitivity", *REDUCED, "--root", str(roots["before"])])
    assert result.exit_code == 0, result.output
    assert "(12 of 12 recorded)" in result.stdout and "note:" not in result.stdout


def test_a_run_stored_before_resumes_its_missing_trials_only(runs):
    roots, resumed = runs
    assert (resumed.n_already, resumed.n_ran, resumed.n_error) == (11, 1, 0)  # (1, 2) ran now
    path = roots["mixed"] / "sensitivity" / "default"
    manifest = json.loads((path / "manifest.json").read_text())
    # the run keeps one name for its config: the resumed session records the stored hash
    assert len(manifest["sessions"]) == 2
    assert {s["config_hash"] for s in manifest["sessions"]} == {manifest["config_hash"]}
    assert FORMER in manifest["config"]["method_factors"]
    assert {FORMER, CURRENT} <= _stored_names(roots["mixed"])  # each session's name, one file
    mixed, now = _records(roots["mixed"]), _records(roots["now"])
    assert mixed["trial_id"].is_unique and FORMER not in mixed
    # every column, pso_at_bound too: a trial run after a resume reads its body back from prepared/,
    # where a body with no identification has a null at_bound (it recorded 'None', '' in one session)
    pd.testing.assert_frame_equal(mixed, now)
    # and again: nothing left to run
    again = run_study(_cfg(roots["mixed"]))
    assert (again.n_already, again.n_ran) == (12, 0)


@pytest.mark.parametrize(("override", "message"), [
    ("b_n_s_per_m=[0.5]", "b_n_s_per_m is the former name of factor b (the MSD nodal damping in the "
     "simulator's internal units, never N·s/m; override 'b_n_s_per_m=[0.5]' rejected); write b=[0.5]."),
    ("factors.b_n_s_per_m=[0.5,1.0]", "factors.b_n_s_per_m is the former name of factor b (the MSD "
     "nodal damping in the simulator's internal units, never N·s/m; override "
     "'factors.b_n_s_per_m=[0.5,1.0]' rejected); write factors.b=[0.5,1.0]."),
    ("+factors.b_n_s_per_m=[0.5]", "factors.b_n_s_per_m is the former name of factor b (the MSD nodal "
     "damping in the simulator's internal units, never N·s/m); write factors.b."),
    ("method_factors=[planner,variant,mass_kg,mu,lambda1,lambda2,n_exp,b_n_s_per_m]",
     "method_factors' b_n_s_per_m is the former name of factor b (the MSD nodal damping in the "
     "simulator's internal units, never N·s/m); write b."),
])
@pytest.mark.parametrize("study", ["sensitivity", "baseline_grid"])
def test_an_override_by_the_former_name_is_told_the_current_one(study, override, message, tmp_path):
    result = CliRunner().invoke(app, ["run", study, override, "--root", str(tmp_path)])
    assert result.exit_code == 2, result.output
    assert result.stderr == f"error: {message}\n"
    assert list(tmp_path.iterdir()) == []  # nothing stored
