"""Words every layer writes alike: the mark of a missing value, the one way to list items and to
count them."""

MISSING = "\u2014"
"""The mark of a value that is missing or could not be computed (its reason stands beside it)."""


def listed(words, empty: str = MISSING) -> str:
    """``a``, ``a and b``, ``a, b and c`` (``empty`` for none): a list in a sentence."""
    words = list(words)
    if not words:
        return empty
    return words[0] if len(words) == 1 else f"{', '.join(words[:-1])} and {words[-1]}"


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

    A name equal to ``word`` but for case or surrounding spaces is the nearest; otherwise
    ``difflib.get_close_matches`` of the lower-cased words, above ``cutoff`` (its default 0.6).
    ``shown`` formats the name as the user would type it ("--run {}": ``did you mean --run
    default? ``)."""
    import difflib

    lowered: dict[str, str] = {}
    for name in map(str, known):  # the first of names alike but for case
        lowered.setdefault(name.lower(), name)
    typed = str(word).strip().lower()
    near = [typed] if typed in lowered else difflib.get_close_matches(typed, list(lowered), n=1,
                                                                      cutoff=cutoff)
    return f"did you mean {shown.format(lowered[near[0]])}? " if near else ""
