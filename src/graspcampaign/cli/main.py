"""The ``graspcampaign`` command line (Typer).

Exit codes: 0 success, 1 trial errors occurred, 2 bad usage or bad input, 130 interrupted (Ctrl-C).
Errors are one sentence on stderr; ``--debug`` adds the traceback. Layers are imported inside
commands so that ``--help``, ``list``, ``show`` and ``status`` answer in well under a second.
Warnings of the layers are printed once each as ``warning: ...``; their loggers stay quiet
unless ``--debug``. The application, its shared options and checks are in
:mod:`graspcampaign.cli.app`; this module has the study, run and report commands, and
:mod:`graspcampaign.cli.hardware` the hardware and mesh ones.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Annotated

import typer

from graspcampaign.cli.app import (
    Overrides,
    RootOpt,
    RunOpt,
    StudyArg,
    app,
    check_root,
    compose,
    fail,
    file_path,
    guard,
    number,
    other_format,
    root_path,
    state,
    writable_stem,
)
from graspcampaign.cli.output import print_list


@app.command("list")
@guard
def list_cmd(
    names: Annotated[bool, typer.Option("--names", help="Print runnable study names only.")] = False,
    extensions: Annotated[bool, typer.Option(
        "--extensions", help="With --names: the studies the paper does not run (SPEC §8) instead "
                             "of the paper's studies.")] = False,
) -> None:
    """List the studies, their trial kinds, trial counts and whether they can run yet.

    Each study file is read directly (no Hydra); a broken file is listed with what is wrong.
    """
    if extensions and not names:  # it was passed over: the table of every study was printed
        fail("--extensions chooses which names --names prints (graspcampaign list --names "
             "--extensions: the studies the paper does not run); the table lists every study, "
             "each marked paper or extension in its 'of' column, so give --names with it or "
             "leave it out.")
    rows = _study_rows()
    if names:
        for name in _runnable(rows, extensions):
            typer.echo(name)
        return
    print_list(rows)


def _study_rows() -> list[dict]:
    from graspcampaign.campaign.catalog import study_row
    from graspcampaign.campaign.studycheck import check_conf
    from graspcampaign.campaign.studyfile import project_dirs, study_files
    from graspcampaign.errors import UserInputError

    def broken(name: str, why: str) -> dict:
        return {"study": name, "kind": "?", "trials": "?", "runnable": "broken", "extension": False,
                "description": why}

    conf = project_dirs()[0]  # a bad GRASPCAMPAIGN_HOME stops here: it is the command's error
    try:  # the group files every study composes with: one broken file is said once, not per study
        check_conf(conf)
    except UserInputError as exc:
        typer.echo(f"warning: every study is broken: {exc}", err=True)
        return [broken(name, str(exc)) for name in study_files()]
    rows = []
    for name, path in study_files().items():
        try:
            rows.append(study_row(path))
        except UserInputError as exc:
            rows.append(broken(name, str(exc)))
            typer.echo(f"warning: study {name} is broken: {exc}", err=True)
    return rows


def _runnable(rows: list[dict], extensions: bool) -> list[str]:
    """The paper's runnable studies (smoke aside), or with ``extensions`` the others."""
    # an extension waiting for its source run is listed: `make extensions` runs it after
    # the paper's studies, and its run names what is missing if that has not happened
    wanted = ("yes", "after") if extensions else ("yes",)
    return [row["study"] for row in rows if row["runnable"].startswith(wanted)
            and row["study"] != "smoke" and row["extension"] == extensions]


def _echo_summary(summary) -> None:
    """One line per run (trials, already recorded, ran, ok, errors, time, path), then its first errors."""
    from graspcampaign.core.words import counted

    typer.echo(
        f"{summary.study}/{summary.run}: {counted(summary.n_trials, 'trial')}, {summary.n_already} already "
        f"recorded, {summary.n_ran} ran ({summary.n_ok} ok, {counted(summary.n_error, 'error')}) in "
        f"{summary.wall_time_s:.1f} s -> {summary.path}"
    )
    for line in summary.errors[:5]:
        typer.echo(f"  error: {line}", err=True)


@app.command()
@guard
def show(study: StudyArg, overrides: Overrides = None, run: RunOpt = None,
         root: RootOpt = None) -> None:
    """Print a study's design, factor levels, trial count, progress and estimated time."""
    from graspcampaign.campaign.status import design_text

    check_root(root)
    typer.echo(design_text(compose(study, overrides, root), run, overrides or []))


@app.command("run")
@guard
def run_cmd(
    study: StudyArg,
    overrides: Overrides = None,
    run: RunOpt = None,
    root: RootOpt = None,
    allow_drift: Annotated[bool, typer.Option(help="Resume even if config or code changed.")] = False,
    fail_fast: Annotated[bool, typer.Option(help="Stop at the first trial error.")] = False,
    report: Annotated[bool, typer.Option(help="Write the study's report after the run.")] = False,
) -> None:
    """Run a study (resuming a run that already has records)."""
    from graspcampaign.campaign.runner import run_path, run_study

    check_root(root, write=True)
    cfg = compose(study, overrides, root)
    path = run_path(cfg, run)
    try:
        summary = run_study(cfg, run=run, allow_drift=allow_drift, fail_fast=fail_fast,
                            given=(study, overrides or []))
    except KeyboardInterrupt:
        _interrupted(cfg, path, study, overrides, run, root)
    _echo_summary(summary)
    if report:
        _report_paths(_reports([cfg.name], run=summary.run, root=cfg.output.root))
    if summary.n_error:
        raise typer.Exit(1)


@app.command()
@guard
def reproduce(
    root: RootOpt = None,
    times: Annotated[Path | None, typer.Option(
        help="Also append each step's '== <step>: <s> s' line to this file.",
        parser=file_path("--times", "a file such as", "reproduce_times.txt", makes_dirs=True),
        metavar="path")] = None,
) -> None:
    """Run every study of `list --names` at paper scale, then write every report.

    The studies run in this one process, so the workers and their caches serve every study; the
    reports are written one process per core. Prints each step's wall time; stops at the first
    study with a trial error (exit 1).
    """
    import time

    from graspcampaign.campaign.paths import stored_root
    from graspcampaign.campaign.runner import run_path, run_study

    check_root(root, write=True)
    if times is not None:  # checked before the first study runs, not after it
        writable_stem(times, "--times", "a file such as", "reproduce_times.txt")
        if other_format(times, (".txt",)):  # lines of text, under a name saying CSV or JSON
            fail(f"--times {times}: reproduce appends lines of text ('== <step>: <s> s') to it, "
                 f"not {times.suffix}; give --times {times.with_suffix('.txt')}.")
        times.parent.mkdir(parents=True, exist_ok=True)

    def timed(step: str, start: float) -> None:
        line = f"== {step}: {time.perf_counter() - start:.0f} s"
        typer.echo(line)
        if times is not None:
            with times.open("a") as out:
                out.write(line + "\n")

    for name in _runnable(_study_rows(), extensions=False):
        start = time.perf_counter()
        cfg = compose(name, [], root)
        try:
            summary = run_study(cfg, given=(name, []))
        except KeyboardInterrupt:  # say what is recorded and how to resume, as `run` does
            _interrupted(cfg, run_path(cfg, None), name, [], None, root)
        _echo_summary(summary)
        if summary.n_error:
            raise typer.Exit(1)
        timed(name, start)
    start = time.perf_counter()
    batch = _reports(None, root=root or stored_root([]), n_jobs=1 if state["debug"] else -1)
    timed("report", start)
    _report_paths(batch)


def _interrupted(cfg, path: Path, study: str, overrides, run, root) -> None:
    """Ctrl-C: say what is recorded and how to resume; exit 130."""
    from graspcampaign.campaign.paths import run_command
    from graspcampaign.campaign.status import recorded_in, study_size

    try:
        done = f"{recorded_in(cfg, run)} of {study_size(cfg)} trials"
    except Exception:  # noqa: BLE001  (a second Ctrl-C or a shard in flight: say less)
        done = "the trials finished so far"
    typer.echo(f"interrupted: {done} are recorded in {path}; resume with: "
               f"{run_command(study, overrides or [], run or None, root)}", err=True)
    raise typer.Exit(130)


@app.command()
@guard
def status(
    study: Annotated[str, typer.Argument(help="Study name.", show_default=False)],
    run: RunOpt = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
    root: RootOpt = None,
) -> None:
    """Summarise a run from its records only (never runs anything)."""
    from graspcampaign.campaign.paths import stored_root
    from graspcampaign.campaign.status import run_status
    from graspcampaign.campaign.studyfile import configured_output

    root = stored_root([study]) if root is None else root
    info = run_status(root, study, configured_output(study, "run") if run is None else run)
    if as_json:
        typer.echo(json.dumps(info, indent=2, default=str))
        return
    for key, value in info.items():
        typer.echo(f"{key}: {value}")


@app.command()
@guard
def report(
    studies: Annotated[list[str] | None, typer.Argument(
        help="Studies (default: every run of every study under the root).")] = None,
    run: RunOpt = None,
    root: Annotated[Path | None, typer.Option(
        help="Results root (default: the studies' output.root, i.e. results).", parser=root_path,
        metavar="path")] = None,
    fmt: Annotated[str, typer.Option("--format", help="Comma-separated: md,csv,json,html.")] = "md,csv",
    figure_format: Annotated[str, typer.Option("--figure-format", help="png, svg or pdf.")] = "png",
    jobs: Annotated[int, typer.Option(
        "--jobs", help="Processes writing the runs' reports (-1: one per core; --debug: 1).",
        parser=number("--jobs", int), metavar="<int>")] = 1,
) -> None:
    """Write reports (Markdown, CSV tables, figures, HTML) from the records; never runs a trial.

    With studies and no `--run`, each study's configured run (its `output.run`) is reported.
    """
    from graspcampaign.campaign.paths import check_name, stored_root
    from graspcampaign.campaign.schema import WORKERS_PER_CORE, most_workers
    from graspcampaign.campaign.status import check_known
    from graspcampaign.campaign.studyfile import configured_output

    root = stored_root(studies or []) if root is None else root
    if run is not None:
        check_name(run, "--run")
    for study in studies or []:
        check_known(root, study)
    if jobs == 0 or jobs < -1:
        fail(f"--jobs {jobs}: give a number of processes (1 or more), or -1 for one per core.")
    cores, most = most_workers()
    if jobs > most:  # as runner.n_jobs
        from graspcampaign.core.words import counted

        fail(f"--jobs {jobs}: more than {WORKERS_PER_CORE} processes per core of this machine "
             f"({counted(cores, 'core')}); give at most {most}, or -1 for one per core.")
    # one batch: every named study and run is checked before any report is written
    runs = {s: configured_output(s, "run") if run is None else run for s in studies} if studies else run
    _report_paths(_reports(studies or None, run=runs, root=root, formats=fmt.split(","),
                                figure_format=figure_format, n_jobs=1 if state["debug"] else jobs))


def _reports(*args, **kwargs):
    """``report.build.build_reports(*args, **kwargs)``; a Ctrl-C said as what it leaves, exit 130
    (every file of a report is written whole, then put in place: ``paths.write_file``)."""
    from graspcampaign.report.build import build_reports

    try:
        return build_reports(*args, **kwargs)
    except KeyboardInterrupt:
        typer.echo("interrupted: each report file written so far is whole (written in full, then put "
                   "in place) and the rest are not written; run the command again to write them.",
                   err=True)
        raise typer.Exit(130) from None


def _report_paths(batch) -> None:
    """Print the written reports and root pages (an HTML page beside its Markdown one), each report
    with the items whose code failed (their notes say why); name every run whose report failed.
    Exit non-zero if a report or an item failed (decisions.md, "A report's items that failed")."""
    html = "html" in batch.formats
    for label, path in [*(("report", p) for p in batch), *((p.stem, p) for p in batch.pages)]:
        if path.suffix == ".md" or path.with_suffix(".md") not in batch.pages:  # a page once
            items, titles = batch.broken.get(path, (0, []))
            failed = (f" ({len(titles)} of {items} items failed: {', '.join(titles)}; their notes in "
                      "the report say why)" if titles else "")
            typer.echo(f"{label}: {path}{' (and .html)' if html and path.suffix == '.md' else ''}{failed}")
            if path in batch.in_progress:  # another process is recording the run: exit 0 all the same
                typer.echo(f"  run in progress: {batch.in_progress[path]}")
    for label, why, _ in batch.failed:
        typer.echo(f"error: the report of {label} could not be written: {why}", err=True)
    broken = any(titles for _, titles in batch.broken.values())
    if batch.failed or broken:
        raise typer.Exit(1 if broken or not all(bad for *_, bad in batch.failed) else 2)


from graspcampaign.cli import hardware  # noqa: E402, F401  (registers schedule, ingest, plan after these)


def main() -> None:
    """Console-script entry point.

    A Ctrl-C inside a command is said by the command (``app.guard``, or a run's own message), and
    Typer turns one anywhere else in its command into a silent exit 130; a Ctrl-C before that (as
    Typer builds the commands, a few milliseconds of each start, or answers a completion request)
    reaches this function, which says it in the same words rather than print a traceback.
    """
    try:
        app()
    except KeyboardInterrupt:
        typer.echo("interrupted (Ctrl-C).", err=True)
        sys.exit(130)


if __name__ == "__main__":
    main()
