"""Check a study file, a config-group file or a ``params`` block against its schema in plain
Python, before Hydra sees it: unknown keys, types (a bool is ``true`` or ``false``, never ``2``),
ranges, factor levels, the trial kind, and the study's name against its file name. Every error is
one sentence naming the file and the line of the key (PyYAML node marks).

OmegaConf would convert ``2`` to ``True`` and say "Merge error: str is not a subclass of
ContactModelCfg" where a user wrote ``model: nosuch``; these checks say it in plain words first.
A value holding an interpolation (``${...}``) is left to OmegaConf, which resolves it.

Nothing here imports Hydra, OmegaConf or the numerical layers: ``graspcampaign list`` checks
every study file with it.
"""

from __future__ import annotations

import dataclasses
import datetime
import functools
from pathlib import Path
from typing import Any

from graspcampaign.campaign.paths import input_file_problem
from graspcampaign.campaign.schema import (
    SCHEMAS,
    StudyCfg,
    check_factor,
    check_value,
    example,
    not_finite_text,
)
from graspcampaign.campaign.written import in_file
from graspcampaign.core.words import listed, meant, plural, typed_value
from graspcampaign.errors import ConfigError

_SCALARS = {"int": int, "float": float, "str": str, "bool": bool}
GROUPS = ("model", "evaluator", "features", "pso", "runner", "output")  # conf/<group>/


# -- types -----------------------------------------------------------------------------------------
def split_optional(typ: str) -> tuple[str, bool]:
    """``'float | None'`` -> ``('float', True)``: the type and whether null is allowed."""
    t = typ.replace(" ", "")
    if t.startswith("Optional[") and t.endswith("]"):
        return t[9:-1], True
    parts = [p for p in t.split("|") if p != "None"]
    return "|".join(parts), len(parts) < len(t.split("|"))


def _args(typ: str) -> list[str]:
    """``'dict[str,list[Any]]'`` -> ``['str', 'list[Any]']`` (top-level commas only)."""
    inner, depth, out, start = typ[typ.index("[") + 1:-1], 0, [], 0
    for i, ch in enumerate(inner):
        depth += ch == "["
        depth -= ch == "]"
        if ch == "," and depth == 0:
            out.append(inner[start:i])
            start = i + 1
    return [*out, inner[start:]]


def _is_interpolation(value: Any) -> bool:
    return isinstance(value, str) and "${" in value


def _got(value: Any) -> str:
    if isinstance(value, datetime.date):  # YAML reads an unquoted 2024-01-01 as a date
        return f"{value} (a date)"
    return "null" if value is None else typed_value(value)


def check_typed(key: str, value: Any, typ: str, meta: dict[str, Any] | None = None) -> None:
    """Check ``value`` of ``key`` against a field's annotation (``'int'``, ``'float | None'``,
    ``'list[str]'``, ``'dict[str, Any]'``, a schema name) and its range metadata.

    Raises
    ------
    ConfigError
        One sentence naming ``key``, what it takes and what it got.
    """
    base, optional = split_optional(typ)
    if _is_interpolation(value) or base in ("Any", ""):
        return
    if value is None:
        if optional:
            return
        raise ConfigError(f"{key} must be {type_words(base, key)}, got null.", key=key)
    if base in SCHEMAS:
        if not isinstance(value, dict):
            raise ConfigError(_mapping_sentence(key, base, value), key=key)
        check_fields(value, SCHEMAS[base], f"{key}.")
        return
    if base.startswith("list["):
        if not isinstance(value, list):
            raise ConfigError(f"{key} must be a list, got {_got(value)}.", key=key)
        for i, item in enumerate(value):  # a list field's ranges hold for each item
            check_typed(f"{key}[{i}]", item, _args(base)[0], meta)
        return
    if base.startswith("dict["):
        if not isinstance(value, dict):
            raise ConfigError(f"{key} must be a mapping of keys, got {_got(value)}.", key=key)
        for sub, item in value.items():
            check_typed(f"{key}.{sub}", item, _args(base)[1])
        return
    scalar = _SCALARS.get(base)
    if scalar is None:  # an annotation these checks do not know: OmegaConf checks it
        return
    if scalar is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{key} must be true or false, got {_got(value)}.", key=key)
    elif isinstance(value, bool) or not isinstance(value, (int, float, str)) or (
            scalar is int and not isinstance(value, int)) or (
            scalar is float and isinstance(value, str)):
        # a str field takes a number as its text (output.run: 2), as OmegaConf does
        raise ConfigError(not_finite_text(key, value) or f"{key} must be of type {base}, got "
                          f"{_got(value)}.", key=key)
    if meta:  # ranges and choices, on the value as the schema will hold it (2 -> 2.0, '2')
        meta = {k: v for k, v in meta.items() if k != "type"}
        check_value(key, str(value) if scalar is str else value,
                    {**meta, "type": scalar} if scalar is float else meta)


def type_words(base: str, key: str) -> str:
    """Say what a value of type ``base`` must be, as in "``key`` must be true or false"."""
    if base == "bool":
        return "true or false"
    if base in SCHEMAS:
        return f"a mapping of its keys ({', '.join(f.name for f in dataclasses.fields(SCHEMAS[base]))})"
    if base.startswith("list["):
        return "a list"
    if base.startswith("dict["):
        return "a mapping of keys"
    return f"of type {base}"


def _mapping_sentence(key: str, base: str, value: Any) -> str:
    sentence = f"{key} must be {type_words(base, key)}, got {_got(value)}"
    if key in GROUPS and isinstance(value, str):
        from graspcampaign.campaign.studyfile import group_options

        options = group_options(key)
        sentence += (f"; a preset of conf/{key}/ ({', '.join(options)}) is chosen on the command "
                     f"line, e.g. {key}={options[0] if options else 'NAME'}")
    return sentence + "."


def known_keys_sentence(key: str, schema: type, typed: str | None = None) -> str:
    """``<key> is not a known key of <its section>[ (override '<typed>' rejected)]; known keys:
    ...``: the section as the user writes it (``evaluator``; the study config at the top)."""
    rejected = f" (override {typed!r} rejected)" if typed else ""
    parent, _, name = key.rpartition(".")
    fields = dataclasses.fields(schema)
    names = [f.name for f in fields]
    # a word another tool uses for a key (its field's `said_as`: cores -> n_jobs) is answered by
    # meaning, which spelling cannot find ("cores" is nearest "progress")
    said = next((f.name for f in fields if name.lower() in f.metadata.get("said_as", ())), name)
    near = meant(said, names, f"{parent}.{{}}" if parent else "{}")
    return (f"{key} is not a known key of {section_of(key)}{rejected}; {near}known keys: "
            f"{', '.join(names)}.")


def section_of(key: str) -> str:
    """The config section holding ``key`` as the user writes it: ``evaluator`` for
    ``evaluator.tau_f``, ``the study config`` for a top-level key."""
    return key.rsplit(".", 1)[0] if "." in key else "the study config"


def check_fields(data: dict[str, Any], schema: type, prefix: str = "") -> None:
    """Check a mapping against a dataclass schema: every key known, every value typed."""
    fields = {f.name: f for f in dataclasses.fields(schema)}
    for name, value in data.items():
        key = f"{prefix}{name}"
        if key == "defaults" and schema is StudyCfg:  # Hydra's own list, written on purpose
            raise ConfigError(_DEFAULTS_SAID, key=key)
        if name not in fields:
            raise ConfigError(known_keys_sentence(key, schema), key=key)
        if key == "factors":
            check_factors(value)
        else:
            check_typed(key, value, str(fields[name].type), dict(fields[name].metadata))


#: Why a study file takes no Hydra ``defaults:`` list: conf/config.yaml's chooses the groups
_DEFAULTS_SAID = (f"defaults is not a key of a study file: the presets of the groups "
                  f"({', '.join(GROUPS)}) are chosen by the defaults list of conf/config.yaml, "
                  "which every study is merged over; set a group's keys under its name in the "
                  "study file (evaluator: {n_cand: 300}), or choose another preset on the command "
                  "line (model=firm).")


def check_factors(factors: Any) -> None:
    """A mapping of known factor names to non-empty lists of levels of the factor's type."""
    if not isinstance(factors, dict):
        raise ConfigError("factors must be a mapping of factor names to lists of levels (e.g. "
                          f"shape: [sphere, pear]), got {_got(factors)}.", key="factors")
    for name, levels in factors.items():
        if not isinstance(levels, list) and not _is_interpolation(levels):
            raise ConfigError(f"factors.{name} must be a list of levels, e.g. {name}: "
                              f"{example(name)}, got {_got(levels)}.", key=f"factors.{name}")
        if isinstance(levels, list) and not any(map(_is_interpolation, levels)):
            check_factor(str(name), list(levels))


def check_kind(study: StudyCfg) -> None:
    """Check what the study's trial kind needs, without importing its numerical code: a known
    kind, the factors a Cartesian design must have on every trial and none it never reads
    (``optional_factors``), and ``params`` against its schema (read from :func:`catalog.kind_facts`).

    Raises
    ------
    ConfigError
        Naming the kind and the missing factor, or the params key and what it takes.
    """
    from graspcampaign.campaign.catalog import kind_facts
    from graspcampaign.campaign.factor_words import it_reads
    from graspcampaign.campaign.kind import kind_available

    check_kind_name(study.kind)
    if not kind_available(study.kind):  # a kind not implemented yet: `run` says so
        return
    facts = kind_facts(study.kind)
    if not facts["design"]:
        check_kind_factors(study.factors, study.kind, facts["factors"])
        reads = [*facts["factors"], *(facts.get("optional_factors") or [])]  # None: undeclared
        unread = [name for name in study.factors if name not in reads]  # it would repeat each trial
        if unread and facts.get("optional_factors") is not None:
            raise ConfigError(f"factor {unread[0]!r} is not read by the {study.kind} kind "
                              f"({it_reads(reads)}); {meant(unread[0], reads)}"
                              "remove it or choose a kind that varies it.", key=f"factors.{unread[0]}")
    elif ignored := [name for name in study.factors if name not in facts["factors"]]:
        reads = (f"reads only the factors {listed(facts['factors'])}" if facts["factors"]
                 else "reads no factor")
        raise ConfigError(f"study {study.name!r} (trial kind {study.kind!r}) builds its own trial list from "
                          f"its params and {reads}: factors.{ignored[0]} would change nothing but the "
                          f"config hash; set its params instead (graspcampaign show {study.name} lists "
                          "them).", key=f"factors.{ignored[0]}")
    check_method_factors(study, facts)
    check_params(study.params, facts["params"], study.kind)


def check_method_factors(study: StudyCfg, facts: dict[str, Any]) -> None:
    """Refuse a name in ``method_factors`` that no trial of the study holds: neither a known
    factor, ``seed``, ``repeat``, a factor of the study nor a key of its kind's trials
    (``TrialKind.trial_keys``: a designed kind's row keys, a protocol's schedule columns); it
    would change nothing but the config hash. One rule for every kind."""
    from graspcampaign.campaign.schema import FACTOR_SPECS

    keys = facts.get("trial_keys") or []
    known = [*FACTOR_SPECS, "seed", "repeat", *study.factors, *keys]
    for name in study.method_factors:
        if name not in known:
            named = sorted({*study.factors, *keys} - {"seed"}) or ["none"]
            raise ConfigError(
                f"method_factors names {name!r}, which is no factor and no key of a trial of kind "
                f"{study.kind!r}, so it would change nothing but the config hash; "
                f"{meant(name, known)}a method factor names a factor or trial key whose levels "
                f"share one scene's random draws (this study's: {', '.join(named)}).",
                key="method_factors")


# -- files -----------------------------------------------------------------------------------------
def check_study_data(data: dict[str, Any]) -> None:
    """Check a study file's own keys (its mapping as parsed) against ``StudyCfg``, its factors
    and its trial kind's name."""
    check_fields(data, StudyCfg)
    kind = data.get("kind")
    if isinstance(kind, str) and not _is_interpolation(kind):
        check_kind_name(kind)


def check_kind_name(kind: str) -> None:
    """Refuse a trial kind that is not registered (one not yet implemented is known)."""
    from graspcampaign.campaign.kind import KINDS, RUNTIME_KINDS

    if kind not in KINDS and kind not in RUNTIME_KINDS:
        raise ConfigError(f"trial kind {kind!r} is unknown; {meant(kind, sorted(KINDS))}known kinds: "
                          f"{', '.join(sorted(KINDS))}.", key="kind")


def check_study_file(path: Path, data: dict[str, Any], files: dict[str, Path] | None = None) -> None:
    """Check a study file before composition (see :func:`check_study_data`), and that its
    ``name:`` is its file name: a study is listed, run, shown and reported by that name (``files``:
    the study files on the search path, ``studyfile.study_files``, when the caller listed them).

    Raises
    ------
    ConfigError
        Naming the file, the line, the key and what is allowed.
    """
    from graspcampaign.campaign.paths import check_name, usable_name
    from graspcampaign.campaign.studyfile import CASE_TWINS, case_twin_study, project_dirs, study_place

    try:
        check_study_data(data)
        name = data.get("name")
        if isinstance(name, str) and not _is_interpolation(name):
            check_name(name, "name")
            stem = Path(path).stem
            if name != stem and not usable_name(stem):  # 'my study': no name can be written so
                raise ConfigError(
                    f"name: {name} is not the file's name {stem!r}, which is no study name (ASCII "
                    "letters, digits, '.', '_' and '-', starting with a letter or digit); a study "
                    f"is listed, run and reported by its file name, so rename the file to "
                    f"{name}.yaml.", key="name")
            if name != stem:
                raise ConfigError(
                    f"name: {name} is not the file's name {stem}; a study is listed, "
                    f"run and reported by its file name (status and report look for "
                    f"{stem}), so write name: {stem} or rename the file "
                    f"to {name}.yaml.", key="name")
            shipped = Path(path).parent.resolve() == project_dirs()[1].resolve()
            if not shipped and (twin := case_twin_study(name, files)) is not None:
                raise ConfigError(
                    f"name: {name} differs only in case from the study {twin[0]} "
                    f"({study_place(twin[1])}): {CASE_TWINS.format(name, twin[0])}; rename the "
                    "study (its file and its name:) to one that differs in more than case.",
                    key="name")
    except ConfigError as exc:
        raise in_file(path, exc) from None


def check_group_file(path: Path, group: str, schema: type, data: dict[str, Any]) -> None:
    """Check one option of a config group (``conf/<group>/<option>.yaml``): not empty, its keys
    known to ``schema``, its values typed and in range; errors name the file and line."""
    if not data:
        names = ", ".join(f.name for f in dataclasses.fields(schema))
        raise ConfigError(f"{path} is empty; a file of config group {group} sets keys of "
                          f"{group} ({names}).")
    try:
        check_fields(data, schema, f"{group}.")
    except ConfigError as exc:
        raise in_file(path, exc, key_prefix=f"{group}.") from None


@functools.cache
def _checked_conf(conf_dir: str, digest: str) -> None:
    """Check every config-group file of ``conf_dir`` once per content (``digest``)."""
    from graspcampaign.campaign.studyfile import read_yaml, schema_of

    for path in sorted(Path(conf_dir).glob("*/*.yaml")):
        data = read_yaml(path)
        schema = SCHEMAS.get(schema_of(path) or "")
        if schema is None and data:
            raise ConfigError(f"{path} does not name a known schema in its header (# schema: "
                              f"Name); known schemas: {', '.join(SCHEMAS)}.")
        check_group_file(path, path.parent.name, schema or schema_at(path.parent.name) or StudyCfg,
                         data)


def check_conf(conf_dir: Path) -> str:
    """Check every config-group file under ``conf_dir`` (once per content of its files) and
    return the digest of that content: every YAML file under ``conf_dir``, path and bytes.

    Raises
    ------
    ConfigError
        The first empty file, unknown key, wrong type or out-of-range value, naming the file and
        the line.
    """
    import hashlib

    digest = hashlib.sha256()
    for path in sorted(Path(conf_dir).rglob("*.yaml")):
        if (why := input_file_problem(path)) is not None:  # a named pipe: the read waited for ever
            raise ConfigError(f"{path} {why}; a config-group file is a YAML file.")
        digest.update(path.as_posix().encode())
        digest.update(path.read_bytes())
    _checked_conf(str(conf_dir), digest.hexdigest())
    return digest.hexdigest()


def check_paper_block(obj: StudyCfg, written: Any, path: Path, campaigns_dir: Path,
                      overrides: list[str] = (), compared: str | None = None) -> None:
    """Check the paper block against the paper values of the study it compares with
    (``written``: the name the study file gives; ``overrides``: those that set paper values or
    compare_with, named in the message beside the file; ``compared``: the one of them that sets
    compare_with, as typed).

    A study renamed on the command line (``name=other``) keeps comparing with the study its file
    holds (its paper block is that study's); a user's file that takes a tool study's name (and
    hides it on the search path) is that study for ``report``, so it needs that study's paper
    block, and the message says so (docs/decisions.md, "A study's name").
    """
    from graspcampaign.campaign.paper import check_paper, paper_types
    from graspcampaign.campaign.studyfile import read_yaml

    if not obj.compare_with and obj.name != written and written in paper_types():
        obj.compare_with = str(written)
    where = f"{campaigns_dir.name}/{path.name}" if path.parent == campaigns_dir else str(path)
    if overrides:
        where += f" with {plural('override', len(overrides))} {' '.join(overrides)}"
    like = obj.compare_with or obj.name
    # the levels a paper dict is keyed by: those of the study the values are of, as its file
    # gives them (an override reducing the design leaves the paper's other levels valid)
    tool = campaigns_dir / f"{like}.yaml"
    data = read_yaml(tool) if tool.is_file() else {}
    levels = {f"{group}.{k}": v for group in ("factors", "params")
              for k, v in (data.get(group) or {}).items() if isinstance(v, list)}
    if data.get("kind") not in (None, obj.kind):  # compared with, or hidden by, the user's file
        _check_compared_kind(obj, str(data["kind"]), path, campaigns_dir, paper_types(), compared)
    try:
        check_paper(like, obj.paper, f"{where}: paper", compare_with=bool(obj.compare_with),
                    levels=levels)
    except ConfigError as exc:
        hidden = campaigns_dir / f"{obj.name}.yaml"
        if obj.compare_with or path.resolve() == hidden.resolve() or not hidden.is_file():
            raise
        raise ConfigError(
            f"{str(exc).rstrip('.')}: this file takes the name of the tool's study {obj.name} "
            f"({campaigns_dir.name}/{hidden.name}), which it hides, so its runs are reported as "
            f"that study and its paper block must hold that study's values; copy the paper block "
            f"of {campaigns_dir.name}/{hidden.name}, or give your study a name of its own.") from None


def _check_compared_kind(obj: StudyCfg, theirs: str, path: Path, campaigns_dir: Path,
                         studies: dict[str, Any], typed: str | None = None) -> None:
    """Refuse a study reported with the report of a study of another trial kind, which reads
    records of that kind (``report.build.spec_for``: by name, then by ``compare_with``): one that
    compares with it (named by the override ``typed`` that sets it, else by its file and line), or
    a user's file that takes its name and hides it."""
    from graspcampaign.campaign.studyfile import read_yaml

    like = obj.compare_with or obj.name
    reported = (f"it would be reported with {like}'s report, which reads {theirs} records")
    if not obj.compare_with and path.resolve() == (campaigns_dir / f"{like}.yaml").resolve():
        raise ConfigError(f"kind = {obj.kind}: {like} is a study of trial kind {theirs}, and {reported}; "
                          "give a study of another kind a study file of its own.", key="kind")
    if not obj.compare_with:
        raise ConfigError(f"{path}: this file takes the name of the tool's study {like} "
                          f"({campaigns_dir.name}/{like}.yaml), of trial kind {theirs}, which it "
                          f"hides, and its kind is {obj.kind}: {reported}; give your study a name of "
                          "its own.", key="name")
    same = [name for name in sorted(studies) if (campaigns_dir / f"{name}.yaml").is_file()
            and read_yaml(campaigns_dir / f"{name}.yaml").get("kind") == obj.kind]
    instead = (f"compare with a study of kind {obj.kind} ({', '.join(same)}) or leave compare_with "
               "out" if same else f"no study of the tool's is of kind {obj.kind}: leave compare_with out")
    said = (f"compare_with = {like} is a study of trial kind {theirs}, and this study's kind is "
            f"{obj.kind}: {reported}; {instead}.")
    if typed:
        raise ConfigError(f"override {typed!r}: {said}", key="compare_with")
    raise in_file(path, ConfigError(said, key="compare_with"))


# -- the trial kind's needs ------------------------------------------------------------------------
def check_params(params: dict[str, Any], spec: dict[str, Any] | None, kind: str) -> None:
    """Check a study's ``params`` against its kind's params schema, described by ``spec``
    (``{"name": class name, "fields": [[name, annotation, metadata], ...]}``, see
    ``catalog.kind_facts``), so that ``show`` refuses what ``run`` would without importing the
    kind's numerical code."""
    if spec is None:
        if params:
            first = next(iter(params))
            raise ConfigError(f"params.{first} is not a parameter of trial kind {kind!r}, which "
                              "takes none.", key=f"params.{first}")
        return
    fields = {name: (typ, meta) for name, typ, meta in spec["fields"]}
    for name, value in params.items():
        key = f"params.{name}"
        if name not in fields:
            raise ConfigError(f"{key} is not a known key of params; "
                              f"{meant(name, fields, 'params.{}')}known keys: {', '.join(fields)}.",
                              key=key)
        typ, meta = fields[name]
        check_typed(key, value, typ, meta)


def check_kind_factors(factors: dict[str, Any], kind: str, required: list[str]) -> None:
    """Refuse a Cartesian design without a factor its trial kind reads on every trial."""
    missing = [name for name in required if name not in factors]
    if missing:
        have = ", ".join(factors) or "none"
        raise ConfigError(f"trial kind {kind!r} needs the {plural('factor', len(missing))} "
                          f"{listed(missing)} on every trial, which this study does not set (its factors: "
                          f"{have}); give each a list of levels under factors, e.g. "
                          f"{missing[0]}: {example(missing[0])}.", key="factors")


def field_at(key: str) -> tuple[type, dataclasses.Field] | None:
    """Return ``(schema, field)`` of a dotted key of the study config (``pso.enabled`` ->
    ``(PsoCfg, enabled)``), or None where the key is not a schema field (``factors.mu``)."""
    schema: type = StudyCfg
    parts = key.split(".")
    for i, part in enumerate(parts):
        fields = {f.name: f for f in dataclasses.fields(schema)}
        if part not in fields:
            return None
        if i == len(parts) - 1:
            return schema, fields[part]
        sub = SCHEMAS.get(split_optional(str(fields[part].type))[0])
        if sub is None:
            return None
        schema = sub
    return None


def schema_at(key: str) -> type | None:
    """The schema of a dotted section of the study config (``evaluator`` -> ``EvaluatorCfg``)."""
    if not key:
        return StudyCfg
    found = field_at(key)
    return SCHEMAS.get(split_optional(str(found[1].type))[0]) if found else None
