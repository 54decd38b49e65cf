"""OmegaConf's and Hydra's errors about a study config, in one plain sentence naming the key
(a type, a missing key, an interpolation that cannot be resolved, a null where none is allowed)."""

from __future__ import annotations

import dataclasses
import re
from typing import Any

from graspcampaign.campaign.schema import example
from graspcampaign.campaign.studycheck import field_at, known_keys_sentence, section_of, split_optional
from graspcampaign.errors import ConfigError


def omegaconf_error_sentence(exc: BaseException, prefix: str = "",
                             typed: dict[str, str] | None = None) -> str:
    """Turn an OmegaConf/Hydra exception into one sentence in plain words naming the key. One
    raised by a check of ours (a ``ConfigError`` a schema's ``__post_init__`` raised, which
    OmegaConf wraps) is already that sentence, its key named: it is returned as it is. ``typed``:
    each override's value as the user typed it, by key, to name a number Hydra read as one
    (``runner.n_jobs=1e3`` is "got 1e3", not Python's "got 1000.0")."""
    own = exc
    while own is not None and not isinstance(own, ConfigError):
        own = own.__cause__ or own.__context__
    if own is not None:
        return str(own)
    while not hasattr(exc, "full_key") and (exc.__cause__ or exc.__context__) is not None:
        exc = exc.__cause__ or exc.__context__
    key = getattr(exc, "full_key", None) or getattr(exc, "key", None)
    text = str(getattr(exc, "msg", None) or exc).strip().splitlines()[0].rstrip(".")
    if not key:
        return f"{text}."
    key = f"{prefix}{key}"
    schema = getattr(exc, "object_type", None)
    value = getattr(exc, "value", None)
    if type(exc).__name__ == "ConfigKeyError" or "not in struct" in text or "not in '" in text:
        if dataclasses.is_dataclass(schema):
            return known_keys_sentence(key, schema)
        return f"{key} is not a known key of {section_of(key)}."
    match = re.search(r"Interpolation key '([^']+)' not found", text)
    if match:
        return f"{key} refers to ${{{match.group(1)}}}, which is not a key of the study config."
    if "Interpolation" in type(exc).__name__:  # ${oc.env:NOPE}, ${nosuch:x}: as written
        written = getattr(exc, "child_node", None)
        shown = f" = {str(written)!r}" if written is not None else ""
        if to := re.search(r"Value (.*) of type '\w+' could not be converted to (Integer|Float)$",
                           text):  # resolved, to what no number is: ${oc.env:HOME} for a seed
            return (f"{key}{shown} resolves to {to[1]}, not "
                    f"{'a whole number' if to[2] == 'Integer' else 'a number'}.")
        return f"{key}{shown} cannot be resolved: {_unresolved(text)}."
    found = None if prefix else field_at(key)
    base = split_optional(str(found[1].type))[0] if found else None
    if "is not Optional" in text:
        return f"{key} cannot be null; it takes {_takes(key, base)}."
    if "is not a valid bool" in text:
        return f"{key} must be true or false, got {value!r}."
    if match := re.search(r"could not be converted to (Integer|Float)", text):
        said = str(value).lower() if isinstance(value, bool) else repr(value)  # seeds=true: as typed
        if not isinstance(value, (str, bool)) and (typed or {}).get(key):
            said = typed[key].strip()
        if said.endswith("."):  # seeds=3.: "got 3.." read as a typo; say what the point is
            said += " (with a decimal point)"
        return f"{key} must be {'a whole number' if match[1] == 'Integer' else 'a number'}, got {said}."
    if key.startswith("factors.") and key.count(".") == 1 and "[" not in key:
        name = key.split(".", 1)[1]
        return (f"{key} takes a list of levels, e.g. {key}={example(name).replace(' ', '')} (or "
                f"the bare {name}={example(name)[1:].split(',')[0]}){_got(value, text)}.")
    if re.search(r"Cannot merge|Cannot assign|incompatible with type hint|is not a ListConfig|"
                 r"is not a subclass|Cannot convert '\w+' to string", text):
        return f"{key} must be {_takes(key, base)}{_got(value, text)}."
    return f"{key}: {text}."


def _got(value: Any, text: str) -> str:
    """``, got <value>`` for a message, or ``""`` when OmegaConf names none. A mapping merged
    into a list (``factors.mu={a:1}``) comes with no value, only "Cannot merge DictConfig with
    ListConfig": it is named as a mapping, not as None."""
    if value is not None:
        return f", got {value!r}"
    return ", got a mapping" if text.startswith("Cannot merge DictConfig") else ""


def _unresolved(text: str) -> str:
    """Why OmegaConf could not resolve an interpolation, in plain words."""
    if match := re.search(r"Environment variable '([^']+)' not found", text):
        return (f"environment variable {match[1]} is not set (set it, or give a default: "
                f"${{oc.env:{match[1]},VALUE}})")
    if match := re.match(r"Unsupported interpolation type (\S+)", text):
        return f"OmegaConf has no resolver named {match[1]}"
    return re.sub(r"^\w+ raised while resolving interpolation: ", "", text)


def _takes(key: str, base: str | None) -> str:
    if key == "factors":
        return "a mapping of factor names to lists of levels (e.g. factors.mu=[0.3])"
    if base is None:
        return "a value"
    if base in ("int", "float", "str"):
        return f"a value of type {base}"
    from graspcampaign.campaign.studycheck import type_words

    return type_words(base, key)
