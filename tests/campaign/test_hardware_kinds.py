"""The ``test2_grasp`` and ``test3_disturbance`` kinds: design, records, workers, schedule.

Reduced sheets (``params.fraction``: whole matched cells and slots with their re-runs) are run
through ``run_study`` sequentially and on two loky workers; the records are checked against the
in-process rig path (:func:`graspcampaign.rig.plan.predict_trial` and
:func:`graspcampaign.rig.virtual.virtual_trial` with the trial's own generator), which no engine
code touches. Their ingest is tested in test_hardware_ingest.py.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd
import pytest
from hardware_checks import REDUCED, TIMING, cli, same

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.kind import get_kind
from graspcampaign.campaign.kinds import hardware as H
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import kind_params, run_study, study_trials
from graspcampaign.cli.main import app
from graspcampaign.rig import protocol
from graspcampaign.rig.plan import predict_trial
from graspcampaign.rig.virtual import virtual_trial

SEEDS = {"test2_grasp": 801, "test3_disturbance": 901}  # campaigns/*.yaml


def _study(name, root, *extra):
    return compose_study(name, ["runner.progress=false", f"output.root={root}", *REDUCED,
                                *extra])


@pytest.fixture(scope="module", params=sorted(SEEDS))
def runs(request, study_run):
    """One reduced study run sequentially (shared with the ingest tests)."""
    name = request.param
    root, seq = study_run(name, *REDUCED)
    study = _study(name, root)
    records = RunStore(seq.path).read().to_pandas()
    return name, root, study, seq, records


@pytest.fixture(scope="module")
def parallel(runs):
    """The run of ``runs`` again on two loky workers."""
    name, root, *_ = runs
    return run_study(_study(name, root, "runner.backend=loky", "runner.n_jobs=2",
                            "runner.batch_size=15", "output.run=par"))


# ------------------------------------------------------------------------------- design


@pytest.mark.parametrize(("name", "maker", "n"), [("test2_grasp", protocol.test2_schedule, 1785),
                                                  ("test3_disturbance", protocol.test3_schedule,
                                                   1245)])
def test_full_design_is_the_commanded_sheet(name, maker, n):
    study = compose_study(name)
    kind = get_kind(name)
    trials = study_trials(study, kind, kind_params(study, kind))
    sheet = maker(SEEDS[name])
    assert len(trials) == n == len(sheet)  # §8.1: 1785 commanded; §9.1: 1245
    assert [t.factors[H.SHEET_ID] for t in trials] == sheet["trial_id"].tolist()
    assert len({t.trial_id for t in trials}) == n
    assert kind.source == "virtual"
    assert all(isinstance(v, (str, int, float, bool)) for t in trials[:40]
               for v in t.factors.values())


def test_reduced_sheet_keeps_matched_cells_and_reruns_whole():
    study = compose_study("test2_grasp", ["params.fraction=0.2"])
    sheet = H.protocol_schedule(study, kind_params(study, get_kind("test2_grasp")))
    full = protocol.test2_schedule(SEEDS["test2_grasp"])
    assert 0.1 * len(full) < len(sheet) < 0.3 * len(full)
    matched = sheet[sheet["matched"]]
    assert (matched.groupby(["object_id", "condition", "repeat"])["slot_id"].nunique() == 5).all()
    faults = set(sheet.loc[sheet["rig_fault"], "slot_id"])
    assert faults == set(sheet.loc[sheet["attempt"] == 2, "slot_id"])
    kept = full[full["trial_id"].isin(sheet["trial_id"])]  # ids and factors unchanged
    pd.testing.assert_frame_equal(sheet, kept.reset_index(drop=True))
    one = compose_study("test3_disturbance", ["params.objects=[pear-01]", "params.blocks=[A,C]"])
    part = H.protocol_schedule(one, kind_params(one, get_kind("test3_disturbance")))
    assert set(part["object_id"]) == {"pear-01"} and set(part["block"]) == {"A", "C"}


def test_params_are_validated_before_anything_runs(tmp_path):
    result = cli.invoke(app, ["run", "test2_grasp", "params.objects=[cup-01]",
                              f"output.root={tmp_path}"])
    assert result.exit_code == 2
    assert re.search(r"params\.objects\[0\] has unknown value 'cup-01'", result.stderr)
    assert not any(tmp_path.iterdir())
    result = cli.invoke(app, ["show", "test3_disturbance", "params.blocks=[F]"])
    assert result.exit_code == 2 and "params.blocks[0] has unknown value 'F'" in result.stderr
    result = cli.invoke(app, ["show", "test2_grasp", "params.fraction=0"])
    assert result.exit_code == 2 and "params.fraction = 0.0 is out of range" in result.stderr


# ------------------------------------------------------------------ engine = in-process


def test_records_equal_the_in_process_rig(runs):
    name, _, study, seq, records = runs
    assert seq.n_error == 0 and seq.n_trials == len(records) > 50
    trials = {t.trial_id: t for t in study_trials(study, get_kind(name),
                                                  kind_params(study, get_kind(name)))}
    rec = records.set_index("trial_id")
    counterfactual = RunStore(seq.path).read(f"tables/{H.COUNTERFACTUAL_TABLE}").to_pandas()
    counterfactual = counterfactual.set_index("trial_id")
    for tid in list(trials)[:: max(1, len(trials) // 40)]:
        t = trials[tid]
        row = {k: v for k, v in t.factors.items() if k not in (H.SHEET_ID, "seed")}
        row.update(trial_id=t.factors[H.SHEET_ID], study=name)
        # one seed from the trial's generator, the same execution noise for both readings
        seed = int(t.rng(SEEDS[name]).integers(0, 2**63))
        pred = predict_trial(row)
        meas = virtual_trial(row, pred, np.random.default_rng(seed))
        for k, v in {**pred, **meas}.items():
            if k in ("plan_time_s", "source"):
                continue
            got = rec.loc[tid, k]
            assert (got is None or (isinstance(got, float) and math.isnan(got))) if v is None \
                or (isinstance(v, float) and math.isnan(v)) else got == v, (tid, k)
        none = virtual_trial(row, pred, np.random.default_rng(seed), belief_error="none")
        for k, v in none.items():
            if k in ("plan_time_s", "source"):
                continue
            got = counterfactual.loc[tid, k]
            assert (got is None or (isinstance(got, float) and math.isnan(got))) if v is None \
                or (isinstance(v, float) and math.isnan(v)) else got == v, (tid, k)


def test_records_carry_the_sheet_row_and_label_the_source(runs):
    name, _, study, _, records = runs
    sheet = H.protocol_schedule(study, kind_params(study, get_kind(name)))
    got = records.set_index(H.SHEET_ID).loc[sheet["trial_id"]].reset_index()
    for col in sheet.columns.drop(["trial_id", "study"]):
        assert same(got[col], sheet[col]), col
    assert (records["source"] == "virtual").all() and (records["study"] == name).all()
    aborted = records["aborted"].astype(bool)
    assert (aborted == records["rig_fault"].astype(bool)).all()
    assert (records.loc[aborted, "outcome"] == "aborted").all()
    assert records.loc[~aborted, "success"].notna().all()


@pytest.mark.slow  # starts loky workers: `make test-slow`
def test_records_and_tables_do_not_depend_on_the_worker_count(runs, parallel):
    *_, seq, records = runs
    par = parallel
    other = RunStore(par.path).read().to_pandas()
    assert par.n_error == 0 and other["worker"].nunique() == 2  # both workers ran trials
    a = records.sort_values("trial_id").reset_index(drop=True)
    b = other.sort_values("trial_id").reset_index(drop=True)
    assert sorted(a.columns) == sorted(b.columns)
    for col in sorted(set(a.columns) - TIMING):
        assert same(a[col], b[col]), col
    table = RunStore(seq.path).read(f"tables/{H.COUNTERFACTUAL_TABLE}").to_pandas()
    other = RunStore(par.path).read(f"tables/{H.COUNTERFACTUAL_TABLE}").to_pandas()
    a = table.sort_values("trial_id").reset_index(drop=True)
    b = other.sort_values("trial_id").reset_index(drop=True)
    for col in sorted(set(a.columns) - TIMING):
        assert same(a[col], b[col]), col


def test_the_counterfactual_reading_is_one_row_per_trial(runs):
    name, root, study, seq, records = runs
    table = RunStore(seq.path).read(f"tables/{H.COUNTERFACTUAL_TABLE}").to_pandas()
    assert sorted(table["trial_id"]) == sorted(records["trial_id"])
    assert (table["belief_error"] == "none").all() and (records["belief_error"] == "paper").all()
    none = H.records_under_belief(records, table)
    assert set(records.columns) <= set(none.columns) and len(none) == len(records)
    pd.testing.assert_series_equal(none.set_index("trial_id")["slot_id"].sort_index(),
                                   records.set_index("trial_id")["slot_id"].sort_index())
    ex = none[~none["aborted"].astype(bool) & (none["g_geo_actual"] > 0)]
    assert len(ex) > 20
    np.testing.assert_allclose(ex["g_geo_believed"], ex["g_geo_actual"], atol=1e-12)
    np.testing.assert_allclose(ex["mu_s_believed"], ex["mu_s_actual"], rtol=1e-12)
    np.testing.assert_allclose(ex["sf_predicted"], ex["sf_actual"], rtol=1e-12)
    # the paper reading keeps each planner's own belief
    paper = records[~records["aborted"].astype(bool)]
    base = paper[paper["planner"] != "heuristic"]
    np.testing.assert_allclose(base["mu_s_believed"], 0.646, atol=5e-4)  # Table 4 mean


def test_belief_error_param(tmp_path):
    study = _study("test3_disturbance", tmp_path, "params.belief_error=[paper]",
                   "params.blocks=[C]", "runner.backend=sequential")
    summary = run_study(study)
    assert summary.n_error == 0
    assert RunStore(summary.path).read(f"tables/{H.COUNTERFACTUAL_TABLE}").num_rows == 0
    result = cli.invoke(app, ["show", "test2_grasp", "params.belief_error=[none]"])
    assert result.exit_code == 2
    assert "params.belief_error must list 'paper' (the records hold the planners' own beliefs; " \
           "'none' is their counterfactual), got ['none']." in result.stderr
    result = cli.invoke(app, ["show", "test2_grasp", "params.belief_error=[paper,oracle]"])
    assert result.exit_code == 2
    assert "params.belief_error[1] has unknown value 'oracle'" in result.stderr


def test_schedule_command_writes_the_sheet_with_its_plans(tmp_path):
    result = cli.invoke(app, ["schedule", "test3_disturbance", "params.blocks=[C]",
                              f"output.root={tmp_path}"])
    assert result.exit_code == 0, result.output
    sheet = pd.read_parquet(tmp_path / "test3_disturbance" / "schedule" / "sheet.parquet")
    full = protocol.test3_schedule(SEEDS["test3_disturbance"])
    want = full[full["block"] == "C"].reset_index(drop=True)
    pd.testing.assert_frame_equal(sheet[want.columns], want)
    for col in ("grip_force_n", "contact_1_x_mm", "normal_3_z", "torque_pred_nm",
                "first_finger_pred", "retention_pred"):
        assert col in sheet and sheet[col].notna().all(), col
    # §9.1: T = W sqrt(SF^2 - 1) r_eff on every row the planner sized to SF >= 1
    ok = sheet[sheet["sf_predicted"] >= 1.0]
    weight = ok["mass_kg"] * 9.81
    np.testing.assert_allclose(ok["torque_pred_nm"], weight * np.sqrt(ok["sf_predicted"] ** 2 - 1)
                               * ok["r_eff_mm"] * 1e-3, rtol=1e-9)
