"""The reports cite design decisions by their `docs/decisions.md` heading (every citation names one,
and each one named is a heading), never by an internal issue number: every string of report/ and
analysis/ (docstrings aside) is read with :mod:`ast`."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import graspcampaign

PACKAGE = Path(graspcampaign.__file__).parent
DECISIONS = PACKAGE.parents[1] / "docs" / "decisions.md"


def modules() -> list[tuple[str, ast.Module, set[int]]]:
    """``(module, syntax tree, ids of its docstrings' nodes)`` of every module of report/ and
    analysis/."""
    out = []
    for path in sorted([*(PACKAGE / "report").rglob("*.py"), *(PACKAGE / "analysis").rglob("*.py")]):
        tree = ast.parse(path.read_text())
        docs = {id(node.body[0].value) for node in ast.walk(tree)
                if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef)
                and node.body and isinstance(node.body[0], ast.Expr)}
        out.append((path.name, tree, docs))
    return out


def report_strings() -> list[tuple[str, str]]:
    """``(module, text)`` of every string literal of report/ and analysis/ but docstrings."""
    return [(name, node.value) for name, tree, docs in modules() for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs]


def headings() -> set[str]:
    """Every heading of docs/decisions.md, also without its trailing "(issue ...)" tag."""
    found = re.findall(r"^#+ (.+)$", DECISIONS.read_text(), flags=re.M)
    return set(found) | {re.sub(r" \(issues? [^)]*\)$", "", h) for h in found}


def test_no_report_text_cites_an_issue_number():
    assert [(m, s) for m, s in report_strings() if re.search(r"\bissues? \d", s)] == []


def test_every_cited_decision_is_a_heading():
    from graspcampaign.report.spec import VALIDITY

    cited = {VALIDITY} | {title for _, s in report_strings() if "docs/decisions.md" in s
                          for title in re.findall(r"\*([^*{}]+)\*", s.split("docs/decisions.md", 1)[1])}
    assert len(cited) > 10 and cited - headings() == set()


def cited_texts() -> list[tuple[str, str]]:
    """``(module, text)`` of every string of report/ and analysis/ but docstrings, an f-string whole
    (its fields as ``{expression}``), so a citation split by a field is read as one."""
    out = []
    for name, tree, docs in modules():
        parts = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.JoinedStr):
                parts |= {id(value) for value in node.values}
                out.append((name, "".join(
                    value.value if isinstance(value, ast.Constant) else f"{{{ast.unparse(value.value)}}}"
                    for value in node.values)))
        out += [(name, node.value) for node in ast.walk(tree) if isinstance(node, ast.Constant)
                and isinstance(node.value, str) and id(node) not in docs | parts]
    return out


#: citations of docs/decisions.md in report text that name no heading, and where their decision is;
#: report text is its owner's to reword (fails here once it names the heading: drop it then)
LOOSE: dict[tuple[str, str], str] = {}


def test_every_citation_of_the_decisions_names_a_heading():
    """A report cites a decision as ``docs/decisions.md`, *<heading>*``: a citation naming no heading
    (``docs/decisions.md`, energy audit``) sends the reader to a 6,000-line file with nothing to find;
    the headings named are checked by :func:`test_every_cited_decision_is_a_heading`."""
    texts = cited_texts()
    loose = [(module, after[:40]) for module, text in texts
             for after in text.split("docs/decisions.md")[1:]
             if not re.match(r"`?,\s*\*[^*]+\*", after)]
    assert len([t for _, t in texts if "docs/decisions.md" in t]) > 10
    assert sorted(loose) == sorted(LOOSE), "cite a decision by its heading: `docs/decisions.md`, *...*"
