"""The hardware and mesh commands: ``schedule`` (a protocol's commanded-trial sheet), ``ingest``
(measured records into a run) and ``plan`` (a grasp on a user's mesh)."""

from __future__ import annotations

import json
import traceback
from pathlib import Path
from typing import Annotated

import typer

from graspcampaign.cli.app import (
    Overrides,
    RootOpt,
    StudyArg,
    app,
    check_root,
    compose,
    fail,
    file_path,
    guard,
    number,
    other_format,
    outside_runs,
    path_or_empty,
    state,
    writable_stem,
)
from graspcampaign.cli.output import print_plan
from graspcampaign.rig import DEFAULT_FINGERTIP_RADIUS_MM, DEFAULT_PLAN_MATERIAL


@app.command()
@guard
def schedule(
    study: StudyArg,
    overrides: Overrides = None,
    out: Annotated[
        Path | None, typer.Option(help="Output file stem: writes <stem>.csv and <stem>.parquet "
                                       "(x.csv or x.parquet names the same two files as x; "
                                       "default: <root>/<study>/schedule/sheet, a folder "
                                       "that `report` does not take for a run).",
                                  parser=file_path("--out", "a file stem such as", "schedule"),
                                  metavar="path")
    ] = None,
    template: Annotated[bool, typer.Option(
        "--template", help="Also write the measured-records sheet to fill in (every column, empty, "
                           "with its unit in <stem>-template-columns.csv).")] = False,
    root: RootOpt = None,
) -> None:
    """Write a hardware protocol's commanded-trial sheet (CSV and Parquet)."""
    from graspcampaign.campaign.kind import get_kind
    from graspcampaign.campaign.paths import path_problem, write_file
    from graspcampaign.campaign.runner import kind_params
    from graspcampaign.core.words import counted

    check_root(root, write=out is None)
    cfg = compose(study, overrides, root)
    kind = get_kind(cfg.kind)
    if kind.schedule is None:
        fail(f"study {cfg.name!r} is a simulation study; only hardware protocols have a schedule.")
    if out and out.suffix.lower() in (".csv", ".parquet"):  # --out x.csv: the stem is x
        out = out.with_suffix("")
    elif out and other_format(out, ()):  # not x.xlsx.csv
        fail(f"--out {out}: schedule writes the sheet as CSV and Parquet (<stem>.csv and "
             f"<stem>.parquet), not as {out.suffix}; give --out {out.with_suffix('')} or "
             f"{out.with_suffix('.csv')}.")
    stem = writable_stem(Path(cfg.output.root) / cfg.name / "schedule" / "sheet" if out is None
                         else out, "--out")
    if out is not None and not out.parent.is_dir():  # as plan --png: a typo grows no tree
        fail(f"--out {out}: directory {out.parent} does not exist.")
    def file(name: str) -> Path:  # one naming for the check and the writes: '<stem><name>'
        return stem.with_name(stem.name + name)

    names = [".csv", ".parquet", *(["-template.csv", "-template-columns.csv"] if template else [])]
    for name in names:  # the files themselves (one may be a directory or a named pipe)
        if (why := path_problem(file(name), write=True, directory=False)):
            fail(f"--out {stem}: {stem.name + name} {why}.")
    params = kind_params(cfg, kind)
    sheet = kind.schedule(cfg, params)
    sheets = {"": sheet}
    if template:
        fill, columns = kind.template(cfg, params, sheet)
        sheets.update({"-template": fill, "-template-columns": columns})
    for suffix, table in sheets.items():  # a sheet filled in or made for other settings stays
        written = file(f"{suffix}.csv")
        if written.is_file() and written.read_bytes() != table.to_csv(index=False).encode():
            fail(f"--out {stem}: {written.name} already exists and differs from the sheet this "
                 "command writes (filled in, or made with other settings?); move it away or give "
                 "another --out, so that it is not written over.")
    try:
        stem.parent.mkdir(parents=True, exist_ok=True)
        for suffix, table in sheets.items():  # each whole or not at all: a Ctrl-C leaves no half
            write_file(file(f"{suffix}.csv"), table.to_csv(index=False))  # sheet that then "differs"
            if not suffix:
                write_file(file(".parquet"), table.to_parquet(index=False))
    except OSError as exc:  # permissions, a full disk
        from graspcampaign.errors import cannot_write

        fail(f"--out {stem}: {cannot_write(exc)}.")
    typer.echo(f"{counted(len(sheet), 'commanded trial')} -> {file('.csv')} and .parquet")
    if template:
        typer.echo(f"measured-records template -> {stem}-template.csv (columns and units: "
                   f"{stem}-template-columns.csv)")


@app.command()
@guard
def ingest(
    study: StudyArg,
    files: Annotated[list[Path], typer.Argument(help="Measured records (CSV, XLSX or Parquet).",
                                                parser=lambda value: Path(path_or_empty(value)))],
    run: Annotated[str, typer.Option("--run", help="Run that receives the measured records.")] = "measured",
    overrides: Annotated[list[str] | None, typer.Option("--set", help="Hydra override (repeatable).")] = None,
    root: RootOpt = None,
) -> None:
    """Validate measured records and store them as a run of their source.

    The source is measured, or virtual for a virtual rig's exports."""
    from graspcampaign.campaign.ingest import ingest_files
    from graspcampaign.core.words import counted

    check_root(root, write=True)
    cfg = compose(study, overrides, root)
    n, path, source = ingest_files(cfg, [str(f) for f in files], run, given=(study, overrides or []))
    typer.echo(f"{counted(n, 'measured record')} stored in {path}" if source == "measured" else
               f"{counted(n, 'virtual-rig record')} (source = {source}: exports, not rig "
               f"measurements) stored in {path}")


@app.command()
@guard
def plan(
    mesh: Annotated[Path, typer.Argument(
        help="Object mesh (STL, OBJ or PLY).", parser=lambda value: path_or_empty(value, "mesh"),
        metavar="mesh")],
    mass_kg: Annotated[float, typer.Option("--mass-kg", help="Object mass in kg.",
                                           parser=number("--mass-kg"), metavar="<float>")],
    material: Annotated[str, typer.Option(help="Table 4 material family.")] = DEFAULT_PLAN_MATERIAL,
    mu: Annotated[float | None, typer.Option(help="Static friction; overrides the material's.",
                                             parser=number("--mu"), metavar="<float>")] = None,
    fingertip_radius_mm: Annotated[float, typer.Option(
        "--fingertip-radius-mm", help="Fingertip radius in mm.", parser=number("--fingertip-radius-mm"),
        metavar="<float>")] = DEFAULT_FINGERTIP_RADIUS_MM,
    unit: Annotated[str, typer.Option(help="Length unit of the mesh file: m, cm or mm.")] = "mm",
    png: Annotated[Path | None, typer.Option(
        help="Picture path, ending in .png (default: <mesh>.plan.png beside the mesh).",
        parser=file_path("--png", "a file path ending in .png, such as", "plan.png"),
        metavar="path")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
) -> None:
    """Plan a three-finger grasp on a mesh and predict the disturbances it resists."""
    from graspcampaign.campaign.paths import input_file_problem, shown
    from graspcampaign.rig.plan import PicturePathError, plan_mesh

    if mesh == "":  # as a Path, "" would read "." (path_or_empty)
        fail("the mesh path is empty; give a mesh file (STL, OBJ or PLY).")
    if png == "":
        fail("--png is empty; give a picture path ending in .png, such as plan.png.")
    if (why := input_file_problem(mesh)) is not None:
        fail(f"{shown(mesh)} {why}; give a mesh file (STL, OBJ or PLY).")
    picture, option = ((mesh.with_suffix(".plan.png"), "the default picture") if png is None
                       else (png, "--png"))
    outside_runs(picture, option)
    try:  # plan_mesh checks the picture path before any planning work
        result = plan_mesh(mesh, mass_kg=mass_kg, material=material, mu=mu,
                           fingertip_radius_mm=fingertip_radius_mm, unit=unit,
                           png_path=picture, names={"png_path": option, "mass_kg": "--mass-kg",
                                                    "mu": "--mu", "unit": "--unit",
                                                    "material": "--material",
                                                    "fingertip_radius_mm": "--fingertip-radius-mm"})
    except PicturePathError as exc:
        fail(str(exc) if png is not None else
              f"{str(exc).rstrip('.')}; pass --png with a path where the picture can be written.")
    except ValueError as exc:  # MeshError and out-of-range values are bad input
        if state["debug"]:
            traceback.print_exc()
        fail(str(exc))
    if as_json:
        typer.echo(json.dumps(result, indent=2, default=str))
        return
    print_plan(result)
