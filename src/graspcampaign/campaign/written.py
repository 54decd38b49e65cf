"""Where a key is written in a YAML file, and what is written there: the line an error names
(``<path>, line 7: ...``, from PyYAML node marks) and, for a value YAML 1.1 read as true or false
from a word (``no``, ``On``), that word. Split from studycheck, which names every error by it.

Nothing here imports Hydra, OmegaConf or the numerical layers.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from graspcampaign.core.words import typed_value
from graspcampaign.errors import ConfigError

_BOOL, _NULL = "tag:yaml.org,2002:bool", "tag:yaml.org,2002:null"


def _key_nodes(text: str) -> dict[str, tuple[int, Any]]:
    """Return ``{dotted key: (1-based line, value node)}`` of every mapping key and list item of
    a YAML text (``factors.mu`` and ``factors.mu[1]``); empty if the text does not parse."""
    import yaml

    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError:
        return {}
    out: dict[str, tuple[int, Any]] = {}

    def walk(node: Any, key: str) -> None:
        if isinstance(node, yaml.MappingNode):
            for key_node, value in node.value:
                sub = f"{key}.{key_node.value}" if key else str(key_node.value)
                out.setdefault(sub, (key_node.start_mark.line + 1, value))
                walk(value, sub)
        elif isinstance(node, yaml.SequenceNode):
            for i, item in enumerate(node.value):
                sub = f"{key}[{i}]"
                out.setdefault(sub, (item.start_mark.line + 1, item))
                walk(item, sub)

    walk(root, "")
    return out


def file_nodes(path: Path) -> dict[str, tuple[int, Any]]:
    """:func:`_key_nodes` of the file at ``path``; empty if it cannot be read as UTF-8."""
    try:
        return _key_nodes(Path(path).read_text(encoding="utf-8-sig"))
    except (OSError, UnicodeDecodeError):
        return {}


def line_of(path: Path, key: str | None, nodes: dict[str, tuple[int, Any]] | None = None
            ) -> int | None:
    """The line of ``path`` that writes ``key`` or, failing that, its nearest parent (``nodes``:
    the file's :func:`file_nodes`, when read already)."""
    if not key:
        return None
    lines = {k: line for k, (line, _) in (file_nodes(path) if nodes is None else nodes).items()}
    while key:
        if key in lines:
            return lines[key]
        cut = max(key.rfind("."), key.rfind("["))
        key = key[:cut] if cut > 0 else ""
    return None


def in_file(path: Path, exc: ConfigError, key_prefix: str = "",
            nodes: dict[str, tuple[int, Any]] | None = None) -> ConfigError:
    """``exc`` with the file (and the line of its key) in front: ``<path>, line 7: ...``; a value
    it names as ``false (a boolean)`` or ``null`` that the file writes as a word YAML 1.1 reads as true,
    false or null (``no``, ``On``, ``NO``, ``~``) is named as written: ``no, which YAML reads as
    false; quote it: 'no'`` (the quotes where text is wanted). ``nodes``: the file's
    :func:`file_nodes`, when read already."""
    key = exc.key[len(key_prefix):] if exc.key and key_prefix else exc.key
    nodes = file_nodes(path) if nodes is None else nodes  # read once, for the line and the word
    line, text = line_of(path, key, nodes), str(exc)
    if (word := _yaml_word(nodes, key)) is not None:
        import yaml

        read = yaml.safe_load(word)  # what every YAML 1.1 reader makes of it
        said, as_read = ("null", "null") if read is None else (typed_value(read), str(read).lower())
        # quotes help where text and nothing else is wanted
        quote = f"; quote it: '{word}'" if f"must be of type str, got {said}." in text else ""
        text = text.replace(f"got {said}", f"got {word}, which YAML reads as {as_read}{quote}")
    where = f"{path}, line {line}" if line else f"{path}"
    return ConfigError(f"{where}: {text}", key=exc.key)


def _yaml_word(nodes: dict[str, tuple[int, Any]], key: str | None) -> str | None:
    """The word a file (its :func:`file_nodes`) writes at ``key`` if YAML reads it as a bool or
    null and it is none of ``true``, ``false``, ``null`` (``yes``, ``no``, ``on``, ``off`` in any
    of their cases, ``~``), else None."""
    written = nodes.get(key or "")
    node = written[1] if written else None
    if getattr(node, "tag", None) not in (_BOOL, _NULL) or node.style is not None:
        return None
    return None if node.value.lower() in ("true", "false", "null", "") else node.value
