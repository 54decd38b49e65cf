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


def meant(word: str, known) -> str:
    """``did you mean 'x'? `` naming the one of ``known`` nearest a misspelt ``word``
    (``difflib.get_close_matches``), or ``""`` when none is alike: the one way a message suggests a
    name ("unknown study 'smok'; did you mean 'smoke'? available studies: ...")."""
    import difflib

    near = difflib.get_close_matches(word, list(known), n=1)
    return f"did you mean {near[0]!r}? " if near else ""
