"""Words every layer writes alike: the mark of a missing value, the one way to list items and to
count them, the one way to say a place this user may not open."""

MISSING = "\u2014"
"""The mark of a value that is missing or could not be computed (its reason stands beside it)."""


#: The one phrasing of a place whose permissions keep this user out (chmod 000, another user's
#: folder), after the place and what cannot be done to it; every layer says it so
#: (errors.access_denied, campaign.paths, core.mesh_file, the command line's files to write).
PERMISSION_DENIED = ("permission denied (its permissions, or those of the directory holding it, keep "
                     "this user out); give this user access (chmod, chown), or run the command as "
                     "the user who owns it")


def listed(words, empty: str = MISSING, last: str = "and") -> str:
    """``a``, ``a and b``, ``a, b and c`` (``empty`` for none): a list in a sentence; ``last`` joins
    the last two ("or": ``a, b or c``)."""
    words = list(words)
    if not words:
        return empty
    return words[0] if len(words) == 1 else f"{', '.join(words[:-1])} {last} {words[-1]}"


def plural(noun: str, n: int, nouns: str | None = None) -> str:
    """``noun`` as ``n`` of it reads: plural unless ``n`` is 1 ("trial", "trials"); ``nouns`` for a
    plural not made with -s ("vertex", "vertices")."""
    return noun if n == 1 else nouns or f"{noun}s"


def counted(n: int, noun: str, nouns: str | None = None) -> str:
    """``n`` and ``noun``, plural unless ``n`` is 1 ("1 trial", "0 trials", "3 vertices")."""
    return f"{n} {plural(noun, n, nouns)}"


def meant(word: str, known, shown: str = "{!r}", cutoff: float = 0.6) -> str:
    """``did you mean 'x'? `` naming the one of ``known`` nearest a misspelt ``word``, or ``""``
    when none is alike: the one way a message suggests a name ("unknown study 'smok'; did you mean
    'smoke'? available studies: ...").

    A name equal to ``word`` but for case or surrounding spaces is the nearest; otherwise the name
    of the highest ``difflib.SequenceMatcher`` ratio with the lower-cased word, at or above
    ``cutoff`` (``difflib.get_close_matches``'s score and default 0.6). Names tied at that ratio
    are all named, in ``known``'s order ("did you mean 'lambda1' or 'lambda2'?"): difflib would
    name the larger string alone, a coin flip shown as a hint (docs/decisions.md, "The near-miss
    rule"). ``shown`` formats a name as the user would type it ("--run {}": ``did you mean --run
    default? ``)."""
    from difflib import SequenceMatcher

    lowered: dict[str, str] = {}
    for name in map(str, known):  # the first of names alike but for case
        lowered.setdefault(name.lower(), name)
    typed = str(word).strip().lower()
    if typed in lowered:
        near = [typed]
    else:  # get_close_matches' score: the candidate first, the word typed second
        scores = {name: SequenceMatcher(None, name, typed).ratio() for name in lowered}
        best = max(scores.values(), default=0.0)
        near = [name for name, score in scores.items() if score == best] if best >= cutoff else []
    if not near:
        return ""
    return f"did you mean {listed([shown.format(lowered[n]) for n in near], last='or')}? "


def as_given(name: str, value: object) -> str:
    """``value`` as given under ``name``: a command-line option (a name starting with ``-``) as
    typed, ``--unit 'inch'``; any other name as ``unit = 'inch'`` (a parameter or a config key):
    the one way a refusal quotes what it refuses."""
    return f"{name} {value!r}" if name.startswith("-") else f"{name} = {value!r}"


def stands_for(char: str) -> str | None:
    """The ASCII a non-ASCII character is taken for when read, or None: a digit of another script
    (Arabic-Indic ``٣``, full-width ``３``) its digit, a full-width letter or a no-break space its
    compatibility form (NFKC: ``Ａ`` -> ``A``, U+00A0 -> a space), a character that shows as
    nothing (format characters: a zero-width space, a byte-order mark, a soft hyphen) ``""``. Such
    a character pasted into a value or key is no typo a reader can see, and quoting it keeps it."""
    import unicodedata

    if char.isascii():
        return None
    if unicodedata.category(char) == "Cf":
        return ""
    if (digit := unicodedata.decimal(char, None)) is not None:
        return str(digit)
    folded = unicodedata.normalize("NFKC", char)
    return folded if folded.isascii() and folded.isprintable() else None


def as_ascii(text: str) -> str:
    """``text`` with every character :func:`stands_for` reads as ASCII written as that ASCII (a
    zero-width space dropped, an Arabic-Indic or full-width digit written as its digit), the
    others kept as they are: what a user who pasted ``text`` meant to type."""
    return "".join(char if (ascii_char := stands_for(char)) is None else ascii_char for char in text)


def typed_value(value: object) -> str:
    """A config value as a refusal names it, with its type: ``0.3 (float)``, ``'x' (str)``; true
    and false as YAML and Hydra spell them, ``true (a boolean)``, never Python's ``True (bool)``
    (which no one writing a study or an override types)."""
    if isinstance(value, bool):
        return f"{str(value).lower()} (a boolean)"
    return f"{value!r} ({type(value).__name__})"
