"""Command line: exit codes, one-sentence errors, nothing written on bad input."""

from __future__ import annotations

import json
import math
import re
import shutil
from pathlib import Path

import pytest
from cli_checks import grid_run, invoke, runner


def test_list_shows_every_study_and_runnability():
    result = invoke("list")
    assert result.exit_code == 0
    for study in ("smoke", "baseline_grid", "test2_grasp", "surrogate"):
        assert study in result.stdout
    from graspcampaign.campaign.kind import KINDS

    assert ("not yet" in result.stdout) == any(v is None for v in KINDS.values())


def test_list_separates_the_papers_studies_from_the_extensions(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # no results/: dynamic_check's source run does not exist
    listing = invoke("list")
    assert listing.exit_code == 0 and "broken" not in listing.output
    row = next(line for line in listing.stdout.splitlines() if "dynamic_check" in line)
    assert "after baseline_grid" in row and "extension" in row
    paper = invoke("list", "--names").stdout.split()
    extensions = invoke("list", "--names", "--extensions").stdout.split()
    # make reproduce runs the first list, make extensions the second (after baseline_grid)
    assert {"baseline_grid", "test1_bench", "friction_mass"} <= set(paper)
    assert extensions == ["dynamic_check", "grip_laws"], "a study file with `extension: true` is listed here"
    assert "smoke" not in paper and not set(paper) & set(extensions)


def test_show_prints_design_without_running(tmp_path):
    result = invoke("show", "smoke", "nodes=[144]", f"output.root={tmp_path}")
    assert result.exit_code == 0, result.output
    assert "= 5 trials" in result.stdout
    assert "(0 of 5 recorded)" in result.stdout
    assert "estimated time" in result.stdout
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("override", "message"),
    [
        ("+factors.mass_kg=[-0.2]", r"factors\.mass_kg\[0\] = -0\.2 is out of range; allowed: >= 0\.0001"),
        ("+factors.mu=[-0.1]", r"factors\.mu\[0\] = -0\.1 is out of range; allowed: >= 0 and <= 3 "),
        ("nodes=[5]", r"factors\.nodes\[0\] = 5 is out of range; allowed: >= 12"),
        ("seeds=0", r"seeds = 0 is out of range; allowed: >= 1"),
        ("+factors.planner=[telepathy]", r"factors\.planner\[0\] has unknown value 'telepathy'; "
                                         r"allowed values: heuristic"),
        ("shape=[cube]", r"factors\.shape\[0\] has unknown value 'cube'; allowed values: sphere, "
                         r"ellipsoid, rounded_cube, pear, handle\.$"),
        ("colour=red", r"colour is neither a known key of the study config nor a factor of this study "
                       r"\(factors: nodes, shape\); override rejected\.$"),
        ("mu=[0.3]", r"mu is not a factor of this study \(override 'mu=\[0\.3\]' rejected; its factors: "
                     r"nodes, shape\), and the mesh_features kind does not read it \(it reads shape, "
                     r"nodes\)\.$"),
        ("model.lambda1=soft", r"model\.lambda1 must be a number, got 'soft'\.$"),
        ("seeds=abc", r"seeds must be a whole number, got 'abc'\.$"),
        ("evaluator.n_cand=1.5", r"evaluator\.n_cand must be a whole number, got 1\.5\.$"),
        ("runner.backend=spark", r"runner\.backend has unknown value 'spark'; allowed values: loky"),
        ("+factors.flavour=[1]", r"factors\.flavour is not a known factor; known factors:"),
        ("nodes=[144", r"cannot parse override 'nodes=\[144'"),
        ("mu", r"cannot parse override 'mu': expected key=value, e\.g\. mu=0\.3\.$"),
    ],
)
def test_bad_overrides_exit_2_naming_the_key_and_write_nothing(tmp_path, override, message):
    for command in ("run", "show"):
        result = invoke(command, "smoke", override, f"output.root={tmp_path}")
        assert result.exit_code == 2, result.output
        assert re.match(r"error: " + message, result.stderr), result.stderr
        assert result.stderr.count("\n") == 1  # one sentence, no traceback
    assert not any(tmp_path.iterdir())


def test_unknown_study_is_bad_input():
    result = invoke("run", "warp_drive")
    assert result.exit_code == 2
    assert "unknown study 'warp_drive'; available studies: ablation" in result.stderr


def test_not_yet_runnable_study_is_refused_and_writes_nothing(tmp_path, monkeypatch):
    from graspcampaign.campaign import kind

    monkeypatch.setitem(kind.KINDS, "test3_disturbance", None)  # as before its kind existed
    listing = invoke("list")
    assert "not yet" in listing.stdout
    result = invoke("run", "test3_disturbance", f"output.root={tmp_path}")
    assert result.exit_code == 2
    assert "trial kind 'test3_disturbance' is not implemented yet" in result.stderr
    assert not any(tmp_path.iterdir())


def test_run_status_and_report_smoke(tmp_path):
    args = ("smoke", "nodes=[144]", "runner.backend=sequential", f"output.root={tmp_path}")
    result = invoke("run", *args)
    assert result.exit_code == 0, result.output
    assert "5 trials, 0 already recorded, 5 ran (5 ok, 0 errors)" in result.stdout
    again = invoke("run", *args)
    assert "5 already recorded, 0 ran" in again.stdout
    status = invoke("status", "smoke", "--json", "--root", str(tmp_path))
    info = json.loads(status.stdout)
    assert info["n_ok"] == 5 and info["complete"] and info["source"] == "simulation"
    report = invoke("report", "smoke", "--root", str(tmp_path))
    assert report.exit_code == 0, report.output
    md = (tmp_path / "smoke" / "default" / "report" / "report.md").read_text()
    assert "Data source:** simulation" in md
    assert (tmp_path / "index.md").exists()


SMOKE = ["nodes=[144]", "runner.backend=sequential"]


@pytest.fixture(scope="module")
def smoke_run(tmp_path_factory):
    """One finished smoke run (5 shapes at 144 nodes) under its own results root."""
    root = tmp_path_factory.mktemp("smoke") / "results"
    result = invoke("run", "smoke", *SMOKE, "--root", str(root))
    assert result.exit_code == 0, result.output
    return root


def test_show_counts_only_the_overridden_design_as_recorded(smoke_run):
    # the run holds 5 trials (every shape); asking about two shapes counts two, at 144 nodes
    out = invoke("show", "smoke", "nodes=[144]", "shape=[sphere,pear]", "--root", str(smoke_run))
    assert "= 2 trials" in out.stdout and "(2 of 2 recorded)" in out.stdout
    assert "estimated time: 0 s for 0 trials" in out.stdout
    # a design the run never covered: nothing recorded, every trial still to run
    out = invoke("show", "smoke", "nodes=[390]", "--root", str(smoke_run))
    assert "(0 of 5 recorded)" in out.stdout and "for 5 trials" in out.stdout
    same = invoke("show", "smoke", "nodes=[144]", "--root", str(smoke_run))  # the run's config
    assert "(5 of 5 recorded)" in same.stdout and "estimated time: 0 s for 0 trials" in same.stdout
    full = invoke("show", "smoke", "--root", str(smoke_run))
    assert "(5 of 10 recorded)" in full.stdout and "for 5 trials" in full.stdout
    # ... and says that `run` would not add them to this run, in run's own words
    refused = invoke("run", "smoke", "--root", str(smoke_run))
    assert refused.exit_code == 2 and "factors.nodes [144] -> [144, 390]" in refused.stderr
    note = f"note: `run` would refuse: {refused.stderr.removeprefix('error: ')}"
    assert note in full.stdout
    assert "note:" not in same.stdout
    # the time per trial is the mean of the run's own records once it has some
    assert "each, mean of the trials recorded, on" in full.stdout
    # no Python reprs; run's sentence, checked above word for word, quotes its resume command's
    # overrides for a shell ('nodes=[144]', since 5eb09e5)
    assert "resume it as started (graspcampaign run smoke 'nodes=[144]'" in note
    shown = full.stdout.replace(note, "")
    assert "{" not in shown and "'" not in shown


def test_report_without_run_reports_the_configured_run(smoke_run, tmp_path):
    root = tmp_path / "results"
    shutil.copytree(smoke_run, root)
    shutil.copytree(root / "smoke" / "default", root / "smoke" / "other")
    result = invoke("report", "smoke", "--root", str(root))
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines() == [f"report: {root / 'smoke' / 'default' / 'report' / 'report.md'}",
                                          f"index: {root / 'index.md'}", f"headline: {root / 'headline.md'}"]
    assert not (root / "smoke" / "other" / "report").exists()


def test_every_link_of_an_html_report_goes_to_a_written_file(results):
    """``report --format html`` wrote ``headline.md`` too, linking ``report.md`` pages it never
    wrote, and the HTML headline linked ``report.html`` of a run reported as Markdown only."""
    page = grid_run(results) / "report" / "report.html"
    for study in ("smoke", "baseline_grid"):  # the grid run: Markdown, then no report, then HTML
        if study == "baseline_grid":
            shutil.rmtree(page.parent)
        before = {p: p.stat().st_mtime_ns for p in results.rglob("*") if p.is_file()}
        result = invoke("report", study, "--root", results, "--format", "html")
        assert result.exit_code == 0, result.output
        pages = [p for p in results.rglob("*.*") if p.suffix in (".md", ".html")]
        for written in [p for p in pages if before.get(p) != p.stat().st_mtime_ns]:
            links = re.findall(r"(?:href|src)='([^']*)'|\]\(([^)]*)\)", written.read_text(errors="replace"))
            for target in {a or b for a, b in links} - {""}:
                if not target.startswith(("#", "data:", "http")):
                    assert (written.parent / target.split("#")[0]).is_file(), f"{written}: {target}"
    assert result.stdout.splitlines() == [f"report: {page}", f"index: {results / 'index.md'} (and .html)",
                                          f"headline: {results / 'headline.md'} (and .html)"]


def test_a_markdown_report_keeps_the_earlier_html_root_pages_true(results):
    """After ``report --format html``, a Markdown-only report rewrote ``index.md`` and left
    ``index.html`` as it was: a run deleted since stayed linked there (a dead link) and the HTML
    headline kept the old numbers. The root pages an earlier report wrote are rewritten too."""
    assert invoke("report", "--root", results, "--format", "html").exit_code == 0
    shutil.rmtree(results / "smoke" / "default")  # a user removes a run they no longer need
    assert invoke("report", "baseline_grid", "--root", results).exit_code == 0
    for page in ("index.html", "headline.html", "index.md"):
        for target in re.findall(r"href='([^'#]*)'|\]\(([^)#]*)\)", (results / page).read_text()):
            target = "".join(target)
            assert not target or (results / target).is_file(), f"{page}: {target}"


def test_status_reads_the_configured_run(smoke_run):
    info = json.loads(invoke("status", "smoke", "--json", "--root", str(smoke_run)).stdout)
    assert (info["run"], info["n_recorded"], info["n_ok"], info["complete"]) == ("default", 5, 5,
                                                                                 True)


def test_a_study_file_of_ones_own_runs_by_path_and_on_the_search_path(tmp_path, monkeypatch):
    studies = tmp_path / "mine"
    studies.mkdir()
    text = (Path(__file__).parents[2] / "campaigns" / "smoke.yaml").read_text()
    # a copy keeps the paper comparison of the study it came from (compare_with)
    (studies / "my_smoke.yaml").write_text(
        text.replace("name: smoke", "name: my_smoke\ncompare_with: smoke"))
    root = tmp_path / "results"
    monkeypatch.chdir(tmp_path)
    by_path = invoke("run", "./mine/my_smoke.yaml", "shape=[sphere]", *SMOKE, "--root", str(root))
    assert by_path.exit_code == 0, by_path.output
    assert "my_smoke/default: 1 trial, 0 already recorded, 1 ran" in by_path.stdout
    monkeypatch.setenv("GRASPCAMPAIGN_PATH", str(studies))
    listing = invoke("list", "--names")
    assert "my_smoke" in listing.stdout.split()
    again = invoke("run", "my_smoke", "shape=[sphere]", *SMOKE, "--root", str(root))
    assert "1 already recorded, 0 ran" in again.stdout  # the same study, found by name


def test_progress_lines_without_a_terminal(tmp_path):
    result = invoke("run", "smoke", "shape=[sphere,pear]", *SMOKE, "runner.progress=true",
                    "runner.progress_interval_s=0", "runner.batch_size=1", "--root",
                     str(tmp_path))
    assert result.exit_code == 0, result.output
    lines = result.stderr.splitlines()
    assert len(lines) == 2, result.stderr  # one per task at interval 0, the last at 2/2
    assert re.fullmatch(r"smoke/default: 1/2 trials \(50%\), 0 failed, [0-9.]+ trials/s, "
                        r"ETA [0-9]+ s", lines[0]), lines[0]
    assert lines[1].startswith("smoke/default: 2/2 trials (100%), 0 failed, ")


def test_ctrl_c_says_what_is_recorded_and_how_to_resume(tmp_path, monkeypatch):
    from graspcampaign.campaign import runner as runner_module

    calls = []

    def advance(self, n, failed):  # Ctrl-C after the second task is recorded
        calls.append(n)
        if len(calls) == 2:
            raise KeyboardInterrupt

    monkeypatch.setattr(runner_module._Progress, "advance", advance)
    args = ["smoke", "shape=[sphere,pear,handle]", *SMOKE, "runner.batch_size=1"]
    result = invoke("run", *args, "--run", "try1", "--root", str(tmp_path))
    assert result.exit_code == 130
    assert result.stderr == (
        f"interrupted: 2 of 3 trials are recorded in {tmp_path / 'smoke' / 'try1'}; resume with: "
        f"graspcampaign run smoke 'shape=[sphere,pear,handle]' 'nodes=[144]' "
        f"runner.backend=sequential runner.batch_size=1 --run try1 --root {tmp_path}\n")
    monkeypatch.undo()
    resumed = invoke("run", *args, "--run", "try1", "--root", str(tmp_path))
    assert "3 trials, 2 already recorded, 1 ran" in resumed.stdout


def test_schedule_template_has_every_column_and_its_unit(tmp_path):
    import pandas as pd

    from graspcampaign.rig.record_schema import record_columns

    (tmp_path / "t3").mkdir()  # --out's directory must exist, as plan --png's
    result = invoke("schedule", "test3_disturbance", "params.fraction=0.05", "--template",
                    "--out", str(tmp_path / "t3" / "sheet"))
    assert result.exit_code == 0, result.output
    sheet = pd.read_csv(tmp_path / "t3" / "sheet.csv")
    fill = pd.read_csv(tmp_path / "t3" / "sheet-template.csv", keep_default_na=False)
    columns = pd.read_csv(tmp_path / "t3" / "sheet-template-columns.csv")
    assert list(fill.columns) == record_columns("test3_disturbance") == list(columns["column"])
    assert fill["trial_id"].tolist() == sheet["trial_id"].tolist()
    assert (fill.drop(columns="trial_id") == "").all().all()
    assert set(columns["unit"]) == {"-", "1", "mm", "N", "N m", "deg"}
    bench = invoke("schedule", "test1_bench", "--template", "--out", str(tmp_path / "t1"),
                   "params.materials=[gel]", "params.specimens=[1]", "params.environments=[normal_lab]")
    assert bench.exit_code == 0, bench.output
    waves = pd.read_csv(tmp_path / "t1-template-columns.csv")
    assert waves["column"].tolist()[:6] == ["event_id", "time_s", "displacement_mm",
                                            "normal_force_n", "tangential_force_n",
                                            "tangential_displacement_mm"]
    assert waves["unit"].tolist()[:6] == ["-", "s", "mm", "N", "N", "mm"]


def test_help_is_quick_to_import_and_offers_completion():
    result = invoke("--help")
    assert result.exit_code == 0 and "--install-completion" in result.stdout


HEAVY = ("numpy", "pandas", "scipy", "trimesh", "numba", "matplotlib", "sklearn", "pyarrow",
         "hydra", "graspcampaign.core.mesh", "graspcampaign.core.planner")


@pytest.mark.parametrize(("args", "allowed"), [
    (["--help"], ()),
    (["list"], ()),
    (["show", "smoke"], ("hydra",)),
    (["show", "baseline_grid"], ("hydra",)),  # its paper block's planner keys: the vocabulary
    (["status", "smoke", "--root", "{root}"], ("pyarrow", "numpy")),  # pyarrow needs numpy
])
def test_answering_commands_import_no_numerical_layer(smoke_run, args, allowed):
    """`list`, `show`, `status`, `--help` answer fast because they import none of these
    (timed by benchmarks/bench_cli.py; here only what they import, which cannot flake)."""
    import subprocess
    import sys

    args = [a.format(root=smoke_run) for a in args]
    # warm the catalog cache of this test process first, as a user's second call would find it
    invoke(*args)
    code = ("import sys\nfrom graspcampaign.cli.main import app\n"
            f"try:\n    app({args!r}, standalone_mode=False)\nexcept SystemExit:\n    pass\n"
            f"print([m for m in {HEAVY!r} if m in sys.modules])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, f"exit {out.returncode}; stderr: {out.stderr[-2000:]}"
    imported = eval(out.stdout.strip().splitlines()[-1])  # noqa: S307  (our own print)
    assert set(imported) <= set(allowed), imported


def test_reproduce_runs_the_listed_studies_then_every_report(tmp_path, monkeypatch):
    """`reproduce` runs what `list --names` lists (here: a small smoke run) and then the reports,
    timing each step into --times."""
    from graspcampaign.cli import main

    compose = main.compose
    monkeypatch.setattr(main, "_runnable", lambda rows, extensions: ["smoke"])
    monkeypatch.setattr(main, "compose", lambda study, overrides, root=None: compose(
        study, [*overrides, "shape=[sphere]", "nodes=[144]", "runner.backend=sequential"], root))
    root, times = tmp_path / "results", tmp_path / "times"
    result = invoke("reproduce", "--root", str(root), "--times", str(times))
    assert result.exit_code == 0, result.output
    assert [line.split(":")[0] for line in times.read_text().splitlines()] == \
        ["== smoke", "== report"]
    assert (root / "smoke" / "default" / "report" / "report.md").exists()
    assert (root / "index.md").exists()


def test_list_fits_the_terminal_and_never_cuts_a_name(monkeypatch):
    """With COLUMNS=80 the table was 157 columns wide (a terminal's own narrow width cut names to
    "baseline_g…"): every line fits, each study and kind appears whole, the kind column gives way
    (``show`` prints it) where it would leave the description no room."""
    from cli_checks import runner

    from graspcampaign.campaign.studyfile import read_yaml, study_files
    from graspcampaign.cli.main import app

    kinds = {name: read_yaml(path)["kind"] for name, path in study_files().items()}
    for columns, with_kind in (("80", False), ("120", True)):
        monkeypatch.setenv("COLUMNS", columns)
        lines = runner.invoke(app, ["list"]).stdout.splitlines()
        assert max(map(len, lines)) <= int(columns)
        cells = [[c.strip() for c in line.split("│")[1:-1]] for line in lines if "│" in line]
        rows = {row[0]: row for row in cells if row[0]}
        assert set(rows) == set(kinds)
        # one line of description per study (it wrapped to five at 80 columns); show prints it whole
        assert sum(1 for row in cells if row[-1]) == len(kinds)
        header = [c.strip() for c in next(line for line in lines if "study" in line).split("┃")]
        assert ("kind" in header) == with_kind
        if with_kind:
            assert {name: row[1] for name, row in rows.items()} == kinds


def test_show_prints_the_overrides_after_the_description_it_changes():
    lines = invoke("show", "baseline_grid", "seeds=2", "mu=[0.3]").stdout.splitlines()
    assert lines[1].startswith("description: Sec. 6.5, Fig. 18: 5 shapes x 3 masses x 3 frictions")
    assert lines[2] == ("overrides: seeds=2 mu=[0.3] (the description is of the study file's "
                        "design; what follows is with them)")
    assert lines[3].startswith("trial kind: ")
    assert "axes: shape 5 x mass_kg 3 x mu 1 x planner 5 x seeds 2 = 150 trials" in lines
    assert not any(line.startswith("overrides:") for line in invoke("show", "smoke").stdout.splitlines())


def test_show_never_prints_an_empty_factors_heading():
    """A study without factors says `factors: none`; one with factors lists one per line."""
    names = invoke("list", "--names").stdout.split() + ["smoke"]
    names += invoke("list", "--names", "--extensions").stdout.split()
    for name in names:
        result = invoke("show", name)  # dynamic_check too, with or without its source run
        assert result.exit_code == 0, (name, result.output)
        lines = result.stdout.splitlines()
        at = next(i for i, line in enumerate(lines) if line.startswith("factors:"))
        listed = lines[at] == "factors:" and lines[at + 1].startswith("  ")
        assert listed or lines[at] == "factors: none", (name, lines[at:at + 2])
    assert "factors: none" in invoke("show", "surrogate").stdout


def test_show_names_every_design_axis():
    """The axes line read "5 x 2 x 1 x 3": which number is the seeds was left to guess."""
    out = invoke("show", "smoke", "seeds=4", "repeats=3").stdout
    axes = next(line for line in out.splitlines() if line.startswith("axes: "))
    names = re.findall(r"^  (\w+) \[(\d+)\]", out, flags=re.M)  # the factors as listed above it
    expected = [*(f"{name} {n}" for name, n in names), "seeds 4", "repeats 3"]
    total = 4 * 3 * math.prod(int(n) for _, n in names)
    assert axes == f"axes: {' x '.join(expected)} = {total} trials"
    assert invoke("show", "surrogate").stdout.count("axes: seeds 1500 = 1500 trials") == 1


def test_one_trial_is_counted_in_the_singular(tmp_path):
    """`show` of a one-trial study printed "= 1 trials" (and "for 1 trials"), `run` "1 trials"."""
    one = ["shape=[sphere]", "nodes=[144]", "runner.backend=sequential", "runner.n_jobs=1",
           "--root", str(tmp_path)]
    lines = invoke("show", "smoke", *one).stdout.splitlines()
    assert "axes: shape 1 x nodes 1 x seeds 1 = 1 trial" in lines
    estimate = next(line for line in lines if line.startswith("estimated time: "))
    # smoke's kind has no stage beside its trials: nothing is said not counted
    assert re.fullmatch(r"estimated time: \S+ m?s for 1 trial \(~\S+ m?s each, as the trial kind "
                        r"estimates, on 1 worker\)", estimate)
    ran = invoke("run", "smoke", *one)
    assert ran.exit_code == 0, ran.output
    assert ran.stdout.startswith("smoke/default: 1 trial, 0 already recorded, 1 ran (1 ok, 0 errors) in ")


def test_schedule_writes_the_files_it_checked_for_a_stem_with_a_dot(tmp_path):
    """`--out sched.v1` was checked as sched.v1.csv but written as sched.csv (Path.with_suffix replaced
    '.v1'): the files written are the ones named, and the message names the written file."""
    result = invoke("schedule", "test3_disturbance", "params.fraction=0.05",
                    "--out", str(tmp_path / "sched.v1"))
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sched.v1.csv", "sched.v1.parquet"]
    assert f"-> {tmp_path / 'sched.v1.csv'} and .parquet" in result.output


@pytest.mark.parametrize("name", ["sheet.csv", "sheet.parquet"])
def test_schedule_out_with_a_sheet_suffix_names_the_files_themselves(tmp_path, name):
    """`--out sheet.csv` wrote sheet.csv.csv and sheet.csv.parquet (the option takes a stem)."""
    import pandas as pd

    result = invoke("schedule", "test3_disturbance", "params.fraction=0.05", "--out",
                    str(tmp_path / name))
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sheet.csv", "sheet.parquet"]
    ids = pd.read_csv(tmp_path / "sheet.csv")["trial_id"]
    assert len(ids) > 0 and ids.tolist() == pd.read_parquet(tmp_path / "sheet.parquet")["trial_id"].tolist()


def test_every_commands_help_prints_each_docstring_paragraph_unbroken():
    # typer keeps a docstring's single line breaks: `reproduce --help` printed '... serve every
    # study; the' and 'reports are written ...' as two short lines (and a summary broken in two
    # across the command table, until each was one line)
    import inspect

    import typer

    from graspcampaign.cli.main import app

    for name, command in typer.main.get_command(app).commands.items():
        # wide enough for every paragraph on one line
        output = runner.invoke(app, [name, "--help"], env={"COLUMNS": "400"}).output
        lines = [" ".join(line.split()) for line in output.splitlines()]
        for paragraph in inspect.getdoc(command.callback).split("\n\n"):
            flowed = " ".join(paragraph.split())
            assert any(flowed in line for line in lines), (name, flowed)
