"""Words every layer writes alike: the mark of a missing value and the one way to list items."""

MISSING = "\u2014"
"""The mark of a value that is missing or could not be computed (its reason stands beside it)."""


def listed(words, empty: str = MISSING) -> str:
    """``a``, ``a and b``, ``a, b and c`` (``empty`` for none): a list in a sentence."""
    words = list(words)
    if not words:
        return empty
    return words[0] if len(words) == 1 else f"{', '.join(words[:-1])} and {words[-1]}"
