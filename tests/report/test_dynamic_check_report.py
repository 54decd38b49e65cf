"""dynamic_check report: Sec. 6.1's claim is the sphere's, so its verdict is the sphere's.

A small synthetic run (the record columns docs/records.md gives dynamic_check) where the sphere's
labels all agree and the other shapes' do not: the kappa table's counts are recomputed with pandas
from the records, the verdict is judged on the sphere alone, every-shape rows carry none. Two of
each group's dynamic grasps are not settled by t_max: undetermined, they enter no agreement.
"""

from __future__ import annotations

import re
from pathlib import Path
from types import SimpleNamespace

import pandas as pd
import pytest
import yaml

from graspcampaign.analysis import dynamic_check as dc
from graspcampaign.analysis.vocabulary import label
from graspcampaign.report.document import cell
from graspcampaign.report.render import Run
from graspcampaign.report.studies import dynamic_check as report

CLAIM = ("Sec. 6.1: the dynamic and quasi-static evaluators agree on the success label (sphere, their "
         "respective optima)")


def _run() -> Run:
    rows = []
    for preset in ("table2", "firm"):
        for shape in ("sphere", "pear"):
            for i in range(20):
                qs = i % 2 == 0
                dyn = qs if shape == "sphere" else i % 4 == 0  # the pear disagrees on a quarter
                rows.append({"trial_id": f"{preset}-{shape}-{i}", "status": "ok", "model_preset": preset,
                             "shape": shape, "planner": "heuristic", "source_trial_id": f"{shape}-{i}",
                             "source_study": "baseline_grid", "qs_success": qs, "success": dyn,
                             "qs_preset_success": qs, "qs_success_unbounded": qs,
                             "success_unbounded": dyn, "qs_preset_success_unbounded": qs,
                             "dynamic_status": "stable" if dyn else "not_settled" if i in (1, 11)
                             else "penetration_limit"})
    return Run(pd.DataFrame(rows), {"config": {"factors": {"model_preset": ["table2", "firm"]}}},
               SimpleNamespace(claim=CLAIM))


def test_the_verdict_is_on_the_sphere_and_every_shape_is_context():
    run = _run()
    kappa = report._kappa(run)
    records = run.records
    for r in kappa.itertuples():
        g = records[records.model_preset == r.model_preset]
        g = g[g["shape"] == "sphere"] if r.scope == "sphere" else g
        assert r.not_settled == int((g.dynamic_status == "not_settled").sum())
        g = g[g.dynamic_status != "not_settled"]
        assert r.n == len(g) and r.both_success + r.both_failure == int((g.qs_success == g.success).sum())
    sphere, every = kappa[kappa.scope == "sphere"], kappa[kappa.scope != "sphere"]
    assert len(sphere) == len(every) == 8  # 2 presets x 4 label pairs
    assert sphere.agreement_pct.eq(100).all() and sphere.differs.eq(False).all()  # the sphere agrees
    assert every.differs.isna().all() and every.paper_pct.isna().all()
    assert all(v.startswith("no verdict") for v in every.verdict)
    run.tables["kappa"] = kappa
    text = report.finding(run)
    assert "0 of 8 sphere comparisons differ (table kappa)" in text and "Why:" not in text  # all agree
    assert "`not_settled`" not in text and "table2" not in text  # the vocabulary's words
    assert f"100.0% of the determined trials under {label('model_preset', 'table2')}" in text
    assert f"{label('dynamic_status', 'not_settled')}" in text


def test_every_kappa_verdict_is_the_rules_words_told_why_context_rows_are_not_compared(verdict_calls):
    """The kappa table's verdicts are the one verdict rule's words, unedited: the rule is told that the
    every-shape rows are context (not compared), and a sphere row with no settled grasp why it has none."""
    run = _run()
    run.records.loc[run.records.model_preset == "firm", "dynamic_status"] = "not_settled"  # none settled
    kappa = report._kappa(run)
    for r in kappa.itertuples():
        told = [c for c in verdict_calls if c["words"] == r.verdict]
        assert told, f"verdict {r.verdict!r} is no word of the verdict rule"
        context, empty = r.scope != "sphere", r.model_preset == "firm"
        assert told[-1].get("because", "").startswith("no verdict") == (context or empty)
        if context or empty:
            assert r.verdict == ("no verdict: context (the claim is on the sphere)" if context else
                                 "no verdict: nothing to compare")


@pytest.mark.parametrize("firm_settles, counts, said", [
    (False, (4, 2, 2), "4 simulations of 2 sphere grasps under 2 presets"),
    (True, (2, 2, 1), "2 simulations of 2 sphere grasps under 1 preset")])
def test_the_judged_verdict_names_the_grasps_not_settled_by_t_max_it_leaves_out(firm_settles, counts, said):
    """A dynamic grasp stopped by t_max is undetermined, not a failure: the verdict on the sphere
    names how many it leaves out and the time budget. It said "4 sphere grasps" of 2 source grasps
    each simulated under 2 presets: now the simulations, the grasps and the presets (the records'
    not-settled sphere rows, their source trials and presets, counted here)."""
    run = _run()
    run.manifest["config"]["params"] = {"t_max_s": 0.05}
    if firm_settles:
        run.records.loc[run.records.model_preset == "firm", "dynamic_status"] = "penetration_limit"
    run.tables["kappa"] = report._kappa(run)
    sphere = run.records[run.records["shape"] == "sphere"]
    out = sphere[sphere.dynamic_status == "not_settled"]
    assert (len(out), out.source_trial_id.nunique(), out.model_preset.nunique()) == counts
    assert f"{said}, not settled by t_max = 0.05 s, are left out." in report.finding(run)


def test_one_simulation_left_out_is_said_in_the_singular():
    """One sphere simulation not settled (source grasp 11 under table2; the others' status set to a
    failure here) read "1 simulation of 1 sphere grasp under 1 preset, ..., are left out"."""
    run = _run()
    run.manifest["config"]["params"] = {"t_max_s": 0.05}
    keep = (run.records.trial_id == "table2-sphere-11") | (run.records.dynamic_status != "not_settled")
    run.records.loc[~keep, "dynamic_status"] = "penetration_limit"
    run.tables["kappa"] = report._kappa(run)
    assert ("1 simulation of 1 sphere grasp under 1 preset, not settled by t_max = 0.05 s, is left out."
            in report.finding(run))


def test_a_run_whose_every_grasp_timed_out_gets_no_verdict():
    """Before, 40 grasps stopped by t_max were 40 'both fail' and a 'consistent' verdict."""
    run = _run()
    run.records["dynamic_status"] = "not_settled"
    run.records[["success", "success_unbounded"]] = False
    run.tables["kappa"] = kappa = report._kappa(run)
    assert kappa.n.eq(0).all() and kappa.not_settled.eq(20).sum() == 8  # the sphere's 20, all 40
    assert kappa.differs.isna().all() and kappa.agreement_pct.isna().all()
    sphere = kappa[kappa.scope == "sphere"]
    assert sphere.verdict.eq("no verdict: nothing to compare").all()
    text = report.finding(run)
    assert "consistent" not in text and "the labels agree on" not in text
    assert ("No sphere comparison can be judged against the paper's full agreement (Sec. 6.1): none of the "
            "baseline_grid trials re-simulated has a "
            "settled dynamic grasp (table kappa). 40 simulations of 20 sphere grasps under 2 presets, not "
            "settled by t_max, are left out.") \
        in text
    assert "0 of 0" not in text and "mutual failure" not in text  # no count or caveat about no comparison


def test_the_closing_caveat_does_not_call_an_undefined_kappa_near_0():
    """Every grasp failing both ways leaves κ undefined (the table's '—'), not near 0."""
    run = _run()
    run.records[[c for c in run.records if "success" in c]] = False
    run.tables["kappa"] = kappa = report._kappa(run)
    assert kappa.kappa.isna().all()
    assert "κ" not in report.finding(run)  # the labels agree: no disagreement to explain


def test_the_opening_says_which_way_the_labels_disagree_counted_from_the_records():
    """The opening once listed every row of table kappa; now, per preset, how many grasps each
    evaluator accepts on the sphere, and κ's mutual failure where the dynamic grasp holds none."""
    run = _run()
    sphere = (run.records["shape"] == "sphere") & (run.records.model_preset == "table2")
    run.records.loc[sphere, ["success", "success_unbounded"]] = False  # table2: no dynamic hold
    run.records.loc[sphere, "dynamic_status"] = "penetration_limit"
    run.tables["kappa"] = report._kappa(run)
    text = report.finding(run)
    for preset in ("table2", "firm"):
        g = run.records[(run.records.model_preset == preset) & (run.records["shape"] == "sphere")]
        g = g[g.dynamic_status != "not_settled"]
        words = (f"under {label('model_preset', preset)} the dynamic grasp holds {int(g.success.sum())} "
                 f"where the quasi-static label passes {int(g.qs_success.sum())}")
        assert (words in text) == (preset == "table2")  # firm agrees on the sphere: nothing to explain
    assert "(κ 0.00: agreement by mutual failure)" in text


def test_a_partial_run_says_so_in_its_opening():
    """A run stopped at 5,516 of 6,750 grasps said so only in its header."""
    run = _run()
    run.tables["kappa"] = report._kappa(run)
    run.manifest["n_trials"] = len(run.records) + 20
    assert f"Partial run: {len(run.records)} of {len(run.records) + 20} dynamic grasps recorded." in \
        report.finding(run)
    run.manifest["n_trials"] = len(run.records)
    assert "Partial run" not in report.finding(run)


def test_the_status_table_gives_the_time_budget_its_not_settled_column_refers_to():
    run = _run()
    run.manifest["config"]["params"] = {"t_max_s": 0.05}
    table = next(i for i in report.SPEC.items if getattr(i, "name", "") == "dynamic_status")
    assert table.caption(run).endswith("(t_max = 0.05 s of simulated time)")


def test_the_time_budget_is_read_from_the_records_when_the_config_leaves_the_default():
    # a study file that does not set params.t_max_s left its 1 s default unsaid: "not settled by
    # t_max" with no value (the kind's default is not in the config; the records now carry it)
    run = _run()
    run.manifest["config"]["params"] = {}
    run.records["t_max_s"] = 1.0
    table = next(i for i in report.SPEC.items if getattr(i, "name", "") == "dynamic_status")
    assert table.caption(run).endswith("(t_max = 1 s of simulated time)")


def _table(run: Run, name: str):
    """The report's table ``name`` as its page shows it (its shown columns chosen from its frame)."""
    return next(i for i in report.SPEC.items if getattr(i, "name", "") == name).render(run)[0]


def test_group_tables_show_each_evaluators_success_as_a_percentage():
    run = _run()
    table = _table(run, "agreement_by_shape")
    shown = {c.label: c for c in table.cols}
    records = run.records
    for r in table.frame.to_dict("records"):
        g = records[(records.model_preset == r["model_preset"]) & (records["shape"] == r["shape"])
                    & (records.dynamic_status != "not_settled")]
        assert cell(r, shown["quasi-static success %"]) == f"{100 * g.qs_success.mean():.1f}"
        assert cell(r, shown["dynamic success %"]) == f"{100 * g.success.mean():.1f}"


def test_the_description_states_no_stale_trial_count():
    """dynamic_check's size is the source run's (the design depends on it), not a fixed count."""
    path = Path(__file__).parents[2] / "campaigns" / "dynamic_check.yaml"
    description = yaml.safe_load(path.read_text())["description"]
    assert not re.search(r"\d+\s*(x|×)\s*\d+\s*trials", description), description


COUNTS = ("n determined", f"{label('dynamic_status', 'not_settled')} (left out)",
          "a label missing (left out)")


def test_a_trial_missing_a_label_has_its_column_so_the_shown_counts_add_up():
    """agreement_table counts a settled trial missing a label apart (``unlabelled``); the report's
    tables showed n and not settled alone, which then fell short of the trials by that count."""
    run = _run()
    run.records["qs_success"] = run.records.qs_success.astype(object)
    run.records.loc[[0, 2, 1], "qs_success"] = None  # table2's sphere 0 and 2 settled, 1 did not
    seen = []
    for name in ("kappa", "agreement_by_shape"):
        table = _table(run, name)
        heads = [c.label for c in table.cols]
        for r, row in zip(table.frame.to_dict("records"), table.grid[0], strict=True):
            shown = dict(zip(heads, (text for text, _ in row), strict=True))
            g = run.records[run.records.model_preset == r["model_preset"]]
            g = g if r.get("scope") == report.ALL else g[g["shape"] == r.get("shape", "sphere")]
            assert sum(int(shown[h]) for h in COUNTS) == len(g)  # every trial counted once
            labels = list(dc.LABEL_PAIRS[r["comparison"]])
            settled = g[g.dynamic_status != "not_settled"]
            seen.append(int(shown[COUNTS[2]]))
            assert seen[-1] == int(settled[labels].isna().any(axis=1).sum())
    assert seen.count(2) == 3  # table2's source pair: sphere and every shape (kappa), sphere (by shape)
    for name in ("kappa", "agreement_by_shape", "agreement_by_planner"):  # none missing: no column
        assert COUNTS[2] not in [c.label for c in _table(_run(), name).cols]
