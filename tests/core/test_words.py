"""Tests of core/words.py: the words every layer writes alike."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import graspcampaign
from graspcampaign.core.words import (
    MISSING,
    as_ascii,
    as_given,
    counted,
    listed,
    meant,
    plural,
    stands_for,
)


def test_a_count_reads_singular_only_for_one():
    assert [counted(n, "trial") for n in (0, 1, 2)] == ["0 trials", "1 trial", "2 trials"]
    assert counted(1, "held-out positive") == "1 held-out positive"
    assert [plural("factor", n) for n in (1, 3)] == ["factor", "factors"]


def test_a_plural_not_made_with_s_is_given():
    # the mesh loader's messages ("has only 3 vertices") and the report's counts share this rule
    assert [counted(n, "vertex", "vertices") for n in (1, 3)] == ["1 vertex", "3 vertices"]
    assert [plural("vertex", n, "vertices") for n in (1, 0)] == ["vertex", "vertices"]


def _lines_matching(pattern: str, but: str = "") -> list[str]:
    """``file:line`` of every line of the package matching ``pattern`` (outside the module ``but``)."""
    made, package = re.compile(pattern), Path(graspcampaign.__file__).parent
    return [f"{p.relative_to(package)}:{i}" for p in sorted(package.rglob("*.py")) if p.name != but
            for i, line in enumerate(p.read_text().splitlines(), 1) if made.search(line)]


def test_no_module_makes_its_own_plural():
    """Every plural of the package goes through ``plural``: no f-string adds its own "s"
    (``{'s' if n > 1 else ''}``, ``{'s' * (n != 1)}``, ``{'' if n == 1 else 's'}``), no expression
    appends one (``noun + 's'``) and no choice spells both forms (``'row' if n == 1 else 'rows'``)."""
    assert _lines_matching(r"""\{\s*['"]s['"]\s*(if\b|\*)|else\s*['"]s['"]\s*\}|\+\s*['"]s['"]"""
                           r"""|['"](?P<noun>[\w ]+)['"] if [^'"]+ == 1 else ['"](?P=noun)s['"]""") == []


def test_no_module_joins_its_own_list():
    """Every "a, b and c" of the package goes through ``listed`` (a copy joined all but the last)."""
    assert _lines_matching(r"""join\([^)]*\[:-1\]\)""", but="words.py") == []


def test_listed_joins_as_a_sentence_does():
    assert listed([]) == MISSING
    assert listed(["a"]) == "a"
    assert listed(["a", "b"]) == "a and b"
    assert listed(["a", "b", "c"]) == "a, b and c"
    assert listed(["a", "b", "c"], last="or") == "a, b or c"


def test_a_value_is_quoted_as_given():
    assert as_given("--unit", "inch") == "--unit 'inch'"  # an option, as typed
    assert as_given("unit", "inch") == "unit = 'inch'"  # a parameter or key
    assert as_given("mass_kg", 0.0) == "mass_kg = 0.0"


def test_no_module_quotes_a_refused_value_its_own_way():
    """Every "--name 'value'" / "name = 'value'" of a refusal goes through ``as_given`` (plan's
    range, material and unit checks each spelt it)."""
    assert _lines_matching(r"""startswith\(["']-["']\) else f["']\{name\} = """, but="words.py") == []


def test_no_module_suggests_a_near_name_its_own_way():
    """Every "did you mean" of the package goes through ``meant``: no other module matches names
    with difflib or writes the question itself (paths, overrides, measured files and the report's
    missing-column note each did)."""
    assert _lines_matching(r"""difflib|get_close_matches|f["'][^"']*did you mean""", but="words.py") == []


def test_meant_names_the_nearest_as_the_user_types_it():
    assert meant("smok", ["smoke", "shapes"]) == "did you mean 'smoke'? "
    assert meant("defualt", ["default"], "--run {}") == "did you mean --run default? "
    assert meant("zzz", ["smoke"]) == ""
    assert meant("smoke", []) == ""


def test_meant_takes_a_name_in_other_case_or_with_spaces_for_the_name():
    # difflib scores 'ID' against 'id' 0 (it compares characters as they are): case first
    assert meant("ID", ["id", "side"]) == "did you mean 'id'? "
    assert meant(" Smoke ", ["smoke", "smoker"]) == "did you mean 'smoke'? "


def test_meant_keeps_difflibs_cutoff():
    """The nearest is the one difflib.get_close_matches gives (its ratio above the cutoff)."""
    import difflib

    known = ["heuristic", "no_pso", "random", "antipodal", "centroid", "ferrari_canny"]
    for word in ("heuristc", "antipdal", "rnd", "centre", "xyz"):
        near = difflib.get_close_matches(word, known, n=1)
        assert meant(word, known) == (f"did you mean {near[0]!r}? " if near else "")
    assert meant("pgn", ["png"], cutoff=0.7) == "" and meant("pgn", ["png"]) == "did you mean 'png'? "


def test_meant_names_every_name_tied_at_the_best_ratio():
    """difflib named the larger of two names tied at the best ratio (lambda2 for lambda3, no_s3
    for no_s, png for pdg): a coin flip shown as a hint; the ties are named, in the order known."""
    import difflib

    for word, known, tied in [("lambda3", ["lambda1", "lambda2", "n_exp"], ["lambda1", "lambda2"]),
                              ("no_s", ["heuristic", "no_s1", "no_s2", "no_s3"],
                               ["no_s1", "no_s2", "no_s3"]),
                              ("pdg", ["png", "svg", "pdf"], ["png", "pdf"])]:
        scores = {k: difflib.SequenceMatcher(None, k, word).ratio() for k in known}
        assert [k for k in known if scores[k] == max(scores.values())] == tied  # a tie, by difflib
    assert meant("lambda3", ["lambda1", "lambda2", "n_exp"], "model.{}") == (
        "did you mean model.lambda1 or model.lambda2? ")
    assert meant("no_s", ["heuristic", "no_s1", "no_s2", "no_s3"]) == (
        "did you mean 'no_s1', 'no_s2' or 'no_s3'? ")
    assert meant("pdg", ["png", "svg", "pdf"]) == "did you mean 'png' or 'pdf'? "
    assert meant("lambda1x", ["lambda1", "lambda2"]) == "did you mean 'lambda1'? "  # no tie: one


@pytest.mark.parametrize(("char", "ascii_char"), [
    # the Unicode Character Database's values (UnicodeData.txt: decimal digit value, compatibility
    # decomposition <wide>/<noBreak>, general category Cf), not this module's rule
    ("\u0663", "3"),  # ARABIC-INDIC DIGIT THREE, decimal 3
    ("\uff13", "3"),  # FULLWIDTH DIGIT THREE, decimal 3
    ("\uff21", "A"),  # FULLWIDTH LATIN CAPITAL LETTER A, <wide> 0041
    ("\u00a0", " "),  # NO-BREAK SPACE, <noBreak> 0020
    ("\u200b", ""),   # ZERO WIDTH SPACE, Cf
    ("\ufeff", ""),   # ZERO WIDTH NO-BREAK SPACE (the byte-order mark), Cf
    ("\u00e9", None),  # LATIN SMALL LETTER E WITH ACUTE: canonical e + U+0301, no ASCII alone
    ("a", None),  # ASCII already
])
def test_a_character_stands_for_the_ascii_unicode_reads_it_as(char, ascii_char):
    assert stands_for(char) == ascii_char


def test_a_pasted_text_is_written_as_the_ascii_it_was_meant_as():
    assert as_ascii("se\u200beds=\u0663") == "seeds=3"
    assert as_ascii("caf\u00e9\u00a0") == "caf\u00e9 "  # a letter that stands for none is kept
