"""What ``list`` and ``show`` need to know about the code, computed once per code version.

``graspcampaign list`` and ``show`` answer in well under a second because they import neither the
numerical layers nor, for ``list``, Hydra. Three facts would need those imports: the names in the
shape and planner registries (to validate factor levels), a trial kind's facts (its time per trial,
whether it has an explicit design, its data source), and the size of an explicit design (a hardware
protocol's schedule takes seconds to build). They are computed on first use and kept in a small
JSON file keyed by a hash of the package's source files, so any change of the code recomputes them:
a cached answer is always the one the code would give.

Cache file: ``$GRASPCAMPAIGN_CACHE/catalog.json`` (default ``$XDG_CACHE_HOME/graspcampaign``, i.e.
``~/.cache/graspcampaign``). It holds nothing but these facts; deleting it costs one slow call. An
unwritable cache directory only makes ``list`` and ``show`` slower.
"""

from __future__ import annotations

import errno
import hashlib
import json
import logging
import os
from functools import cache
from pathlib import Path
from typing import Any

import graspcampaign
from graspcampaign.campaign.paths import config_root, expand_home, path_problem

log = logging.getLogger(__name__)


@cache
def source_hash() -> str:
    """Hash of every ``.py`` file of the installed package (paths and contents)."""
    root = Path(graspcampaign.__file__).resolve().parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def cache_path() -> Path:
    """Return the catalog's cache file (see the module docstring), ``~`` read as a shell reads it.

    Raises
    ------
    OSError
        When its place names a home directory that cannot be found (``~nosuchuser/cache``; no
        HOME): there is no cache then, as when it cannot be written.
    """
    base = os.environ.get("GRASPCAMPAIGN_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join("~", ".cache"), "graspcampaign")
    path, unknown = expand_home(base)
    if unknown:
        raise OSError(errno.ENOENT, unknown)
    return path / "catalog.json"


def _cache_unusable(exc: OSError) -> None:
    """Say that the cache cannot be written (``list`` and ``show`` then recompute their facts,
    slower): a warning, printed once per command, where the user chose the place; quietly
    otherwise."""
    chosen = os.environ.get("GRASPCAMPAIGN_CACHE")
    if not chosen:
        log.debug("catalog cache not written (%s)", exc)
        return
    import warnings

    base = expand_home(chosen)[0]
    reason = ("is not a directory" if os.path.exists(base) and not os.path.isdir(base)
              else path_problem(base) if os.path.islink(base) and not os.path.exists(base)
              else f"cannot be written ({exc.strerror or type(exc).__name__})")
    warnings.warn(f"GRASPCAMPAIGN_CACHE={chosen} {reason}, so the catalog cache is not kept; list "
                  "and show work without it, recomputing what they need (slower).", stacklevel=3)


def _load() -> dict[str, Any]:
    try:  # no regular file there (a named pipe, whose read waits for ever): none
        data = json.loads(path.read_text()) if (path := cache_path()).is_file() else None
    except (OSError, ValueError):
        return {"source": source_hash()}
    # a file this code did not write (valid JSON, but a list, or a section that is no mapping) is
    # as good as none: the facts are recomputed and the file written over
    if not isinstance(data, dict) or data.get("source") != source_hash():
        return {"source": source_hash()}
    return {k: v for k, v in data.items() if k == "source" or isinstance(v, dict)}


def _remember(section: str, key: str, value: Any) -> None:
    """Store one fact (re-reading the file first, so concurrent writers lose little)."""
    data = _load()
    data.setdefault(section, {})[key] = value
    try:
        path = cache_path()
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        tmp.write_text(json.dumps(data, sort_keys=True))
        os.replace(tmp, path)
    except OSError as exc:
        _cache_unusable(exc)


def _fact(section: str, key: str, compute) -> Any:
    known = _load().get(section, {})
    if key in known:
        return known[key]
    value = compute()
    _remember(section, key, value)
    return value


def registry_names(name: str) -> tuple[str, ...]:
    """Return the names of the ``shape`` or ``planner`` registry (``core.mesh.SHAPES``,
    ``core.planner.PLANNERS``)."""

    def compute() -> list[str]:
        if name == "shape":
            from graspcampaign.core.mesh import SHAPES

            return list(SHAPES)
        if name == "planner":
            from graspcampaign.core.planner import PLANNERS

            return list(PLANNERS)
        raise KeyError(name)

    return tuple(_fact("registries", name, compute))


def kind_facts(name: str) -> dict[str, Any]:
    """Return ``{"seconds_per_trial", "design", "source", "factors", "trial_keys", "params",
    "stages", "finalize"}`` of an available trial kind (``finalize``: whether it has that
    stage): ``factors`` the factors a Cartesian design must have, ``optional_factors`` those
    its ``run`` reads when set (None: not declared),
    ``trial_keys`` the keys its trials hold besides the factors (``TrialKind.trial_keys``),
    ``params`` its params schema as ``{"name", "fields": [[name, annotation, metadata], ...]}``
    (None: it takes none), so that ``show`` checks a study's params as ``run`` does without
    importing the kind."""
    from graspcampaign.campaign.kind import RUNTIME_KINDS, get_kind

    def compute() -> dict[str, Any]:
        kind = get_kind(name)
        return {"seconds_per_trial": kind.seconds_per_trial, "design": kind.design is not None,
                "source": kind.source, "factors": list(kind.factors),
                "optional_factors": (None if kind.optional_factors is None
                                     else list(kind.optional_factors)),
                "trial_keys": list(kind.trial_keys),
                "params": params_spec(kind.params), "stages": kind.stages,
                "finalize": kind.finalize is not None}

    if name in RUNTIME_KINDS:  # kinds registered at run time (tests) are never cached
        return compute()
    return _fact("kinds", name, compute)


def params_spec(schema: type | None) -> dict[str, Any] | None:
    """Describe a params dataclass in JSON terms: its name, and each field's name, annotation
    (``'int'``, ``'list[str]'``) and validation metadata (tuples as lists)."""
    import dataclasses

    if schema is None:
        return None
    fields = [[f.name, f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type)),
               json.loads(json.dumps(dict(f.metadata), default=str))]
              for f in dataclasses.fields(schema)]
    return {"name": schema.__name__, "fields": fields}


def design_size(study) -> int:
    """Return a study's trial count: its Cartesian product, or its kind's explicit design."""
    from graspcampaign.campaign.grid import n_trials
    from graspcampaign.campaign.kind import kind_available

    if not kind_available(study.kind) or not kind_facts(study.kind)["design"]:
        return n_trials(study)
    from graspcampaign.campaign.provenance import config_hash

    def compute() -> int:
        from graspcampaign.campaign.kind import get_kind
        from graspcampaign.campaign.runner import kind_params

        kind = get_kind(study.kind)
        rows = kind.design(study, kind_params(study, kind))
        from graspcampaign.campaign.schema import check_design_rows

        check_design_rows(rows)
        return len(rows)

    from graspcampaign.campaign.kind import RUNTIME_KINDS

    if study.kind in RUNTIME_KINDS:
        return compute()
    # a design read from another run's records: keyed on that run too, which its config hash
    # leaves out (output.root is where it runs, not what)
    source = _source_key(study.params, study.output.root)
    read = f":{source}" if source is not None else ""
    return int(_fact("designs", f"{study.kind}:{config_hash(study)}{read}", compute))


def _source_key(params: dict[str, Any], root: str) -> str | None:
    """What a cached design or size of a study is keyed on besides the study, where its design is
    read from another run (``params.source_study`` and ``source_run``, dynamic_check's): that
    run's absolute path and what of its manifest the design follows (:func:`_source_state`);
    None for a study whose design reads no run."""
    source = params.get("source_study")
    if not source:
        return None
    run = Path(config_root(root)) / source / params.get("source_run", "default")  # ~ as compose
    state = [str(run.absolute()), _source_state(_read_or_none(run / "manifest.json"))]  # reads it
    return hashlib.sha256(json.dumps(state).encode()).hexdigest()[:16]


def _source_state(manifest: bytes) -> Any:
    """What of a source run's ``manifest`` (its bytes) the design read from the run follows: its
    config hash (its trials), its recorded count and every session that may have recorded trials
    (their records' labels are the trials checked): a session that ran none, such as a resume of
    the finished run, changes neither, so it adds no entry to the catalog. The text itself where
    it is no manifest (none, or damaged: reading the design names what is wrong)."""
    try:
        read = json.loads(manifest)
        return [read["config_hash"], read.get("n_recorded"),
                [session for session in read["sessions"] if session.get("ran") != 0]]
    except (ValueError, KeyError, TypeError, AttributeError):
        return manifest.decode("utf-8", "replace")


def _read_or_none(path: Path) -> bytes:
    try:
        return path.read_bytes()
    except OSError:
        return b"<none>"


def _light_study(path: Path, data: dict[str, Any]):
    """A StudyCfg from a study file's own keys, without Hydra (the groups keep their defaults),
    and whether every value could be checked.

    ``list`` checks what it can without composing: every key, type and range of the file (groups
    included, :func:`studycheck.check_study_file`), the design and its size, the trial kind, its
    factors and params, the paper block. A value holding an interpolation (``${...}``) is
    resolved by ``show`` and ``run`` only: such a study is listed as not checked.
    """
    import copy
    import dataclasses

    from graspcampaign.campaign import studycheck
    from graspcampaign.campaign.schema import SCHEMAS, StudyCfg, check_study
    from graspcampaign.campaign.studyfile import project_dirs
    from graspcampaign.campaign.written import in_file
    from graspcampaign.errors import ConfigError

    studycheck.check_study_file(path, data)
    plain = {"name", "kind", "description", "seed", "seeds", "repeats", "factors", "zip",
             "method_factors", "params", "paper", "compare_with", "extension"}
    kwargs = {k: copy.deepcopy(v) for k, v in data.items()
              if k in plain and v is not None and not _interpolated(v)}
    checked = all(not _interpolated(v) for v in data.values())
    study = StudyCfg(**kwargs)
    for group in (f.name for f in dataclasses.fields(StudyCfg) if f.type in SCHEMAS):
        if isinstance(data.get(group), dict) and not _interpolated(data[group]):
            for key, value in data[group].items():
                setattr(getattr(study, group), key, value)
    try:
        check_study(study)
        if checked:
            studycheck.check_kind(study)
    except ConfigError as exc:
        raise in_file(path, exc) from None
    studycheck.check_paper_block(study, data.get("name"), path, project_dirs()[1])
    return study, checked


def _interpolated(value: Any) -> bool:
    """Whether a value holds an OmegaConf interpolation (``${...}``) anywhere."""
    if isinstance(value, str):
        return "${" in value
    if isinstance(value, dict):
        return any(map(_interpolated, value.values()))
    if isinstance(value, list):
        return any(map(_interpolated, value))
    return False


def study_row(path: Path) -> dict[str, Any]:
    """Return what ``graspcampaign list`` shows of a study file: name, kind, trials, runnable
    (the group files it composes with are checked once for every study, by the caller).

    Raises
    ------
    ConfigError
        A broken file (invalid YAML, missing header, unknown key, bad factor), naming it.
    """
    from graspcampaign.campaign.grid import n_trials
    from graspcampaign.campaign.kind import KINDS, kind_available
    from graspcampaign.campaign.studyfile import check_package_header, project_dirs, read_yaml
    from graspcampaign.errors import MissingSourceRunError

    data = read_yaml(path, study=True)
    check_package_header(path)
    study, checked = _light_study(path, data)
    ready = kind_available(study.kind)
    if ready and kind_facts(study.kind)["design"]:
        digest = hashlib.sha256(path.read_bytes())
        for conf in sorted(project_dirs()[0].rglob("*.yaml")):
            digest.update(conf.read_bytes())
        digest.update((_source_key(study.params, study.output.root) or "").encode())

        def compute() -> int | str:
            from graspcampaign.campaign.compose import compose_study

            try:
                return design_size(compose_study(str(path)))
            except MissingSourceRunError as exc:  # runnable once its source run exists
                return f"after {exc.source}"

        n = _fact("listed", digest.hexdigest()[:16], compute)
    else:
        n = n_trials(study)
    if isinstance(n, str):  # "after <source>": its design needs another run first
        n, state = "?", n
    else:
        state = "yes" if ready else "not yet" if study.kind in KINDS else "unknown kind"
        if not checked:  # a ${...} value: composing resolves it, and show or run check it
            state += " (not checked)"
    return {"study": path.stem, "kind": study.kind, "trials": n, "runnable": state,
            "extension": study.extension, "description": " ".join(study.description.split())}
