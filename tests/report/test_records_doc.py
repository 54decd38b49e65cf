"""docs/records.md lists every column of every trial kind's real records.

The records are the engine's own (the reduced runs of ``sim_root``, tests/report/conftest.py), so a
column a kind starts writing without a line in docs/records.md fails here.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import pandas as pd
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


def test_every_record_column_of_every_kind_is_documented(sim_root, reduced):
    base, by_kind = documented_columns()
    studies = sorted(path.name for path in sim_root.iterdir() if (path / "default").is_dir())
    assert studies == reduced  # every study run reduced (was `len(studies) == 17`: "18 == 17" once a
    # study joined REDUCED, as docs/ARCHITECTURE.md says to)
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


#: "the `sensitivity` outcome columns but `identified` and `runtime_ms`": another section's Outputs,
#: less the columns named after "but"
REFERENCE = re.compile(r"the `(\w+)`\s+outcome\s+columns(?:\s+but\s+((?:`\w+`(?:,|\s+and|\s)*)+))?")


#: backticked names in a records table that are no column of the records, and why
NOT_COLUMNS = {"actual": "belief_model's value in the belief_none trace table only",
               "g_geo_predicted": "the former name of g_geo_believed",
               "n_believed": "the former name of believed_n_exp"}


def outputs(body: str) -> str:
    """A section's *Outputs* paragraph (the trace and study-level tables after it are no records)."""
    found = re.search(r"\bOutputs?\b(.*?)(?=Trace tables?\b|Study-level|\n\n|\Z)", body, re.S)
    return found[1] if found else ""


def named(text: str) -> set[str]:
    """The column-like names of ``text``: backticked, no dotted path, value or comma list."""
    tokens = re.findall(r"`([a-z][a-z0-9_]*(?:(?:\.\.\d|\{[a-z0-9_,]+\})[a-z0-9_]*)*)`", text)
    return set().union(*map(expand, tokens))


def claimed_columns() -> dict[str, tuple[list[str], set[str], set[str]]]:
    """Per section: the kinds its heading names, the columns it says their records hold (the first
    cell of its tables' rows, or the second where the first names no column; the names of its
    Outputs and of the Outputs it refers to) and the columns it says they lack (after "but")."""
    sections = {}
    for block in re.split(r"^## ", DOC.read_text(), flags=re.M)[1:]:
        heading, _, body = block.partition("\n")
        sections[heading] = body
    of_kind = {kind: body for heading, body in sections.items()
               for kind in re.findall(r"`(\w+)`", heading)}
    out = {}
    for heading, body in sections.items():
        rows = [line.split("|") for line in body.splitlines()
                if line.startswith("| ") and not line.startswith("| column")]
        # a row named in words ("measured (virtual rig or ingested file)") lists its columns after
        cells = "\n".join(row[1] if named(row[1]) else row[2] for row in rows)
        claimed, lacks = named(cells) | named(outputs(body)), set()
        for other, but in REFERENCE.findall(outputs(body)):
            lacks |= named(but)
            claimed |= named(outputs(of_kind[other])) - lacks
        out[heading] = (re.findall(r"`(\w+)`", heading), claimed - lacks - set(of_kind), lacks)
    return out


def test_every_column_docs_records_md_names_is_in_the_records(sim_root):
    kinds: dict[str, pd.DataFrame] = {}
    for path in sorted(sim_root.iterdir()):
        if (path / "default").is_dir():
            records = load_records(path.name, root=sim_root)
            kinds[records["kind"].iloc[0]] = pd.concat([kinds.get(records["kind"].iloc[0]), records])
    wrong = {}
    for heading, (names, claimed, lacks) in claimed_columns().items():
        base = heading.startswith("Base columns")  # in every kind's records
        frames = list(kinds.values()) if base else [kinds[name] for name in names if name in kinds]
        if not frames:  # prepared/ and the run files are no trial kind's records
            continue
        column_sets = [set(frame.columns) for frame in frames]
        columns = set.intersection(*column_sets) if base else set.union(*column_sets)
        # a name that is a value of the records (`resolution` of `panel`, `ferrari_canny` rows) is no column
        values = {str(v) for f in frames for c in f.columns if not pd.api.types.is_numeric_dtype(f[c])
                  for v in f[c].unique()[:50]}
        missing = sorted(claimed - columns - values - set(NOT_COLUMNS))
        present = sorted(lacks & columns)
        if missing or present:
            wrong[heading] = {"named, not in the records": missing, "said to lack, present": present}
    assert wrong == {}, f"docs/records.md names columns the records do not hold: {wrong}"
