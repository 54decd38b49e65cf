"""Mutation round 9: ``core.words``' near-name hint and the ASCII a pasted character stands for,
checked against difflib's ``get_close_matches`` and Python's own reading of digits and Unicode's
compatibility forms (docs/decisions.md, mutation round 9)."""

from __future__ import annotations

import difflib
import sys
import unicodedata

import pytest

from graspcampaign.core.words import as_ascii, meant, stands_for

#: the study config's factor names and top-level keys, as an override's key is matched against
KEYS = ["mass_kg", "mu", "dt_s", "pso", "shape", "nodes", "planner", "seeds", "lambda1", "lambda2"]


@pytest.mark.parametrize("word", ["mas", "dsts", "opo", "shap", "xyz"])
def test_the_nearest_name_is_get_close_matches_own(word):
    """``mas`` scores exactly the cutoff 0.6 against ``mass_kg`` (2*3/10), which
    ``get_close_matches`` keeps; ``dsts`` scores 0.75 against ``dt_s`` but 0.5 the other way round
    (SequenceMatcher's ratio depends on which string is the second), and ``get_close_matches``
    scores the candidate first."""
    near = difflib.get_close_matches(word, KEYS, n=1)
    assert meant(word, KEYS) == (f"did you mean {near[0]!r}? " if near else "")
    assert difflib.SequenceMatcher(None, "mass_kg", "mas").ratio() == 0.6
    assert difflib.SequenceMatcher(None, "dsts", "dt_s").ratio() < 0.6 <= difflib.SequenceMatcher(
        None, "dt_s", "dsts").ratio()


def test_a_name_typed_in_other_case_is_shown_as_it_is_known():
    """The hint names the name as the program knows it (the first of names alike but for case, in
    the order given), never the word lower-cased: a suggestion the user copies must be a name."""
    assert meant("FORCE_N", ["Force_N", "time_s"]) == "did you mean 'Force_N'? "
    assert meant("mu", ["Mu", "mu"]) == "did you mean 'Mu'? "
    assert meant("MU", ["mU", "Mu", "mu"], "{}") == "did you mean mU? "


def test_a_short_name_typed_with_spaces_around_it_is_the_name():
    """`` n `` is ``n`` typed with the spaces of a padded column or a pasted word; difflib alone
    scores it 0.5 (2*1/4), under its cutoff, and would suggest nothing."""
    assert difflib.get_close_matches(" n ", ["n", "m"]) == []
    assert meant(" n ", ["n", "m"]) == "did you mean 'n'? "


def _decimal_digits() -> list[str]:
    """Every non-ASCII character of Unicode's decimal digits (general category Nd)."""
    return [chr(cp) for cp in range(0x80, sys.maxunicode + 1) if unicodedata.category(chr(cp)) == "Nd"]


def test_every_digit_python_reads_stands_for_the_digit_it_reads():
    """Python's int() reads a decimal digit of any script (Arabic-Indic ``٠``, full-width ``０``...)
    as its value, zero included: that digit is what the character stands for."""
    digits = _decimal_digits()
    assert len(digits) > 500
    assert [c for c in digits if stands_for(c) != str(int(c))] == []
    assert as_ascii("seeds=\u0663\u0660") == "seeds=30"  # ARABIC-INDIC THREE, ZERO


@pytest.mark.parametrize("char", ["\u1369", "\u136a", "\u2460", "\u2474", "\u00b2", "\u2488"])
def test_a_digit_python_does_not_read_stands_for_its_compatibility_form(char):
    """Ethiopic digits, circled, parenthesized and superscript numbers have a digit value but are
    no decimal digit: int() refuses them, and each stands for its NFKC form where that is ASCII
    (``⑴`` is "(1)", ``²`` is "2", ``⒈`` is "1."), else for nothing (``፩``)."""
    with pytest.raises(ValueError):
        int(char)
    folded = unicodedata.normalize("NFKC", char)
    assert stands_for(char) == (folded if folded.isascii() else None)
