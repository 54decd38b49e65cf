"""The ``graspcampaign`` command line (Typer).

Exit codes: 0 success, 1 trial errors occurred, 2 bad usage or bad input. Errors are one
sentence on stderr; ``--debug`` adds the traceback. Layers are imported inside commands so that
``--help`` stays fast.
"""

from __future__ import annotations

import json
import sys
import traceback
from pathlib import Path
from typing import Annotated

import typer

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="Reproducible experiment campaigns for soft-object grasp planning.",
    pretty_exceptions_enable=False,
)
_state = {"debug": False}

Overrides = Annotated[
    list[str] | None,
    typer.Argument(help="Hydra overrides, e.g. mu=[0.3] seeds=2 runner.n_jobs=2.", show_default=False),
]
RunOpt = Annotated[str | None, typer.Option("--run", help="Run name (default: output.run).")]


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
    return wrapper


# ValueErrors from the core that mean bad input (a mesh, an ingested file).
_INPUT_ERRORS = {"MeshError", "IngestError"}


@app.callback()
def _main(debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks.")] = False):
    _state["debug"] = debug


@app.command("list")
@_guard
def list_cmd(
    names: Annotated[bool, typer.Option("--names", help="Print runnable study names only.")] = False,
) -> None:
    """List the studies, their trial kinds, trial counts and whether they can run yet."""
    from rich.console import Console
    from rich.table import Table

    from graspcampaign.campaign.compose import compose_study, list_studies
    from graspcampaign.campaign.kind import KINDS, kind_available
    from graspcampaign.campaign.status import study_size

    if names:
        for name in list_studies():
            if name != "smoke" and kind_available(compose_study(name).kind):
                typer.echo(name)
        return
    from graspcampaign.errors import UserInputError

    table = Table("study", "kind", "trials", "runnable", "description")
    for name in list_studies():
        study = compose_study(name)
        ready = kind_available(study.kind)
        try:
            size = str(study_size(study))
        except UserInputError:  # a design read from another study's records, not run yet
            size = "?"
        table.add_row(name, study.kind, size,
                      "yes" if ready else "not yet" if study.kind in KINDS else "unknown kind",
                      " ".join(study.description.split())[:70])
    Console(width=160).print(table)


@app.command()
@_guard
def show(study: str, overrides: Overrides = None, run: RunOpt = None) -> None:
    """Print a study's design, factor levels, trial count, progress and estimated time."""
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.status import design_text

    cfg = compose_study(study, overrides or [])
    typer.echo(design_text(cfg, run))


@app.command("run")
@_guard
def run_cmd(
    study: str,
    overrides: Overrides = None,
    run: RunOpt = None,
    allow_drift: Annotated[bool, typer.Option(help="Resume even if config or code changed.")] = False,
    fail_fast: Annotated[bool, typer.Option(help="Stop at the first trial error.")] = False,
    report: Annotated[bool, typer.Option(help="Write the study's report after the run.")] = False,
) -> None:
    """Run a study (resuming a run that already has records)."""
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.runner import run_study

    cfg = compose_study(study, overrides or [])
    summary = run_study(cfg, run=run, allow_drift=allow_drift, fail_fast=fail_fast)
    typer.echo(
        f"{summary.study}/{summary.run}: {summary.n_trials} trials, {summary.n_already} already "
        f"recorded, {summary.n_ran} ran ({summary.n_ok} ok, {summary.n_error} errors) in "
        f"{summary.wall_time_s:.1f} s -> {summary.path}"
    )
    for line in summary.errors[:5]:
        typer.echo(f"  error: {line}", err=True)
    if report:
        from graspcampaign.report.build import build_reports

        for path in build_reports([cfg.name], run=summary.run, root=cfg.output.root):
            typer.echo(f"report: {path}")
    if summary.n_error:
        raise typer.Exit(1)


@app.command()
@_guard
def status(
    study: str,
    run: RunOpt = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
    root: Annotated[Path, typer.Option(help="Results root.")] = Path("results"),
) -> None:
    """Summarise a run from its records only (never runs anything)."""
    from graspcampaign.campaign.status import run_status

    info = run_status(root, study, run or "default")
    if as_json:
        typer.echo(json.dumps(info, indent=2, default=str))
        return
    for key, value in info.items():
        typer.echo(f"{key}: {value}")


@app.command()
@_guard
def report(
    studies: Annotated[list[str] | None, typer.Argument(help="Studies (default: all with records).")] = None,
    run: RunOpt = None,
    root: Annotated[Path, typer.Option(help="Results root.")] = Path("results"),
    fmt: Annotated[str, typer.Option("--format", help="Comma-separated: md,csv,json,html.")] = "md,csv",
) -> None:
    """Write reports (Markdown, CSV tables, PNG figures) from the records; never runs a trial."""
    from graspcampaign.report.build import build_reports

    for path in build_reports(studies or None, run=run, root=root, formats=fmt.split(",")):
        typer.echo(f"report: {path}")


@app.command()
@_guard
def schedule(
    study: str,
    overrides: Overrides = None,
    out: Annotated[
        Path | None, typer.Option(help="Output file stem (default: results/<study>/schedule).")
    ] = None,
) -> None:
    """Write a hardware protocol's commanded-trial sheet (CSV and Parquet)."""
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.kind import get_kind
    from graspcampaign.campaign.runner import kind_params

    cfg = compose_study(study, overrides or [])
    kind = get_kind(cfg.kind)
    if kind.schedule is None:
        _fail(f"study {study!r} is a simulation study; only hardware protocols have a schedule.")
    sheet = kind.schedule(cfg, kind_params(cfg, kind))
    stem = out or Path(cfg.output.root) / cfg.name / "schedule"
    stem.parent.mkdir(parents=True, exist_ok=True)
    sheet.to_csv(stem.with_suffix(".csv"), index=False)
    sheet.to_parquet(stem.with_suffix(".parquet"), index=False)
    typer.echo(f"{len(sheet)} commanded trials -> {stem.with_suffix('.csv')} and .parquet")


@app.command()
@_guard
def ingest(
    study: str,
    files: Annotated[list[Path], typer.Argument(help="Measured records (CSV, XLSX or Parquet).")],
    run: Annotated[str, typer.Option("--run", help="Run that receives the measured records.")] = "measured",
    overrides: Annotated[list[str] | None, typer.Option("--set", help="Hydra override (repeatable).")] = None,
) -> None:
    """Validate measured records and store them as a run with source = measured."""
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.ingest import ingest_files

    cfg = compose_study(study, overrides or [])
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
    png: Annotated[Path | None, typer.Option(help="Picture path (default: <mesh>.plan.png).")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
) -> None:
    """Plan a three-finger grasp on a mesh and predict the disturbances it resists."""
    from graspcampaign.rig.plan import plan_mesh

    if not mesh.is_file():
        _fail(f"{mesh}: no such mesh file.")
    png = png or mesh.with_suffix(".plan.png")
    try:
        result = plan_mesh(mesh, mass_kg=mass_kg, material=material, mu=mu,
                           fingertip_radius_mm=fingertip_radius_mm, unit=unit, png_path=png)
    except ValueError as exc:  # MeshError and out-of-range values are bad input
        if _state["debug"]:
            traceback.print_exc()
        _fail(str(exc))
    if as_json:
        typer.echo(json.dumps(result, indent=2, default=str))
        return
    _print_plan(result)


def _print_plan(r: dict) -> None:
    typer.echo(f"mesh: {r['mesh']}  mass: {r['mass_kg']} kg (W = {r['weight_n']:.3f} N)  "
               f"material: {r['material']}  mu_s: {r['mu_s']:.3f}")
    for c in r["contacts"]:
        point = ", ".join(f"{v:.1f}" for v in c["point_mm"])
        normal = ", ".join(f"{v:.2f}" for v in c["normal"])
        typer.echo(f"finger {c['finger']}: vertex {c['vertex']} at ({point}) mm, normal ({normal}), "
                   f"f_n = {c['normal_force_n']:.3f} N, deformation = {c['deformation_mm']:.2f} mm")
    typer.echo("H: " + ", ".join(f"{k}={v:.3f}" for k, v in r["h"].items()))
    typer.echo(f"G_geo = {r['g_geo']:.3f}  grip = {r['grip_force_n']:.3f} N"
               f"{' (capped at the damage depth)' if r['grip_capped'] else ''}  "
               f"SF = {r['sf_predicted']:.3f}  predicted stable: {r['predicted_stable']}")
    typer.echo(f"predicted limits: F_lat = {r['f_lat_n']:.3f} N, F_down = {r['f_down_n']:.3f} N, "
               f"T = {r['torque_nm']:.4f} N m (r_eff = {r['r_eff_mm']:.1f} mm)")
    typer.echo(f"first finger to slip: {r['first_finger']}")
    typer.echo(f"picture: {r['png']}")


def main() -> None:
    """Console-script entry point."""
    try:
        app()
    except KeyboardInterrupt:
        typer.echo("interrupted", err=True)
        sys.exit(130)


if __name__ == "__main__":
    main()
