"""Compose a study config with Hydra's Compose API and convert it once to plain dataclasses.

``conf/config.yaml`` is the primary config (groups: model, evaluator, features, pso, runner,
output); each study in ``campaigns/`` is an experiment-style config (``# @package _global_``)
selected as ``+campaigns=<study>``. Hydra is used for composition and override parsing only; the
code that does the work never sees a Hydra or OmegaConf object.

Overrides follow Hydra's grammar. A factor may be overridden by its bare name:
``mu=[0.3]`` means ``factors.mu=[0.3]`` and ``mu=0.3`` means ``factors.mu=[0.3]``.
"""

from __future__ import annotations

import contextlib
import copy
import functools
import hashlib
import re
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from hydra import compose, initialize_config_dir
from hydra.core.config_store import ConfigStore
from omegaconf import OmegaConf

from graspcampaign.campaign.paper import check_paper
from graspcampaign.campaign.schema import SCHEMAS, StudyCfg, check_config, check_study
from graspcampaign.campaign.studyfile import (  # noqa: F401  (project_dirs, list_studies: public here too)
    check_group_files,
    check_package_header,
    find_study,
    group_options,
    list_studies,
    project_dirs,
    read_yaml,
)
from graspcampaign.errors import ConfigError, UserInputError

_SCHEMA_LINE = re.compile(r"^#\s*schema:\s*(\w+)")


@functools.cache
def group_config(group: str, name: str):
    """Load ``conf/<group>/<name>.yaml`` into the schema its header names and check its ranges.

    Used where one study needs several options of a group at once (e.g. the ``model_preset``
    factor); a study's own group selection goes through :func:`compose_study`.

    Raises
    ------
    ConfigError
        Unknown option, a file without a known schema, an unknown key, a wrong type or an
        out-of-range value; one sentence naming the file and the key.
    """
    options = group_options(group)
    if name not in options:
        raise ConfigError(f"{group}={name!r} is not an option of conf/{group}/; "
                          f"available: {', '.join(options)}.")
    path = project_dirs()[0] / group / f"{name}.yaml"
    schema = SCHEMAS.get(schema_of(path) or "")
    if schema is None:
        raise ConfigError(f"{path} does not name a known schema in its header (# schema: Name).")
    try:
        obj = OmegaConf.to_object(OmegaConf.merge(OmegaConf.structured(schema), OmegaConf.load(path)))
    except Exception as exc:  # OmegaConf raises several unrelated types; all mean a bad file
        raise ConfigError(f"{path}: {omegaconf_error_sentence(exc)}") from None
    check_config(obj, prefix=f"{group}.")
    return obj


def schema_of(path: Path) -> str | None:
    """Return the schema a YAML file names in its header (``# schema: Name``).

    The header is the leading block of comment lines (a study's first line is Hydra's
    ``# @package _global_``).
    """
    with open(path) as fh:
        for line in fh:
            if not line.startswith("#"):
                break
            match = _SCHEMA_LINE.match(line)
            if match:
                return match.group(1)
    return None


@functools.cache
def _register_schema() -> None:
    """Put StudyCfg in Hydra's ConfigStore (once per process: converting it costs ~50 ms)."""
    ConfigStore.instance().store(name="study_schema", node=StudyCfg)


def omegaconf_error_sentence(exc: BaseException, prefix: str = "") -> str:
    """Turn an OmegaConf/Hydra exception into one sentence naming the key."""
    while not hasattr(exc, "full_key") and (exc.__cause__ or exc.__context__) is not None:
        exc = exc.__cause__ or exc.__context__
    key = getattr(exc, "full_key", None) or getattr(exc, "key", None)
    text = str(getattr(exc, "msg", None) or exc).strip().splitlines()[0].rstrip(".")
    type_name = type(exc).__name__
    if key:
        key = f"{prefix}{key}"
        if type_name == "ConfigKeyError" or "not in struct" in text or "not in '" in text:
            parent = getattr(exc, "object_type_str", None) or "the schema"
            return f"{key} is not a known key of {parent}."
        return f"{key}: {text}."
    return f"{text}."


def _rewrite_overrides(factors: set[str], overrides: list[str]) -> list[str]:
    """Map bare factor names to ``factors.<name>`` and scalars to one-level lists."""
    out = []
    for item in overrides:
        key, sep, value = item.partition("=")
        if sep and key in factors:
            value = value.strip()
            out.append(f"factors.{key}={value if value.startswith('[') else f'[{value}]'}")
        else:
            out.append(item)
    return out


def compose_study(study: str, overrides: list[str] | None = None) -> StudyCfg:
    """Compose a study with the ``conf/`` groups and ``overrides``.

    ``study`` is a name on the config search path (``campaigns/`` and ``$GRASPCAMPAIGN_PATH``, see
    :mod:`graspcampaign.campaign.studyfile`) or the path of a study file.

    Raises
    ------
    ConfigError
        Unknown study, invalid YAML (file and line), unknown key, wrong type or out-of-range
        value; one sentence naming it.
    """
    conf_dir, campaigns_dir = project_dirs()
    path = find_study(study)
    data = read_yaml(path, study=True)
    check_package_header(path)
    _check_file_keys(path, data)
    given = list(overrides or [])
    key = _inputs_key(path, conf_dir, given)
    if key in _COMPOSED:
        return copy.deepcopy(_COMPOSED[key])
    factors = data.get("factors")
    overrides = _rewrite_overrides(set(factors) if isinstance(factors, dict) else set(), given)
    _register_schema()
    with _study_search_dir(path, campaigns_dir) as (search_dir, option):
        try:
            with initialize_config_dir(config_dir=str(conf_dir), version_base=None):
                cfg = compose(
                    config_name="config",
                    overrides=[f"hydra.searchpath=[file://{search_dir}]",
                               f"+campaigns={option}", *overrides],
                )
            _check_known_keys(cfg, given)
            obj = OmegaConf.to_object(cfg)
        except UserInputError:
            raise
        except Exception as exc:  # Hydra/OmegaConf raise many unrelated types; all mean bad input
            check_group_files()  # a broken group file is named with its line
            names = sorted(factors) if isinstance(factors, dict) else []
            raise ConfigError(_override_sentence(exc, overrides, given, names)) from None
    check_study(obj)
    where = f"{campaigns_dir.name}/{path.name}" if path.parent == campaigns_dir else str(path)
    check_paper(obj.compare_with or obj.name, obj.paper, f"{where}: paper",
                compare_with=bool(obj.compare_with))
    if len(_COMPOSED) >= _COMPOSED_MAX:
        _COMPOSED.pop(next(iter(_COMPOSED)))
    _COMPOSED[key] = copy.deepcopy(obj)
    return obj


# Compositions of this process by their inputs: the bytes of every conf/ file and of the study file,
# and the overrides as given. Hydra takes ~0.2 s per composition; a notebook or a test suite that
# composes the same inputs again gets a copy of the first result (failures are never kept).
_COMPOSED: dict[tuple, StudyCfg] = {}
_COMPOSED_MAX = 64


def _inputs_key(path: Path, conf_dir: Path, overrides: list[str]) -> tuple:
    digest = hashlib.sha256()
    for file in [*sorted(conf_dir.rglob("*.yaml")), path]:
        digest.update(file.as_posix().encode())
        digest.update(file.read_bytes())
    return str(Path(path).resolve()), str(conf_dir.resolve()), digest.hexdigest(), tuple(overrides)


@contextlib.contextmanager
def _study_search_dir(path: Path, campaigns_dir: Path) -> Iterator[tuple[Path, str]]:
    """Yield a Hydra search directory and the ``campaigns/<option>`` that is the study file.

    A study of the tool's own ``campaigns/`` is used in place; any other file is copied into a
    temporary ``campaigns/`` (under a name no study can have) for the composition only.
    """
    if path.resolve().parent == campaigns_dir.resolve():
        yield campaigns_dir.parent, path.stem
        return
    with tempfile.TemporaryDirectory(prefix="graspcampaign-") as tmp:
        (Path(tmp) / "campaigns").mkdir()
        shutil.copyfile(path, Path(tmp) / "campaigns" / "_user_study.yaml")
        yield Path(tmp), "_user_study"


def _unknown_key(cfg: Any, schema: type, prefix: str = "") -> tuple[str, type] | None:
    """Return the first key of a mapping (or DictConfig) outside ``schema``, with its schema."""
    import dataclasses

    if not hasattr(cfg, "keys"):
        return None
    fields = {f.name: f for f in dataclasses.fields(schema)}
    for key in cfg.keys():
        if key not in fields:
            return f"{prefix}{key}", schema
        sub = fields[key].type
        sub = SCHEMAS.get(sub) if isinstance(sub, str) else sub
        if dataclasses.is_dataclass(sub):
            found = _unknown_key(cfg[key], sub, f"{prefix}{key}.")
            if found:
                return found
    return None


def _known_keys_sentence(key: str, schema: type) -> str:
    import dataclasses

    return (f"{key} is not a known key of {schema.__name__}; known keys: "
            f"{', '.join(f.name for f in dataclasses.fields(schema))}.")


def _check_file_keys(path: Path, data: dict[str, Any]) -> None:
    """Refuse a key of a study file outside the schema, naming the file and its line."""
    found = _unknown_key(data, StudyCfg)
    if found:
        key, schema = found
        leaf = key.rsplit(".", 1)[-1]
        lines = Path(path).read_text().splitlines()
        line = next((i + 1 for i, text in enumerate(lines)
                     if re.match(rf"\s*{re.escape(leaf)}\s*:", text)), None)
        where = f"{path}, line {line}" if line else f"{path}"
        raise ConfigError(f"{where}: {_known_keys_sentence(key, schema)}")


def _check_known_keys(cfg: Any, given: list[str]) -> None:
    """Refuse keys a ``+key=value`` override added outside the schema (Hydra accepts them)."""
    found = _unknown_key(cfg, StudyCfg)
    if found:
        key, schema = found
        typed = next((o for o in given if o.lstrip("+~").partition("=")[0] == key), None)
        sentence = _known_keys_sentence(key, schema)
        if typed:
            sentence = sentence.replace(f"of {schema.__name__};",
                                        f"of {schema.__name__} (override {typed!r} rejected);")
        raise ConfigError(sentence)


def _override_sentence(exc: BaseException, overrides: list[str], given: list[str],
                       factors: list[str] = ()) -> str:
    """One sentence for a composition error, naming the user's override as they typed it (and, for a
    bare key, the study's factors: ``shape=[...]`` works only where shape is a factor)."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    if type(exc).__name__ == "OverrideParseException":
        from hydra.core.override_parser.overrides_parser import OverridesParser

        parser = OverridesParser.create()
        for item, typed in zip(overrides, given, strict=True):
            try:
                parser.parse_overrides([item])
            except Exception:  # the one that fails is the one to name
                return f"cannot parse override {typed!r}: {text.rstrip('.')}."
        return f"cannot parse overrides: {text.rstrip('.')}."
    match = re.match(r"Could not override '([^']+)'", text)
    if match:
        key = match.group(1)
        if "." in key:
            return f"{key} is not a known key of the study config (override rejected)."
        return (f"{key} is neither a known key of the study config nor a factor of this study "
                f"(factors: {', '.join(factors) or 'none'}); override rejected.")
    match = re.match(r"Could not append to config\. An item is already at '([^']+)'", text)
    if match:
        return f"{match.group(1)} already exists; override it without the leading '+'."
    match = re.search(r"Could not find '([\w-]+)/([^']+)'", text)
    if match:
        return _missing_option_sentence(match.group(1), match.group(2))
    return omegaconf_error_sentence(exc)


def _missing_option_sentence(group: str, option: str) -> str:
    """``model=nosuch``: name the group's options (the files of ``conf/<group>/``)."""
    directory = project_dirs()[0] / group
    options = sorted(p.stem for p in directory.glob("*.yaml")) if directory.is_dir() else []
    if not options:
        groups = sorted(p.name for p in project_dirs()[0].iterdir() if p.is_dir())
        return f"{group} is not a config group; config groups: {', '.join(groups)}."
    return (f"{group}={option} is not an option of config group {group}; available options: "
            f"{', '.join(options)}.")


def check_yaml_schemas() -> list[tuple[Path, str]]:
    """Return ``(file, schema)`` for every YAML in conf/ and campaigns/ (used by tests).

    Raises
    ------
    ConfigError
        For a file whose header names no known schema.
    """
    conf_dir, campaigns_dir = project_dirs()
    out = []
    for path in sorted([*conf_dir.rglob("*.yaml"), *campaigns_dir.glob("*.yaml")]):
        name = schema_of(path)
        if name not in SCHEMAS:
            raise ConfigError(f"{path} does not name a known schema in its header (# schema: Name).")
        out.append((path, name))
    return out
