"""Planner predictions for the hardware campaigns and the ``graspcampaign plan MESH`` computation.

What each planner *knows* (materials, friction, contact law, creep, geometry) lives in
:mod:`graspcampaign.rig.belief`; this module plans the contacts (the hardware form of the proposed
planner, §8.1: weights 0.45/0.30/0.25, continuous penalties, maximised score H~; the registry
baselines) and sizes each planner's grip from its own belief (§8.1, SPEC §2.10).

The contacts are planned in :mod:`graspcampaign.rig.plan_contacts` and the predictions made in
:mod:`graspcampaign.rig.plan_predict`; this module holds :func:`plan_mesh` and re-exports every
public name of both, so ``graspcampaign.rig.plan`` keeps its interface.

* :func:`predict_trial` -- the pre-execution predictions of one schedule row (contacts, H~ terms,
  believed G_geo and mu_s, grip sizing, SF_predicted, per-finger forces and deformations,
  ``predicted_stable``, F_lat / F_down / T, first finger to slip, retention flag).
* :func:`plan_mesh` -- the same pipeline for a user's mesh, plus a PNG of contacts and forces.

Per-object work is cached per process: the mesh, its sharp features and heuristic context per
shape, and each plan per ``plan_key`` (an object's plan is shared by all its trials with the same
planner; the random planner draws a new triple per slot, see :mod:`graspcampaign.rig.protocol`).

References
----------
Paper §8.1 (planners, hardware weighting, grip sizing from believed quality, kappa, tau_F), §9.1
(closed-form predicted thresholds), §7.4 (damage depth), Table 4; SPEC §2.8, §2.10, §4, §7.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from graspcampaign.core import disturbance as dist
from graspcampaign.core import slip
from graspcampaign.core.equilibrium import EvaluatorParams
from graspcampaign.core.planner import DEFAULT_N_CAND
from graspcampaign.core.statics import GRAVITY
from graspcampaign.core.words import as_given
from graspcampaign.errors import cannot_write
from graspcampaign.rig import DEFAULT_FINGERTIP_RADIUS_MM, DEFAULT_PLAN_MATERIAL
from graspcampaign.rig.belief import (  # noqa: F401  (re-exported: the planners' knowledge)
    CHARACTERISTIC_Z,
    COATING_MU_S,
    MaterialModel,
    PlannerBelief,
    believed_contact_law,
    family_damage_depth,
    material_model,
    planner_belief,
)
from graspcampaign.rig.plan_contacts import (
    HARDWARE_PLANNERS,
    N_NODES,
    STABLE_RESIDUAL_N,
    HardwarePlan,
    hardware_plan,
    make_body,
)
from graspcampaign.rig.plan_predict import (
    commanded_disturbance,
    grip_time_s,
    predict_trial,
    predictions_from_plan,
)

__all__ = [
    # the graspcampaign plan MESH computation (this module)
    "plan_mesh",
    "check_picture_path",
    "PicturePathError",
    # re-exported: they live in graspcampaign.rig.belief
    "CHARACTERISTIC_Z",
    "COATING_MU_S",
    "MaterialModel",
    "family_damage_depth",
    "material_model",
    # re-exported: they live in graspcampaign.rig.plan_contacts
    "HARDWARE_PLANNERS",
    "HardwarePlan",
    "hardware_plan",
    "N_NODES",
    "STABLE_RESIDUAL_N",
    # re-exported: they live in graspcampaign.rig.plan_predict
    "commanded_disturbance",
    "grip_time_s",
    "predict_trial",
    "predictions_from_plan",
]

logger = logging.getLogger(__name__)


# --------------------------------------------------------------------------------------------
# graspcampaign plan MESH
# --------------------------------------------------------------------------------------------
def _check_plausible(value: object, quantity: str, unit: str, names: Mapping[str, str]) -> float:
    """Return ``value`` as a float inside its plausible range (``core.plausible.PLAUSIBLE``);
    ``quantity`` is also the parameter of :func:`plan_mesh` that gives it. A refusal names it as
    ``names[quantity]`` (else ``quantity``): ``name = value``, or, for a command-line option (a
    name starting with ``-``), as typed: ``--mass-kg value``."""
    from graspcampaign.core.plausible import PLAUSIBLE

    name = names.get(quantity, quantity)

    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}.") from None
    rng = PLAUSIBLE[quantity]
    if not rng.contains(number):
        unit = f" {unit}" if unit else ""
        raise ValueError(f"{as_given(name, value)} is out of range; allowed: {rng.text()}{unit} "
                         f"({rng.why}).")
    return number


def _check_material(material: object, names: Mapping[str, str]) -> str:
    """Return ``material``, a Table 4 family (``core.bench.FAMILIES``); a refusal names it as
    ``core.mesh_file.check_unit`` names a unit (``--material 'steel'`` on the command line),
    suggests the nearest family and lists them."""
    from graspcampaign.core.bench import FAMILIES
    from graspcampaign.core.words import meant

    if material in FAMILIES:
        return material  # type: ignore[return-value]
    raise ValueError(f"{as_given(names.get('material', 'material'), material)} is not a Table 4 "
                     f"material family; {meant(material, FAMILIES)}use one of {', '.join(FAMILIES)}.")


def _check_size(mesh, name: str, unit: str) -> float:
    """Return the object's size [mm]; refuse one no hand can grasp, naming the likely unit."""
    from graspcampaign.core.mesh import UNITS
    from graspcampaign.core.plausible import OBJECT_SIZE_MM

    size_mm = float(np.ptp(np.asarray(mesh.vertices), axis=0).max()) * 1e3
    if OBJECT_SIZE_MM.contains(size_mm):
        return size_mm
    raw = size_mm * 1e-3 / UNITS[unit]  # the size in the file's own numbers
    fits = [u for u, scale in UNITS.items() if OBJECT_SIZE_MM.contains(raw * scale * 1e3)]
    hint = (f"its coordinates look like {' or '.join(_UNIT_WORDS[u] for u in fits)}: pass "
            f"--unit {fits[0]}" if fits else "no length unit makes it graspable")
    across = f"{size_mm / 1e3:.3g} m" if size_mm >= 1e3 else f"{size_mm:.3g} mm"
    raise ValueError(f"mesh {name!r} is {across} across read with --unit {unit}, outside "
                     f"the {OBJECT_SIZE_MM.low:g}-{OBJECT_SIZE_MM.high:g} mm a three-finger hand "
                     f"grasps; {hint}.")


_UNIT_WORDS = {"m": "metres", "cm": "centimetres", "mm": "millimetres"}

DENSE_FACES = 1_000_000
"""A mesh with more faces is said to be slow: reading, checking, planning on and drawing a mesh take
time and memory in proportion to its faces (1.3 M faces: 37-88 s and 2 GB; 5.2 M: 162 s and 7 GB;
80 k: 6 s; docs/decisions.md)."""


def _coarse_checked_body(mesh, name: str):
    """Return the planning body of ``mesh``, warning once, in the planner's words, if it is coarse
    (or, with more than :data:`DENSE_FACES` faces, that it is slow to plan).

    The core's :class:`~graspcampaign.core.feature.CoarseMeshWarning` names a Python remedy
    (resolution-aware thresholds); for a plan the remedy is a finer mesh, because the planner's
    contacts are mesh vertices: raising the thresholds would call a coarse cube's corners smooth
    and still leave the fingers only its corners to choose from.
    """
    import warnings

    from graspcampaign.core.feature import (
        CoarseMeshWarning,
        FeatureThresholds,
        is_coarse,
        smooth_mean_defect,
    )

    n_vertices = len(mesh.vertices)
    if len(mesh.faces) > DENSE_FACES:
        warnings.warn(
            f"mesh {name!r} has {len(mesh.faces)} faces: planning on it takes half a minute or more "
            "per million faces and gigabytes of memory (every step scales with the faces); a copy "
            f"decimated to under {DENSE_FACES // 10} faces plans in seconds (the paper's objects "
            f"have {N_NODES} vertices)", stacklevel=3)
    if is_coarse(n_vertices):
        warnings.warn(
            f"mesh {name!r} has only {n_vertices} vertices and the planner places fingers on "
            f"vertices only: a surface this coarse leaves it few places to choose from and its "
            f"smooth regions look sharp (mean angular defect {smooth_mean_defect(n_vertices):.3f} "
            f"rad against the {FeatureThresholds().vertex_defect_rad} rad sharp-vertex threshold); "
            f"remesh or subdivide it finer for a better plan (the paper's objects have {N_NODES} "
            "vertices)", CoarseMeshWarning, stacklevel=3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoarseMeshWarning)  # said above, in the planner's words
        return make_body(mesh)


class PicturePathError(ValueError):
    """A picture path that cannot be written exactly (one sentence naming it)."""


def check_picture_path(path, option: str = "picture path") -> Path:
    """Return ``path`` as a Path a PNG can be written at, exactly; refuse any other, naming it.

    Checked before any work: a directory, a name not ending in ``.png`` (matplotlib would pick
    another format or append ``.png``, so the file written would not be the path named), a
    missing parent directory (a mistyped one grows no tree), or a place where no file can be
    written (:func:`graspcampaign.campaign.paths.path_problem`, the rule every output path obeys).

    Parameters
    ----------
    path : str or path
        Where the picture goes.
    option : str
        How the messages name the path (the command line passes ``--png``).

    Raises
    ------
    PicturePathError
        One sentence naming the path and what is wrong with it.
    """
    from graspcampaign.campaign.paths import control_character, path_problem

    if (control := control_character(path, option)) is not None:
        raise PicturePathError(control)
    path = Path(path)
    if os.path.isdir(path):  # Path.is_dir raises below a directory this user may not search
        raise PicturePathError(f"{option} {path} is a directory: give a file path ending in .png, "
                               f"such as {path / 'plan.png'}.")
    if path.suffix.lower() != ".png":
        raise PicturePathError(f"{option} {path} does not end in .png: the picture is a PNG file, "
                               f"so give a path such as {path.with_suffix('.png')}.")
    why = path_problem(path, write=True, directory=False)  # first: a parent in a loop of links
    if why is not None:
        raise PicturePathError(f"{option} {path}: {why}.")
    if not os.path.exists(path.parent):
        raise PicturePathError(f"{option} {path}: directory {path.parent} does not exist.")
    return path


UNLOADED_N = 1e-6
"""A finger pressing with less than this [N] carries no load (the plan's forces are N-scale)."""


def plan_mesh(mesh_or_path, *, mass_kg: float, material: str | None = None, mu: float | None = None,
              fingertip_radius_mm: float = DEFAULT_FINGERTIP_RADIUS_MM, unit: str = "mm", png_path=None,
              names: Mapping[str, str] | None = None, seed: int = 0) -> dict[str, Any]:
    """Plan a proposed-planner grasp on a user's mesh and predict its disturbance limits.

    Parameters
    ----------
    mesh_or_path : str, path or trimesh.Trimesh
        Mesh file (STL/OBJ/PLY, read with :func:`graspcampaign.core.mesh.load_mesh`) or a mesh in
        metres; either is validated by :func:`graspcampaign.core.mesh.check_mesh` and centred on
        its volume centroid, the frame of the returned contacts.
    mass_kg : float
        Object mass, in its plausible range (``core.plausible.PLAUSIBLE``: [0.1 g, 10 kg]).
    material : str, optional
        Table 4 family; default :data:`~graspcampaign.rig.DEFAULT_PLAN_MATERIAL` (also for the contact
        law when only ``mu`` is given).
    mu : float, optional
        Static friction [0, 3]; overrides the material's mu_s.
    fingertip_radius_mm : float
        Fingertip radius (0, 50] mm (K scales with sqrt(R), Eq. 14).
    unit : str
        Length unit of the mesh file (a ``Trimesh`` is in metres, the package's unit).
    png_path : path, optional
        Where to write the picture (mesh, contacts, force arrows), exactly this path; none when
        omitted. Checked first (:func:`check_picture_path`).
    names : mapping of str to str, optional
        How refusals name the arguments, by parameter (the command line passes its options:
        ``{"mass_kg": "--mass-kg", "png_path": "--png", ...}``); any other is named as its
        parameter (``mass_kg = 0.0``), ``png_path`` as "picture path".
    seed : int
        Candidate sampling seed.

    Returns
    -------
    dict
        ``mesh`` (name, nodes, faces, size_mm), ``material``, ``mu_s``, ``mass_kg``, ``weight_n``,
        ``contacts`` (per finger: point mm, outward normal, normal force N, deformation mm),
        ``h`` (``h_tilde, s1, s2, s3, pc_mag, pe_mag``), ``g_geo``, ``grip_force_n``,
        ``grip_capped``, ``sf_predicted``, ``f_lat_n``, ``f_down_n``, ``torque_nm``, ``r_eff_mm``,
        ``first_finger`` (per disturbance: lateral +x, +y, down, yaw), ``predicted_stable``
        (§9.5, as :func:`predict_trial`: the believed margin ``sf_predicted > 1``, and every finger
        loaded), ``unloaded_fingers`` (1-based, fingers whose normal force is not above
        :data:`UNLOADED_N`), ``residual_n`` (Algorithm 2's normal-only residual ``|R|`` at the
        planned contacts under the material's contact law, friction ignored [N]; a different
        quantity from the one ``predicted_stable`` judges), ``tau_f_n`` (0.0886 N, §8.1),
        ``predicted_stable_residual`` (the paper's §8.1 check ``residual_n <= tau_f_n``, friction-
        blind; at SI constants it almost never holds, see docs/decisions.md), ``png``.

    Raises
    ------
    graspcampaign.core.mesh.MeshError
        An unknown unit (:func:`graspcampaign.core.mesh_file.check_unit`, named as
        ``names["unit"]``), an unreadable or invalid mesh, or one of more than one body or with an
        internal cavity (:func:`graspcampaign.core.mesh_file.check_one_body`).
    ValueError
        Out-of-range mass, friction, radius, an unknown material, an object whose size no
        three-finger hand grasps (``core.plausible.OBJECT_SIZE_MM``; the message names the unit
        its coordinates look like); :class:`PicturePathError` for a picture path that cannot be
        written.
    """
    from graspcampaign.core.mesh import check_mesh, check_unit, load_mesh

    names = {"png_path": "picture path", **(names or {})}
    if png_path is not None:  # before any work: a plan whose picture cannot be written is lost
        png_path = check_picture_path(png_path, names["png_path"])
    mass = _check_plausible(mass_kg, "mass_kg", "kg", names)
    radius_mm = _check_plausible(fingertip_radius_mm, "fingertip_radius_mm", "mm", names)
    if mu is not None:
        mu = _check_plausible(mu, "mu", "", names)
    unit = check_unit(unit, names.get("unit", "unit"))
    name_material = _check_material(DEFAULT_PLAN_MATERIAL if material is None else material,
                                    names)  # "" is no material
    mat = material_model(name_material, "natural", radius_mm * 1e-3)
    if mu is not None:
        mat = replace(mat, mu_s=mu, mu_k=mu * mat.mu_k / mat.mu_s, friction_level="user")
    if isinstance(mesh_or_path, (str, Path)):
        mesh = load_mesh(mesh_or_path, unit=unit)
        name = Path(mesh_or_path).name
    else:  # the checks load_mesh makes of a file's mesh (closed, outward, one body, centred)
        name = "mesh"
        mesh = check_mesh(mesh_or_path, name)
    size_mm = _check_size(mesh, name, unit)
    body = _coarse_checked_body(mesh, name)
    ctx = replace(body.ctx, mass=mass, mu=mat.mu_s,
                  contact=mat.contact_params(radius_mm * 1e-3), n_cand=DEFAULT_N_CAND,
                  evaluator=EvaluatorParams())
    plan = hardware_plan(ctx, "heuristic", np.random.default_rng(seed), mat.k_n_per_mm_n, mat.n)
    belief = planner_belief("heuristic", plan.points, plan.normals, mat, ctx.centroid)
    pred = predictions_from_plan(plan, belief, mass, ctx.centroid)
    forces = np.array([pred[f"normal_force_pred_{j}_n"] for j in (1, 2, 3)])
    first = {}
    for label, kind, direction in (("lateral_x", "lateral", 0.0), ("lateral_y", "lateral", 90.0),
                                   ("down", "down", 0.0), ("yaw", "yaw", 0.0)):
        first[label] = slip.first_slip_finger(plan.points, plan.normals, forces, ctx.centroid,
                                              mass, mat.mu_s, kind, direction)
    contacts = [{"finger": j + 1, "vertex": int(plan.vertex_ids[j]),
                 "point_mm": [round(float(v) * 1e3, 3) for v in plan.points[j]],
                 "normal": [round(float(v), 4) for v in plan.normals[j]],
                 "normal_force_n": float(forces[j]),
                 "deformation_mm": pred[f"deformation_pred_{j + 1}_mm"]} for j in range(3)]
    # a finger that presses on nothing leaves a two-finger grasp: never stable (Sec. 8.1 needs all
    # three contacts loaded), whatever the residual criterion says
    unloaded = [j + 1 for j in range(3) if not forces[j] > UNLOADED_N]
    out = {
        "mesh": {"name": name, "nodes": int(len(mesh.vertices)), "faces": int(len(mesh.faces)),
                 "size_mm": size_mm},
        "material": name_material, "mu_s": mat.mu_s, "mass_kg": mass, "weight_n": mass * GRAVITY,
        "fingertip_radius_mm": radius_mm, "kappa": dist.KAPPA, "target_sf": dist.SF_TARGET,
        "contacts": contacts,
        "h": {k: pred[k] for k in ("h_tilde", "s1", "s2", "s3", "pc_mag", "pe_mag")},
        "g_geo": pred["g_geo_believed"], "grip_force_n": pred["grip_force_n"],
        "grip_capped": pred["grip_capped"], "grip_cap_n": pred["grip_cap_n"],
        "sf_predicted": pred["sf_predicted"], "f_lat_n": pred["f_lat_pred_n"],
        "f_down_n": pred["f_down_pred_n"], "torque_nm": pred["torque_pred_nm"],
        "r_eff_mm": pred["r_eff_mm"], "first_finger": first,
        "predicted_stable": bool(pred["predicted_stable"]) and not unloaded,
        "unloaded_fingers": unloaded, "residual_n": pred["residual_pred_n"],
        "tau_f_n": STABLE_RESIDUAL_N,
        "predicted_stable_residual": bool(pred["predicted_stable_residual"]),
        "png": None,
    }
    if png_path is not None:
        try:
            out["png"] = str(plot_plan(mesh, plan.points, plan.normals, forces, png_path,
                                       title=f"{name}: SF {out['sf_predicted']:.2f}, "
                                             f"F_lat {out['f_lat_n']:.2f} N"))
        except OSError as exc:  # a full disk, or the directory changed since the check
            raise PicturePathError(f"{names['png_path']} {png_path}: {cannot_write(exc)}.") from None
    return out


def plot_plan(mesh, points, normals, forces, path, title: str = "") -> Path:
    """Write the PNG of :func:`plan_figure`."""
    path = Path(path)
    plan_figure(mesh, points, normals, forces, title).savefig(path, dpi=100, format="png")
    return path  # the path check_picture_path accepted: its parent exists


def plan_figure(mesh, points, normals, forces, title: str = ""):
    """The mesh with the contacts and their force arrows (a matplotlib Figure, no pyplot).

    Arrows start at each contact and point along the applied force ``-n_out``, their length
    proportional to the finger's normal force (the largest drawn at 40 % of the object's size).
    """
    from matplotlib.figure import Figure

    v = np.asarray(mesh.vertices) * 1e3
    p = np.asarray(points) * 1e3
    size = float(np.ptp(v, axis=0).max())
    f = np.asarray(forces, dtype=float)
    scale = 0.4 * size / max(float(f.max()), 1e-9)
    arrows = -np.asarray(normals) * (f * scale)[:, None]
    fig = Figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="3d")
    ax.plot_trisurf(v[:, 0], v[:, 1], v[:, 2], triangles=np.asarray(mesh.faces), color="0.8",
                    alpha=0.35, linewidth=0.1, edgecolor="0.5")
    colours = ("tab:red", "tab:green", "tab:blue")
    for j in range(3):  # each finger's force in the legend below the view: labels on it overlapped
        ax.scatter(*p[j], color=colours[j], s=50, depthshade=False, label=f"finger {j + 1}: {f[j]:.2f} N")
        ax.quiver(*(p[j] - arrows[j]), *arrows[j], color=colours[j], linewidth=2,
                  arrow_length_ratio=0.25)
    fig.legend(loc="lower center", ncols=3, frameon=False)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    # one scale on every axis (a sphere drawn round): a cube around the mesh and the arrows' tails
    drawn = np.vstack([v, p - arrows])
    centre, half = drawn.min(axis=0) / 2 + drawn.max(axis=0) / 2, float(np.ptp(drawn, axis=0).max()) / 2
    ax.set(xlim=(centre[0] - half, centre[0] + half), ylim=(centre[1] - half, centre[1] + half),
           zlim=(centre[2] - half, centre[2] + half))
    ax.set_box_aspect((1, 1, 1))
    ax.set_title(title, fontsize=9)
    return fig
