"""`graspcampaign report` names, per run, the items whose code failed (their note in the report says
why) and exits 1; an item legitimately empty (a ValueError or KeyError: the data's reason, e.g. a
column a run whose trials all errored lacks) is not counted. Before, every report printed only its
path and the command exited 0: a table whose computation raised went unnoticed unless the page was
read."""

from __future__ import annotations

import pytest
from cli_checks import invoke

from graspcampaign.report import build
from graspcampaign.report.spec import ReportSpec, Table
from graspcampaign.report.studies import smoke


def mini_spec(study: str, kind: str) -> ReportSpec:
    """Four tables of the smoke run: two whose code raises, one the data leaves without a value,
    one reading a column the records lack."""
    def empty(run):
        raise ValueError("no sphere in this run")

    return ReportSpec("smoke", [
        Table("raises", "c", lambda run: run.ok.assign(n=len(run.paper.sphere_defect_nodes))),
        Table("legit", "c", empty),
        Table("column", "c", lambda run: run.ok.assign(n=run.ok["n_sharp_vertx"])),
        Table("series", "c", lambda run: run.ok.groupby("shape")["n_sharp_vertex"].sum())])


def test_a_report_names_its_items_whose_code_failed_and_exits_1(results, monkeypatch):
    monkeypatch.setattr(build, "spec_for", mini_spec)
    out = invoke("report", "smoke", "--root", results)
    page = results / "smoke" / "default" / "report" / "report.md"
    # six items: the spec's four tables and every report's status and errors tables
    assert f"report: {page} (2 of 6 items failed: Table raises, Table series; their notes in the " \
           "report say why)\n" in out.stdout
    assert out.exit_code == 1
    md = page.read_text()
    assert "*Table raises not computed: TypeError: object of type 'int' has no len().*" in md
    assert "*Table legit not computed: no sphere in this run.*" in md
    assert "*Table column not computed: the records have no `n_sharp_vertx` column.*" in md
    assert "*Table series not computed: TypeError: its compute returned a Series, not a DataFrame" in md


@pytest.mark.parametrize("error, failed", [(RuntimeError, "2 of 6 items failed: Table meshes, Figure "
                                                          "sharp_features;"), (ValueError, None)])
def test_a_study_report_counts_a_raised_error_not_the_datas_reason(results, monkeypatch, error, failed):
    # the smoke report's mesh table and figure read _meshes, which orders the shapes
    def ordered(*args):
        raise error("the shapes cannot be ordered")

    monkeypatch.setattr(smoke, "ordered", ordered)
    out = invoke("report", "smoke", "--root", results)
    line = next(r for r in out.stdout.splitlines() if r.startswith("report: "))
    assert (failed in line) if failed else line.endswith("report.md"), out.output
    assert out.exit_code == (1 if failed else 0)
    md = (results / "smoke" / "default" / "report" / "report.md").read_text()
    prefix = "RuntimeError: " if failed else ""
    assert f"*Table meshes not computed: {prefix}the shapes cannot be ordered.*" in md
