"""Compose a study config with Hydra's Compose API and convert it once to plain dataclasses.

``conf/config.yaml`` is the primary config (groups: model, evaluator, features, pso, runner,
output); each study in ``campaigns/`` is an experiment-style config (``# @package _global_``)
selected as ``+campaigns=<study>``. Hydra is used for composition and override parsing only; the
code that does the work never sees a Hydra or OmegaConf object.

Overrides follow Hydra's grammar. A factor may be overridden by its bare name:
``mu=[0.3]`` means ``factors.mu=[0.3]`` and ``mu=0.3`` means ``factors.mu=[0.3]``.
"""

from __future__ import annotations

import codecs
import contextlib
import copy
import functools
import hashlib
import os
import re
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from hydra import compose, initialize_config_dir
from hydra.core.config_store import ConfigStore
from omegaconf import OmegaConf

from graspcampaign.campaign.override import (  # noqa: F401  (omegaconf_error_sentence: public here too)
    check_overrides,
    check_sweeps,
    group,
    omegaconf_error_sentence,
    override_sentence,
    rewrite,
    split,
)
from graspcampaign.campaign.paths import check_root, config_root
from graspcampaign.campaign.schema import SCHEMAS, StudyCfg, check_config, check_study
from graspcampaign.campaign.studycheck import (
    check_conf,
    check_kind,
    check_paper_block,
    check_study_file,
    known_keys_sentence,
)
from graspcampaign.campaign.studyfile import (  # noqa: F401  (project_dirs, list_studies: public here too)
    CASE_TWINS,
    case_twin_study,
    check_group_files,
    check_package_header,
    find_study,
    group_options,
    is_path_argument,
    list_studies,
    project_dirs,
    read_yaml,
    schema_of,
    study_files,
    study_place,
)
from graspcampaign.campaign.written import file_nodes, in_file, line_of
from graspcampaign.errors import ConfigError, UserInputError


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


@functools.cache
def _register_schema() -> None:
    """Put StudyCfg in Hydra's ConfigStore (once per process: converting it costs ~50 ms)."""
    ConfigStore.instance().store(name="study_schema", node=StudyCfg)


def compose_study(study: str, overrides: list[str] | None = None) -> StudyCfg:
    """Compose a study with the ``conf/`` groups and ``overrides``.

    ``study`` is a name on the config search path (``campaigns/`` and ``$GRASPCAMPAIGN_PATH``, see
    :mod:`graspcampaign.campaign.studyfile`) or the path of a study file. The study file and every
    config-group file are checked first in plain words with their lines
    (:mod:`~graspcampaign.campaign.studycheck`), the overrides next
    (:mod:`~graspcampaign.campaign.override`); then Hydra composes, and the result is checked as
    a whole: ranges, the design's size, the trial kind's factors and params, the paper block.

    Raises
    ------
    ConfigError
        Unknown study, invalid YAML (file and line), unknown key, wrong type or out-of-range
        value; one sentence naming it (and the file and line it is written on).
    """
    if isinstance(overrides, str) or not all(isinstance(o, str) for o in overrides or []):
        raise ConfigError(f"overrides = {overrides!r} is not a list of KEY=VALUE texts; give one, "
                          "e.g. ['seeds=2'].")
    conf_dir, campaigns_dir = project_dirs()
    # the search path listed once, for every check below (a study given by name)
    files = study_files() if isinstance(study, str) and not is_path_argument(study) else None
    path = find_study(study, files)
    data = read_yaml(path, study=True)
    check_package_header(path)
    check_study_file(path, data, files)
    given = list(overrides or [])
    conf_digest = check_conf(conf_dir)
    check_overrides(given)
    key = (str(path.resolve()), str(conf_dir.resolve()), conf_digest,
           hashlib.sha256(path.read_bytes()).hexdigest(), tuple(given))
    if key in _COMPOSED:
        return copy.deepcopy(_COMPOSED[key])
    factors = data.get("factors")
    overrides = rewrite(set(factors) if isinstance(factors, dict) else set(), given)
    check_sweeps(overrides, given)
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
            set_keys = [f"{section}.{k}" for section in ("params", "paper")
                        if isinstance(data.get(section), dict) for k in data[section]]
            reads = _kind_reads(data.get("kind"))
            sentence = override_sentence(exc, overrides, given, names, set_keys, reads)
            raise _blamed(ConfigError(sentence, key=_error_key(exc)), path, overrides) from None
    try:
        obj.output.root = config_root(obj.output.root)  # read once, for every reader of the config
        _check_output_root(obj.output.root)
        check_study(obj)
    except ConfigError as exc:
        raise _blamed(exc, path, overrides) from None
    said = [o for o in given if group(o) in ("paper", "compare_with")]
    compared = next((o for o in said if group(o) == "compare_with"), None)
    try:
        check_kind(obj)
    except ConfigError as exc:  # about the kind as much as its factors or params
        if str(exc.key).startswith("factors.") and any(group(o) == "kind" for o in given):
            # factors the kind set on the command line does not read: first, is it this study's kind at all
            check_paper_block(obj, data.get("name"), path, campaigns_dir, said, compared)
        raise _blamed(exc, path, overrides, also=("kind",)) from None
    _check_renamed(obj.name, data.get("name"), path, given, files)
    check_paper_block(obj, data.get("name"), path, campaigns_dir, said, compared)
    if len(_COMPOSED) >= _COMPOSED_MAX:
        _COMPOSED.pop(next(iter(_COMPOSED)))
    _COMPOSED[key] = copy.deepcopy(obj)
    return obj


def _kind_reads(kind: Any) -> tuple[str, list[str]] | None:
    """Trial kind ``kind`` and the factors it reads (a designed kind: those its design reads), for the
    sentence of an override naming a factor the study lacks; None for an unknown kind or one that
    declares no ``optional_factors`` (:func:`~graspcampaign.campaign.studycheck.check_kind`'s rule)."""
    from graspcampaign.campaign.catalog import kind_facts
    from graspcampaign.campaign.kind import kind_available

    if not isinstance(kind, str) or not kind_available(kind):
        return None
    facts = kind_facts(kind)
    if facts["design"]:
        return kind, list(facts["factors"])
    optional = facts.get("optional_factors")
    return None if optional is None else (kind, [*facts["factors"], *optional])


def _check_output_root(root: str) -> None:
    """Refuse an ``output.root`` that `run` refuses (empty, a file, a run's or a study's place;
    ``paths.check_root``) when composed, so that `show` refuses it too, and each names the file
    and line or the override that sets it (whether it can be written is `run`'s to check)."""
    try:
        check_root(root, "output.root")
    except UserInputError as exc:
        raise ConfigError(str(exc), key="output.root") from None


def _check_renamed(name: str, written: Any, path: Path, given: list[str],
                   files: dict[str, Path] | None = None) -> None:
    """Refuse a study renamed on the command line (``name=...``) after another study on the search
    path: runs are stored (``<root>/<name>/``) and reported (``report/studies/``, by name) by their
    study's name, so its runs would be taken for that study's (docs/decisions.md, "A study's
    name")."""
    if name == written:
        return
    files = study_files() if files is None else files
    other = files.get(name)
    typed = next((o for o in given if split(o)[1] == "name"), f"name={name}")
    if other is not None and other.resolve() != path.resolve():
        raise ConfigError(f"override {typed!r} names the study {name} ({study_place(other)}): runs "
                          f"are stored and reported by their study's name, so this run of {written} "
                          f"would be taken for one of {name}'s; give a name no study has "
                          "(graspcampaign list shows them).", key="name")
    if (twin := case_twin_study(name, files)) is None:
        return
    why = CASE_TWINS.format(name, twin[0])
    if twin[1].resolve() == path.resolve():  # smoke name=SMOKE
        raise ConfigError(f"override {typed!r} differs only in case from the study's own name "
                          f"{twin[0]}: {why}, so this run would be taken for one of {twin[0]}'s; "
                          "leave the override out, or give a name that differs in more than case.",
                          key="name")
    raise ConfigError(f"override {typed!r} names the study {name}, which differs only in case from "
                      f"the study {twin[0]} ({study_place(twin[1])}): {why}, so this run of "
                      f"{written} would be taken for one of {twin[0]}'s; give a name that differs "
                      "in more than case from every study's (graspcampaign list shows them).",
                      key="name")


def _error_key(exc: BaseException) -> str | None:
    while not hasattr(exc, "full_key") and (exc.__cause__ or exc.__context__) is not None:
        exc = exc.__cause__ or exc.__context__
    key = getattr(exc, "full_key", None)
    return str(key) if key else None


def _blamed(exc: ConfigError, path: Path, overrides: list[str],
            also: tuple[str, ...] = ()) -> ConfigError:
    """``exc`` naming the study file and line when its key is written there and no override
    sets it, nor any of the keys ``also`` (an override's error names the override instead)."""
    key = exc.key
    if not key or str(exc).startswith(str(path)):
        return exc
    for item in overrides:
        set_key = split(item)[1]
        for blamed in (key, *also):  # as an override writes it: factors.shape[0] is factors.shape.0
            blamed = re.sub(r"\[(\d+)\]", r".\1", blamed)
            if set_key == blamed or blamed.startswith(f"{set_key}.") or set_key.startswith(f"{blamed}."):
                return exc
    nodes = file_nodes(path)  # read once: the line of each key tried, then the message's
    for blamed in (key, *also):  # a factor the file lacks: the line of its kind
        if line_of(path, blamed, nodes) is not None:
            return in_file(path, ConfigError(str(exc), key=blamed), nodes=nodes)
    return exc


# Compositions of this process by their inputs: the bytes of every conf/ file and of the study file,
# and the overrides as given. Hydra takes ~0.2 s per composition; a notebook or a test suite that
# composes the same inputs again gets a copy of the first result (failures are never kept).
_COMPOSED: dict[tuple, StudyCfg] = {}
_COMPOSED_MAX = 64


@contextlib.contextmanager
def _study_search_dir(path: Path, campaigns_dir: Path) -> Iterator[tuple[Path, str]]:
    """Yield a Hydra search directory and the ``campaigns/<option>`` that is the study file.

    A study of the tool's own ``campaigns/`` is used in place; any other file (or one starting
    with a UTF-8 byte-order mark, which hides the ``# @package`` line from Hydra) is copied,
    without the mark, into a temporary ``campaigns/`` (under a name no study can have) for the
    composition only.
    """
    text = Path(path).read_bytes()
    if path.resolve().parent == campaigns_dir.resolve() and not text.startswith(codecs.BOM_UTF8):
        yield campaigns_dir.parent, path.stem
        return
    with tempfile.TemporaryDirectory(prefix="graspcampaign-") as tmp:
        (Path(tmp) / "campaigns").mkdir()
        (Path(tmp) / "campaigns" / "_user_study.yaml").write_bytes(text.removeprefix(codecs.BOM_UTF8))
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


def _check_known_keys(cfg: Any, given: list[str]) -> None:
    """Refuse keys a ``+key=value`` override added outside the schema (Hydra accepts them)."""
    found = _unknown_key(cfg, StudyCfg)
    if found:
        key, schema = found
        typed = next((o for o in given if split(o)[1] == key), None)
        raise ConfigError(known_keys_sentence(key, schema, typed))


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


def as_given(study: str, overrides: list[str], composed: StudyCfg) -> dict[str, Any]:
    """What a run's manifest keeps of its command: the ``overrides`` as given, the absolute path of
    a study file ``study`` gives by path (``study_file``; a name is the manifest's ``study``), and
    the design the study file composes to without them (``default_design``: its config hash and
    trial count; the count None where it cannot be counted, as a design read from a run that is
    not stored; no ``default_design`` for a study file that needs overrides to compose)."""
    from graspcampaign.campaign.catalog import design_size
    from graspcampaign.campaign.provenance import config_hash

    given: dict[str, Any] = {"overrides": list(overrides)}
    if is_path_argument(study):  # a command resuming the run finds it so from any directory
        given["study_file"] = os.path.abspath(find_study(study))
    try:
        default = compose_study(study, [])
    except UserInputError:
        return given
    default.output = composed.output  # a design read from another run reads it where this one is
    try:
        size = design_size(default)
    except UserInputError:
        size = None
    return {**given, "default_design": {"config_hash": config_hash(default), "n_trials": size}}
