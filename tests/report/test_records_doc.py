"""docs/records.md lists every column of every trial kind's real records.

The records are the engine's own (the reduced runs of ``sim_root``, tests/report/conftest.py), so a
column a kind starts writing without a line in docs/records.md fails here.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import pytest

from graspcampaign.api import load_records

DOC = Path(__file__).resolve().parents[2] / "docs" / "records.md"


def expand(name: str) -> set[str]:
    """The columns one backticked name stands for (`a_1..3_b`, `a_{x,y}`; docs/records.md's top)."""
    name = re.sub(r"(\d)\.\.(\d)",
                  lambda m: "{" + ",".join(str(i) for i in range(int(m[1]), int(m[2]) + 1)) + "}",
                  name)
    parts = re.split(r"\{([^}]*)\}", name)
    choices = [part.split(",") if i % 2 else [part] for i, part in enumerate(parts)]
    return {"".join(choice) for choice in itertools.product(*choices)}


def documented_columns() -> tuple[set[str], dict[str, set[str]]]:
    """The base columns and, per kind, the names its section (and the sections it names) lists."""
    sections = {}
    for block in re.split(r"^## ", DOC.read_text(), flags=re.M)[1:]:
        heading, _, body = block.partition("\n")
        sections[heading] = body
    names = {heading: set().union(*map(expand, re.findall(r"`([^`]+)`", body)))
             for heading, body in sections.items()}
    heading_of = {kind: heading for heading in sections
                  for kind in re.findall(r"`([a-z0-9_]+)`", heading)}

    def columns(kind: str, seen: tuple[str, ...] = ()) -> set[str]:
        body = sections[heading_of[kind]]
        found = set(names[heading_of[kind]])
        for other in heading_of:
            if heading_of[other] != heading_of[kind] and other not in seen and f"`{other}`" in body:
                found |= columns(other, (*seen, kind))
        return found

    return names["Base columns (every kind)"], {kind: columns(kind) for kind in heading_of}


def test_expand_reads_the_notation():
    assert expand("normal_force_1..3_n") == {"normal_force_1_n", "normal_force_2_n",
                                             "normal_force_3_n"}
    assert expand("contact_{1,2}_{x,y}_mm") == {"contact_1_x_mm", "contact_1_y_mm",
                                                "contact_2_x_mm", "contact_2_y_mm"}


def test_every_record_column_of_every_kind_is_documented(sim_root):
    base, by_kind = documented_columns()
    studies = sorted(path.name for path in sim_root.iterdir() if (path / "default").is_dir())
    assert len(studies) == 17
    undocumented = {}
    for study in studies:
        records = load_records(study, root=sim_root)
        kind = records["kind"].iloc[0]
        missing = [c for c in records.columns if c not in base | by_kind.get(kind, set())]
        if missing:
            undocumented[f"{study} ({kind})"] = missing
    assert undocumented == {}, f"columns missing from docs/records.md: {undocumented}"


@pytest.mark.parametrize("kind, column", [("quasi_static", "vertex_2"),
                                          ("sensitivity", "residual_norm_n"),
                                          ("dynamic_check", "wrench_fy_n")])
def test_a_section_includes_the_kind_it_names(kind, column):
    assert column in documented_columns()[1][kind]
