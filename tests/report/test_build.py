"""build_reports: spec registry, formats, index and headline pages, failures kept per run.

Small runs are written here through ``RunStore`` and a manifest from ``campaign.provenance`` (the
record columns of docs/records.md), with the paper values of the study files; reference
intervals come from statsmodels.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pandas as pd
import pytest
from statsmodels.stats.proportion import proportion_confint
from synthetic_runs import report_md, study_paper_block
from typer.testing import CliRunner

from graspcampaign.campaign.grid import expand
from graspcampaign.campaign.provenance import config_digest, new_manifest, write_manifest
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.schema import StudyCfg
from graspcampaign.cli.main import app
from graspcampaign.errors import UserInputError
from graspcampaign.report.build import KIND_SPECS, SPECS, build_reports, spec_for
from graspcampaign.report.document import check_formats
from graspcampaign.report.spec import ReportSpec

cli = CliRunner()


def write_run(root, name="ablation", kind="quasi_static", n_success=None, error_rows=(),
              source="simulation", planners=("heuristic", "random"), aborted_rows=None,
              run="r1", columns=None):
    """A run of ``len(planners) * 10`` trials; ``n_success[planner]`` successes each (the first
    ones of its trials); ``columns(trial_index)``: more columns of a record."""
    study = StudyCfg(name=name, kind=kind, seed=3, seeds=10,
                     factors={"shape": ["sphere"], "planner": list(planners)},
                     paper=study_paper_block(name))
    n_success = n_success or {"heuristic": 7, "random": 1}
    rows, counts = [], dict.fromkeys(planners, 0)
    for trial in expand(study):
        planner = trial.factors["planner"]
        row = {"trial_id": trial.trial_id, "study": name, "run": run, "kind": kind,
               "trial_index": trial.index, "scene_id": trial.scene_id, "status": "ok",
               "error_type": None, "error_message": None, "wall_time_s": 0.01, "worker": "w",
               "host": "h", "source": source, **trial.factors}
        row.update(columns(trial.index) if columns else {})
        if kind == "quasi_static":  # every quasi-static record names its grip law (docs/records.md)
            row["grip_law"] = "paper"
        if aborted_rows is not None:  # hardware protocols: an aborted attempt stays "ok"
            row["aborted"] = trial.index in aborted_rows
        if trial.index in error_rows:
            row.update(status="error", error_type="ValueError", error_message="bad")
        elif row.get("aborted"):
            row.update(success=None)
        else:
            success = counts[planner] < n_success.get(planner, 0)
            counts[planner] += success
            row.update(success=success, failure_check="none" if success else "residual",
                       residual_norm_n=0.1 if success else 2.0, delta_max_mm=0.5 + trial.index,
                       exceeds_1mm=0.5 + trial.index > 1)
        rows.append(row)
    store = RunStore(root / name / run)
    store.write_shard("records", "aaaaaaaaaa", rows)
    write_manifest(store.manifest_path, new_manifest(study, run, len(rows), source))
    return store


def test_every_spec_resolves():
    for study in SPECS:
        assert isinstance(spec_for(study, "no_such_kind"), ReportSpec), study
    for kind in KIND_SPECS:
        assert isinstance(spec_for("a_study_of_mine", kind), ReportSpec), kind


def test_formats_md_csv_json_html(tmp_path):
    store = write_run(tmp_path)
    paths = build_reports(["ablation"], root=tmp_path, formats=["json", "html"])
    out = store.path / "report"
    assert list(paths) == [out / "report.html"] and paths.failed == []
    assert not (out / "report.md").exists() and not (out / "tables").exists()
    data = json.loads((out / "tables.json").read_text())
    assert data["success_by_planner"][0]["planner"] == "heuristic"
    html = (out / "report.html").read_text()
    assert "<table" in html and "src='data:image/png;base64," in html
    assert "Data: simulation (this tool&#x27;s numerical model)" in html
    assert (out / "figures" / "fig16_ablation.png").exists()
    assert "ablation/r1/report/report.html" in (tmp_path / "index.html").read_text()
    build_reports(["ablation"], root=tmp_path, formats=["md", "csv"])
    assert (out / "report.md").exists() and (out / "tables" / "success_by_planner.csv").exists()
    assert "ablation/r1/report/report.md" in (tmp_path / "index.md").read_text()


def test_an_html_report_keeps_every_run_in_the_markdown_index(tmp_path):
    """Each index page lists the runs with a report page of its format: an HTML report of one
    run had rewritten index.md with the HTML runs only; the command names every page written."""
    write_run(tmp_path, run="r1"), write_run(tmp_path, run="r2")
    build_reports(["ablation"], run="r2", root=tmp_path)
    result = cli.invoke(app, ["report", "ablation", "--run", "r1", "--root", str(tmp_path),
                              "--format", "md,html"])
    assert result.exit_code == 0, result.output
    md, html = (tmp_path / "index.md").read_text(), (tmp_path / "index.html").read_text()
    assert "ablation/r1/report/report.md" in md and "ablation/r2/report/report.md" in md
    assert "ablation/r1/report/report.html" in html and "r2/report" not in html
    assert result.stdout.splitlines() == [
        f"{page}: {tmp_path / path} (and .html)" for page, path in (
            ("report", "ablation/r1/report/report.md"), ("index", "index.md"),
            ("headline", "headline.md"))]
    result = cli.invoke(app, ["report", "ablation", "--run", "r1", "--root", str(tmp_path),
                              "--format", "json"])
    assert result.stdout.splitlines() == [
        f"report: {tmp_path / 'ablation/r1/report/tables.json'}",
        f"index: {tmp_path / 'index.md'}", f"headline: {tmp_path / 'headline.md'}"]


def test_the_header_states_the_design_the_run_ran(tmp_path):
    """A reduced run (overrides) is told apart from the study's full design: the header lists the
    levels its manifest's config holds, counted beyond four."""
    store = write_run(tmp_path, planners=("heuristic", "random", "antipodal", "centroid", "no_pso"))
    build_reports(["ablation"], root=tmp_path)
    md = report_md(store)
    assert "- **Design:** shape sphere; planner (5 levels); seeds 10\n" in md


def test_unknown_format_is_bad_input_and_writes_nothing(tmp_path):
    store = write_run(tmp_path)
    with pytest.raises(UserInputError, match="unknown report format 'pdf'; choose from md, csv"):
        build_reports(["ablation"], root=tmp_path, formats=["md", "pdf"])
    with pytest.raises(UserInputError, match="unknown figure format 'gif'; choose from png, "
                                             "svg, pdf."):
        build_reports(["ablation"], root=tmp_path, figure_format="gif")
    assert not (store.path / "report").exists() and not (tmp_path / "index.md").exists()
    assert check_formats("md, CSV,md") == ["md", "csv"]


@pytest.mark.parametrize("figure_format", ["png", "svg", "pdf"])
def test_every_figure_of_an_html_page_zooms_to_full_size_within_the_page(tmp_path, figure_format):
    """The page fits each figure to its width (Fig. 19's three panels at about half size, their tick
    labels unreadable at 1280 px): a click on each image toggles it to full size by a checkbox and its
    label (one per figure, ids unique), with no link out of the self-contained page."""
    import re

    write_run(tmp_path)
    build_reports(["ablation"], root=tmp_path, formats=["md", "html"], figure_format=figure_format)
    page = (tmp_path / "ablation" / "r1" / "report" / "report.html").read_text()
    toggles = re.findall(r"<figure id='([^']+)'><input type='checkbox' class='zoom' id='([^']+)' "
                         r"aria-label='[^']+'><label for='([^']+)'[^>]*><img ", page)
    assert len(toggles) == page.count("<figure ") > 0
    assert all(box == target == f"zoom-{anchor}" for anchor, box, target in toggles)
    assert len({box for _, box, _ in toggles}) == len(toggles)
    assert ".zoom:checked+label img{max-width:none" in page and "href='figures/" not in page


def test_cli_format_and_figure_format_options(tmp_path):
    write_run(tmp_path)
    bad = cli.invoke(app, ["report", "ablation", "--root", str(tmp_path), "--format", "pdf"])
    assert bad.exit_code == 2
    good = cli.invoke(app, ["report", "ablation", "--run", "r1", "--root", str(tmp_path), "--format",
                            "md,json,html", "--figure-format", "svg"])
    assert good.exit_code == 0, good.output
    out = tmp_path / "ablation" / "r1" / "report"
    assert (out / "tables.json").exists() and (out / "figures" / "fig16_ablation.svg").exists()
    assert "src='data:image/svg+xml;base64," in (out / "report.html").read_text()
    pdf = cli.invoke(app, ["report", "ablation", "--run", "r1", "--root", str(tmp_path),
                           "--figure-format", "pdf"])
    assert pdf.exit_code == 0 and (out / "figures" / "fig16_ablation.pdf").read_bytes()[:4] \
        == b"%PDF"
    assert "[fig16_ablation (PDF)](figures/fig16_ablation.pdf)" in (out / "report.md").read_text()


def test_errored_trials_enter_no_denominator(tmp_path):
    # trials 0-9 are the heuristic's (the seed axis is innermost)
    store = write_run(tmp_path, error_rows=(0, 2))
    build_reports(["ablation"], root=tmp_path)
    table = pd.read_csv(store.path / "report" / "tables" / "success_by_planner.csv")
    row = table.set_index("planner").loc["heuristic"]
    assert (row["n"], row["n_error"], row["successes"]) == (8, 2, 7)
    low, high = proportion_confint(7, 8, method="wilson")  # statsmodels reference
    assert (row["wilson_low_pct"], row["wilson_high_pct"]) == pytest.approx((100 * low, 100 * high))
    md = report_md(store)
    assert "20 recorded of 20; 18 executed; 2 errored, excluded from every denominator" in md


def test_report_never_runs_a_trial(tmp_path, monkeypatch):
    import graspcampaign.campaign.kind as kind_module
    import graspcampaign.campaign.runner as runner_module

    def forbidden(*args, **kwargs):
        raise AssertionError("the report ran a trial")

    monkeypatch.setattr(runner_module, "run_task", forbidden)
    monkeypatch.setattr(kind_module, "KINDS", {})
    write_run(tmp_path)
    assert build_reports(root=tmp_path)[0].exists()


def test_two_reports_of_the_same_records_give_identical_tables(tmp_path):
    store = write_run(tmp_path, name="baseline_grid", planners=("heuristic", "antipodal"))
    tables = store.path / "report" / "tables"
    build_reports(["baseline_grid"], root=tmp_path, formats=["csv", "json"])
    first = {p.name: p.read_bytes() for p in tables.iterdir()}
    first["json"] = (store.path / "report" / "tables.json").read_bytes()
    build_reports(["baseline_grid"], root=tmp_path, formats=["csv", "json"])
    second = {p.name: p.read_bytes() for p in tables.iterdir()}
    second["json"] = (store.path / "report" / "tables.json").read_bytes()
    assert first == second and len(first) > 5


def test_headline_page_and_index(tmp_path):
    write_run(tmp_path, name="baseline_grid", planners=("heuristic", "antipodal", "random"),
              n_success={"heuristic": 6, "antipodal": 4, "random": 1})
    write_run(tmp_path, name="other", kind="no_section_kind", planners=("heuristic",))
    build_reports(root=tmp_path, formats=["md", "csv", "html"])
    rows = pd.read_csv(tmp_path / "headline.csv").set_index("headline")
    grid = rows.loc["Baseline grid"]
    assert (grid["n"], grid["rate_pct"], grid["paper_pct"]) == (10, 60.0, 67.6)
    assert grid["ours_baselines"] == "antipodal 40.0%, random 10.0%"
    assert grid["paper_baselines"] == "antipodal 40.0%, random 11.0%, centroid 0.0%"
    assert grid["verdict"] == "consistent (\u22127.6 pp): paper inside our 95% CI"
    assert rows.loc["Heuristic ablation", "verdict"] == "no records yet"
    assert rows.loc["Heuristic ablation", "paper_pct"] == 72.0  # from campaigns/ablation.yaml
    md = (tmp_path / "headline.md").read_text()
    assert "simulation: 10 seeds" in md and "[r1](baseline_grid/r1/report/report.md)" in md
    assert "virtual rig" not in md.lower()  # no row is the virtual rig's: no note about them
    assert "rows differ from the paper" not in md  # the one row with records is consistent
    assert "href='baseline_grid/r1/report/report.html'" in (tmp_path / "headline.html").read_text()
    index = (tmp_path / "index.md").read_text()
    assert "[Table 1 headline](headline.md)" in index and "other/r1/report/report.md" in index


def test_the_headline_gives_the_n_the_papers_table_1_prints_for_every_row(tmp_path):
    """Table 1 (paper.txt) prints every row's n: 50, 675, 465 (validation groups A/B/D), 819, 740
    (natural-friction envelope), 830. The nominal and natural-μ rows printed "—" under "paper n", as if
    the paper gave none, beside our 465 and 740 trials of the same sub-populations."""
    from graspcampaign.report.headline import headline_rows, write_headline

    frame = headline_rows(tmp_path)
    assert frame.set_index("headline")["n_paper"].to_dict() == {
        "Heuristic ablation": 50, "Baseline grid": 675, "Grasp validation, nominal": 465,
        "Grasp validation, all": 819, "Disturbance, natural μ": 740, "Disturbance, all": 830}
    write_headline(tmp_path, ["md"], frame)
    md = (tmp_path / "headline.md").read_text()
    assert "| Grasp validation, nominal | — | — | 86.5 | 465 |" in md
    # Table 1 prints "∼86%": the paper's approximate value as it prints it, not as 86.0
    assert "| Disturbance, natural μ | — | — | ≈ 86 | 740 |" in md
    assert frame.set_index("headline").loc["Disturbance, natural μ", "paper_pct"] == 86.0  # judged as before


def test_the_headline_links_only_a_report_written(tmp_path):
    # the headline summarises every run under the root from its records; it linked the report of a
    # run never reported (`report baseline_grid --run r1` beside r2): a dead link
    for run in ("r1", "r2"):
        write_run(tmp_path, name="baseline_grid", planners=("heuristic", "antipodal"), run=run)
    build_reports(["baseline_grid"], run="r1", root=tmp_path)
    assert not (tmp_path / "baseline_grid" / "r2" / "report").exists()
    page = (tmp_path / "headline.md").read_text().splitlines()
    rows = [line for line in page if line.startswith("| Baseline grid |")]
    assert [row.split(" | ")[2] for row in rows] == ["[r1](baseline_grid/r1/report/report.md)", "r2"]


def test_the_index_pages_read_no_run_again(tmp_path, opened):
    # a run's source comes from the facts its check kept of each records file: the file is opened
    # to verify it and once for its report, no more (was once more for each index page)
    write_run(tmp_path / "results", name="other", kind="no_section_kind", planners=("heuristic",))
    build_reports(root=tmp_path / "results", formats=["md", "html"])
    assert opened == {"other/r1/records/part-aaaaaaaaaa.parquet": 2}
    assert "| other | [r1](other/r1/report/report.md) | simulation | 10 |" in \
        (tmp_path / "results" / "index.md").read_text()


def test_a_report_lists_the_results_root_once(tmp_path, monkeypatch):
    # was three times: to check it can be listed, that it holds no run, and for its studies
    write_run(tmp_path, run="r1")
    listed, real = [], os.listdir
    monkeypatch.setattr(os, "listdir", lambda path=".": (listed.append(Path(path)), real(path))[1])
    assert len(build_reports(root=tmp_path)) == 1
    assert listed.count(tmp_path) == 1


def test_the_headline_says_how_many_rows_differ_and_where_to_read_why(tmp_path):
    # the table alone said "differs by −67.6 pp" and no more: the page now points to the reports
    write_run(tmp_path, name="baseline_grid", n_success={"heuristic": 0, "random": 1})
    build_reports(root=tmp_path)
    rows = pd.read_csv(tmp_path / "headline.csv")
    low, high = proportion_confint(0, 10, method="wilson")  # 0 of 10: 0.0-27.8 %, not the paper's 67.6
    assert 67.6 > 100 * high and rows["n"].gt(0).sum() == 1
    # of the one row compared: the other rows have no records (it read "1 of 6 rows differ")
    assert ("1 of 1 compared row differs from the paper (the paper's value outside our 95% interval); "
            "each run's report, linked in *run*, opens with where and why.") in \
        (tmp_path / "headline.md").read_text()


def test_virtual_rig_rows_say_so(tmp_path):
    # the Test 2 section needs the full protocol columns; the headline needs only these
    write_run(tmp_path, name="test2_grasp", kind="no_section_kind", source="virtual",
              aborted_rows={0, 15})
    build_reports(["test2_grasp"], root=tmp_path)
    rows = pd.read_csv(tmp_path / "headline.csv").set_index("headline")
    assert rows.loc["Grasp validation, all", "testbed"].startswith("VIRTUAL RIG")
    assert "Rows from the virtual rig are synthetic data, not hardware results." in \
        (tmp_path / "headline.md").read_text()
    # trials 0-9 are the heuristic's (the seed axis is innermost): one aborted, one random one
    assert rows.loc["Grasp validation, all", ["n", "n_aborted", "rate_pct"]].tolist() == \
        [9, 1, pytest.approx(700 / 9)]
    assert rows.loc["Grasp validation, nominal", "verdict"] == \
        "the records lack the `group` column this sub-population needs"


def test_one_broken_run_never_stops_the_others(tmp_path):
    write_run(tmp_path, run="good")
    broken = write_run(tmp_path, run="broken")
    broken.manifest_path.write_text("{not json")
    result = cli.invoke(app, ["report", "--root", str(tmp_path)])
    assert result.exit_code == 2
    assert (tmp_path / "ablation" / "good" / "report" / "report.md").exists()
    assert (f"error: the report of ablation/broken could not be written: run ablation/broken at "
            f"{broken.path} has a damaged manifest.json (not valid JSON: Expecting property name "
            "enclosed in double quotes (line 1, column 2))") in result.output.replace("\n", "")
    assert (tmp_path / "index.md").exists() and (tmp_path / "headline.md").exists()


def test_a_run_whose_every_trial_errored_is_reported_with_reasons(tmp_path):
    store = write_run(tmp_path, error_rows=set(range(20)))
    result = cli.invoke(app, ["report", "ablation", "--run", "r1", "--root", str(tmp_path)])
    assert result.exit_code == 0, result.output
    table = pd.read_csv(store.path / "report" / "tables" / "success_by_planner.csv")
    assert table["rate_why"].tolist() == ["no executed trial"] * 2
    assert table["n_error"].tolist() == [10, 10]
    md = report_md(store)
    assert "| proposed H(G) | Algorithm 2 (paper) | 72.0 | no executed trial |" in md  # law by planner
    assert "20 recorded of 20; 0 executed; 20 errored" in md
    errors = pd.read_csv(store.path / "report" / "tables" / "errors.csv")
    assert set(errors["error_message"]) == {"bad"}


def test_a_mistyped_paper_block_of_an_old_run_falls_back_to_the_study_file(tmp_path):
    store = write_run(tmp_path)
    manifest = json.loads(store.manifest_path.read_text())
    manifest["config"]["paper"]["sucess_pct"] = manifest["config"]["paper"].pop("success_pct")
    manifest["config_hash"] = config_digest(manifest["config"])  # as that run hashed its config
    store.manifest_path.write_text(json.dumps(manifest))
    build_reports(["ablation"], root=tmp_path)
    md = report_md(store)
    assert ("this run's paper block does not match the current schema (the run's paper "
            "block.sucess_pct is not a known key") in md
    table = pd.read_csv(store.path / "report" / "tables" / "success_by_planner.csv")
    assert table["paper_pct"].tolist() == [72.0, 6.0]


def test_a_measured_run_filled_with_virtual_exports_is_labelled_virtual(tmp_path):
    store = write_run(tmp_path, name="test2_grasp", kind="no_section_kind", source="virtual",
                      aborted_rows=set())
    manifest = json.loads(store.manifest_path.read_text())
    manifest["source"] = "measured"  # as `ingest` declares it
    store.manifest_path.write_text(json.dumps(manifest))
    build_reports(["test2_grasp"], root=tmp_path, formats=["md", "html"])
    md = report_md(store)
    assert "**Data source:** VIRTUAL RIG: synthetic data" in md
    assert "measured on hardware" not in (store.path / "report" / "report.html").read_text()
    rows = pd.read_csv(tmp_path / "headline.csv").set_index("headline")
    assert rows.loc["Grasp validation, all", "source"] == "virtual"


@pytest.mark.slow  # starts loky workers: `make test-slow`
def test_reports_written_in_two_processes_are_the_files_written_one_by_one(tmp_path):
    """--jobs 2 writes each run's report in a worker: the same bytes, the same failures."""
    roots = [tmp_path / "one", tmp_path / "two"]
    write_run(roots[0], run="r1")
    write_run(roots[0], run="broken").manifest_path.write_text("{not json")
    shutil.copytree(roots[0], roots[1])
    one = cli.invoke(app, ["report", "--root", str(roots[0]), "--jobs", "1"])
    two = cli.invoke(app, ["report", "--root", str(roots[1]), "--jobs", "2"])
    assert one.exit_code == two.exit_code == 2
    assert one.output.replace(str(roots[0]), "ROOT") == two.output.replace(str(roots[1]), "ROOT")
    files = [{p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*"))
              if p.is_file()} for root in roots]
    assert "ablation/r1/report/report.md" in files[0]
    assert files[0] == files[1]


def test_the_headline_lists_a_runs_records_once_after_its_check(tmp_path, monkeypatch):
    # was twice: reading the records' columns and asking their data source each listed the files
    from graspcampaign.campaign.records import RunStore
    from graspcampaign.report import headline

    write_run(tmp_path, name="baseline_grid", planners=("heuristic", "random"),
              n_success={"heuristic": 6, "random": 1})
    listed, listing, check = [], RunStore.listing, RunStore.check
    monkeypatch.setattr(RunStore, "listing", lambda self, part: (
        listed.append(part), listing(self, part))[1])
    monkeypatch.setattr(RunStore, "check", lambda self, *a, **k: (check(self, *a, **k), listed.clear())[0])
    rows = headline.headline_rows(tmp_path).set_index("headline")
    assert rows.loc["Baseline grid", "n"] == 10  # the run was read
    assert listed == ["records"]


def test_the_headline_reads_each_run_once_for_every_row_it_serves(tmp_path, monkeypatch):
    # Test 2 and Test 3 each serve two Table 1 rows; each row checked and read its run again
    from graspcampaign.report import headline

    for study in ("test2_grasp", "test3_disturbance"):
        write_run(tmp_path, name=study, kind="no_section_kind", source="virtual", aborted_rows={0})
    calls, check, read = [], RunStore.check, RunStore.read_records
    monkeypatch.setattr(RunStore, "check", lambda self, *a, **k: (
        calls.append(("check", self.path.parent.name)), check(self, *a, **k))[1])
    monkeypatch.setattr(RunStore, "read_records", lambda self, *a, **k: (
        calls.append(("read", self.path.parent.name)), read(self, *a, **k))[1])
    rows = headline.headline_rows(tmp_path).set_index("headline")
    assert sorted(calls) == [("check", "test2_grasp"), ("check", "test3_disturbance"),
                             ("read", "test2_grasp"), ("read", "test3_disturbance")]
    # each row is still its run's: the proposed planner's 10 trials but the one aborted
    assert rows.loc[["Grasp validation, all", "Disturbance, all"], "n"].tolist() == [9, 9]
    assert rows.loc["Disturbance, natural μ", "verdict"] == \
        "the records lack the `friction_level` column this sub-population needs"


def test_report_jobs_start_no_more_processes_than_runs(tmp_path, monkeypatch):
    """loky starts every process ``n_jobs`` asks for, whether or not a task comes for it: two runs
    reported with ``n_jobs=8`` ask it for two."""
    import joblib

    asked, Parallel = [], joblib.Parallel

    class Counted(Parallel):
        def __init__(self, n_jobs=None, **kw):
            asked.append(n_jobs)
            super().__init__(n_jobs=n_jobs, **kw)

    monkeypatch.setattr(joblib, "Parallel", Counted)
    for run in ("r1", "r2"):
        write_run(tmp_path, run=run)
    batch = build_reports(root=tmp_path, formats=["md"], n_jobs=8)
    assert asked == [2] and len(batch) == 2 and batch.failed == []


def test_a_sub_population_row_reads_its_column_beside_the_row_of_all(tmp_path):
    """Table 1's Test 2 rows read one run: the nominal row needs its ``group`` column though the
    row of all trials, read with it, does not. Groups A-E in turn over the heuristic's trials 0-9
    (A, B and D: trials 0, 1, 3, 5, 6 and 8), of which trials 0-6 succeed: 5 of 6 nominal."""
    write_run(tmp_path, name="test2_grasp", kind="no_section_kind", source="virtual", aborted_rows=set(),
              columns=lambda i: {"group": "ABCDE"[i % 5]})
    from graspcampaign.report import headline

    rows = headline.headline_rows(tmp_path).set_index("headline")
    assert rows.loc["Grasp validation, nominal", ["n", "rate_pct"]].tolist() == [6, pytest.approx(500 / 6)]
    assert rows.loc["Grasp validation, all", ["n", "rate_pct"]].tolist() == [10, pytest.approx(70.0)]
