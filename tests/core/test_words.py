"""Tests of core/words.py: the words every layer writes alike."""

from __future__ import annotations

import re
from pathlib import Path

import graspcampaign
from graspcampaign.core.words import MISSING, counted, listed, plural


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
