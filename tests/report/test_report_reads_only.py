"""``report`` never fits a model or times anything (issue 14 item 4): two reports of the same records
give byte-identical tables, and the report path never imports scikit-learn.

Both claims share one report of the reduced ``surrogate`` and ``test1_bench`` runs, written in a
fresh interpreter (the one place whose ``sys.modules`` says what the report path imports); the
other report of the same records is the one the ``sim_root`` fixture wrote (same formats; PNG
figures there, SVG here, which the tables do not depend on), so each run is reported once here
instead of three times.
"""

from __future__ import annotations

import pytest
from synthetic_runs import FRESH_STUDIES


@pytest.mark.parametrize("study", FRESH_STUDIES)
def test_two_reports_of_the_same_records_give_identical_tables(sim_root, fresh_reports, study):
    root, out = fresh_reports
    assert out.returncode == 0, out.stderr[-2000:]
    tables = []
    for report in (sim_root / study / "default" / "report", root / study / "default" / "report"):
        tables.append({p.name: p.read_bytes() for p in [*(report / "tables").iterdir(),
                                                        report / "tables.json"]})
    assert tables[0] == tables[1] and len(tables[0]) > 5


def test_the_report_path_never_imports_scikit_learn(fresh_reports):
    root, out = fresh_reports
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip() == "[]"
    assert (root / "surrogate" / "default" / "report" / "tables" / "surrogate_timing.csv").exists()


def test_the_tables_do_not_depend_on_the_order_a_run_stored_its_trials(sim_root, tmp_path):
    """The reduced test3_disturbance run again, one trial per task: the same records in another
    order in its files (tasks finish and are named otherwise). Its tables are byte for byte the
    sim_root run's: they differed in their last digits (sums, a logistic fit) and could differ in
    a resampled interval, as ``n_jobs``, the task size or a resume reorder the files."""
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.runner import run_study
    from graspcampaign.report.build import build_reports

    root = tmp_path / "results"
    run_study(compose_study("test3_disturbance", ["runner.backend=sequential", "runner.progress=false",
                                                  "runner.batch_size=1", f"output.root={root}",
                                                  "params.fraction=0.1"]))  # as conftest's REDUCED
    assert build_reports(root=root, formats=["csv", "json"]).failed == []
    tables = [{p.name: p.read_bytes() for p in [*(r / "tables").iterdir(), r / "tables.json"]}
              for r in (sim_root / "test3_disturbance" / "default" / "report",
                        root / "test3_disturbance" / "default" / "report")]
    assert tables[0] == tables[1] and len(tables[0]) > 5
