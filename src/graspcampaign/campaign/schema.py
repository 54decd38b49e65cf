"""Typed config schemas for every group in ``conf/`` and for studies in ``campaigns/``.

Every YAML file names its schema on its first line (``# schema: StudyCfg``); ``SCHEMAS`` maps
those names to the dataclasses below. Hydra merges each YAML into its dataclass, so an unknown
key or a wrong type fails at load; ranges and allowed values are declared in each field's
``metadata`` and checked by :func:`check_config`, which names the offending key in one sentence.

Ranges: ``gt``/``ge``/``le`` bounds and ``choices`` (a tuple, or the name of a registry). Physical
quantities take their plausible range from :data:`graspcampaign.core.plausible.PLAUSIBLE`, with the
reason (``why``) shown in the error and the source documented there.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass, field
from typing import Any

from graspcampaign.campaign.former_names import FORMER_FACTORS, RENAMED_FACTORS, former_factor
from graspcampaign.campaign.override_scan import not_finite
from graspcampaign.core.plausible import FINGERTIP_RADIUS, PLAUSIBLE, bound_text
from graspcampaign.core.words import counted, meant, typed_value
from graspcampaign.errors import ConfigError

_LAMBDA = PLAUSIBLE["lambda"].meta()

#: The most trials one study may hold. A trial in memory costs ~0.8 KB before it runs (its factor
#: dict, ids and random-stream key; 813 B measured on baseline_grid at 450,000 trials, expanded in
#: 15 s on one core), so 10^6 trials are ~0.8 GB and ~35 s before the first one runs: 52 times
#: the largest study of the paper (test1_bench, 19,168 events), and the most a 2-core machine
#: with a few GB should be asked to hold (docs/decisions.md, "At most 10^6 trials per study").
MAX_TRIALS = 1_000_000
_MAX_TRIALS_WHY = f"a study holds at most {MAX_TRIALS:,} trials, docs/decisions.md"
#: The largest study seed: 2**32 - 1, the range of numpy's ``RandomState`` seed, which
#: scikit-learn's ``random_state`` (the surrogate's models and split) passes the seed to.
SEED_MAX = 2**32 - 1
_SEED_WHY = "a 32-bit word, the seeds numpy's RandomState takes"


def config_field(default: Any, **meta: Any) -> Any:
    """Declare a config dataclass field with the validation metadata :func:`check_value` reads.

    A list or dict default is copied for each instance; a list field's ``meta`` applies to each
    of its items.
    """
    if isinstance(default, (list, dict)):
        return field(default_factory=lambda d=default: type(d)(d), metadata=meta)
    return field(default=default, metadata=meta)


@dataclass
class ContactModelCfg:
    """Contact-law constants (Eq. 13-14, Table 2, Table 3)."""

    lambda1: float = config_field(0.332, **_LAMBDA)  # Table 3
    lambda2: float = config_field(0.880, **_LAMBDA)  # Table 3
    n_exp: float = config_field(0.487, **PLAUSIBLE["n_exp"].meta())  # Table 3 (Hunt-Crossley exponent)
    fingertip_radius_m: float = config_field(  # Table 2; the range is plan's, in metres
        FINGERTIP_RADIUS, **PLAUSIBLE["fingertip_radius_mm"].meta(scale=1e-3))
    e_finger_pa: float = config_field(0.0893e6, gt=0.0)  # Table 2
    e_object_pa: float = config_field(0.14e6, gt=0.0)  # Table 2
    nu_finger: float = config_field(0.5, ge=0.0, le=0.5)  # Table 2
    nu_object: float = config_field(0.45, ge=0.0, le=0.5)  # Table 2
    # Rate term of Eq. 13: linear C*delta_dot (the paper) or the original Hunt-Crossley form
    damping_law: str = config_field("linear", choices=("linear", "hunt_crossley"))
    alpha_hc_s_per_m: float = config_field(5.9, ge=0.0)  # (1 - e)/v_i, e = 0.882 (Sec. 7.2), v_i = 20 mm/s


@dataclass
class EvaluatorCfg:
    """Quasi-static evaluator (Algorithms 1-2, Sec. 6.1, Sec. 11)."""

    seed_depth_m: float = config_field(5e-4, gt=0.0)  # Alg. 2 line 1
    n_max: int = config_field(100, ge=1)  # Sec. 11
    alpha: float = config_field(1.0, gt=0.0)  # documented in docs/decisions.md
    eps: float = config_field(1e-6, gt=0.0)  # N/m; documented in docs/decisions.md
    tau_f_n: float = config_field(0.5, gt=0.0)  # Sec. 3.7: simulation criterion
    tau_t_nm: float = config_field(0.025, gt=0.0)  # documented in docs/decisions.md
    n_cand: int = config_field(1000, ge=1)  # documented in docs/decisions.md
    residual_check: str = config_field("norm", choices=("norm", "vertical"))  # SPEC 2.7: |R|
    # Grip laws (issue 13; SPEC 8): paper = Algorithm 2 as published (the default).
    grip_law: str = config_field("paper", choices=("paper", "slip", "oracle"))
    grip_safety_factor: float = config_field(1.5, gt=1.0)  # slip/oracle design margin; docs/decisions.md
    # Deepest penetration slip/oracle may command [m]; None: the Table 4 damage depth of the
    # family nearest in modulus to model.e_object_pa, bounded by the fingertip radius.
    grip_cap_depth_m: float | None = config_field(None, gt=0.0)
    oracle_cone_facets: int = config_field(16, ge=3)  # facets of the oracle's polyhedral cones (statics)
    fc_cone_edges: int = config_field(8, ge=3)  # Ferrari-Canny linearised cone edges (issue 17)


@dataclass
class FeatureCfg:
    """Sharp-feature thresholds (Sec. 3.1, Sec. 11)."""

    vertex_defect_rad: float = config_field(0.2, gt=0.0)
    edge_dihedral_deg: float = config_field(30.0, gt=0.0, le=180.0)
    edge_proximity_factor: float = config_field(0.5, ge=0.0)
    resolution_aware: bool = False


@dataclass
class PsoCfg:
    """Particle swarm identification (Sec. 4, Sec. 11)."""

    enabled: bool = True
    n_particles: int = config_field(8, ge=1)  # Sec. 6.8 repeatability budget
    n_iterations: int = config_field(15, ge=1)  # Sec. 6.8
    inertia: float = config_field(0.7, ge=0.0)  # Sec. 11
    c1: float = config_field(1.5, ge=0.0)  # Sec. 11
    c2: float = config_field(1.5, ge=0.0)  # Sec. 11


@dataclass
class RunnerCfg:
    """Where and how trials run."""

    backend: str = config_field("loky", choices=("loky", "dask", "sequential"))
    # joblib's n_jobs (0 means nothing); said_as: other tools' words for it, answered with n_jobs
    n_jobs: int = config_field(-1, ne=0, said_as=("cores", "workers", "jobs", "threads"), why="joblib's "
                               "n_jobs: a number of worker processes, or -1 for every core, -2 for every "
                               "core but one")
    address: str | None = None  # Dask scheduler address; None starts a LocalCluster
    # trials per task (no more than a study holds); 0 sizes tasks to ~target_task_s
    batch_size: int = config_field(0, ge=0, le=MAX_TRIALS, why=_MAX_TRIALS_WHY)
    target_task_s: float = config_field(0.5, gt=0.0)  # SPEC Sec. 5: 0.2-1 s of compute per task
    progress: bool = True
    # without a terminal (make, CI, batch jobs): one progress line at most this often; 30 s keeps a
    # 10-minute study at ~20 lines of log (docs/decisions.md)
    progress_interval_s: float = config_field(30.0, ge=0.0)
    # a Dask scheduler that does not answer within this time is reported, not waited for; 5 s is
    # ~100x a LAN round trip (docs/decisions.md)
    connect_timeout_s: float = config_field(5.0, gt=0.0)

    def workers(self) -> int:
        """Worker processes a run uses (joblib's reading of ``n_jobs``: -1 every core, -2 every
        core but one, ..., at least one)."""
        import os

        if self.backend == "sequential":
            return 1
        if self.n_jobs < 0:
            return max(1, (os.cpu_count() or 1) + 1 + self.n_jobs)
        return self.n_jobs


@dataclass
class OutputCfg:
    """Where records go: ``<root>/<study>/<run>/``."""

    root: str = "results"
    run: str = "default"


@dataclass
class StudyCfg:
    """One study: its design (factors, seeds), trial kind, fixed parameters and paper values."""

    name: str = "???"
    kind: str = "???"
    description: str = ""
    seed: int = config_field(0, ge=0, le=SEED_MAX, why=_SEED_WHY)  # root of every trial's stream
    seeds: int = config_field(1, ge=1, le=MAX_TRIALS, why=_MAX_TRIALS_WHY)  # seed indices 0..seeds-1
    repeats: int = config_field(1, ge=1, le=MAX_TRIALS, why=_MAX_TRIALS_WHY)  # repeats of each scene
    factors: dict[str, list[Any]] = field(default_factory=dict)
    zip: list[list[str]] = field(default_factory=list)  # factor groups advanced together
    method_factors: list[str] = field(default_factory=lambda: ["planner", "variant"])
    params: dict[str, Any] = field(default_factory=dict)  # kind-specific, see the kind's schema
    paper: dict[str, Any] = field(default_factory=dict)  # the paper's reported values
    # the paper study whose values the `paper:` block holds and whose report this study uses
    # (default: the study's own name); lets a variant (grip_laws, a user's copy) compare with it
    compare_with: str = ""
    # a study the paper does not run (SPEC §8: grip_laws, dynamic_check): `make reproduce` runs
    # the paper's studies, `make extensions` these (docs/decisions.md, "make reproduce")
    extension: bool = False
    model: ContactModelCfg = field(default_factory=ContactModelCfg)
    evaluator: EvaluatorCfg = field(default_factory=EvaluatorCfg)
    features: FeatureCfg = field(default_factory=FeatureCfg)
    pso: PsoCfg = field(default_factory=PsoCfg)
    runner: RunnerCfg = field(default_factory=RunnerCfg)
    output: OutputCfg = field(default_factory=OutputCfg)


SCHEMAS: dict[str, type] = {
    "StudyCfg": StudyCfg,
    "ContactModelCfg": ContactModelCfg,
    "EvaluatorCfg": EvaluatorCfg,
    "FeatureCfg": FeatureCfg,
    "PsoCfg": PsoCfg,
    "RunnerCfg": RunnerCfg,
    "OutputCfg": OutputCfg,
}


def _registry_names(name: str) -> tuple[str, ...]:
    """Return the allowed values of a registry-backed choice (``shape``, ``planner``)."""
    from graspcampaign.campaign.catalog import registry_names

    if name == "model":  # the presets of the model group: conf/model/<name>.yaml (files, not code)
        from graspcampaign.campaign.studyfile import group_options

        return group_options("model")
    return registry_names(name)


PSO_BUDGETS = ("repeatability", "converged")
"""pso_repeatability's ``budget`` levels: the study's ``pso`` group (Sec. 6.8's 8 x 15), or the
kind's converged budget of Sec. 11 (``campaign.kinds.pso``)."""

#: Mesh resolution bounds of the ``nodes`` factor and of every kind parameter that names a node
#: count. 12 is ``core.mesh.MIN_NODES`` (the smallest closed mesh the generators build); 20,000 is
#: 11x the paper's finest mesh (1750 nodes, Sec. 6.7): on a 120 mm object its nodes lie 1.5 mm
#: apart, a third of the 5 mm fingertip radius (Table 2), so a finer mesh resolves nothing a
#: fingertip feels, while each body costs ~4 s to build (docs/decisions.md, "Mesh and time bounds").
NODES = {"ge": 12, "le": 20_000,
         "why": "a closed mesh needs 12 nodes, and one finer than 20,000 resolves nothing a 5 mm "
                "fingertip feels"}

#: Bound of a dynamic kind's simulated time budget [s]: a grasp closes, lifts and holds within about
#: a second (the default 1 s; 1 mm gap at 20 mm/s, a 0.1 s lift), so 60 s is 60x that and, at the
#: ~31 us RK4 step, ~2x10^6 steps per trial (docs/decisions.md, "Mesh and time bounds").
SIM_TIME_S = {"gt": 0.0, "le": 60.0,
              "why": "a grasp closes, lifts and holds within seconds; 60 s is ~2x10^6 RK4 steps"}

# Known factors: name -> validation metadata. A factor not listed here is rejected, so a typo in a
# study file or an override fails at load instead of silently adding an axis.
FACTOR_SPECS: dict[str, dict[str, Any]] = {
    "shape": {"type": str, "choices": "shape"},
    "planner": {"type": str, "choices": "planner"},
    "mass_kg": {"type": float, **PLAUSIBLE["mass_kg"].meta()},
    "mu": {"type": float, **PLAUSIBLE["mu"].meta()},
    "nodes": {"type": int, **NODES},
    "n_cand": {"type": int, "ge": 1},
    "lambda1": {"type": float, **_LAMBDA},
    "lambda2": {"type": float, **_LAMBDA},
    "n_exp": {"type": float, **PLAUSIBLE["n_exp"].meta()},
    "b": {"type": float, **PLAUSIBLE["b"].meta()},  # MSD nodal damping, internal units (Sec. 11)
    "n_max": {"type": int, "ge": 1},
    "dt_s": {"type": float, "gt": 0.0},
    "weight_scale": {"type": float, "gt": 0.0},
    "w1": {"type": float, "ge": 0.0},
    "w2": {"type": float, "ge": 0.0},
    "w3": {"type": float, "ge": 0.0},
    "variant": {"type": str},
    "pso_seed": {"type": int, "ge": 0},
    "budget": {"type": str, "choices": PSO_BUDGETS},
    "integrator": {"type": str, "choices": ("rk4", "implicit")},
    "damping_law": {"type": str, "choices": ("linear", "hunt_crossley")},
    # a conf/model preset per trial, in place of the study's model group (dynamic_grasp)
    "model_preset": {"type": str, "choices": "model"},
    "grip_law": {"type": str, "choices": ("paper", "slip", "oracle")},  # issue 13, item 3
}


def _fmt_allowed(meta: dict[str, Any]) -> str:
    """The bounds of ``meta`` as ``plan`` prints a plausible range: ``>= 0 and <= 3``."""
    signs = {"gt": ">", "ge": ">=", "le": "<=", "ne": "!="}
    return " and ".join(f"{sign} {bound_text(meta[key])}" for key, sign in signs.items() if key in meta)


def not_finite_text(key: str, value: Any) -> str | None:
    """The sentence refusing text given for a number ``key`` that reads as no finite number (YAML
    reads ``1e400`` as text, Python's ``float`` as inf; ``nan``), naming it as typed; or None."""
    if isinstance(value, str) and len(value.split()) == 1 and (number := not_finite(value.strip())):
        return f"{key}: {number}; give a finite number."
    return None


def check_value(key: str, value: Any, meta: dict[str, Any]) -> Any:
    """Check one value against its metadata and return it (coerced to the declared type).

    Raises
    ------
    ConfigError
        One sentence naming ``key``, the offending value and the allowed values.
    """
    typ = meta.get("type")
    if typ is not None and value is not None:
        if typ is float and isinstance(value, (int, float)) and not isinstance(value, bool):
            value = float(value) + 0.0  # -0.0 + 0.0 is 0.0: one zero, one level, one id
        elif typ is int and isinstance(value, int) and not isinstance(value, bool):
            pass
        elif typ is str and isinstance(value, str):
            pass
        elif typ in (int, float) and (overflow := not_finite_text(key, value)):
            raise ConfigError(overflow, key=key)
        else:
            raise ConfigError(f"{key} must be of type {typ.__name__}, got {typed_value(value)}.", key=key)
    choices = meta.get("choices")
    if choices is not None:
        allowed = _registry_names(choices) if isinstance(choices, str) else tuple(choices)
        if value not in allowed:
            near = meant(value, allowed) if isinstance(value, str) else ""
            raise ConfigError(f"{key} has unknown value {value!r}; {near}allowed values: "
                              f"{', '.join(map(str, allowed))}.", key=key)
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if isinstance(value, float) and not math.isfinite(value):
            raise ConfigError(f"{key} must be finite, got {value!r}.", key=key)
        bad = (
            ("gt" in meta and not value > meta["gt"])
            or ("ge" in meta and not value >= meta["ge"])
            or ("le" in meta and not value <= meta["le"])
            or ("ne" in meta and value == meta["ne"])
        )
        if bad:
            why = f" ({meta['why']})" if meta.get("why") else ""
            raise ConfigError(f"{key} = {value!r} is out of range; allowed: {_fmt_allowed(meta)}"
                              f"{why}.", key=key)
    return value


def check_config(obj: Any, prefix: str = "") -> None:
    """Walk a config dataclass and check every field's range and allowed values."""
    for f in dataclasses.fields(obj):
        key = f"{prefix}{f.name}"
        value = getattr(obj, f.name)
        if dataclasses.is_dataclass(value):
            check_config(value, prefix=f"{key}.")
        elif f.metadata:
            check_value(key, value, dict(f.metadata))


def check_study(study: StudyCfg) -> None:
    """Check a whole study: group ranges, factor names and levels, zip groups (``grid.check_zip``).

    Raises
    ------
    ConfigError
        For the first problem found, naming its key.
    """
    from graspcampaign.campaign.paths import check_name

    check_name(study.name, "name")
    check_name(study.output.run, "output.run")
    check_config(study)
    address = study.runner.address
    if address is not None and not re.fullmatch(
            r"(tcp|tls|ucx|inproc|ws|wss)://[^\s/:]+(:\d+)?/?", str(address)):
        raise ConfigError(f"runner.address = {address!r} is not a Dask scheduler address; "
                          "expected e.g. tcp://host:8786.", key="runner.address")
    if address is not None and study.runner.backend != "dask":  # else the trials run here, unsaid
        raise ConfigError(f"runner.address = {address!r} names a Dask scheduler, but runner.backend = "
                          f"{study.runner.backend} runs the trials on this machine and would ignore "
                          "it: add runner.backend=dask, or drop runner.address.", key="runner.address")
    check_workers(study.runner)
    if (name := next((n for n in study.method_factors if n in FORMER_FACTORS), None)) is not None:
        raise ConfigError(former_factor(name, f"method_factors' {name}", fixed=RENAMED_FACTORS[name]),
                          key="method_factors")
    for name, levels in study.factors.items():
        check_factor(name, levels)
    from graspcampaign.campaign.grid import check_zip  # grid imports this module

    check_zip(study)
    check_design_size(study)


#: The most worker processes per core a run starts (docs/decisions.md, "A bound on runner.n_jobs").
WORKERS_PER_CORE = 4


def most_workers() -> tuple[int, int]:
    """This machine's cores (1 where unknown) and the most worker processes allowed on it,
    :data:`WORKERS_PER_CORE` per core (``runner.n_jobs``, ``report --jobs``)."""
    import os

    cores = os.cpu_count() or 1
    return cores, WORKERS_PER_CORE * cores


def check_workers(runner: RunnerCfg) -> None:
    """Refuse more worker processes than :data:`WORKERS_PER_CORE` per core of this machine (joblib
    and a Dask LocalCluster start as many as ``n_jobs`` says; a remote cluster has its own), and a
    negative ``n_jobs`` leaving more cores unused than the machine has (joblib reads it as one
    worker, silently: -1000000 meant 1)."""
    cores, most = most_workers()
    if runner.address is None and runner.backend != "sequential" and runner.n_jobs < -cores:
        raise ConfigError(
            f"runner.n_jobs = {runner.n_jobs} would leave {-runner.n_jobs - 1:,} cores unused, "
            f"and this machine has {cores}; give a number of worker processes (1 to {most}), or "
            f"-1 for one per core down to -{cores} for one worker.", key="runner.n_jobs")
    if runner.address is None and runner.workers() > most:
        raise ConfigError(
            f"runner.n_jobs = {runner.n_jobs} would start {runner.n_jobs:,} worker processes, more "
            f"than {WORKERS_PER_CORE} per core of this machine ({counted(cores, 'core')}); trials "
            "compute, so more workers than cores only share them, each holding its own memory: "
            f"give at most {most}, or -1 for one per core.", key="runner.n_jobs")


def check_factor(name: str, levels: Any) -> None:
    """Check one factor: a known name and a non-empty list of distinct levels, each of its type
    (null is no level) and in its range; levels are coerced in place (``1`` -> ``1.0``).

    Raises
    ------
    ConfigError
        Naming ``factors.<name>`` (or the level ``factors.<name>[i]``) and what is allowed.
    """
    key = f"factors.{name}"
    if name in FORMER_FACTORS:
        raise ConfigError(former_factor(name, key), key=key)
    if name not in FACTOR_SPECS:
        raise ConfigError(f"{key} is not a known factor; {meant(name, FACTOR_SPECS, 'factors.{}')}"
                          f"known factors: {', '.join(sorted(FACTOR_SPECS))}.", key=key)
    if not isinstance(levels, list) or not levels:
        raise ConfigError(f"{key} must be a non-empty list of levels.", key=key)
    spec = FACTOR_SPECS[name]
    for i, value in enumerate(levels):
        if value is None:  # a factor's level is a value: null would reach a trial as None
            raise ConfigError(f"{key}[{i}] must be of type {spec['type'].__name__}, got null; "
                              f"give the factor's levels, e.g. {name}: {example(name)}.",
                              key=f"{key}[{i}]")
    levels[:] = [check_value(f"{key}[{i}]", v, spec) for i, v in enumerate(levels)]
    first: dict[str, int] = {}
    for i, value in enumerate(levels):  # the level itself: a long list is never printed whole
        j = first.setdefault(repr(value), i)
        if j != i:
            raise ConfigError(f"{key} lists the level {value!r} twice ({key}[{j}] and {key}[{i}]); "
                              "give each level once.", key=f"{key}[{i}]")


def example(name: str) -> str:
    """A level list to show in a message about factor ``name``."""
    spec = FACTOR_SPECS.get(name, {})
    if spec.get("type") is str:
        choices = spec.get("choices")  # a placeholder [a, b] would itself be refused
        return {"shape": "[sphere, pear]", "planner": "[heuristic, random]"}.get(
            name, f"[{', '.join(choices[:2])}]" if choices else "[a, b]")
    return {"mu": "[0.3, 0.5]", "mass_kg": "[0.2, 0.4]", "nodes": "[144, 390]"}.get(
        name, "[1, 2]" if spec.get("type") is int else "[0.5, 1.0]")


def design_shape(study: StudyCfg) -> dict[str, int]:
    """Return the length of every design axis by its name (see ``grid.design_axes``; a zipped group
    ``a + b``, then ``seeds`` and ``repeats`` when more than one), computed from the level counts
    alone: nothing is expanded, so a design of 10^20 trials costs nothing."""
    zipped = {name: group for group in study.zip for name in group}
    sizes = {}
    for name in study.factors:
        group = zipped.get(name, [name])
        sizes[" + ".join(group)] = min(len(study.factors[g]) for g in group)
    sizes["seeds"] = study.seeds
    if study.repeats > 1:
        sizes["repeats"] = study.repeats
    return sizes


def check_design_size(study: StudyCfg, n: int | None = None) -> None:
    """Refuse a design of more than :data:`MAX_TRIALS` trials before it is expanded.

    ``n`` is the size of an explicit design (a kind's schedule); by default the Cartesian product.

    Raises
    ------
    ConfigError
        Naming the trial count, its axes and the limit.
    """
    sizes = design_shape(study).values()
    count = math.prod(sizes) if n is None else n
    if count > MAX_TRIALS:
        axes = f" ({' x '.join(map(str, sizes))})" if n is None else ""
        raise ConfigError(
            f"study {study.name} has {count:,} trials{axes}, more than the {MAX_TRIALS:,} a study "
            f"may hold (each costs ~0.8 KB of memory before it runs, docs/decisions.md); reduce "
            f"seeds, repeats or the factor levels, or split the study.")


def check_design_rows(rows: list[dict[str, Any]]) -> None:
    """Check the physical factors of an explicit design (one dict per trial) against their
    plausible ranges (the factors whose spec carries a ``why``).

    A kind's design is computed from its ``params``; a value out of its plausible range means a
    parameter set it so. Other factors are the kind's own business (e.g. ``n_cand = 0`` meaning
    "the study's default").

    Raises
    ------
    ConfigError
        Naming the trial, the factor and the allowed range.
    """
    numeric = {k: v for k, v in FACTOR_SPECS.items() if "why" in v}
    for name, meta in numeric.items():
        for i, row in enumerate(rows):
            if name in row and row[name] is not None:
                try:
                    check_value(f"factor {name}", row[name], meta)
                except ConfigError as exc:
                    raise ConfigError(f"trial {i} of the design computed from params: {exc} "
                                      "Check the params that set it.") from None
