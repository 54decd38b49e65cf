"""The ``graspcampaign`` command line (Typer).

Exit codes: 0 success, 1 trial errors occurred, 2 bad usage or bad input, 130 interrupted (Ctrl-C).
Errors are one sentence on stderr; ``--debug`` adds the traceback. Layers are imported inside
commands so that ``--help``, ``list``, ``show`` and ``status`` answer in well under a second.
Warnings of the layers are printed once each as ``warning: ...``; their loggers stay quiet
unless ``--debug``.
"""

from __future__ import annotations

import errno
import json
import logging
import os
import shlex
import sys
import traceback
import warnings
from pathlib import Path
from typing import Annotated

import typer

from graspcampaign.cli.output import print_list, print_plan

app = typer.Typer(
    add_completion=True,
    no_args_is_help=True,
    help="Reproducible experiment campaigns for soft-object grasp planning.",
    pretty_exceptions_enable=False,
)
_state = {"debug": False}

StudyArg = Annotated[str, typer.Argument(help="Study name (see `list`) or path of a study file.",
                                         show_default=False)]
Overrides = Annotated[
    list[str] | None,
    typer.Argument(help="Hydra overrides, e.g. mu=[0.3] seeds=2 runner.n_jobs=2.", show_default=False),
]
RunOpt = Annotated[str | None, typer.Option("--run", help="Run name (default: the study's output.run).")]


def _path_or_empty(value: str) -> Path | str:
    """A path option's value, ``""`` kept as given (as a Path it would read as "."), so that an
    empty ``--root`` is refused instead of meaning the current directory."""
    return Path(value) if value else value


RootOpt = Annotated[Path | None, typer.Option("--root", help="Results root (default: output.root, "
                                                             "i.e. results).",
                                              parser=_path_or_empty, metavar="path")]

# ValueErrors from the core and rig layers that mean bad input (a mesh, an ingested file).
_INPUT_ERRORS = {"MeshError", "IngestError"}


def _fail(message: str, code: int = 2) -> None:
    typer.echo(f"error: {message}", err=True)
    raise typer.Exit(code)


def _guard(fn):
    """Turn bad-input exceptions into one sentence and exit 2 (traceback with --debug)."""
    import functools

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        from graspcampaign.errors import UserInputError

        try:
            return fn(*args, **kwargs)
        except typer.Exit:
            raise
        except (UserInputError, ValueError) as exc:
            if _state["debug"]:
                traceback.print_exc()
            if isinstance(exc, UserInputError) or type(exc).__name__ in _INPUT_ERRORS:
                _fail(str(exc))
            raise
        except OSError as exc:  # a full disk where no layer said so itself (a report's figure)
            if exc.errno not in (errno.ENOSPC, errno.EDQUOT):
                raise
            if _state["debug"]:
                traceback.print_exc()
            _fail(f"cannot write {exc.filename or 'a file'}: {os.strerror(exc.errno).lower()}; free "
                  "some space there and run the command again.")
    return wrapper


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Print a warning of the layers as one ``warning: ...`` line (no file, no line, no class)."""
    text = str(message)
    if text not in _shown:
        _shown.add(text)
        print(f"warning: {text}", file=sys.stderr)


_shown: set[str] = set()


@app.callback()
def _main(debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks and logs.")] = False):
    _state["debug"] = debug
    _shown.clear()
    package_log = logging.getLogger("graspcampaign")
    if debug:
        logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    elif not package_log.handlers:
        package_log.addHandler(logging.NullHandler())  # warnings reach the user once, below
    warnings.showwarning = _show_warning


def _configure(cfg, root: Path | None):
    """Apply ``--root`` to a composed study (where records go never changes a result)."""
    if root is not None:
        cfg.output.root = str(root)
    return cfg


def _check_root(root: Path | None, write: bool = False) -> None:
    """Refuse a bad ``--root`` (empty, a file, unwritable when ``write``) before any work."""
    if root is not None:
        from graspcampaign.campaign.paths import check_root

        check_root(root, "--root", write=write)


def _compose(study: str, overrides: list[str] | None, root: Path | None = None):
    from graspcampaign.campaign.compose import compose_study

    return _configure(compose_study(study, overrides or []), root)


@app.command("list")
@_guard
def list_cmd(
    names: Annotated[bool, typer.Option("--names", help="Print runnable study names only.")] = False,
    extensions: Annotated[bool, typer.Option(
        "--extensions", help="With --names: the studies the paper does not run (SPEC §8) instead "
                             "of the paper's studies.")] = False,
) -> None:
    """List the studies, their trial kinds, trial counts and whether they can run yet.

    Each study file is read directly (no Hydra); a broken file is listed with what is wrong.
    """
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
    typer.echo(
        f"{summary.study}/{summary.run}: {summary.n_trials} trials, {summary.n_already} already "
        f"recorded, {summary.n_ran} ran ({summary.n_ok} ok, {summary.n_error} errors) in "
        f"{summary.wall_time_s:.1f} s -> {summary.path}"
    )
    for line in summary.errors[:5]:
        typer.echo(f"  error: {line}", err=True)


@app.command()
@_guard
def show(study: StudyArg, overrides: Overrides = None, run: RunOpt = None,
         root: RootOpt = None) -> None:
    """Print a study's design, factor levels, trial count, progress and estimated time."""
    from graspcampaign.campaign.status import design_text

    _check_root(root)
    typer.echo(design_text(_compose(study, overrides, root), run))


@app.command("run")
@_guard
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

    _check_root(root, write=True)
    cfg = _compose(study, overrides, root)
    path = run_path(cfg, run)
    try:
        summary = run_study(cfg, run=run, allow_drift=allow_drift, fail_fast=fail_fast)
    except KeyboardInterrupt:
        _interrupted(cfg, path, study, overrides, run, root)
    _echo_summary(summary)
    if report:
        from graspcampaign.report.build import build_reports

        _report_paths(build_reports([cfg.name], run=summary.run, root=cfg.output.root))
    if summary.n_error:
        raise typer.Exit(1)


@app.command()
@_guard
def reproduce(
    root: RootOpt = None,
    times: Annotated[Path | None, typer.Option(
        help="Also append each step's '== <step>: <s> s' line to this file.")] = None,
) -> None:
    """Run every study of `list --names` at paper scale, then write every report (one process
    per core), in this one process: the workers and their caches serve every study.

    Prints each step's wall time; stops at the first study with a trial error (exit 1).
    """
    import time

    from graspcampaign.campaign.runner import run_path, run_study
    from graspcampaign.report.build import build_reports

    _check_root(root, write=True)
    if times is not None:  # checked before the first study runs, not after it
        _writable_stem(times, "--times", "a file such as", "reproduce_times.txt")
        times.parent.mkdir(parents=True, exist_ok=True)

    def timed(step: str, start: float) -> None:
        line = f"== {step}: {time.perf_counter() - start:.0f} s"
        typer.echo(line)
        if times is not None:
            with times.open("a") as out:
                out.write(line + "\n")

    for name in _runnable(_study_rows(), extensions=False):
        start = time.perf_counter()
        cfg = _compose(name, [], root)
        try:
            summary = run_study(cfg)
        except KeyboardInterrupt:  # say what is recorded and how to resume, as `run` does
            _interrupted(cfg, run_path(cfg, None), name, [], None, root)
        _echo_summary(summary)
        if summary.n_error:
            raise typer.Exit(1)
        timed(name, start)
    start = time.perf_counter()
    batch = build_reports(None, root=root or Path("results"), n_jobs=1 if _state["debug"] else -1)
    timed("report", start)
    _report_paths(batch)


def _interrupted(cfg, path: Path, study: str, overrides, run, root) -> None:
    """Ctrl-C: say what is recorded and how to resume; exit 130."""
    from graspcampaign.campaign.status import recorded_in, study_size

    try:
        done = f"{recorded_in(cfg, run)} of {study_size(cfg)} trials"
    except Exception:  # noqa: BLE001  (a second Ctrl-C or a shard in flight: say less)
        done = "the trials finished so far"
    again = ["graspcampaign", "run", study, *(overrides or [])]
    if run:
        again += ["--run", run]
    if root is not None:
        again += ["--root", str(root)]
    typer.echo(f"interrupted: {done} are recorded in {path}; resume with: "
               f"{shlex.join(again)}", err=True)
    raise typer.Exit(130)


@app.command()
@_guard
def status(
    study: Annotated[str, typer.Argument(help="Study name.", show_default=False)],
    run: RunOpt = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
    root: Annotated[Path, typer.Option(help="Results root.", parser=_path_or_empty,
                                       metavar="path")] = Path("results"),
) -> None:
    """Summarise a run from its records only (never runs anything)."""
    from graspcampaign.campaign.status import run_status
    from graspcampaign.campaign.studyfile import configured_run

    info = run_status(root, study, configured_run(study) if run is None else run)
    if as_json:
        typer.echo(json.dumps(info, indent=2, default=str))
        return
    for key, value in info.items():
        typer.echo(f"{key}: {value}")


@app.command()
@_guard
def report(
    studies: Annotated[list[str] | None, typer.Argument(
        help="Studies (default: every run of every study under the root).")] = None,
    run: RunOpt = None,
    root: Annotated[Path, typer.Option(help="Results root.", parser=_path_or_empty,
                                       metavar="path")] = Path("results"),
    fmt: Annotated[str, typer.Option("--format", help="Comma-separated: md,csv,json,html.")] = "md,csv",
    figure_format: Annotated[str, typer.Option("--figure-format", help="png, svg or pdf.")] = "png",
    jobs: Annotated[int, typer.Option(
        "--jobs", help="Processes writing the runs' reports (-1: one per core; --debug: 1).")] = 1,
) -> None:
    """Write reports (Markdown, CSV tables, figures, HTML) from the records; never runs a trial.

    With studies and no ``--run``, each study's configured run (its ``output.run``) is reported.
    """
    from graspcampaign.campaign.status import check_known
    from graspcampaign.campaign.studyfile import check_name, configured_run
    from graspcampaign.report.build import build_reports

    if run is not None:
        check_name(run, "--run")
    for study in studies or []:
        check_known(root, study)
    if jobs == 0 or jobs < -1:
        _fail(f"--jobs {jobs}: give a number of processes (1 or more), or -1 for one per core.")
    # one batch: every named study and run is checked before any report is written
    runs = {s: configured_run(s) if run is None else run for s in studies} if studies else run
    _report_paths(build_reports(studies or None, run=runs, root=root, formats=fmt.split(","),
                                figure_format=figure_format, n_jobs=1 if _state["debug"] else jobs))


def _report_paths(batch) -> None:
    """Print the written reports and root pages (an HTML page beside its Markdown one); name
    every run whose report failed and exit non-zero."""
    html = "html" in batch.formats
    for label, path in [*(("report", p) for p in batch), *((p.stem, p) for p in batch.pages)]:
        if path.suffix == ".md" or path.with_suffix(".md") not in batch.pages:  # a page once
            typer.echo(f"{label}: {path}{' (and .html)' if html and path.suffix == '.md' else ''}")
    _exit_if_failed(batch.failed)


def _exit_if_failed(failed) -> None:
    for label, why, _ in failed:
        typer.echo(f"error: the report of {label} could not be written: {why}", err=True)
    if failed:
        raise typer.Exit(2 if all(bad for _, _, bad in failed) else 1)


def _writable_stem(out: Path, option: str, hint: str = "a file stem such as",
                   example: str = "schedule") -> Path:
    """Check that files ``<out>.<ext>`` (or ``out``) can be written, before any work: a directory
    in its place, a file on its path or a directory that cannot be written is bad input."""
    from graspcampaign.campaign.paths import path_problem

    why = path_problem(out, write=True, directory=False)
    if why == "is a directory, not a file":
        _fail(f"{option} {out} is a directory; give {hint} {out / example}.")
    if why is not None:
        _fail(f"{option} {out}: {why}.")
    return out


@app.command()
@_guard
def schedule(
    study: StudyArg,
    overrides: Overrides = None,
    out: Annotated[
        Path | None, typer.Option(help="Output file stem (default: <root>/<study>/schedule).")
    ] = None,
    template: Annotated[bool, typer.Option(
        "--template", help="Also write the measured-records sheet to fill in (every column, empty, "
                           "with its unit in <stem>-template-columns.csv).")] = False,
    root: RootOpt = None,
) -> None:
    """Write a hardware protocol's commanded-trial sheet (CSV and Parquet)."""
    from graspcampaign.campaign.kind import get_kind
    from graspcampaign.campaign.runner import kind_params

    _check_root(root, write=out is None)
    cfg = _compose(study, overrides, root)
    kind = get_kind(cfg.kind)
    if kind.schedule is None:
        _fail(f"study {cfg.name!r} is a simulation study; only hardware protocols have a schedule.")
    stem = _writable_stem(out or Path(cfg.output.root) / cfg.name / "schedule", "--out")
    if out is not None and not out.parent.is_dir():  # as plan --png: a typo grows no tree
        _fail(f"--out {out}: directory {out.parent} does not exist.")
    params = kind_params(cfg, kind)
    sheet = kind.schedule(cfg, params)
    sheets = {"": sheet}
    if template:
        fill, columns = kind.template(cfg, params, sheet)
        sheets.update({"-template": fill, "-template-columns": columns})
    try:
        stem.parent.mkdir(parents=True, exist_ok=True)
        for suffix, table in sheets.items():
            path = stem.with_name(stem.name + suffix)
            table.to_csv(path.with_suffix(".csv"), index=False)
            if not suffix:
                table.to_parquet(path.with_suffix(".parquet"), index=False)
    except OSError as exc:  # permissions, a full disk
        _fail(f"--out {stem}: cannot write there ({exc.strerror or type(exc).__name__}).")
    typer.echo(f"{len(sheet)} commanded trials -> {stem.with_suffix('.csv')} and .parquet")
    if template:
        typer.echo(f"measured-records template -> {stem}-template.csv (columns and units: "
                   f"{stem}-template-columns.csv)")


@app.command()
@_guard
def ingest(
    study: StudyArg,
    files: Annotated[list[Path], typer.Argument(help="Measured records (CSV, XLSX or Parquet).")],
    run: Annotated[str, typer.Option("--run", help="Run that receives the measured records.")] = "measured",
    overrides: Annotated[list[str] | None, typer.Option("--set", help="Hydra override (repeatable).")] = None,
    root: RootOpt = None,
) -> None:
    """Validate measured records and store them as a run with source = measured."""
    from graspcampaign.campaign.ingest import ingest_files

    _check_root(root, write=True)
    cfg = _compose(study, overrides, root)
    n, path = ingest_files(cfg, [str(f) for f in files], run)
    typer.echo(f"{n} measured records stored in {path}")


@app.command()
@_guard
def plan(
    mesh: Annotated[Path, typer.Argument(help="Object mesh (STL, OBJ or PLY).")],
    mass_kg: Annotated[float, typer.Option("--mass-kg", help="Object mass [kg].")],
    material: Annotated[str | None, typer.Option(help="Table 4 material family.")] = None,
    mu: Annotated[float | None, typer.Option(help="Static friction; overrides the material's.")] = None,
    fingertip_radius_mm: Annotated[float, typer.Option("--fingertip-radius-mm")] = 5.0,
    unit: Annotated[str, typer.Option(help="Length unit of the mesh file: m, cm or mm.")] = "mm",
    png: Annotated[Path | None, typer.Option(
        help="Picture path, ending in .png (default: <mesh>.plan.png beside the mesh).")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
) -> None:
    """Plan a three-finger grasp on a mesh and predict the disturbances it resists."""
    from graspcampaign.rig.plan import PicturePathError, plan_mesh

    if not mesh.is_file():
        _fail(f"{mesh}: no such mesh file.")
    try:  # plan_mesh checks the picture path before any planning work
        result = plan_mesh(mesh, mass_kg=mass_kg, material=material, mu=mu,
                           fingertip_radius_mm=fingertip_radius_mm, unit=unit,
                           png_path=mesh.with_suffix(".plan.png") if png is None else png,
                           png_option="the default picture" if png is None else "--png")
    except PicturePathError as exc:
        _fail(str(exc) if png is not None else
              f"{str(exc).rstrip('.')}; pass --png with a path where the picture can be written.")
    except ValueError as exc:  # MeshError and out-of-range values are bad input
        if _state["debug"]:
            traceback.print_exc()
        _fail(str(exc))
    if as_json:
        typer.echo(json.dumps(result, indent=2, default=str))
        return
    print_plan(result)


def main() -> None:
    """Console-script entry point."""
    try:
        app()
    except KeyboardInterrupt:
        typer.echo("interrupted", err=True)
        sys.exit(130)


if __name__ == "__main__":
    main()
