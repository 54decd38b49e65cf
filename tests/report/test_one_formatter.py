"""One formatter (issue 14): no number a reader sees is written by a raw format spec in report/.

The source of every report module is parsed (``ast``, not a regex on its text): an f-string's
replacement field with a numeric format spec (``:.3f``, ``:.3g``, ``:.1e``, ``:g``, ``:,``, ``:d``,
``:%``), a ``str.format`` template held in a string constant (``"{:.1f}"``), a printf-style template
(``"%.1f" % x``) and the builtin ``format(x, ".1f")`` are refused outside the allow-list below, where
the spec writes no number a reader sees."""

from __future__ import annotations

import ast
import re
import string
from pathlib import Path

import pytest

import graspcampaign.report

REPORT = Path(graspcampaign.report.__file__).parent
NUMERIC = set("bcdeEfFgGnoxX%,_")  # a spec's type or grouping character that formats a number
PRINTF = re.compile(r"%(?:\([^)]*\))?[#0 +-]*(?:\*|\d+)?(?:\.(?:\*|\d*))?[diouxXeEfFgG]")  # "%.1f", not "%%"

ALLOWED = {
    # the one formatter itself: these specs are how fmt.number, fmt.scaled and fmt.p_value write digits
    ("report/format.py", "exact.quantize(Decimal(1).scaleb(-int(digits)), rounding=ROUND_HALF_EVEN, "
     "context=wide)"),
    ("report/format.py", "value"),
    ("report/format.py", "float(value)"),
    ("report/format.py", "sys.float_info.min"),
    # a key into the paper's oblique_margin_n mapping ("30", "45"), looked up, never printed
    ("report/studies/test1.py", "a"),
}


def numeric(spec: str) -> bool:
    """Whether a format spec (its text, nested fields as ``{}``) formats a number."""
    return bool(spec) and (spec[-1] in NUMERIC or "," in spec or "_" in spec or "." in spec)


def raw_specs(source: str) -> list[tuple[str, str]]:
    """The (expression, spec) of each numeric format spec in ``source``: f-string fields and
    positional ``str.format`` templates in string constants (``"{:.1f}"``, ``"{0:.1f}"``; a named field,
    as CSS's ``{margin:0}`` reads, is not one), the expression of a template being its text."""
    found, tree = [], ast.parse(source)
    inside = {id(v) for node in ast.walk(tree) if isinstance(node, ast.JoinedStr) for v in node.values}
    for node in ast.walk(tree):
        if isinstance(node, ast.FormattedValue) and node.format_spec is not None:
            spec = "".join(v.value if isinstance(v, ast.Constant) else "{}" for v in node.format_spec.values)
            if numeric(spec):
                found.append((ast.unparse(node.value), spec))
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in inside:
            try:
                fields = list(string.Formatter().parse(node.value))
            except ValueError:  # not a template (an unmatched brace in prose or CSS)
                continue
            found += [(node.value, spec) for _, name, spec, _ in fields
                      if name is not None and (name == "" or name.isdigit()) and numeric(spec)]
        elif (isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mod)
              and isinstance(node.left, ast.Constant) and isinstance(node.left.value, str)):
            template = node.left.value
            found += [(template, m.group(0)) for m in PRINTF.finditer(template.replace("%%", ""))]
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "format"
              and len(node.args) == 2 and isinstance(node.args[1], ast.Constant)
              and isinstance(node.args[1].value, str) and numeric(node.args[1].value)):
            found.append((ast.unparse(node.args[0]), node.args[1].value))
    return found


def test_no_raw_numeric_format_spec_in_report():
    found = {(path.relative_to(REPORT.parent).as_posix(), expr, spec)
             for path in sorted(REPORT.rglob("*.py")) for expr, spec in raw_specs(path.read_text())}
    assert len({f for f, _, _ in found}) >= 2  # the scan sees format.py and the allowed key
    assert {(f, e, s) for f, e, s in found if (f, e) not in ALLOWED} == set()
    assert {(f, e) for f, e, _ in found} == ALLOWED  # every allow-list entry is still needed


@pytest.mark.parametrize(("source", "expected"), [
    ('f"{x:.3f} N"', [("x", ".3f")]),
    ('f"{x:.3g} N"', [("x", ".3g")]),
    ('f"{x:.1e}"', [("x", ".1e")]),
    ('f"{x:g} mm"', [("x", "g")]),
    ('f"{n:,} runs"', [("n", ",")]),
    ('f"{n:d}"', [("n", "d")]),
    ('f"{x:.{k}f}"', [("x", ".{}f")]),
    ('CELLS = ("{:.0f}", "{:.1f}")', [("{:.0f}", ".0f"), ("{:.1f}", ".1f")]),
    ('"%.2f N" % x', [("%.2f N", "%.2f")]),
    ('"%d of %s (%5.1f%%)" % (k, n, r)', [("%d of %s (%5.1f%%)", "%d"), ("%d of %s (%5.1f%%)", "%5.1f")]),
    ('format(x, ".3g")', [("x", ".3g")]),
    ('"%s mm" % name', []),  # a text put in a text
    ('format(name, ">12")', []),
    ('f"{name:>12}"', []),  # padding a text is no number
    ('f"{fmt.number(x, 3)} N"', []),
    ('"{} nodes".format(n)', []),
    ('s = "a { b"', []),
    ('CSS = "nav{opacity:.85}"', []),  # CSS, not a template
])
def test_the_scan_finds_each_kind_of_spec(source, expected):
    assert raw_specs(source) == expected
