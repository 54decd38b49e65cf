"""Where study and group files live, and a first look at a YAML file before Hydra sees it.

Config search path (documented in the README):

- ``GRASPCAMPAIGN_HOME``: a directory holding ``conf/`` (the config groups) and ``campaigns/`` (the
  studies) that replaces the ones shipped with the package (default: the source checkout the
  package is imported from, else the copies inside the wheel);
- ``GRASPCAMPAIGN_PATH``: further directories of study files (``*.yaml``), separated by ``:`` (``;``
  on Windows), searched in order *before* ``campaigns/``, so a study of your own can keep a name of
  the tool's;
- a study argument that names a file (``./my_study.yaml``, anything ending in ``.yaml``/``.yml`` or
  holding a path separator) is that file.

Nothing here imports Hydra, numpy or the numerical layers: ``graspcampaign list`` runs on this
module alone.
"""

from __future__ import annotations

import math
import os
import re
from functools import cache
from pathlib import Path
from typing import Any

from graspcampaign.campaign.paths import (
    expand_home,
    input_file_problem,
    path_problem,
    read_denied,
    shown,
    unreachable,
)
from graspcampaign.core.words import as_ascii, meant
from graspcampaign.errors import ConfigError, UserInputError, utf8_text

_SCHEMA_LINE = re.compile(r"^#\s*schema:\s*(\w+)")
_SUFFIXES = (".yaml", ".yml")
_MAX_BYTES = 2**20  # a study or config-group file (docs/decisions.md)
_MAX_DEPTH = 100  # lists and mappings within each other: OmegaConf's recursion fails at ~150
NESTED_TOO_DEEPLY = (f"its lists or mappings are nested too deeply to read (over {_MAX_DEPTH} "
                     "levels within each other); a config nests a few.")


@cache
def project_dirs() -> tuple[Path, Path]:
    """Return ``(conf_dir, campaigns_dir)``.

    ``$GRASPCAMPAIGN_HOME`` when set (non-empty): it must hold both, or the error says what it
    lacks (a home that is silently passed over would run the shipped configs instead of the
    user's). Otherwise the source checkout the package is imported from (editable installs), then
    the copies shipped inside the wheel.

    Raises
    ------
    UserInputError
        ``GRASPCAMPAIGN_HOME`` does not exist, is not a directory, or lacks ``conf/config.yaml``
        or ``campaigns/``; or no copy of them is found at all.
    """
    home = os.environ.get("GRASPCAMPAIGN_HOME", "").strip()
    if home:
        root, unknown = expand_home(home)
        problem = unknown or _home_problem(root)
        if problem:
            raise UserInputError(f"GRASPCAMPAIGN_HOME={home} {problem}; point it at a directory "
                                 "holding conf/ (with conf/config.yaml and the config groups) and "
                                 "campaigns/ (the study files), e.g. a copy of the shipped ones, "
                                 "or unset it to use those.")
        return root / "conf", root / "campaigns"
    here = Path(__file__).resolve()
    for root in (here.parents[3], here.parents[1] / "_data"):
        if (root / "conf" / "config.yaml").is_file() and (root / "campaigns").is_dir():
            return root / "conf", root / "campaigns"
    raise UserInputError("cannot find conf/config.yaml and campaigns/; set GRASPCAMPAIGN_HOME to "
                         "a directory that has both.")


def _home_problem(root: Path) -> str | None:
    """What a ``GRASPCAMPAIGN_HOME`` directory lacks, in words (None: nothing); a directory of it
    this user may not read is named."""
    if not os.path.exists(root):  # a symbolic link leading nowhere: said so
        return unreachable(root) or os.path.islink(root) and path_problem(root) or "does not exist"
    if not root.is_dir():
        return "is a file, not a directory"
    for place in ("", "conf", "campaigns"):
        if os.path.isdir(root / place) and (why := read_denied(root / place)):
            return f"has {place}/, which {why}" if place else why
    if not (root / "conf").is_dir():
        return "has no conf/ directory"
    if not (root / "conf" / "config.yaml").is_file():
        return "has no conf/config.yaml"
    if not (root / "campaigns").is_dir():
        return "has no campaigns/ directory"
    return None


def study_dirs() -> list[Path]:
    """Return the directories searched for study files: ``$GRASPCAMPAIGN_PATH``, then campaigns/.

    An entry of ``GRASPCAMPAIGN_PATH`` that is not a directory is skipped with a warning naming
    it.
    """
    extra = []
    for entry in os.environ.get("GRASPCAMPAIGN_PATH", "").split(os.pathsep):
        if not entry.strip():
            continue
        path, problem = _search_entry(entry)
        if problem:
            _warn(f"GRASPCAMPAIGN_PATH entry {entry} {problem}; it is skipped.")
            continue
        extra.append(path)
    return [*extra, project_dirs()[1]]


def _search_entry(entry: str) -> tuple[Path, str | None]:
    """A ``GRASPCAMPAIGN_PATH`` entry as the directory it names (``~`` read as a shell reads it)
    and why it is skipped (a home that cannot be found, no directory there), or None: one reading
    for the search and for the words that describe it."""
    path, unknown = expand_home(entry)
    return path, unknown or _path_problem(path)


def _path_problem(path: Path) -> str | None:
    """Why ``path`` is no directory of study files (missing, or a file: then how to run it; one
    this user may not read)."""
    if not os.path.exists(path):  # a symbolic link leading nowhere: said so
        return unreachable(path) or os.path.islink(path) and path_problem(path) or "does not exist"
    if not path.is_dir():
        hint = (" (run a study file by giving its path: graspcampaign run " + str(path) + ")"
                if path.suffix in _SUFFIXES else "")
        return f"is a file, not a directory of study files{hint}"
    return read_denied(path)


def _warn(message: str) -> None:
    """A warning the command line prints once per command as ``warning: ...``."""
    import warnings

    warnings.warn(message, stacklevel=3)


def search_path_text() -> str:
    """The study search path in words, for a message: the directories searched, in order, and
    the ``GRASPCAMPAIGN_PATH`` entries skipped with why."""
    searched, skipped = [], []
    for entry in os.environ.get("GRASPCAMPAIGN_PATH", "").split(os.pathsep):
        if entry.strip():
            problem = _search_entry(entry)[1]
            (skipped.append(f"{entry} ({problem.split(' (')[0]})") if problem
             else searched.append(entry))
    text = ", ".join([*searched, str(project_dirs()[1])])
    if skipped:
        text += f"; GRASPCAMPAIGN_PATH entries skipped: {', '.join(skipped)}"
    elif not searched:
        text += "; GRASPCAMPAIGN_PATH adds directories of your own"
    return text


def study_files() -> dict[str, Path]:
    """Return ``{study name: file}`` over the search path (the first directory holding a name wins)."""
    out: dict[str, Path] = {}
    for directory in study_dirs():
        for path in sorted(directory.iterdir()):
            if path.suffix in _SUFFIXES and path.is_file():
                out.setdefault(path.stem, path)
    return dict(sorted(out.items()))


def list_studies() -> list[str]:
    """Return the study names on the search path, sorted."""
    return list(study_files())


def is_path_argument(study: str) -> bool:
    """Whether a study argument names a file rather than a study."""
    return study.lower().endswith(_SUFFIXES) or "/" in study or os.sep in study


def find_study(study: str) -> Path:
    """Return the file of a study given by name (on the search path) or by path.

    Raises
    ------
    ConfigError
        No such study or file, naming the available studies.
    """
    if not isinstance(study, str):
        raise ConfigError(f"study = {study!r} is not a study's name or file path: give it as text.")
    if is_path_argument(study):
        path, unknown = expand_home(study)
        if unknown:
            raise ConfigError(f"study file {shown(study)} {unknown}; give its path in full.")
        if (why := input_file_problem(path)) is not None:
            raise ConfigError(f"study file {shown(study)} {why}; give a YAML file.")
        if path.suffix.lower() in _SUFFIXES and path.suffix not in _SUFFIXES:
            raise ConfigError(f"study file {shown(study)} {_MISCASED} rename it "
                              f"{path.with_suffix(path.suffix.lower()).name}.")
        if path.suffix not in _SUFFIXES:
            raise ConfigError(f"study file {shown(study)} must end in .yaml or .yml.")
        return path
    files = study_files()
    if study not in files:
        for directory in study_dirs():  # a mine.YAML there is not listed, nor a mine.yaml that is
            found = [p for p in directory.iterdir() if p.stem == study and p.suffix.lower() in _SUFFIXES]
            if found and found[0].suffix in _SUFFIXES:  # no file (a link leading nowhere, a folder)
                raise ConfigError(f"unknown study {study!r}: {found[0]} {input_file_problem(found[0])}"
                                  "; make it a study file (YAML) or move it aside.")
            if found:
                raise ConfigError(f"unknown study {study!r}: the file {found[0]} {_MISCASED} rename "
                                  f"it {study}{found[0].suffix.lower()}.")
        raise ConfigError(f"unknown study {study!r}; {meant(study, files)}"
                          f"available studies: {', '.join(files)} (searched: {search_path_text()}).")
    return files[study]


#: why a study file ending in .YAML (.Yml, ...) is not read: the case of a suffix matters
_MISCASED = ("is not read: a study file's name ends in .yaml or .yml in lower case, as the study "
             "search path and Hydra's look for it (the case of a file name matters on Linux);")


def schema_of(path: Path) -> str | None:
    """Return the schema a YAML file names in its header (``# schema: Name``).

    The header is the leading block of comment lines (a study's first line is Hydra's
    ``# @package _global_``); a UTF-8 byte-order mark before it is allowed.
    """
    with open(path, encoding="utf-8-sig") as fh:
        for line in fh:
            if not line.startswith("#"):
                break
            match = _SCHEMA_LINE.match(line)
            if match:
                return match.group(1)
    return None


def check_package_header(path: Path) -> None:
    """Refuse a study file without Hydra's ``# @package _global_`` in its leading comments.

    Without it Hydra would nest the whole study under a ``campaigns:`` key. A UTF-8 byte-order
    mark before it is allowed (the composition reads a copy without it).
    """
    with open(path, encoding="utf-8-sig") as fh:
        for line in fh:
            if not line.startswith("#"):
                break
            if re.match(r"#\s*@package\s+_global_\s*$", line):
                return
    raise ConfigError(f"{path} does not start with the comment line '# @package _global_', which "
                      "every study file needs (see campaigns/smoke.yaml).")


def _yaml_error_sentence(path: Path, exc: Exception, n_lines: int) -> str:
    mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
    # past the last line (an item left open): the last line is where it was left open
    where = f"{path}, line {min(mark.line + 1, max(n_lines, 1))}" if mark is not None else f"{path}"
    problem = (getattr(exc, "problem", None) or str(exc).splitlines()[0]).strip()
    context = (getattr(exc, "context", None) or "").strip()
    if problem.startswith(_REFUSALS) or any(words in problem for words in _MISREADINGS):
        return f"{where}: {problem}."
    if tag := re.match(r"could not determine a constructor for the tag '(.+)'", problem):
        return (f"{where}: the tag {tag[1].replace('tag:yaml.org,2002:', '!!')} is not read; a "
                "study or group file holds plain values (numbers, text, true/false, lists, "
                "mappings), so remove it.")
    if "'\\t'" in problem:
        return f"{where}: a tab character where YAML allows only spaces for indentation."
    text = f"{context}: {problem}" if context else problem
    return f"{where}: this is not valid YAML ({text})."


_REFUSALS = ("the alias *", "the merge key <<", "the key ")  # what the loader refuses, in words
_MERGE, _NULL = "tag:yaml.org,2002:merge", "tag:yaml.org,2002:null"
_INT, _FLOAT = "tag:yaml.org,2002:int", "tag:yaml.org,2002:float"
_LEADING_ZERO = " has a leading zero"  # the loader's refusal of an octal integer, in words
_BASE_60 = ", which YAML reads as a base-60"  # and of a sexagesimal one
_GROUPED = " has an underscore, which YAML reads as grouping digits"  # and of 1_0 (10)
_MISREADINGS = (_LEADING_ZERO, _BASE_60, _GROUPED)


def _key_part(parent: Any, index: Any) -> str:
    """How a node composed at ``index`` of ``parent`` extends the key it is under: ``.name`` for a
    mapping's value, ``[i]`` for a list's item, nothing for the file or a mapping's key."""
    if isinstance(index, int):
        return f"[{index}]"
    return f".{index.value}" if getattr(index, "value", None) is not None and parent is not None else ""


def _octal(node: Any) -> str | None:
    """Why an integer written with a leading zero (``010``) is refused, in words, or None: YAML 1.1,
    which PyYAML and OmegaConf read, takes it for octal (8), which no one writing a study means;
    one the same in both readings (``07``, ``00``) is not refused."""
    value = getattr(node, "value", None)
    if getattr(node, "tag", None) != _INT or not isinstance(value, str):
        return None
    sign, digits = ("-" if value[:1] == "-" else ""), value.lstrip("+-").replace("_", "")
    if (len(digits) < 2 or digits[0] != "0" or not set(digits) <= set("01234567")
            or int(digits, 8) == int(digits)):
        return None
    octal, decimal = f"{sign}{int(digits, 8)}", f"{sign}{int(digits)}"
    return f"{_LEADING_ZERO}, which YAML reads as octal {octal}; write {decimal} or {octal}"


def _separated(loader: Any, node: Any) -> str | None:
    """Why a number written with colons (``1:30``, ``1:30.5``) or an underscore (``1_0``) is
    refused, in words, or None: YAML 1.1 takes the first for base 60 (90, 90.5: a clock time) and
    reads the second with its digits grouped (10, as an override's is refused, ``check_overrides``),
    which no one writing a study means: a setting that wants a number gets another one, one that
    wants text gets its digits."""
    value, tag = getattr(node, "value", None), getattr(node, "tag", None)
    if tag not in (_INT, _FLOAT) or not isinstance(value, str) or not {":", "_"} & set(value):
        return None
    read = (loader.construct_yaml_int if tag == _INT else loader.construct_yaml_float)(node)
    if ":" not in value:
        return (f"{_GROUPED}, the number {read!r}; write the number without it ({read!r}, if that "
                f"is what you meant), or '{value}' in quotes to mean text")
    colons = "a colon" if value.count(":") == 1 else "colons"
    return (f" has {colons}{_BASE_60} (sexagesimal) number, {read!r}; write {read!r}, or '{value}' "
            "in quotes to mean text")


def _misread(loader: Any, node: Any) -> str | None:
    """Why a number YAML 1.1 reads as other than it is written is refused (:func:`_octal`,
    :func:`_separated`), or None: the one rule the loader checks each value by."""
    return _octal(node) or _separated(loader, node)


def _unprintable_key(key: str) -> str:
    """The loader's refusal of a key holding a character that does not print (a zero-width or
    no-break space pasted in): shown, the key would read as the known key it differs from."""
    import unicodedata

    char = next(c for c in key if not c.isprintable())
    folded = as_ascii(key).strip()
    fix = f"write {folded!r}" if folded.isprintable() and folded.isascii() else "remove it"
    name = unicodedata.name(char, "a control character").lower()
    return f"the key {key!r} holds U+{ord(char):04X} ({name}), which does not print; {fix}"


@cache
def _loader() -> type:
    """A SafeLoader that refuses a key given twice in one mapping, as OmegaConf does, a null key
    (``~: 1``), an alias (``*name``) or a merge key (``<<:``): expanded, a few lines of aliases
    of aliases are billions of values; and a number YAML 1.1 reads as other than it is written,
    octal (``010``), base 60 (``1:30``) or grouped (``1_0``) (:func:`_misread`), named by its key
    (``factors.nodes[1]``)."""
    import yaml

    class Loader(yaml.SafeLoader):
        def compose_node(self, parent, index):  # index: the key node when composing its value
            tag = getattr(index, "tag", None)
            if tag == _MERGE:
                raise yaml.composer.ComposerError(
                    None, None, "the merge key << repeats keys given elsewhere, and merge keys are "
                                "not read (as aliases are not: expanded, a few can make billions "
                                "of values); write the keys out", index.start_mark)
            if tag == _NULL:  # ~: 1 or null: 1 (OmegaConf takes it for the key None)
                written = index.value or "''"
                raise yaml.composer.ComposerError(
                    None, None, f"the key {written} is YAML's null, not a name; write the name of "
                                "the setting", index.start_mark)
            if self.check_event(yaml.events.AliasEvent):
                event = self.peek_event()
                said = ("repeats a value given elsewhere" if event.anchor in self.anchors
                        else f"names no anchor (&{event.anchor}) before it")
                raise yaml.composer.ComposerError(
                    None, None, f"the alias *{event.anchor} {said}, and aliases are not read "
                                "(expanded, a few can make billions of values); write the value "
                                "out", event.start_mark)
            self.key_path = [*getattr(self, "key_path", []), _key_part(parent, index)]
            node = super().compose_node(parent, index)
            if (misread := _misread(self, node)) is not None:
                raise yaml.composer.ComposerError(
                    None, None, f"{''.join(self.key_path).lstrip('.')} = {node.value}{misread}",
                    node.start_mark)
            self.key_path.pop()
            return node

    def mapping(loader: yaml.SafeLoader, node: yaml.MappingNode, deep: bool = False) -> dict:
        seen: dict[Any, int] = {}
        for key_node, _ in node.value:
            key = loader.construct_object(key_node, deep=True)
            if isinstance(key, (list, dict)):  # '? [a, b]': a complex key, which no setting has
                start, end = key_node.start_mark, key_node.end_mark
                raise yaml.constructor.ConstructorError(
                    None, None, f"the key {start.buffer[start.index:end.index]} is a "
                                f"{'list' if isinstance(key, list) else 'mapping'}, not a name; "
                                "write the name of the setting", start)
            if isinstance(key, str) and not key.isprintable():  # 'se\u200beds', 'seeds\xa0'
                raise yaml.constructor.ConstructorError(
                    None, None, _unprintable_key(key), key_node.start_mark)
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None, None, f"key {key!r} is given twice (first on line {seen[key] + 1})",
                    key_node.start_mark)
            seen[key] = key_node.start_mark.line
        return loader.construct_mapping(node, deep)

    Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, mapping)
    return Loader


def read_yaml(path: Path, *, study: bool = False) -> dict[str, Any]:
    """Parse a study or group file and return its mapping.

    Raises
    ------
    ConfigError
        A file that cannot be read, is not UTF-8 (naming the line and byte), invalid YAML
        or YAML this loader refuses (naming the file and line), an empty study file, or a file
        that is not a mapping of keys.
    """
    import yaml

    try:
        size = Path(path).stat().st_size
        if size > _MAX_BYTES:  # PyYAML reads ~1 MB/s, and show reads it twice: 50 MB took minutes
            raise ConfigError(f"{path} is {math.ceil(size / 2**20 * 10) / 10:.1f} MiB; a study or "
                              "config-group file is at most 1 MiB (the shipped ones are under "
                              "5 KB, and each command reads YAML at about a second per MB, "
                              "twice, docs/decisions.md).")
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise ConfigError(f"{path} cannot be read ({exc.strerror or type(exc).__name__}).") from None
    text, why = utf8_text(raw)  # a byte-order mark is no content
    if text is None:
        raise ConfigError(f"{path}{why}; save it as UTF-8.")
    try:
        data = yaml.load(text, Loader=_loader())  # noqa: S506  (a SafeLoader subclass)
    except yaml.YAMLError as exc:
        raise ConfigError(_yaml_error_sentence(Path(path), exc, len(text.splitlines()))) from None
    except RecursionError:
        raise ConfigError(f"{path}: {NESTED_TOO_DEEPLY}") from None
    if _depth(data) > _MAX_DEPTH:
        raise ConfigError(f"{path}: {NESTED_TOO_DEEPLY}")
    if data is None:
        if study:
            raise ConfigError(f"{path} is empty; a study file needs at least the keys name and "
                              "kind.")
        return {}
    if not isinstance(data, dict):
        raise ConfigError(f"{path} must be a mapping of keys (name: ..., kind: ...), not a "
                          f"{type(data).__name__}.")
    if study:
        missing = [k for k in ("name", "kind") if k not in data]
        if missing:
            raise ConfigError(f"{path} has no {' and no '.join(missing)} key; a study file needs "
                              "at least the keys name and kind.")
    return data


def _depth(data: Any) -> int:
    """How many lists or mappings are nested within each other in ``data`` (read level by level,
    without recursion)."""
    depth, items = 0, [data]
    while containers := [item for item in items if isinstance(item, (dict, list))]:
        depth += 1
        items = [v for c in containers for v in (c.values() if isinstance(c, dict) else c)]
    return depth


def check_group_files() -> None:
    """Parse every YAML under ``conf/``; the first invalid one raises naming its file and line."""
    conf_dir, _ = project_dirs()
    for path in sorted(conf_dir.rglob("*.yaml")):
        read_yaml(path)


def configured_output(study: str | None, key: str = "run") -> str:
    """Return where a study writes by default, read without Hydra: its ``output.run`` (``key``
    ``"run"``) or its results root, ``output.root`` (``"root"``, ``~`` not yet read as a home).

    The study file's ``output.<key>`` if it sets one, else the ``conf/output`` default's
    (``default``, ``results``); for no study, or a name not on the search path (records of a study
    of another tool version), the ``conf/output`` default's.
    """
    try:
        data = {} if study is None else read_yaml(find_study(study), study=True)
    except ConfigError:
        data = {}
    output = data.get("output")
    if isinstance(output, dict) and output.get(key):
        return str(output[key])
    default = project_dirs()[0] / "output" / "default.yaml"
    value = read_yaml(default).get(key) if default.is_file() else None
    return str(value or {"run": "default", "root": "results"}[key])


def group_options(group: str) -> tuple[str, ...]:
    """Return the options of a config group (the YAML files in ``conf/<group>/``), sorted."""
    return tuple(sorted(p.stem for p in (project_dirs()[0] / group).glob("*.yaml")))
