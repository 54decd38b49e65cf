"""Compose a study config with Hydra's Compose API and convert it once to plain dataclasses.

``conf/config.yaml`` is the primary config (groups: model, evaluator, features, pso, runner,
output); each study in ``campaigns/`` is an experiment-style config (``# @package _global_``)
selected as ``+campaigns=<study>``. Hydra is used for composition and override parsing only; the
code that does the work never sees a Hydra or OmegaConf object.

Overrides follow Hydra's grammar. A factor may be overridden by its bare name:
``mu=[0.3]`` means ``factors.mu=[0.3]`` and ``mu=0.3`` means ``factors.mu=[0.3]``.
"""

from __future__ import annotations

import os
import re
from functools import cache
from pathlib import Path

from hydra import compose, initialize_config_dir
from hydra.core.config_store import ConfigStore
from omegaconf import OmegaConf

from graspcampaign.campaign.paper import check_paper
from graspcampaign.campaign.schema import SCHEMAS, StudyCfg, check_config, check_study
from graspcampaign.errors import ConfigError, UserInputError

_SCHEMA_LINE = re.compile(r"^#\s*schema:\s*(\w+)")


@cache
def project_dirs() -> tuple[Path, Path]:
    """Return ``(conf_dir, campaigns_dir)``.

    Looked up in order: ``$GRASPCAMPAIGN_HOME``, the source checkout the package is imported from
    (editable installs), then the copies shipped inside the wheel.
    """
    candidates = []
    if os.environ.get("GRASPCAMPAIGN_HOME"):
        candidates.append(Path(os.environ["GRASPCAMPAIGN_HOME"]))
    here = Path(__file__).resolve()
    candidates += [here.parents[3], here.parents[1] / "_data"]
    for root in candidates:
        if (root / "conf" / "config.yaml").is_file() and (root / "campaigns").is_dir():
            return root / "conf", root / "campaigns"
    raise UserInputError("cannot find conf/config.yaml and campaigns/; set GRASPCAMPAIGN_HOME.")


def group_options(group: str) -> tuple[str, ...]:
    """Return the options of a config group (the YAML files in ``conf/<group>/``), sorted."""
    return tuple(sorted(p.stem for p in (project_dirs()[0] / group).glob("*.yaml")))


@cache
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


def list_studies() -> list[str]:
    """Return the study names (files in ``campaigns/``), sorted."""
    return sorted(p.stem for p in project_dirs()[1].glob("*.yaml"))


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


def _register_schema() -> None:
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


def _rewrite_overrides(study: str, overrides: list[str]) -> list[str]:
    """Map bare factor names to ``factors.<name>`` and scalars to one-level lists."""
    path = project_dirs()[1] / f"{study}.yaml"
    factors = set((OmegaConf.load(path).get("factors") or {}).keys())
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
    """Compose ``campaigns/<study>.yaml`` with the ``conf/`` groups and ``overrides``.

    Raises
    ------
    ConfigError
        Unknown study, unknown key, wrong type or out-of-range value; one sentence naming it.
    """
    conf_dir, campaigns_dir = project_dirs()
    names = list_studies()
    if study not in names:
        raise ConfigError(f"unknown study {study!r}; available studies: {', '.join(names)}.")
    given = list(overrides or [])
    overrides = _rewrite_overrides(study, given)
    _register_schema()
    try:
        with initialize_config_dir(config_dir=str(conf_dir), version_base=None):
            cfg = compose(
                config_name="config",
                overrides=[f"hydra.searchpath=[file://{campaigns_dir.parent}]",
                           f"+campaigns={study}", *overrides],
            )
        obj = OmegaConf.to_object(cfg)
    except UserInputError:
        raise
    except Exception as exc:  # Hydra/OmegaConf raise many unrelated types; all mean bad input
        raise ConfigError(_override_sentence(exc, overrides, given)) from None
    check_study(obj)
    check_paper(obj.name, obj.paper, f"{campaigns_dir.name}/{study}.yaml: paper")
    return obj


def _override_sentence(exc: BaseException, overrides: list[str], given: list[str]) -> str:
    """One sentence for a composition error, naming the user's override as they typed it."""
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
        return f"{match.group(1)} is not a known key of the study config (override rejected)."
    match = re.match(r"Could not append to config\. An item is already at '([^']+)'", text)
    if match:
        return f"{match.group(1)} already exists; override it without the leading '+'."
    return omegaconf_error_sentence(exc)


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
