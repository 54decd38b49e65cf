"""Quote-aware scans of an override's value as Hydra's grammar reads it, made before Hydra parses it
(its parse keeps only the last of a repeated key, takes a time quadratic in the values, and
evaluates a function before anything can name it): the characters outside quoted strings, a
mapping's keys, the count of values, a call of one of Hydra's functions of sweeps, the numbers
written with an underscore, those no finite number.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from typing import Any


def unquoted(value: str) -> Iterator[tuple[int, str]]:
    """``(index, character)`` of each character of an override's ``value`` outside its quoted
    strings, as Hydra's grammar (``QUOTED_VALUE``) reads them: a string runs from a quote to the
    same quote not escaped by a backslash (``'a\\'b'`` is one string). A quote never closed is no
    string to Hydra either: its characters are outside."""
    i = 0
    while i < len(value):
        char = value[i]
        if char in "'\"":
            end = re.match(rf"(?:\\.|[^\\{char}])*{char}", value[i + 1:], re.DOTALL)
            if end:
                i += 1 + end.end()
                continue
        yield i, char
        i += 1


def blanked(value: str) -> str:
    """An override's ``value`` with each character of its quoted strings (:func:`unquoted`) a space."""
    kept = dict(unquoted(value))
    return "".join(kept.get(i, " ") for i in range(len(value)))


def words(value: str, quoted: bool = False) -> list[str]:
    """The words of an override's ``value`` outside its quoted strings (``quoted``: inside them too)."""
    return re.findall(r"[^\s\[\]{}(),:='\"]+", value if quoted else blanked(value))


def underscored_numbers(value: str, quoted: bool = False) -> list[str]:
    """The :func:`words` of an override's ``value`` written as a number with an underscore (``1_0``,
    ``[144,1_750]``, ``-0.1_5``): those Hydra's grammar may read as a number with its digits grouped
    (``1_0`` is 10), which the caller asks it."""
    return [w for w in words(value, quoted) if "_" in w
            and re.fullmatch(r"[+-]?[\d_.]+(?:[eE][+-]?[\d_]+)?", w)]


def not_finite(value: str, quoted: bool = False) -> str | None:
    """The first of the :func:`words` of an override's ``value`` that Hydra's grammar (or the
    float() of a number field) reads as a float that is no finite number (``1e400`` overflows to
    inf; ``nan``, ``-inf``, ``Infinity``), said as typed with what it is (``'1e400 overflows to inf
    (...)'``); None if there is none."""
    for word in words(value, quoted):
        if not re.fullmatch(r"[+-]?(?:[\d_]*\.?[\d_]*(?:[eE][+-]?[\d_]+)?|inf(?:inity)?|nan)", word, re.I):
            continue
        try:
            read = float(word.replace("_", ""))
        except ValueError:  # '.', '1.2.3'
            continue
        if read != read:
            return f"{word} is not a number"
        if abs(read) == float("inf"):
            return (f"{word} is infinite" if word.lower().lstrip("+-").startswith("inf") else
                    f"{word} overflows to {read} (no float is that large)")
    return None


def not_finite_leaves(key: str, value: Any) -> Iterator[str]:
    """The dotted path of each value in an override's parsed ``value`` set at ``key`` that is no finite
    number: a float (``nan``, ``1e400``) or a text that float() reads as one (``Infinity``, text to
    Hydra, a number to a number field); a mapping's keys and a list's indices extend the path
    (``pso.inertia``, ``factors.mu.0``)."""
    if isinstance(value, dict | list):
        for k, v in value.items() if isinstance(value, dict) else enumerate(value):
            yield from not_finite_leaves(f"{key}.{k}", v)
    elif isinstance(value, float) and not math.isfinite(value):
        yield key
    elif isinstance(value, str) and not_finite(value, quoted=True):
        yield key


def mapping_keys(value: str) -> list[str]:
    """The top-level keys of a ``{k: v, ...}`` value as typed, repeats kept (Hydra's parser keeps
    only the last of a repeated key, so a repeat must be seen before it parses); a quoted string
    (:func:`unquoted`) is part of the key or value it stands in."""
    return [key for key, _ in mapping_entries(value)]


def mapping_entries(value: str) -> list[tuple[str, str]]:
    """:func:`mapping_keys` each with the text typed after it, up to the next key (``{a: [1, 2], b: 3}``:
    ``('a', ' [1, 2],')``, ``('b', ' 3}')``)."""
    if not value.lstrip().startswith("{"):
        return []
    keys, depth, start, in_key = [], 0, 0, False
    for i, char in unquoted(value):
        if char in "[{(":
            depth += 1
            if depth == 1:
                start, in_key = i + 1, True
        elif char in "]})":
            depth -= 1
        elif depth == 1 and char == ",":
            start, in_key = i + 1, True
        elif depth == 1 and char == ":" and in_key:
            keys.append((value[start:i].strip(), start, i + 1))
            in_key = False
    ends = [start for _, start, _ in keys[1:]] + [len(value)]
    return [(key, value[after:end]) for (key, _, after), end in zip(keys, ends, strict=False)]  # no key: []


def n_values(value: str) -> int:
    """The elements an override's ``value`` holds: one more than its commas outside quoted strings,
    at any depth of brackets (``[1,2],3`` counts 3, where Hydra's grammar splits the top level
    into 2 values). Elements, not top-level values, are the measure of the limit this guards:
    Hydra's parse time grows with the elements it reads, nested or not. A comma inside a quoted
    string (:func:`unquoted`; ``'a,b'``) separates nothing, and its parse takes a time linear
    in the string."""
    return 1 + sum(char == "," for _, char in unquoted(value))


#: Hydra's functions of sweeps (its grammar's sweeps choice, range, interval and glob, and tag,
#: sort and shuffle, which tag, order or shuffle a sweep's values or a list): a value calling one
#: is refused as a sweep is, whatever it returns (sort([b,a]) is the list [a,b]).
SWEEP_FUNCTIONS = ("choice", "range", "interval", "glob", "tag", "sort", "shuffle")


def sweep_function(value: str) -> str | None:
    """The first of :data:`SWEEP_FUNCTIONS` an override's ``value`` calls where Hydra's grammar
    reads a call (at the start of the value or of an element, ``[a,sort([b,c])]``), outside its
    quoted strings (:func:`unquoted`; ``'sort(x)'`` is text), or None."""
    plain, names = blanked(value), "|".join(SWEEP_FUNCTIONS)
    match = re.search(rf"(?:^|[\[{{,:(=])\s*({names})\s*\(", plain)
    return match[1] if match else None
