"""No module over ~500 lines (STYLE.md, the developers' guide): a module that outgrows it is split
by responsibility, never golfed. The limit is 500 lines as ``wc -l`` counts them (newline characters)."""

from __future__ import annotations

from pathlib import Path

import graspcampaign

PACKAGE = Path(graspcampaign.__file__).parent
LIMIT = 500


def test_no_module_is_over_the_limit():
    sizes = {p.relative_to(PACKAGE.parent).as_posix(): p.read_bytes().count(b"\n")
             for p in PACKAGE.rglob("*.py")}
    assert len(sizes) > 50  # the whole package is walked
    assert {name: n for name, n in sizes.items() if n > LIMIT} == {}
