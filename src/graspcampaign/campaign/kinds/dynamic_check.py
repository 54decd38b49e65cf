"""``dynamic_check``: every quasi-static label of a study re-simulated by the dynamic grasp.

The paper claims that the dynamic and the quasi-static evaluators "agree on the labels" (§6.1)
but checked it on the sphere's optimum only. This kind takes every recorded trial of a
quasi-static study (``baseline_grid`` by default; ``params.source_study`` / ``params.source_run``),
rebuilds its planned contacts, runs them through the dynamic grasp in the order of Fig. 11
(closure on the held object, lift-off, hold; ``core.grasp_phases``, compiled step) for each
material preset of the ``model_preset`` factor, and records both labels side by side.

Where the contacts come from (docs/decisions.md, dynamic check): the source run's records must
exist, since its labels are what is checked. The contacts are *re-planned* from the source
trial's own random stream (the source run's resolved config from its manifest, the trial's scene
seed, the same planner and body), because the records hold vertex ids only and one planner
(``centroid``) contacts the surface at exact ray hits with horizontal normals, not at vertices.
The re-planned vertex ids must equal the recorded ``vertex_1..3``; a mismatch (e.g. a planner
changed since the source ran) is an error record naming the ids, never a silent substitution.

Labels recorded per trial (docs/records.md): the source's quasi-static labels (``qs_success``,
``qs_success_unbounded``, ``qs_valid_geometry``, ``qs_delta_max_mm``, read by column name), the
quasi-static evaluator re-run on the same contacts under the trial's preset (``qs_preset_*``:
the like-for-like label, same contact law as the dynamic run), and the dynamic outcome
(``success``, ``success_unbounded``, ``valid_geometry``, ``dynamic_status``, δ_max, phase times).
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common
from graspcampaign.campaign.schema import SIM_TIME_S, config_field
from graspcampaign.errors import MissingSourceRunError, UserInputError

SOURCE_ID = "source_trial_id"
# Factors of the source records copied into each trial (the scene of the check), in order.
SCENE = ("shape", "mass_kg", "mu", "planner", "seed")
# Source factors that may restrict the check (``graspcampaign run dynamic_check planner=[...]``).
FILTERS = ("shape", "mass_kg", "mu", "planner")


@dataclass
class DynamicCheckParams:
    """Fixed parameters of the dynamic check (phase constants as ``friction_mass``'s)."""

    source_study: str = "baseline_grid"  # a quasi-static study whose records are checked
    source_run: str = "default"  # its run name under output.root
    bulk_modulus_pa: float = config_field(0.0, ge=0.0)  # 0: the paper's shell
    t_max_s: float = config_field(1.0, **SIM_TIME_S)  # simulated budget of one grasp
    grip_speed_m_per_s: float = config_field(0.02, gt=0.0)
    lift_time_s: float = config_field(0.1, gt=0.0)
    open_gap_m: float = config_field(1e-3, ge=0.0)
    step: str = config_field("compiled", choices=("compiled", "numpy"))


@dataclass(frozen=True)
class Source:
    """A source run: its resolved config, records (ok trials, by id) and trials (by id)."""

    study: Any
    path: Path
    records: Any  # pandas.DataFrame indexed by trial_id
    trials: dict
    nodes: int
    config_hash: str


def _source_path(study, params) -> Path:
    return Path(study.output.root) / params.source_study / params.source_run


def load_source(root: str, name: str, run: str) -> Source:
    """Read a source run (cached per worker, :func:`_read_source`): manifest config, ok records,
    trials. A relative ``root`` is read from the working directory, and cached with it: one
    process may ask for ``results`` from two directories (a notebook's ``chdir``, the tests).

    Raises
    ------
    MissingSourceRunError
        When the run does not exist or is not complete; the message names the run and the
        command that makes it (``source``: the study to run first).
    UserInputError
        When the source is not a quasi-static study (its run's kind, or its study file's when
        there is no run) or no study at all, or ``name`` or ``run`` is no name of one path
        component (``paths.check_name``: ``params.source_run=../x`` left the study's directory,
        and ``''`` named the study's directory itself).
    """
    return _read_source(root, name, run, "" if Path(root).is_absolute() else os.getcwd())


@lru_cache(maxsize=4)
def _read_source(root: str, name: str, run: str, cwd: str) -> Source:
    """:func:`load_source` of the run ``name``/``run`` under ``root`` (relative: to ``cwd``, the
    working directory it was asked from, which names the cached read)."""
    from omegaconf import OmegaConf

    from graspcampaign.campaign.kind import get_kind
    from graspcampaign.campaign.paths import check_name, how_to_make
    from graspcampaign.campaign.provenance import overrides_given, study_given
    from graspcampaign.campaign.records import RunStore
    from graspcampaign.campaign.runner import kind_params, study_trials
    from graspcampaign.campaign.schema import StudyCfg
    from graspcampaign.campaign.studyfile import configured_output

    path = Path(root) / check_name(name, "params.source_study") / check_name(run, "params.source_run")
    store = RunStore(path)
    manifest = store.check(["records"])  # the source's records as its manifest says
    # what to run first
    source = name + ("" if run == configured_output(name, "run") else f" --run {run}")
    if manifest is None:
        check_source_study(root, name)  # advice to make a run this kind would refuse is none
        raise MissingSourceRunError(
            f"dynamic_check re-simulates the records of {name}/{run}, but {path} holds no run; "
            + how_to_make(root, name, run, then="first (or set params.source_study / "
                                                "params.source_run)"), source)
    if manifest.get("kind") != "quasi_static":
        raise UserInputError(
            f"dynamic_check re-simulates quasi-static plans, but {name}/{run} is a "
            f"{manifest.get('kind')!r} run; {_choose()}")
    study = OmegaConf.to_object(OmegaConf.merge(OmegaConf.structured(StudyCfg),
                                                manifest["config"]))
    kind = get_kind(study.kind)
    trials = {t.trial_id: t for t in study_trials(study, kind, kind_params(study, kind))}
    records = store.read().to_pandas()
    recorded = set(records["trial_id"]) if len(records) else set()
    missing = len(set(trials) - recorded)
    if missing:  # like a missing run, one that `show` and `list` name as still to make
        raise MissingSourceRunError(
            f"dynamic_check needs every trial of {name}/{run}, but {missing} of {len(trials)} are "
            f"not recorded under {path}; "
            + how_to_make(root, study_given(manifest, name), run, overrides_given(manifest) or [],
                          then="again to finish it"),
            source)
    records = records[records["status"] == "ok"].set_index("trial_id", drop=False)
    return Source(study=study, path=path, records=records, trials=trials,
                  nodes=int(kind_params(study, kind).nodes), config_hash=manifest["config_hash"])


def quasi_static_studies() -> list[str]:
    """The studies on the config search path whose kind is ``quasi_static``: the sources this kind
    can check."""
    from graspcampaign.campaign.studyfile import read_yaml, study_files

    return [name for name, path in study_files().items()
            if read_yaml(path, study=True).get("kind") == "quasi_static"]


def _choose() -> str:
    return f"choose a study of kind quasi_static ({', '.join(quasi_static_studies())}) as " \
           "params.source_study."


def check_source_study(root: str, name: str) -> None:
    """Refuse, before its run is asked for, a source study whose run this kind would refuse: one
    whose study file names another kind, or one neither on the search path nor stored under
    ``root``.

    Raises
    ------
    UserInputError
        Naming the study, its kind and the studies to choose from.
    """
    from graspcampaign.campaign.studyfile import read_yaml, study_files
    from graspcampaign.core.words import meant

    files = study_files()
    if name in files:
        kind = read_yaml(files[name], study=True).get("kind")
        if kind != "quasi_static":
            raise UserInputError(f"dynamic_check re-simulates quasi-static plans, but {name} is a "
                                 f"study of kind {kind!r}; {_choose()}")
    elif not (Path(root) / name).is_dir():  # a study known by its records alone is its runs'
        raise UserInputError(
            f"params.source_study {name!r} is neither a study on the config search path nor "
            f"stored under {root}; {meant(name, quasi_static_studies())}{_choose()}")


def design(study, params) -> list[dict[str, Any]]:
    """One trial per (model preset, recorded ok source trial), in the source's order.

    Factors of the study other than ``model_preset`` filter the source trials (levels of
    ``shape``, ``mass_kg``, ``mu``, ``planner``).
    """
    presets = study.factors.get("model_preset")
    if not presets:
        raise UserInputError("dynamic_check needs the factor model_preset (conf/model presets to "
                             "simulate), e.g. model_preset=[table2,firm].")
    # another factor is refused when the study is composed (the kind's factors, studycheck)
    source = load_source(study.output.root, params.source_study, params.source_run)
    rows = source.records
    for name in FILTERS:
        if name in study.factors:
            rows = rows[rows[name].isin(study.factors[name])]
    order = [t for t in source.trials if t in rows.index]
    out = []
    for preset in presets:
        for trial_id in order:
            row = rows.loc[trial_id]
            factors = {"model_preset": preset}
            for name in SCENE:
                value = row[name]
                factors[name] = value.item() if isinstance(value, np.generic) else value
            factors[SOURCE_ID] = trial_id
            out.append(factors)
    return out


def _replan(source: Source, row) -> tuple[np.ndarray, np.ndarray, np.ndarray, Any, float]:
    """Re-plan a source trial from its own stream; return ids, points, normals, ctx, time."""
    from graspcampaign.campaign.kinds.quasi_static import plan_and_judge

    study = source.study
    trial = source.trials[row["trial_id"]]
    contact = common.contact_params(study, lambda1=float(row["lambda1"]),
                                    lambda2=float(row["lambda2"]), n=float(row["n_exp"]))
    nodes = int(trial.factors.get("nodes", source.nodes))
    start = time.perf_counter()
    judged = plan_and_judge(study, trial.factors["shape"], nodes, trial.factors["mass_kg"],
                            trial.factors["mu"], contact, trial.factors["planner"],
                            trial.rng(study.seed))
    plan_time = time.perf_counter() - start
    recorded = np.array([int(row[f"vertex_{j}"]) for j in (1, 2, 3)])
    replanned = np.asarray(judged.plan.vertex_ids, dtype=np.int64)
    if not np.array_equal(recorded, replanned):
        raise RuntimeError(
            f"re-planning {row['trial_id']} gave vertices {replanned.tolist()}, its record has "
            f"{recorded.tolist()}: the planner or its config changed since the source ran")
    return replanned, np.asarray(judged.plan.points), np.asarray(judged.plan.normals), \
        judged.ctx, plan_time


def source_labels(source: Source, row) -> dict[str, Any]:
    """The source's quasi-static labels, read by column name; a label the source trial did not
    record is None (null in the records), never a verdict.

    Records written before the validity gate (no ``success_unbounded`` / ``valid_geometry``
    columns) hold the unbounded reading in ``success``; then the gate is applied here with the
    source's fingertip radius and ``qs_gate_derived`` says so. Where the columns exist but a trial
    has no reading (null: an older file of a resumed run, an ingested one), its label is None: the
    agreement tables count the trial in ``unlabelled`` (``analysis.dynamic_check``), where
    ``bool()`` made a None a failure and a NaN a success.
    """
    radius_mm = source.study.model.fingertip_radius_m * 1e3
    delta = float(row["delta_max_mm"])
    gated = "success_unbounded" in row.index and "valid_geometry" in row.index
    if gated:
        unbounded, valid, success = (_label(row[c]) for c in ("success_unbounded", "valid_geometry",
                                                               "success"))
    else:
        unbounded, valid = _label(row["success"]), None if np.isnan(delta) else delta <= radius_mm
        success = None if unbounded is None or valid is None else unbounded and valid
    return {"qs_success": success, "qs_success_unbounded": unbounded, "qs_valid_geometry": valid,
            "qs_delta_max_mm": delta, "qs_gate_derived": not gated,
            "qs_failure_check": str(row.get("failure_check", ""))}


def _label(value) -> bool | None:
    """A recorded label as bool, None where it is missing (None or NaN, as a row of a records frame
    holds a null)."""
    return None if pd.isna(value) else bool(value)


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Re-plan one source trial, re-evaluate it quasi-statically under the preset, grasp it."""
    from graspcampaign.campaign.kinds.dynamic import grasp_params, grasp_record, msd_model, trial_study
    from graspcampaign.core.dynamics import prepare_grasp
    from graspcampaign.core.phase_kernel import GRASP_RUNNERS
    from graspcampaign.core.planner import evaluate_triple

    f, params = inp.trial.factors, inp.params
    source = load_source(inp.study.output.root, params.source_study, params.source_run)
    row = source.records.loc[f[SOURCE_ID]]
    vertex_ids, points, normals, ctx, plan_time = _replan(source, row)
    study = trial_study(inp.study, f)
    contact = common.contact_params(study)
    # like for like: Algorithms 1-2 (the source's settings) on these contacts under the preset
    preset_eq = evaluate_triple(ctx, points, normals, contact=contact)
    preset_valid = bool(preset_eq.delta_max_mm[0] <= contact.fingertip_radius * 1e3)
    nodes = len(ctx.vertices)
    mesh, msd, body = msd_model(f["shape"], nodes, study.model.e_object_pa, f["mass_kg"],
                                params.bulk_modulus_pa)
    start = time.perf_counter()
    setup, state = prepare_grasp(mesh, f["mu"], msd, contact, grasp_params(study, params),
                                 points=points, normals=normals, body=body)
    res = GRASP_RUNNERS[params.step](setup, state)
    grasp_time = time.perf_counter() - start
    return {
        "source_study": params.source_study, "source_run": params.source_run,
        "source_config_hash": source.config_hash, "nodes": nodes,
        **{f"vertex_{j + 1}": int(v) for j, v in enumerate(vertex_ids)},
        **{f"contact_normal_z_{j + 1}": float(normals[j, 2]) for j in range(3)},
        **source_labels(source, row),
        "qs_preset_success": bool(preset_eq.success[0]) and preset_valid,
        "qs_preset_success_unbounded": bool(preset_eq.success[0]),
        "qs_preset_valid_geometry": preset_valid,
        "qs_preset_delta_max_mm": float(preset_eq.delta_max_mm[0]),
        "qs_preset_failure_check": str(preset_eq.failure_labels()[0]),
        **grasp_record(res, contact, msd, params.t_max_s),
        "plan_time_s": plan_time, "grasp_time_s": grasp_time,
    }


DYNAMIC_CHECK = TrialKind(
    name="dynamic_check", run=run, params=DynamicCheckParams, design=design,
    seconds_per_trial=0.2, factors=("model_preset", *FILTERS), trial_keys=(*SCENE, SOURCE_ID),
    description="every quasi-static trial of a study re-run through the dynamic grasp "
                "(closure, lift-off, hold) per material preset; both labels recorded",
)
