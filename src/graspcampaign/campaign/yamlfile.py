"""The first look at a study or config-group YAML file, before Hydra sees it: :func:`read_yaml`
and its checking loader, which refuses in words what YAML would read otherwise than it is written
(a key given twice, an alias, a merge key, a null or a list as a key, a key holding a character
that does not print or a space at an end, an octal, base-60 or digit-grouped number), a file too
large or nested too deeply to read, and one that is not UTF-8.

Split from :mod:`graspcampaign.campaign.studyfile` (where study and group files live), which
imports :func:`read_yaml` from here; nothing here imports Hydra, numpy or the numerical layers.
"""

from __future__ import annotations

import math
import re
from functools import cache
from pathlib import Path
from typing import Any

from graspcampaign.core.words import as_ascii
from graspcampaign.errors import ConfigError, utf8_text

_MAX_BYTES = 2**20  # a study or config-group file (docs/decisions.md)
_MAX_DEPTH = 100  # lists and mappings within each other: OmegaConf's recursion fails at ~150
NESTED_TOO_DEEPLY = (f"its lists or mappings are nested too deeply to read (over {_MAX_DEPTH} "
                     "levels within each other); a config nests a few.")


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


def _spaced_key(key: str) -> str | None:
    """The loader's refusal of a key that is empty or begins or ends with a space (``"seeds ":
    2``, quoted), or None: no setting's name has one, and shown bare the key reads as the known
    key it differs from ("seeds  is not a known key ...; did you mean seeds?")."""
    if not key.strip(" "):
        return (f"the key {key!r} is {'only spaces' if key else 'empty'}, and no setting is named "
                "so; write the name of the setting")
    if key == key.strip(" "):
        return None
    where = ("begins and ends" if key[0] == key[-1] == " " else
             "begins" if key[0] == " " else "ends")
    return (f"the key {key!r} {where} with a space, which no setting's name has; write "
            f"{key.strip(' ')!r}")


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
            if isinstance(key, str) and (spaced := _spaced_key(key)) is not None:
                raise yaml.constructor.ConstructorError(
                    None, None, spaced, key_node.start_mark)
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
