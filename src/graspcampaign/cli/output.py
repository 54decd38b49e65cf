"""What the command line prints: the study list and a grasp plan, in words and tables (no reprs)."""

from __future__ import annotations

from typing import Any

import typer


def print_list(rows: list[dict[str, Any]]) -> None:
    """Print the study table of ``graspcampaign list``, one line per study (a broken file's reason
    folds, whole), as wide as the terminal (or ``COLUMNS``);
    a pipe or file gets 160 columns. Study and kind names are never cut (they
    are what the user types); where they leave the description under 16 columns, the kind is left
    out (``show`` names it)."""
    import os
    import sys
    import textwrap

    from rich.console import Console
    from rich.measure import Measurement
    from rich.table import Column, Table
    from rich.text import Text

    console = Console(width=None if sys.stdout.isatty() or os.environ.get("COLUMNS") else 160)
    for names in (("study", "kind", "trials", "runnable", "of"), ("study", "trials", "runnable", "of")):
        table = Table(*(Column(name, no_wrap=name in ("study", "kind")) for name in names),
                      Column("description", width=16, overflow="fold"))  # a path folds, whole
        for row in rows:
            description = Text(row["description"], overflow="fold")  # a broken file's reason: whole
            if row["runnable"] != "broken":  # one line per study (show prints the whole description)
                description = Text(textwrap.shorten(row["description"], 70, placeholder=" …"),
                                   no_wrap=True, overflow="ellipsis")
            cells = {**row, "trials": str(row["trials"]),
                     "of": "extension" if row["extension"] else "paper"}
            table.add_row(*(cells[name] for name in names), description)
        unbounded = console.options.update_width(10_000)  # Measurement.get clamps to the width
        if Measurement.get(console, unbounded, table).minimum <= console.width:
            break
    table.columns[-1].width, table.columns[-1].min_width = None, 16  # measured at 16; takes the rest
    console.print(table)


def _vector(values, fmt: str) -> str:
    return "(" + ", ".join(format(float(v), fmt) for v in values) + ")"


def print_plan(r: dict[str, Any]) -> None:
    """Print the result of :func:`graspcampaign.rig.plan.plan_mesh` for a person."""
    mesh = r["mesh"]
    typer.echo(f"mesh: {mesh['name']} ({mesh['nodes']} nodes, {mesh['faces']} faces, "
               f"{mesh['size_mm']:.1f} mm across)  mass: {r['mass_kg']} kg "
               f"(W = {r['weight_n']:.3f} N)  material: {r['material']}  mu_s: {r['mu_s']:.3f}")
    for c in r["contacts"]:
        typer.echo(f"finger {c['finger']}: vertex {c['vertex']} at {_vector(c['point_mm'], '.1f')} mm, "
                   f"normal {_vector(c['normal'], '.2f')}, f_n = {c['normal_force_n']:.3f} N, "
                   f"deformation = {c['deformation_mm']:.2f} mm")
    typer.echo("H: " + ", ".join(f"{k} = {v:.3f}" for k, v in r["h"].items()))
    if r["unloaded_fingers"]:
        fingers = ", ".join(map(str, r["unloaded_fingers"]))
        stable = f"no (finger {fingers} carries no load, so the grasp is not a three-finger grasp)"
    elif r["predicted_stable"]:
        stable = "yes (SF > 1 with every finger loaded, §9.5)"
    else:
        stable = "no (SF <= 1: friction does not carry the weight, §9.5)"
    typer.echo(f"G_geo = {r['g_geo']:.3f}  grip = {r['grip_force_n']:.3f} N"
               f"{' (capped at the damage depth)' if r['grip_capped'] else ''}  "
               f"SF = {r['sf_predicted']:.3f}  predicted stable: {stable}")
    # the paper's residual check judges another quantity: say which, so the two never read as
    # one verdict contradicting its own number
    within = r["predicted_stable_residual"]
    typer.echo(f"residual check (§8.1: Algorithm 2, normal forces only, friction ignored): |R| = "
               f"{r['residual_n']:.3f} N {'<=' if within else '>'} tau_F = {r['tau_f_n']} N, "
               f"{'passed' if within else 'not passed'}; not part of the verdict above")
    typer.echo(f"predicted limits: F_lat = {r['f_lat_n']:.3f} N, F_down = {r['f_down_n']:.3f} N, "
               f"T = {r['torque_nm']:.4f} N m (r_eff = {r['r_eff_mm']:.1f} mm)")
    first = ", ".join(f"{k.replace('_', ' ')}: finger {v}" if v else f"{k.replace('_', ' ')}: none"
                      for k, v in r["first_finger"].items())
    typer.echo(f"first finger to slip: {first}")
    if r["png"]:
        typer.echo(f"picture: {r['png']}")
