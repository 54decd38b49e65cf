"""No module over ~500 lines (STYLE.md, the developers' guide): a module that outgrows it is split
by responsibility, never golfed. The limit is 500 lines as ``wc -l`` counts them (newline characters),
for the package and for its tests alike."""

from __future__ import annotations

from pathlib import Path

import pytest

import graspcampaign

PACKAGE = Path(graspcampaign.__file__).parent
TESTS = Path(__file__).parent
LIMIT = 500


@pytest.mark.parametrize(("root", "at_least"), [(PACKAGE, 50), (TESTS, 50)], ids=["package", "tests"])
def test_no_module_is_over_the_limit(root, at_least):
    sizes = {p.relative_to(root.parent).as_posix(): p.read_bytes().count(b"\n")
             for p in root.rglob("*.py")}
    assert len(sizes) > at_least  # the whole tree is walked
    assert {name: n for name, n in sizes.items() if n > LIMIT} == {}
