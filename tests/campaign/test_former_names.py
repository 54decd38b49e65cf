"""campaign.former_names: a run stored under a column's former name reads under its current name.

A run "stored before the rename" is made here as the code before it made it (commits c34ea4d and
b3d2459): the kind as it is now, its outputs written under the names that code wrote, typed out
below from that code (``dynamic_grasp``'s and ``dynamic_check``'s ``slip_margin_n``;
``test1_bench``'s ``exponent_n`` and ``shifted_m``, ``exponent_n`` in its ``truths`` summary table
and ``n`` in its ``pso_runs``; ``wrench_balance``'s ``slip_margin_rel`` in its ``iterations``
trace; ``test2_grasp``'s and ``test3_disturbance``'s ``n_believed`` in their records and their
``belief_none`` trace). Its records (through every reader: ``load_records``, the dataset,
``status``), its other parts, its report tables and its checks must be those of the same run
stored now.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from graspcampaign.api import load_records
from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.former_names import current_names, renamed
from graspcampaign.campaign.kind import RUNTIME_KINDS, get_kind
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study
from graspcampaign.campaign.status import run_status
from graspcampaign.report.build import build_reports

#: What the code before the rename wrote, per kind and part: current name -> the name it wrote.
WROTE = {**dict.fromkeys(("dynamic_grasp", "dynamic_check"),
                         {"records": {"slip_margin_ratio": "slip_margin_n"}}),
         "test1_bench": {"records": {"n_exp": "exponent_n", "shifted_m_exp": "shifted_m"},
                         "summary/truths": {"n_exp": "exponent_n"}, "summary/pso_runs": {"n_exp": "n"}},
         "wrench_balance": {"tables/iterations": {"slip_margin_ratio": "slip_margin_rel"}},
         **dict.fromkeys(("test2_grasp", "test3_disturbance"), {
             "records": {"believed_n_exp": "n_believed"},
             "tables/belief_none": {"believed_n_exp": "n_believed"}})}
#: Columns two runs of one study differ in whatever they store (when and where a trial ran).
WHEN_WHERE = ["wall_time_s", "worker", "host"]
DYNAMIC = ["nodes=[144]", "mass_kg=[0.4]", "+params.t_max_s=0.06"]  # ~0.5 s a trial
TEST1 = ["params.materials=[gel]", "params.specimens=[1]", "params.environments=[normal_lab]",
         "params.pso_restarts=1", "params.pso_particles=4", "params.pso_iterations=2",
         "params.pso_max_reruns=0"]  # 162 events and a token PSO: every table of the report


# ----------------------------------------------------------------------------- current_names


def test_a_former_name_is_renamed_in_its_place():
    table = pa.table({"a": [1, 2], "exponent_n": [0.4, 0.5], "b": ["x", "y"]})
    out = current_names(table, {"exponent_n": "n_exp", "shifted_m": "shifted_m_exp"})
    assert out.column_names == ["a", "n_exp", "b"]
    assert out.column("n_exp").to_pylist() == [0.4, 0.5]


def test_both_names_become_one_column_no_value_lost():
    # a compacted file of shards written before and after the rename (a resumed run)
    table = pa.table({"slip_margin_ratio": [None, 0.8, None], "x": [1, 2, 3],
                      "slip_margin_n": [0.3, None, -0.2]})
    out = current_names(table, {"slip_margin_n": "slip_margin_ratio"})
    assert out.column_names == ["slip_margin_ratio", "x"]
    assert out.column("slip_margin_ratio").to_pylist() == [0.3, 0.8, -0.2]
    # a current column with no type of its own (all missing) takes the former's values and type
    table = pa.table({"n_exp": pa.nulls(2), "exponent_n": pa.array([1, 2], pa.int32())})
    out = current_names(table, {"exponent_n": "n_exp"})
    assert out.column_names == ["n_exp"] and out.column("n_exp").type == pa.int32()


@pytest.mark.parametrize(("current", "former", "merged"), [
    (pa.array([1, None], pa.int64()), pa.array([None, 1.5]), pa.array([1.0, 1.5])),
    (pa.array([1, None], pa.int32()), pa.array([None, 2**40]), pa.array([1, 2**40], pa.int64())),
])
def test_both_names_of_different_types_become_one_column_of_the_type_both_fit(current, former, merged):
    # the shards of a compacted file typed apart (whole numbers before, fractions after): the type
    # pyarrow's permissive unification gives them, as it gives the files of a run read together
    table = pa.table({"n_exp": current, "n": former})
    out = current_names(table, {"n": "n_exp"})
    assert out.column_names == ["n_exp"]
    assert out.column("n_exp").combine_chunks().equals(merged)


def test_where_both_names_hold_a_value_the_current_one_is_kept():
    """A row written under both names (no run writes one: a shard holds one name) reads the
    current name's value, as ``current_names`` promises, never the former's."""
    table = pa.table({"n_exp": [0.4, None], "exponent_n": [0.9, 0.5]})
    out = current_names(table, {"exponent_n": "n_exp"})
    assert out.column("n_exp").to_pylist() == [0.4, 0.5]


def test_a_table_without_former_names_is_unchanged():
    table = pa.table({"slip_margin_n": [1.5], "slip_margin_ratio": [0.7]})
    assert current_names(table, renamed("quasi_static")).equals(table)


@pytest.mark.parametrize("kind", ["quasi_static", "wrench_balance", "pso_repeatability",
                                  "sensitivity"])
def test_a_newton_slip_margin_keeps_its_name(kind):
    """The quasi-static kinds' ``slip_margin_n`` is min_j f_n,j (μ − |η|) in newtons; mapping it
    onto their ``slip_margin_ratio`` would overwrite the ratio (wrench_balance's trace holds both)."""
    for part in ("records", "tables/iterations", "prepared"):
        assert "slip_margin_n" not in renamed(kind, part)


def test_the_part_decides_a_former_name():
    """``n`` is Test 1's exponent in its PSO log only: a column ``n`` of another part (a count, in
    the reports' tables) keeps its name, as does a part of another kind."""
    table = pa.table({"n": [3, 4], "trial_id": ["a", "b"]})
    for kind, part in (("test1_bench", "records"), ("test1_bench", "summary/table5"),
                       ("pso_repeatability", "summary/pso_runs")):
        assert current_names(table, renamed(kind, part)).equals(table)
    pso_log = current_names(table, renamed("test1_bench", "summary/pso_runs"))
    assert pso_log.column_names == ["n_exp", "trial_id"]


# ---------------------------------------------------------------------- runs stored before


def _as_before(kind_name: str, stop_at_mu: float | None = None):
    """Trial kind ``kind_name`` as the code before the rename ran it: its outputs, its trace
    tables and the rows of its finalize tables under the names it wrote (``WROTE``); interrupted
    (Ctrl-C) at the first trial of ``stop_at_mu``, if given."""
    kind, wrote = get_kind(kind_name), WROTE[kind_name]

    def back(row: dict, part: str = "records") -> dict:
        return {wrote.get(part, {}).get(k, k): v for k, v in row.items()}

    def run(inp, rng):
        if stop_at_mu is not None and inp.trial.factors.get("mu") == stop_at_mu:
            raise KeyboardInterrupt
        out = back(kind.run(inp, rng))
        if "__tables__" in out:  # trace tables: column -> values
            out["__tables__"] = {n: back(t, f"tables/{n}") for n, t in out["__tables__"].items()}
        return out

    def finalize(study, params, records, store=None):
        tables = kind.finalize(study, params, records, store)
        return {n: [back(r, f"summary/{n}") for r in rows] for n, rows in tables.items()}

    return dataclasses.replace(kind, run=run, finalize=finalize if kind.finalize else None)


def _run(root, study: str, overrides: list[str], before: bool = False,
         stop_at_mu: float | None = None, **kw):
    """Run ``study`` reduced by ``overrides`` into ``root``; ``before``: by the code before the rename."""
    cfg = compose_study(study, ["runner.backend=sequential", "runner.progress=false",
                                f"output.root={root}", *overrides])
    if before:
        RUNTIME_KINDS[cfg.kind] = _as_before(cfg.kind, stop_at_mu)
    try:
        return run_study(cfg, **kw)
    finally:
        RUNTIME_KINDS.pop(cfg.kind, None)


def _stored_names(path, part: str = "records") -> set[str]:
    """Every column name of the run's stored ``part`` files, as written."""
    return set().union(*(pq.read_schema(p).names for p in (path / part).glob("*.parquet")))


def _records(root, study: str) -> pd.DataFrame:
    df = load_records(study, root=root)
    return df.drop(columns=WHEN_WHERE).sort_values("trial_id").reset_index(drop=True)


@pytest.fixture(scope="module")
def dynamic_runs(tmp_path_factory):
    """friction_mass (dynamic_grasp) at μ = 0.1 and 0.5 stored now, stored before the rename, and
    stored before it until interrupted at μ = 0.5, then resumed now (``--allow-drift``: in earnest
    the code version differs)."""
    roots = {name: tmp_path_factory.mktemp(name) for name in ("now", "before", "mixed")}
    both = [*DYNAMIC, "mu=[0.1,0.5]"]
    _run(roots["now"], "friction_mass", both)
    _run(roots["before"], "friction_mass", both, before=True)
    with pytest.raises(KeyboardInterrupt):
        _run(roots["mixed"], "friction_mass", both, before=True, stop_at_mu=0.5)
    resumed = _run(roots["mixed"], "friction_mass", both, allow_drift=True)
    return roots, resumed


def test_a_dynamic_run_stored_before_reads_as_one_stored_now(dynamic_runs):
    roots, _ = dynamic_runs
    path = roots["before"] / "friction_mass" / "default"
    assert "slip_margin_n" in _stored_names(path) and "slip_margin_ratio" not in _stored_names(path)
    written_now = _stored_names(roots["now"] / "friction_mass" / "default")  # the kind's names now
    assert "slip_margin_ratio" in written_now and "slip_margin_n" not in written_now
    before, now = _records(roots["before"], "friction_mass"), _records(roots["now"], "friction_mass")
    assert before.columns.tolist() == now.columns.tolist()  # same names, same places
    assert "slip_margin_n" not in before and before["slip_margin_ratio"].notna().all()
    pd.testing.assert_frame_equal(before, now)
    # the dataset of the API and a read of chosen columns too
    table = load_records("friction_mass", root=roots["before"], dataset=True).to_table()
    assert "slip_margin_n" not in table.column_names
    assert sorted(table.column("slip_margin_ratio").to_pylist()) == sorted(now["slip_margin_ratio"])
    picked = RunStore(path).read(columns=["trial_id", "slip_margin_ratio", "qs_slip_margin_n"])
    assert picked.column_names == ["trial_id", "slip_margin_ratio", "qs_slip_margin_n"]


def test_a_run_stored_before_is_no_damaged_run(dynamic_runs):
    """The digest is of the values under the names written; no check reads an output's name."""
    roots, _ = dynamic_runs
    store = RunStore(roots["before"] / "friction_mass" / "default")
    store.verify()
    assert store.check()["kind"] == "dynamic_grasp"
    status = run_status(roots["before"], "friction_mass")
    assert (status["n_recorded"], status["n_ok"], status["complete"]) == (4, 4, True)  # μ x 2 presets
    # resumed by the code now (same config and code version): nothing to repair or run again
    summary = _run(roots["before"], "friction_mass", [*DYNAMIC, "mu=[0.1,0.5]"])
    assert (summary.n_already, summary.n_ran) == (4, 0)


def test_a_run_resumed_across_the_rename_has_one_column_and_every_trial(dynamic_runs):
    roots, resumed = dynamic_runs
    assert (resumed.n_already, resumed.n_ran) == (2, 2)  # μ = 0.1 before, 0.5 now (2 presets each)
    stored = list((roots["mixed"] / "friction_mass" / "default" / "records").glob("*.parquet"))
    # the shards of both sessions were compacted into one file holding both names, each missing
    # where the other is set
    assert len(stored) == 1 and {"slip_margin_n", "slip_margin_ratio"} <= set(pq.read_schema(stored[0]).names)
    mixed, now = _records(roots["mixed"], "friction_mass"), _records(roots["now"], "friction_mass")
    assert len(mixed) == 4 and "slip_margin_n" not in mixed
    pd.testing.assert_series_equal(mixed["slip_margin_ratio"], now["slip_margin_ratio"])
    assert mixed["slip_margin_ratio"].notna().all()


def _tables(root, study: str) -> dict[str, pd.DataFrame]:
    """The report's tables (csv), without the columns of when and where a trial ran."""
    folder = root / study / "default" / "report" / "tables"
    return {p.name: pd.read_csv(p).drop(columns=WHEN_WHERE, errors="ignore")
            for p in sorted(folder.glob("*.csv"))}


def test_a_dynamic_run_stored_before_is_reported_as_one_stored_now(dynamic_runs):
    roots, _ = dynamic_runs
    for name in ("now", "before"):
        assert build_reports(["friction_mass"], root=roots[name], formats=["csv"]).failed == []
    before, now = _tables(roots["before"], "friction_mass"), _tables(roots["now"], "friction_mass")
    assert before.keys() == now.keys() and len(now) >= 4
    for name, table in now.items():
        pd.testing.assert_frame_equal(before[name], table, obj=name)


@pytest.fixture(scope="module")
def test1_runs(tmp_path_factory):
    """test1_bench (162 events, finalize tables) stored now and stored before the rename."""
    roots = {name: tmp_path_factory.mktemp(f"t1{name}") for name in ("now", "before")}
    _run(roots["now"], "test1_bench", TEST1)
    _run(roots["before"], "test1_bench", TEST1, before=True)
    for root in roots.values():
        assert build_reports(["test1_bench"], root=root, formats=["csv"]).failed == []
    return roots


def test_a_test1_run_stored_before_reads_and_reports_as_one_stored_now(test1_runs):
    roots = test1_runs
    path = roots["before"] / "test1_bench" / "default"
    assert {"exponent_n", "shifted_m"} <= _stored_names(path)
    written_now = _stored_names(roots["now"] / "test1_bench" / "default")
    assert {"n_exp", "shifted_m_exp"} <= written_now and not {"exponent_n", "shifted_m"} & written_now
    assert "exponent_n" in pq.read_schema(next((path / "summary" / "truths").glob("*.parquet"))).names
    before, now = _records(roots["before"], "test1_bench"), _records(roots["now"], "test1_bench")
    assert {"n_exp", "shifted_m_exp"} <= set(before) and not {"exponent_n", "shifted_m"} & set(before)
    pd.testing.assert_frame_equal(before, now)
    truths = [RunStore(r / "test1_bench" / "default").read("summary/truths").to_pandas()
              for r in (roots["before"], roots["now"])]
    pd.testing.assert_frame_equal(*truths)
    before, now = _tables(roots["before"], "test1_bench"), _tables(roots["now"], "test1_bench")
    assert before.keys() == now.keys() and "table4.csv" in now
    for name, table in now.items():
        pd.testing.assert_frame_equal(before[name], table, obj=name)
    # Table 4's paper rows stand in the records' column of n, beside ours
    table4 = now["table4.csv"].set_index("row")
    assert table4.loc["paper", "n_exp"] == 0.473 and table4.loc["ours", "n_exp"] > 0


def test_a_test1_pso_log_stored_before_reads_as_one_stored_now(test1_runs):
    """``summary/pso_runs`` called the exponent ``n``; read, it is the records' ``n_exp``, and Table 5
    and the §7.5 rows (its median over the converged runs) are reported from it as now."""
    roots = test1_runs
    written = {name: _stored_names(roots[name] / "test1_bench" / "default", "summary/pso_runs")
               for name in roots}
    assert "n" in written["before"] and "n_exp" not in written["before"]
    assert "n_exp" in written["now"] and "n" not in written["now"]
    runs = [RunStore(roots[name] / "test1_bench" / "default").read("summary/pso_runs").to_pandas()
            for name in ("before", "now")]
    assert "n" not in runs[0] and runs[0]["n_exp"].notna().all()
    pd.testing.assert_frame_equal(*runs)
    before, now = _tables(roots["before"], "test1_bench"), _tables(roots["now"], "test1_bench")
    for name in ("table5.csv", "pso_summary.csv"):
        pd.testing.assert_frame_equal(before[name], now[name], obj=name)
    median = before["pso_summary.csv"].set_index("quantity").loc["n over the converged runs: median", "value"]
    assert median == pytest.approx(float(np.median(pq.read_table(
        next((roots["before"] / "test1_bench" / "default" / "summary" / "pso_runs").glob("*.parquet")),
        filters=[("converged", "==", True)]).column("n").to_numpy())), rel=1e-12)


WRENCH = ["mu=[0.1,0.5]", "evaluator.n_max=12"]  # two friction levels, a short closing ramp


@pytest.fixture(scope="module")
def wrench_runs(tmp_path_factory):
    """wrench_balance at μ = 0.1 and 0.5 stored now, stored before the trace's rename, and stored
    before it until interrupted at μ = 0.5, then resumed now (``--allow-drift``)."""
    roots = {name: tmp_path_factory.mktemp(f"w{name}") for name in ("now", "before", "mixed")}
    _run(roots["now"], "wrench_balance", WRENCH)
    _run(roots["before"], "wrench_balance", WRENCH, before=True)
    with pytest.raises(KeyboardInterrupt):
        _run(roots["mixed"], "wrench_balance", WRENCH, before=True, stop_at_mu=0.5)
    _run(roots["mixed"], "wrench_balance", WRENCH, allow_drift=True)
    for root in roots.values():
        assert build_reports(["wrench_balance"], root=root, formats=["csv"]).failed == []
    return roots


def _trace(root) -> pd.DataFrame:
    table = RunStore(root / "wrench_balance" / "default").read("tables/iterations").to_pandas()
    return table.sort_values(["trial_id", "iteration"]).reset_index(drop=True)


def test_a_wrench_trace_stored_before_reads_and_reports_as_one_stored_now(wrench_runs):
    """The trace's ``slip_margin_rel`` was the records' ``slip_margin_ratio`` per iteration; read, it
    is that column, the records' own ``slip_margin_ratio`` is left as it is, and the report's
    tables (the final slip margin of each μ) are those of the run stored now."""
    roots = wrench_runs
    path = roots["before"] / "wrench_balance" / "default"
    assert {"slip_margin_rel", "slip_margin_n"} <= _stored_names(path, "tables/iterations")
    assert "slip_margin_ratio" not in _stored_names(path, "tables/iterations")
    assert "slip_margin_ratio" in _stored_names(path)  # the records' ratio, written so then already
    now = _trace(roots["now"])
    assert "slip_margin_rel" not in _stored_names(roots["now"] / "wrench_balance" / "default",
                                                  "tables/iterations")
    before = _trace(roots["before"])
    assert before.columns.tolist() == now.columns.tolist() and "slip_margin_rel" not in before
    pd.testing.assert_frame_equal(before, now)
    records = _records(roots["now"], "wrench_balance").set_index("trial_id")
    last = now.groupby("trial_id").last()  # the records are the end of the closing ramp
    pd.testing.assert_series_equal(last["slip_margin_ratio"], records.loc[last.index, "slip_margin_ratio"])
    pd.testing.assert_frame_equal(_records(roots["before"], "wrench_balance"),
                                  _records(roots["now"], "wrench_balance"))
    before, now = _tables(roots["before"], "wrench_balance"), _tables(roots["now"], "wrench_balance")
    assert before.keys() == now.keys() and "wrench_balance.csv" in now
    for name, table in now.items():
        pd.testing.assert_frame_equal(before[name], table, obj=name)


def test_a_wrench_trace_resumed_across_the_rename_has_one_column(wrench_runs):
    roots = wrench_runs
    stored = list((roots["mixed"] / "wrench_balance" / "default" / "tables" / "iterations").glob("*.parquet"))
    # μ = 0.1's trace under the former name, μ = 0.5's under the current one, in one compacted file
    assert len(stored) == 1
    assert {"slip_margin_rel", "slip_margin_ratio"} <= set(pq.read_schema(stored[0]).names)
    mixed, now = _trace(roots["mixed"]), _trace(roots["now"])
    assert sorted(mixed) == sorted(now) and "slip_margin_rel" not in mixed  # the two names are one column
    pd.testing.assert_frame_equal(mixed[now.columns], now)  # each row's value, none lost


def test_a_dynamic_check_run_stored_before_reads_as_one_stored_now(tmp_path):
    """dynamic_check recorded the dynamic grasp's ``slip_margin_n`` (its record is the dynamic
    grasp's) before the rename too: a run of it stored then reads as one stored now."""
    source = ["shape=[sphere]", "mass_kg=[0.2]", "mu=[0.5]", "seeds=1", "+params.nodes=144"]
    for name in ("now", "before"):
        _run(tmp_path / name, "baseline_grid", source)
        _run(tmp_path / name, "dynamic_check", ["+params.t_max_s=0.12"], before=name == "before")
    assert "slip_margin_n" in _stored_names(tmp_path / "before" / "dynamic_check" / "default")
    before, now = (_records(tmp_path / n, "dynamic_check").drop(columns=["plan_time_s", "grasp_time_s"])
                   for n in ("before", "now"))  # wall times (docs/records.md): run to run
    assert "slip_margin_n" not in before and now["slip_margin_ratio"].notna().all()
    pd.testing.assert_frame_equal(before, now)


@pytest.mark.parametrize("study", ["test2_grasp", "test3_disturbance"])
def test_a_hardware_run_stored_before_reads_as_one_stored_now(study, tmp_path):
    """The believed contact exponent was ``n_believed`` in Tests 2-3 and is ``believed_n_exp``, as
    ``quasi_static`` calls the planner's believed exponent, in the records and the counterfactual
    ``belief_none`` trace alike (a few dozen attempts, each with its ``belief_none`` reading)."""
    roots = {name: tmp_path / name for name in ("now", "before")}
    _run(roots["now"], study, ["params.fraction=0.02"])
    _run(roots["before"], study, ["params.fraction=0.02"], before=True)
    path = roots["before"] / study / "default"
    for part in ("records", "tables/belief_none"):
        assert "n_believed" in _stored_names(path, part) and "believed_n_exp" not in _stored_names(path, part)
    names_now = _stored_names(roots["now"] / study / "default")
    assert "believed_n_exp" in names_now and "n_believed" not in names_now
    timing = ["plan_time_s"]  # 0 when the worker's cache held the plan: differs run to run
    before, now = (_records(roots[n], study).drop(columns=timing) for n in ("before", "now"))
    assert before.columns.tolist() == now.columns.tolist() and "n_believed" not in before
    pd.testing.assert_frame_equal(before, now)
    assert now["believed_n_exp"].notna().all()
    before, now = (RunStore(roots[n] / study / "default").read("tables/belief_none").to_pandas()
                   .drop(columns=timing).sort_values("trial_id").reset_index(drop=True)
                   for n in ("before", "now"))
    assert "n_believed" not in before
    pd.testing.assert_frame_equal(before, now)
