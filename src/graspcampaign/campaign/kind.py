"""Trial kinds: what one trial computes, and the explicit registry that maps names to code.

A study names its trial kind; the name maps to an implementation through ``KINDS`` below, never
through a string a config could point anywhere. A kind whose implementation does not exist yet is
registered with ``None``: ``graspcampaign list`` shows its studies as not yet runnable and ``run``
refuses them before writing anything.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from graspcampaign.campaign.grid import Trial
from graspcampaign.campaign.schema import StudyCfg
from graspcampaign.core.words import meant
from graspcampaign.errors import StudyNotRunnableError


@dataclass(frozen=True)
class TrialInput:
    """What a kind's ``run`` receives for one trial."""

    trial: Trial
    study: StudyCfg
    params: Any  # the kind's params dataclass instance (or the raw dict if it has none)
    prepared: dict[str, Any] | None  # the shared preparation of this trial's body, if any


@dataclass(frozen=True)
class TrialKind:
    """What one trial of a study computes.

    ``run(inp, rng)`` returns a flat dict of record columns (units in every name). It may also
    return ``"__tables__": {name: {column: list}}`` for per-step traces, stored beside the records
    and keyed by ``trial_id``.

    ``body_key(factors)`` and ``prepare(study, params, body, rng)`` describe a shared preparation
    computed once per distinct key before the trials that need it (e.g. a PSO identification per
    soft body); preparations are stored as records of their own and reused on resume.

    ``design(study, params)``, when given, returns the trial list explicitly (one dict of factor
    values per trial, e.g. a hardware protocol's commanded schedule) instead of the Cartesian
    product of ``study.factors``.

    ``finalize(study, params, records, store)`` runs once every trial is recorded and returns
    study-level tables ``{name: list of row dicts}`` (e.g. the PSO re-identification of Test 1,
    or the surrogate's model fits); they are stored in ``summary/<name>/`` and recomputed only when
    missing.

    Hardware protocols also supply ``schedule(study, params) -> DataFrame`` (the commanded sheet
    written by ``graspcampaign schedule``) and ``ingest(study, params, paths, stored) ->
    list[dict]`` (measured records, validated before anything is stored, ``stored`` the run's
    records already stored as a DataFrame or None; raises a ``UserInputError`` / ``IngestError``
    naming file, row and column), and ``template(study, params, schedule) -> (sheet, columns)``:
    the measured-records sheet to fill in (every column, empty) and a table of its columns with
    type, unit, allowed values and when required (``graspcampaign schedule --template``).

    ``factors`` names the factors ``run`` reads on every trial of a Cartesian design; a study
    without one of them is refused when it is composed, naming it (a ``KeyError`` in every trial
    otherwise). With an explicit ``design`` it names the factors the design reads from the study
    (dynamic_check's presets and source filters); a study setting another is refused, as it
    would change nothing but the config hash.

    ``optional_factors`` names the further factors ``run`` reads when a Cartesian study sets them
    (``nodes``, ``grip_law``, ...); a Cartesian study setting a factor in neither tuple is refused
    when it is composed, as it would only repeat every trial with an unread column. ``None`` (the
    default, kept for kinds registered at run time by tests and benchmarks) declares nothing and
    skips that check; every shipped kind declares it (tests/cli/test_bad_input_round22.py).

    ``trial_keys`` names the keys a trial of this kind holds besides the study's factors, ``seed``
    and ``repeat`` (a designed kind's own columns, dynamic_check's ``source_trial_id``): with every
    known factor name, what ``method_factors`` may name (a name outside them has no effect). A
    protocol declares its schedule's columns (``rig``'s column tuples, which build the schedule).
    """

    name: str
    run: Callable[[TrialInput, Any], dict[str, Any]]
    params: type | None = None
    source: str = "simulation"  # simulation | virtual | measured
    seconds_per_trial: float = 0.01  # rough estimate for `show` and task sizing
    body_key: Callable[[dict[str, Any]], dict[str, Any]] | None = None
    prepare: Callable[..., dict[str, Any]] | None = None
    design: Callable[[StudyCfg, Any], list[dict[str, Any]]] | None = None
    finalize: Callable[..., dict[str, list[dict[str, Any]]]] | None = None
    schedule: Callable[[StudyCfg, Any], Any] | None = None
    ingest: Callable[[StudyCfg, Any, list[str], Any], list[dict[str, Any]]] | None = None
    template: Callable[[StudyCfg, Any, Any], tuple[Any, Any]] | None = None
    description: str = ""
    #: what a run does besides its trials (its prepare or finalize stage), in words for `show`,
    #: whose time estimate counts trials only; with its cost at paper scale where it was measured
    stages: str = ""
    factors: tuple[str, ...] = ()
    optional_factors: tuple[str, ...] | None = None
    trial_keys: tuple[str, ...] = ()
    extra: dict[str, Any] = field(default_factory=dict)


# name -> "module:attribute" of a TrialKind, or None while not implemented (`graspcampaign list`
# then shows its studies as not yet runnable).
KINDS: dict[str, str | None] = {
    "mesh_features": "graspcampaign.campaign.kinds.smoke:MESH_FEATURES",
    "quasi_static": "graspcampaign.campaign.kinds.quasi_static:QUASI_STATIC",
    "heuristic_weights": "graspcampaign.campaign.kinds.weights:HEURISTIC_WEIGHTS",
    "wrench_balance": "graspcampaign.campaign.kinds.wrench:WRENCH_BALANCE",
    "pso_repeatability": "graspcampaign.campaign.kinds.pso:PSO_REPEATABILITY",
    "gravity_settle": "graspcampaign.campaign.kinds.dynamic:GRAVITY_SETTLE",
    "dynamic_grasp": "graspcampaign.campaign.kinds.dynamic:DYNAMIC_GRASP",
    "dynamic_check": "graspcampaign.campaign.kinds.dynamic_check:DYNAMIC_CHECK",
    "sensitivity": "graspcampaign.campaign.kinds.sensitivity:SENSITIVITY",
    "mesh_resolution": "graspcampaign.campaign.kinds.mesh_resolution:MESH_RESOLUTION",
    "surrogate": "graspcampaign.campaign.kinds.surrogate:SURROGATE",
    "test1_bench": "graspcampaign.campaign.kinds.test1:TEST1_BENCH",
    "test2_grasp": "graspcampaign.campaign.kinds.hardware:TEST2_GRASP",
    "test3_disturbance": "graspcampaign.campaign.kinds.hardware:TEST3_DISTURBANCE",
}

RUNTIME_KINDS: dict[str, TrialKind] = {}
"""Kinds registered at run time by :func:`register_kind` (tests and benchmarks); never cached."""


def register_kind(kind: TrialKind) -> None:
    """Register a kind defined outside this package (tests and benchmarks)."""
    RUNTIME_KINDS[kind.name] = kind


def kind_available(name: str) -> bool:
    """Return whether a kind is implemented and importable."""
    return name in RUNTIME_KINDS or KINDS.get(name) is not None


def get_kind(name: str) -> TrialKind:
    """Resolve a kind name to its implementation.

    Raises
    ------
    StudyNotRunnableError
        When the kind is unknown or not implemented yet.
    """
    if name in RUNTIME_KINDS:
        return RUNTIME_KINDS[name]
    if name not in KINDS:
        raise StudyNotRunnableError(
            f"trial kind {name!r} is unknown; {meant(name, sorted(KINDS))}known kinds: "
            f"{', '.join(sorted(KINDS))}.")
    target = KINDS[name]
    if target is None:
        raise StudyNotRunnableError(
            f"trial kind {name!r} is not implemented yet, so this study cannot run."
        )
    module, attr = target.split(":")
    return getattr(importlib.import_module(module), attr)
