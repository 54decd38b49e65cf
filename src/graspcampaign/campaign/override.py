"""Command-line overrides of a study: what is refused before Hydra sees it, bare factor names, and
one plain sentence for every error Hydra or OmegaConf raises about an override.

Refused up front: an override without a key (``=3``); a key named twice (Hydra keeps the last);
one of more than :data:`MAX_OVERRIDE_VALUES` values (Hydra's parser is quadratic in them); Hydra's
own keys (``hydra.run.dir=/tmp``, ``+hydra.x=1``), which the Compose API accepts and ignores
because this tool runs the study itself; a whole config group deleted (``~runner``); a bool set
to anything but ``true``/``false`` (OmegaConf reads ``pso.enabled=2`` as true); a number with a
leading zero (text to Hydra) or an underscore (``seeds=1_0``: its digits grouped, 10).
"""

from __future__ import annotations

import dataclasses
import errno
import json
import re
import unicodedata
from typing import Any

from graspcampaign.campaign import override_groups, override_scan
from graspcampaign.campaign.factor_words import not_a_factor
from graspcampaign.campaign.former_names import FORMER_FACTORS, former_factor
from graspcampaign.campaign.omegaconf_words import omegaconf_error_sentence
from graspcampaign.campaign.override_groups import missing_option_sentence
from graspcampaign.campaign.override_scan import mapping_keys, n_values, sweep_function, underscored_numbers
from graspcampaign.campaign.schema import FACTOR_SPECS, StudyCfg
from graspcampaign.campaign.studycheck import GROUPS, field_at, known_keys_sentence, schema_at, split_optional
from graspcampaign.campaign.studyfile import NESTED_TOO_DEEPLY, group_options
from graspcampaign.core.words import as_ascii, meant, stands_for
from graspcampaign.errors import ConfigError

#: The most comma-separated values one override holds: Hydra's parser takes a time quadratic in
#: them (one parse of 2,000 about 1 s, 4,000 about 2.3 s, 20,000 over 2 minutes; a command parses
#: an override several times: docs/decisions.md, "Long list overrides").
MAX_OVERRIDE_VALUES = 2000


def split(item: str) -> tuple[str, str, str, str]:
    """``'+factors.mu=[0.3]'`` -> ``('+', 'factors.mu', '=', '[0.3]')``."""
    prefix = re.match(r"[+~]*", item).group(0)
    key, sep, value = item[len(prefix):].partition("=")
    return prefix, key.strip(), sep, value


def group(item: str) -> str:
    """The top-level config key an override as given sets (``paper`` of ``paper.auc=0.7``)."""
    return split(item)[1].split(".")[0]


def check_overrides(given: list[str]) -> None:
    """Refuse, before composition, overrides Hydra would misread or silently ignore.

    Raises
    ------
    ConfigError
        Naming the override as typed and what to write instead.
    """
    named: dict[str, str] = {}  # a key (a factor by its bare name) -> the override naming it
    for item in given:
        prefix, key, sep, value = split(item)
        if not key:
            raise ConfigError(f"override {item!r} has no key before '='; write KEY=VALUE, e.g. "
                              "seeds=3 or mu=[0.3,0.5].")
        for name in [key] + [f"{key}.{inner}" for inner in mapping_keys(value)]:
            if (first := named.get(name.removeprefix("factors."))) is not None:
                said = (f"override {item!r} names {name} twice" if first == item else
                        f"overrides {first!r} and {item!r} both name {name}")
                raise ConfigError(f"{said}; give it once (Hydra would keep the last silently).", key=name)
            named[name.removeprefix("factors.")] = item
        if (values := n_values(value)) > MAX_OVERRIDE_VALUES:  # before Hydra parses it
            raise ConfigError(f"override {item!r} holds {values:,} comma-separated values, more "
                              f"than an override can hold ({MAX_OVERRIDE_VALUES:,}); give them in "
                              "a study file instead (a copy of the study run by its path, e.g. "
                              "graspcampaign run ./my_study.yaml; README, Your own studies).",
                              key=key)
        if key == "hydra" or key.startswith(("hydra.", "hydra/")):
            raise ConfigError(f"override {item!r} sets {key}, a key of Hydra's own runtime; this "
                              "tool uses Hydra to compose studies and runs them itself, so hydra "
                              "keys have no effect: leave it out.", key=key)
        if "~" in prefix and key in GROUPS:  # Hydra drops the group's file: the schema's values
            raise ConfigError(f"override {item!r} deletes the config group {key}, which every "
                              f"study needs; set one of its options instead ({key}=OPTION; "
                              f"options: {', '.join(group_options(key))}).", key=key)
        required = field_at(key) if "~" in prefix else None
        # ~name: OmegaConf's missing mark, '???'; ~model.lambda1: a section's schema keeps its keys
        if required and (required[1].default == "???" or "." in key):
            raise ConfigError(f"override {item!r} deletes {key}, which every study needs; set it "
                              f"instead ({key}=...).", key=key)
        if required:  # ~seeds: the schema's default stands in for the study's 15, unsaid
            field = required[1]  # (checked before composition: whether the study sets it is unknown)
            default = (field.default if field.default_factory is dataclasses.MISSING
                       else field.default_factory())
            raise ConfigError(f"override {item!r} deletes {key}, a key every study has: it would "
                              f"only put back the schema's default ({json.dumps(default)}), which "
                              f"a study that does not set {key} already holds; set the value you "
                              f"want instead ({key}=...).", key=key)
        setting, parts = bool(sep) and "~" not in prefix, key.split(".")
        for i in range(1, len(parts) if setting else 0):  # evaluator.alpha.x=1, factors.mu.0.x=1
            single = ".".join(parts[:i])
            if _one_value(single):
                raise ConfigError(f"{single} takes one value, so {key} names nothing in it (override "
                                  f"{item!r} rejected); set it as {single}=VALUE.", key=single)
        parsed = _parse(item) if setting else None  # once: the checks below read it
        if setting and (why := override_groups.problem(item, prefix, key, value, _value(parsed))):
            raise ConfigError(why, key=key)
        if setting and key in GROUPS and isinstance(_value(parsed), list):  # Hydra merges all
            raise ConfigError(missing_option_sentence(key, value.strip()), key=key)
        if setting and _value(parsed) == {}:  # merged into the study's: it changes nothing
            choose = (f"choose one of its options ({key}=OPTION; options: "
                      f"{', '.join(group_options(key))}) or " if key in GROUPS else "")
            raise ConfigError(f"override {item!r} gives {key} an empty mapping, which changes "
                              f"nothing (it is merged into the study's {key}); {choose}set one of "
                              f"its keys ({key}.KEY=VALUE), or leave the override out.", key=key)
        found = field_at(key) if setting else None
        if found and split_optional(str(found[1].type))[0] == "bool":
            read = _value(parsed)
            if read is not _UNPARSED and not isinstance(read, bool):
                raise ConfigError(f"{key} must be true or false, got {read!r} (override "
                                  f"{item!r}).", key=key)
        numeric = setting and _numeric(key, found)
        if setting and (zero := _leading_zero(parsed)):
            number = int(zero.replace("_", ""))
            raise ConfigError(f"override {item!r}: {zero} has a leading zero, which Hydra reads as "
                              f"the text '{zero}', not the number {number}; write {number}"
                              + ("." if numeric else f", or quote it ('{zero}') to mean text."), key=key)
        # 1e400 is inf to Hydra, refused by the schema as "inf"; a mapping's numbers too (pso={...}), as
        # typed in the entry whose key takes a number ({run: nan, ...}: nan is a run's name), quoted
        # text there included (pso={inertia: 'Infinity'}: text to Hydra, inf to the number field)
        bad = [at[len(key) + 1:].split(".")[0] for at in override_scan.not_finite_leaves(key, _value(parsed))
               if _numeric(at, field_at(at))] if setting else []
        typed = dict(override_scan.mapping_entries(value)).get(bad[0], "") if bad else ""
        if number := override_scan.not_finite(value if numeric else typed, numeric or bool(typed)):
            raise ConfigError(f"override {item!r}: {number}; give a finite number.", key=key)
        # seeds=1_0 is ten to Hydra, seeds='1_0' to OmegaConf's int(): seldom what was meant
        for word in underscored_numbers(value, quoted=numeric) if setting else ():
            read = _parsed_value(f"x={word}")
            if isinstance(read, int | float) and not isinstance(read, bool):
                raise ConfigError(f"override {item!r}: {word} has an underscore, which is read as "
                                  f"grouping digits, the number {read}; write the value without it "
                                  f"({read}, if that is what you meant)"
                                  + ("." if numeric else f", or quote it ('{word}') to mean text."), key=key)


def _numeric(key: str, found: Any) -> bool:
    """Whether ``key`` (``found``: its schema field, or None) takes a number: a field of type int or
    float, or a level of a factor whose levels are not text (``nodes.0``)."""
    name, index = _factor_and_index(key)
    factor = FACTOR_SPECS.get(name) if index.isdigit() or not index else None
    return (split_optional(str(found[1].type))[0] in ("int", "float") if found else
            factor is not None and factor["type"] is not str)  # quoting makes no text


def _one_value(key: str) -> bool:
    """Whether ``key`` names a single value: a field of a scalar type (``evaluator.alpha``) or a
    level of a known factor (``factors.mu.0``; every factor's levels are single values)."""
    parts = key.split(".")
    if parts[0] == "factors" and len(parts) == 3:
        return parts[1] in FACTOR_SPECS and parts[2].isdigit()
    head = field_at(key)
    return bool(head) and split_optional(str(head[1].type))[0] in ("int", "float", "str", "bool")


_UNPARSED = object()


def _parse(item: str) -> Any:
    """Hydra's reading of an override (its ``Override``), or None where its grammar refuses it:
    the one parse that :func:`_value` and :func:`_leading_zero` read (a parse takes a time
    quadratic in the values, docs/decisions.md, "Long list overrides")."""
    from hydra.core.override_parser.overrides_parser import OverridesParser

    try:
        return OverridesParser.create().parse_overrides([item])[0]
    except Exception:  # noqa: BLE001  (a parse error is Hydra's to report, with its position)
        return None


def _value(parsed: Any) -> Any:
    """The value of a parsed override (``'2'`` -> 2; :func:`_parse`), or ``_UNPARSED``."""
    if parsed is None:
        return _UNPARSED
    value = parsed.value()
    return _UNPARSED if isinstance(value, str) and "${" in value else value


def _parsed_value(item: str) -> Any:
    """The value Hydra's grammar reads from an override (``'2'`` -> 2), or ``_UNPARSED``."""
    return _value(_parse(item))


def _leading_zero(parsed: Any) -> str | None:
    """An integer written with a leading zero, unquoted, in a parsed override's value (``010``,
    ``[144,0144]``; :func:`_parse`), or None: Hydra's grammar reads it as text, which ``seeds``
    took as 10 and ``nodes`` refused unexplained (docs/decisions.md)."""
    if parsed is None:
        return None
    # Hydra's private _value, read here only: its public value() turns a QuotedString into the
    # same str as unquoted text, and only the rendering get_value_element_as_str() shows the
    # quotes, which would have to be parsed again
    items = [parsed._value]
    while items:  # a QuotedString is quoted text, no str
        value = items.pop()
        items += value if isinstance(value, list) else value.values() if isinstance(value, dict) else []
        if type(value) is str and re.fullmatch(r"[+-]?0[0-9_]*[0-9]", value):
            return value
    return None


def rewrite(factors: set[str], overrides: list[str]) -> list[str]:
    """Map bare factor names to ``factors.<name>`` and scalars to one-level lists.

    Only ``name=value`` and ``name.N=value`` (level ``N``) exactly; a bare factor name in any
    other form (``+name=``, ``+name.0=``, ``name.x=``) is refused, as is one with a dotted tail
    that is no factor of this study. A space around the key is left to Hydra, which refuses it,
    as it does for every other key; ``~name`` is the deletion's to name, but a level deleted by
    its index (``~name.N``, ``~factors.name.N``) is refused: Hydra deletes no list item.

    Raises
    ------
    ConfigError
        Naming the override as typed and what to write instead.
    """
    out = []
    for item in overrides:
        prefix, key, sep, value = split(item)
        head, dot, tail = key.partition(".")
        if "~" in prefix and (level := _deleted_level(key, factors)):
            raise ConfigError(f"override {item!r} deletes level {level[1]} of the factor {level[0]} "
                              f"(factors.{level[0]}.{level[1]}), but a level cannot be deleted by "
                              f"its index (Hydra deletes no item of a list); give the levels to "
                              f"keep instead, as {level[0]}=[...].", key=f"factors.{level[0]}")
        if key in factors and item.startswith(f"{key}="):
            value = value.strip()
            out.append(f"factors.{key}={value if value.startswith('[') else f'[{value}]'}")
        elif head in factors and tail.isdigit() and item.startswith(f"{key}="):
            out.append(f"factors.{item}")  # one level, as factors.shape.0=cube
        elif ((dot or "+" in prefix) and "~" not in prefix and sep and item.startswith(prefix + key)
              and (head in factors or head in FACTOR_SPECS) and field_at(head) is None):
            if head not in factors:  # planner.0=pso where planner is no factor: add it first
                raise ConfigError(_unknown_override(head, item, sorted(factors)), key=key)
            level = f"{head}.{tail}={value.strip()}" if tail.isdigit() else f"{head}.0=VALUE"
            raise ConfigError(f"override {item!r} names the factor {head} by its bare name in a "
                              f"form it does not take; write {level} (one level, as "
                              f"factors.{level}) or {head}=[...] (all its levels).", key=key)
        else:
            out.append(item)
    return out


def _deleted_level(key: str, factors: set[str]) -> tuple[str, str] | None:
    """The factor and level index a deletion's ``key`` names (``shape.0`` or ``factors.shape.0``,
    read as ``shape.0=cube`` is), or None where it names no level of a factor of this study."""
    name, index = _factor_and_index(key)
    return (name, index) if name in factors and index.isdigit() else None


def _factor_and_index(key: str) -> tuple[str, str]:
    """A key read as a factor and what follows its name, with or without ``factors.``
    (``nodes.0`` and ``factors.nodes.0``: ``('nodes', '0')``, a level of nodes; ``nodes``:
    ``('nodes', '')``): whether the name is a factor and the rest a level's index is the
    caller's to ask."""
    name, _, index = key.removeprefix("factors.").partition(".")
    return name, index


def check_sweeps(overrides: list[str], given: list[str]) -> None:
    """Refuse Hydra's sweeps (``seeds=1,2``, ``choice()``, ``range()``, ``interval()``,
    ``glob()``, also inside a list) and its other functions of sweeps (``tag()``, ``sort()``,
    ``shuffle()``; :data:`~graspcampaign.campaign.override_scan.SWEEP_FUNCTIONS`): a sweep is many
    studies (Hydra's ``--multirun``), and this tool composes one study per command. Checked after
    bare factor names are rewritten, where ``shape=sphere,pear`` is already the list
    ``factors.shape=[sphere,pear]``.

    Raises
    ------
    ConfigError
        Naming the override as typed and what to write instead.
    """
    from hydra.core.override_parser.types import Glob, Sweep

    def holds_sweep(value: Any) -> bool:  # the whole value a sweep, or one inside a list or dict
        if isinstance(value, (list, dict)):
            return any(holds_sweep(v) for v in (value.values() if isinstance(value, dict) else value))
        return isinstance(value, (Sweep, Glob))

    for item, typed in zip(overrides, given, strict=True):
        # unparsed: Hydra names the error when it composes, unless the value calls a function of
        # sweeps (tag(a,[sphere]) is Hydra's TypeError); a list sort() or shuffle() returns is none
        if holds_sweep(_parsed_value(item)):
            what = "is a sweep"
        elif (function := sweep_function(split(item)[3])) is not None:
            what = f"calls {function}(), a function of Hydra's sweeps"
        else:
            continue
        raise ConfigError(f"override {typed!r} {what} (one study per value, Hydra's --multirun), "
                          "which this tool does not run; give a factor its levels as a list (e.g. "
                          "mu=[0.3,0.5]), or run the study once per value.", key=split(item)[1])


def _typed(key: str, overrides: list[str], given: list[str]) -> str | None:
    """The override as the user typed it that sets ``key`` (after bare-name rewriting)."""
    return next((typed for item, typed in zip(overrides, given, strict=True)
                 if split(item)[1] == key), None)


def override_sentence(exc: BaseException, overrides: list[str], given: list[str], factors: list[str] = (),
                      set_keys: list[str] = (), reads: tuple[str, list[str]] | None = None) -> str:
    """One sentence for a composition error, naming the user's override as they typed it (and, for a
    bare key, the study's factors: ``shape=[...]`` works only where shape is a factor, and is added only
    where its trial kind reads it, ``reads``: (kind, the factors it reads), None if unknown; for a
    ``params.``/``paper.`` key the study does not set, the nearest of the keys it sets, ``set_keys``)."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    if isinstance(exc, RecursionError):  # Hydra's parser recurses once per level of [ or {
        deepest = max(given, key=lambda typed: typed.count("[") + typed.count("{"))
        return f"override {deepest!r}: {NESTED_TOO_DEEPLY}"
    if type(exc).__name__ == "OverrideParseException":
        from hydra.core.override_parser.overrides_parser import OverridesParser

        parser = OverridesParser.create()
        for item, typed in zip(overrides, given, strict=True):
            try:
                parser.parse_overrides([item])
            except Exception as error:  # noqa: BLE001  (the one that fails is the one to name)
                if "=" not in item and not item.startswith("~"):  # ~key deletes: no value
                    return f"cannot parse override {typed!r}: expected key=value, e.g. mu=0.3."
                return (_character_sentence(item, typed, str(error))
                        or f"cannot parse override {typed!r}: {_parse_reason(str(error), typed, parser)}"
                           "; write KEY=VALUE, a list as [a,b], and quote a value holding other "
                           "characters.")
        return f"cannot parse overrides: {text.rstrip('.')}."
    if getattr(exc, "errno", None) == errno.ENAMETOOLONG:  # Hydra looked for the key as a group
        key = max((split(item)[1] for item in overrides), key=len)
        return _unknown_override(key, _typed(key, overrides, given), factors, set_keys, reads)
    match = re.match(r"Could not override '([^']+)'", text)
    if match:
        return _unknown_override(match.group(1), _typed(match.group(1), overrides, given),
                                 factors, set_keys, reads)
    match = re.match(r"Could not delete from config\. '([^']+)' does not exist", text)
    if match:
        return _nothing_to_delete(match.group(1), _typed(match.group(1), overrides, given), factors)
    match = re.match(r"Could not append to config\. An item is already at '([^']+)'", text)
    if match:  # Hydra names the key alone
        typed = _typed(match[1], overrides, given) or f"+{match[1]}=..."
        return (f"override {typed!r} adds {match[1]}, which every study has already; set it "
                f"without the leading '+': {typed.lstrip('+')}.")
    match = re.search(r"Could not find '([\w-]+)/([^']*)'", text)
    if match:
        return missing_option_sentence(match.group(1), match.group(2))
    match = re.fullmatch(r"invalid literal for int\(\) with base 10: '([^']*)'", text)
    for item, typed in zip(overrides, given, strict=True) if match else ():  # factors.mu.x=1
        parts = split(item)[1].split(".")
        if match[1] in parts[1:]:
            listed = ".".join(parts[:parts.index(match[1], 1)])
            return (f"{listed} is a list, so {listed}.{match[1]} is not an item of it (override "
                    f"{typed!r} rejected); an item is named by its index, e.g. {listed}.0.")
    if text.startswith("Config group override must be"):  # evaluator=3: Hydra names no group
        for item in overrides:
            _, key, _, value = split(item)
            if key in GROUPS and not re.fullmatch(r"[A-Za-z_][\w-]*", value.strip()):
                return missing_option_sentence(key, value.strip())
    return omegaconf_error_sentence(exc, typed={split(item)[1]: split(typed)[3]
                                                for item, typed in zip(overrides, given, strict=True)})


_LEXER = "LexerNoViableAltException: "


def _parse_reason(error: str, typed: str, parser: Any) -> str:
    """The reason Hydra's parser gives (its second line), in plain words, for the override as
    ``typed`` if it fails too (``mu=(0.3,0.5)``, whose rewriting fails at ``[(``, which no one
    typed): ``extraneous input '(' expecting {<EOF>, ...}`` -> ``unexpected '('``."""
    try:
        parser.parse_overrides([typed])
    except Exception as own:  # noqa: BLE001  (any refusal of Hydra's parser)
        error = str(own)
    lines = error.splitlines()
    reason = lines[1] if len(lines) > 1 and not lines[1].startswith("See ") else lines[0]
    match = re.match(r"(?:extraneous|mismatched) input ('.*') expecting", reason)
    if match:
        return f"unexpected {match[1]}"
    match = re.match(r"no viable alternative at input ('.*')", reason)
    return f"cannot read {match[1]}" if match else reason.rstrip(".")


def _character_sentence(item: str, typed: str, error: str) -> str | None:
    """Name the character Hydra's lexer stopped at (its message marks it with a caret under the
    override) and the fix: a key of ASCII characters without spaces, or a quoted value."""
    lines = error.splitlines()
    controls = [i for i, c in enumerate(item) if unicodedata.category(c) == "Cc"]
    if not lines[0].startswith(_LEXER) or not controls and (len(lines) < 2 or "^" not in lines[1]):
        return None
    at = controls[0] if controls else lines[1].index("^") - len(_LEXER)
    if not 0 <= at < len(item):
        return None
    # the caret marks where the lexer's token began ('factors.' of 'factors.μ'): the character is
    # the first one after it that no key or prefix holds
    at = next((i for i in range(at, item.find("=") if "=" in item else len(item))
               if not (item[i].isascii() and (item[i].isalnum() or item[i] in "_-./+~@"))), at)
    char = item[at]
    shown = (repr(char) if char.isprintable() and not char.isspace() or char == " " else
             f"byte 0x{ord(char) - 0xDC00:02X}" if 0xDC80 <= ord(char) <= 0xDCFF else
             f"U+{ord(char):04X} ({unicodedata.name(char, 'a control character').lower()})")
    equal = typed.find("=")
    if unicodedata.category(char) == "Cc":  # a newline or a control character: no quote helps
        return (f"cannot parse override {typed!r}: {shown} (character {typed.find(char) + 1}) is "
                "not allowed in an override; remove it.")
    # a look-alike (٣, a no-break space, a zero-width space): quoting keeps it; its ASCII is meant
    folded = as_ascii(typed)
    if equal < 0 or at < item.find("="):  # in the key (or the prefix before it)
        where = typed.find(char) + 1
        fix = (f"; write {''.join(folded.split())!r}"
               if char.isspace() or stands_for(char) is not None else "")
        return (f"cannot parse override {typed!r}: its key has {shown} at character {where}, but "
                f"a key takes only ASCII letters, digits, '_', '-', '.' and '/'{fix}.")
    where = typed.find(char, equal + 1) + 1
    if (ascii_char := stands_for(char)) is not None:
        looks = ("shows as nothing" if not ascii_char else
                 f"looks like {'a space' if ascii_char == ' ' else repr(ascii_char)} but is not ASCII")
        return f"cannot parse override {typed!r}: {shown} (character {where}) {looks}; write {folded!r}."
    if shown.startswith("byte"):  # an argument's byte the locale could not decode (surrogateescape)
        return (f"cannot parse override {typed!r}: {shown} (character {where}) is not UTF-8 text (a "
                "terminal in another encoding?); type the override in UTF-8.")
    # the unquoted word holding the character, between [ ] { } , = outside an interpolation ${…}
    spans = [range(*m.span()) for m in re.finditer(r"\$\{[^}]*\}", item)]

    def bounds(i: int) -> bool:
        return item[i] in "[]{},=\"'" and not any(i in span for span in spans)

    start, end = at, at + 1
    while start > 0 and not bounds(start - 1):
        start -= 1
    while end < len(item) and not bounds(end):
        end += 1
    word = item[start:end].strip()
    quote = "'" if '"' in word else '"'
    fixed = typed[:equal + 1] + typed[equal + 1:].replace(word, f"{quote}{word}{quote}", 1)
    shell = "" if "'" in fixed else ", typed in single quotes on the shell"
    return (f"cannot parse override {typed!r}: {shown} (character {where}) is not allowed in an "
            "unquoted value (only ASCII letters, digits, spaces and _-+.$%*@?|/\\ are); quote "
            f"it: {fixed}{shell}.")


def _unknown_override(key: str, typed: str | None, factors: list[str], set_keys: list[str] = (),
                      reads: tuple[str, list[str]] | None = None) -> str:
    """``evaluator.nosuch=1``: name the section's known keys, as the ``+`` form does; a ``params.``
    or ``paper.`` key near one the study sets (``set_keys``) is taken for a typo of it; a factor by
    its former name (``b_n_s_per_m=[0.5]``) is told its current one."""
    if key.removeprefix("factors.") in FORMER_FACTORS:
        return former_factor(key.removeprefix("factors."), key, typed)
    inside = [k for k in mapping_keys(split(typed)[3] if typed else "")
              if field_at(f"{key}.{k}") is None and f"{key}.{k}" not in set_keys
              and not (key == "factors" and k in factors)]
    if "." not in key and field_at(key) is not None and inside:  # runner={nosuch: 1}: the key in it
        return _unknown_override(f"{key}.{inside[0]}", typed, factors, set_keys, reads)
    if "." not in key and key not in FACTOR_SPECS:
        names = [*factors, *(f.name for f in dataclasses.fields(StudyCfg)), *sorted(FACTOR_SPECS)]
        return (f"{key} is neither a known key of the study config nor a factor of this study "
                f"(factors: {', '.join(factors) or 'none'}); {meant(key, names, '{}')}override rejected.")
    if "." not in key:  # a known factor by its bare name (`planner=[...]`), not one of this study's
        key = f"factors.{key}"
    parent, name = key.rsplit(".", 1)
    schema = schema_at(parent)
    rejected = f"override {typed!r} rejected" if typed else "override rejected"
    if schema is not None:
        return known_keys_sentence(key, schema, typed)
    if parent == "factors":
        if name not in FACTOR_SPECS:
            return (f"{key} is not a known factor ({rejected}); "
                    f"{meant(name, FACTOR_SPECS, 'factors.{}')}known factors: "
                    f"{', '.join(sorted(FACTOR_SPECS))}.")
        return not_a_factor(name, rejected, factors, reads)
    if (section := parent.split(".")[0]) in ("params", "paper"):
        checker = "its trial kind's schema" if section == "params" else "the study's paper schema"
        near = meant(name, [k.rsplit(".", 1)[1] for k in set_keys if k.rsplit(".", 1)[0] == parent],
                     f"{parent}.{{}}")
        add = f"{near}A key it does not set is added " if near else "add it "
        return (f"{key} is not set by this study ({rejected}); {add}with a leading '+' "
                f"(+{key}=...), and {checker} checks it.")
    known = parent  # evaluator.tau.x: the first unknown part (tau) in the deepest known section
    while known and schema_at(known) is None:
        known = known.rpartition(".")[0]
    first = f"{known}.{key[len(known) + 1:].split('.')[0]}" if known else key.split(".")[0]
    if field_at(first) is not None:  # a known key the override goes astray below (factors.nosuch.0.x)
        return f"{key} is not a known key of the study config ({rejected})."
    return known_keys_sentence(first, schema_at(known), typed)


def _nothing_to_delete(key: str, typed: str | None, factors: list[str]) -> str:
    """``~nosuch``: the study has no such key (``~mu`` names the factor it means, factors.mu)."""
    name = key.rpartition(".")[2]
    factor = (f", or write ~factors.{name} to delete the factor {name}"
              if name in factors and key != f"factors.{name}" else "")
    return (f"override {typed or '~' + key!r} deletes {key}, which this study does not have, so "
            f"there is nothing to delete; leave it out{factor}.")
