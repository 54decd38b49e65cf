"""Mutation round 8: edges of the one formatter, the page writer and the renderer that no test pinned.

Each test checks a consequence against something outside the code under test: Python's own
formatting, scipy's underflowing p-value, an HTML parser reading the page, pandas' own KeyError,
the files a write leaves, counts made by hand (docs/decisions.md, mutation round 8)."""

from __future__ import annotations

import inspect
import json
import math
import sys
from html.parser import HTMLParser

import pandas as pd
import pytest
from scipy import stats

from graspcampaign.report import format as fmt
from graspcampaign.report.document import Col, Document, Section, Table, Text, short
from graspcampaign.report.render import Run, Tables, design_text, drifted, reason, render
from graspcampaign.report.spec import Claims, Finding, ReportSpec, Value


class Cells(HTMLParser):
    """Every table cell's text and class, and the text of each ``span.nb`` inside a cell."""

    def __init__(self):
        super().__init__()
        self.cells, self.nowrap, self._cell, self._span = [], [], None, None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "td":
            self._cell = [a.get("class"), ""]
        elif tag == "span" and a.get("class") == "nb" and self._cell is not None:
            self._span = ""

    def handle_endtag(self, tag):
        if tag == "td":
            self.cells.append(tuple(self._cell))
            self._cell = None
        elif tag == "span" and self._span is not None:
            self.nowrap.append(self._span)
            self._span = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell[1] += data
        if self._span is not None:
            self._span += data


def cells(table: Table) -> Cells:
    page = Cells()
    page.feed(Document("t", "simulation", [], table.render(None)).html())
    return page


# --- report/format.py ---------------------------------------------------------------------------

@pytest.mark.parametrize("digit", range(1, 10))
def test_a_negative_value_of_one_digit_keeps_its_sign(digit):
    """Only a value that prints as zero loses its minus; -0.9 is no zero (a "9" was once no digit)."""
    value = -digit / 10
    assert fmt.number(value, 1) == f"{value:.1f}".replace("-", fmt.MINUS)
    assert fmt.number(-value, 1, signed=True) == f"{-value:+.1f}"


@pytest.mark.parametrize("value", [1.2345, 123.456, 0.0123456, 2.71828, 9876.5])
def test_a_value_without_digits_prints_four_significant_digits_as_python_does(value):
    """No ``digits`` and no ``sig``: four significant digits, trailing zeros dropped (Python's ``.4g``
    in fixed notation, the same correctly rounded half-even of the exact binary value)."""
    assert fmt.number(value) == f"{value:.4g}"


def test_a_p_value_that_underflows_to_zero_prints_below_the_smallest_normal_float():
    """scipy's chi-square tail of 2000 on one dof underflows to exactly 0: "< 2e-308", not "0.0e+00"."""
    p = stats.chi2.sf(2000, 1)
    assert p == 0.0
    assert fmt.p_value(p) == f"< {sys.float_info.min:.0e}" == "< 2e-308"


@pytest.mark.parametrize(("big", "small", "each"), [(1.0, 0.01, False), (0.5, 0.005, False),
                                                    (1.0, 0.0099, True), (0.5, 0.0049, True)])
def test_a_column_exactly_two_decades_wide_keeps_one_rounding(big, small, each):
    """Each value alone only when its magnitudes lie *more* than two decades apart (log10 of the
    ratio above 2); exactly two decades share one rounding."""
    assert (math.log10(big / small) > 2 + 1e-12) is each
    assert (fmt.decimals([big, small]) == fmt.EACH) is each


def test_an_estimate_with_one_missing_end_prints_the_value_alone():
    """An interval with one end missing is no interval: the value as the paper prints one without."""
    assert fmt.estimate(0.5, 0.4, math.nan, 1) == "0.5"
    assert fmt.estimate(0.5, None, 0.6, 1) == "0.5"
    assert fmt.estimate(0.5, 0.4, 0.6, 1) == "0.5 (0.4\u20130.6)"


def test_a_consistent_difference_prints_at_the_tables_digits():
    """Ours 0.342 (0.335-0.35) against the paper's 0.33: the interval's lower end is 0.005 from it,
    within one printed digit, so consistent; the difference 0.012 prints at 2 decimals, +0.01 (only
    a difference called *differs* gets a further digit to set it apart from the tolerance)."""
    judged = fmt.verdict(0.342, 0.33, low=0.335, high=0.35, digits=2)
    assert judged.differs is False
    assert judged.word == f"consistent (+{0.342 - 0.33:.2f})" == "consistent (+0.01)"


# --- report/document.py -------------------------------------------------------------------------

def test_a_document_written_without_formats_writes_the_clis_default(tmp_path):
    """`report` without --format writes md,csv; Document.write and build_reports given no formats the same."""
    from graspcampaign.cli.main import report

    default = inspect.signature(report).parameters["fmt"].default
    blocks = Table("a", "a table", pd.DataFrame({"x": [1, 2]})).render(None)
    Document("t", "simulation", [], blocks).write(tmp_path / "none", None)
    Document("t", "simulation", [], blocks).write(tmp_path / "cli", default.split(","))
    listed = [sorted(p.relative_to(tmp_path / d).as_posix() for p in (tmp_path / d).rglob("*"))
              for d in ("none", "cli")]
    assert listed[0] == listed[1] == ["report.md", "tables", "tables/a.csv"]


def test_a_count_with_its_share_prints_as_a_whole_number():
    """``k (p%)``: the count as it is, the share to 1 decimal (1 of 3 is 33.3%, not "1.0 (33.3%)")."""
    frame = pd.DataFrame({"n": [1, 2], "n_pct": [100 / 3, 200 / 3]})
    page = cells(Table("s", "shares", frame, [Col("n", "n", share="n_pct")]))
    assert [text for _, text in page.cells] == ["1 (33.3%)", "2 (66.7%)"]


@pytest.mark.parametrize("flag", [True, False])
def test_yes_or_no_among_numbers_keeps_the_column_right_aligned(flag):
    """A column of numbers with a yes or a no in it lines up on the right, as one with the missing mark."""
    frame = pd.DataFrame({"value": pd.Series([2.5, flag], dtype=object)})
    page = cells(Table("v", "values", frame, [Col("value", "value", 1)]))
    assert page.cells == [("num", "2.5"), ("num", "yes" if flag else "no")]


def test_an_interval_cell_never_breaks_anywhere_inside_its_interval():
    """The whole "(25.5–47.4)" is one unbreakable span, not only its en dash (a line could break
    after "(25.5")."""
    frame = pd.DataFrame({"rate_pct": [35.7], "rate_low_pct": [25.5], "rate_high_pct": [47.4]})
    page = cells(Table("t", "rates", frame, [Col("rate_pct", "rate", 1, low="rate_low_pct",
                                                 high="rate_high_pct")]))
    assert page.cells == [("num", "35.7 (25.5\u201347.4)")]
    assert page.nowrap == ["(25.5\u201347.4)"]


def test_a_caption_exactly_at_the_limit_is_kept_whole():
    caption = "word " * 11 + "abcd"
    assert len(caption) == 59 and short(caption) == caption
    caption += "e"
    assert len(caption) == 60 and short(caption) == caption
    caption += "f"
    assert short(caption) == ("word " * 11).rstrip() + "\u2026"


def test_the_json_tables_keep_the_sign_of_an_infinity(tmp_path):
    """Strict JSON has no infinity: "inf" and "-inf", which float() reads back as the two infinities."""
    frame = pd.DataFrame({"x": [math.inf, -math.inf, 1.5]})
    path = Document("t", "simulation", [], Table("a", "a", frame).render(None)).write(tmp_path, ["json"])
    values = [row["x"] for row in json.loads(path.read_text())["a"]]
    assert values == ["inf", "-inf", 1.5]
    assert [float(v) for v in values] == [math.inf, -math.inf, 1.5]


# --- report/render.py ---------------------------------------------------------------------------

class Wrapper:
    """An item of another class (duck-typed): it may read a table of any name."""

    title = "Wrapped item"

    def render(self, run):
        return [Text(str(len(run.tables["computed_elsewhere"])))]


def test_an_unknown_item_reading_a_table_not_computed_is_the_datas_reason():
    """With an item render cannot check, no table name is a misspelling: a table not computed is
    the data's reason (a note), not broken code."""
    run = Run(pd.DataFrame({"x": [1]}), {})
    render(ReportSpec("s", [Section("a"), Wrapper()]), run, Document("t", "simulation", []))
    assert run.broken == []
    assert run.failures == ["Wrapped item: its table computed_elsewhere was not computed"]
    with pytest.raises(ValueError, match="its table nope was not computed"):
        Tables()["nope"]


def test_a_run_counts_its_tables_figures_and_findings_not_its_headings_or_paragraphs():
    frame = pd.DataFrame({"x": [1.0]})
    spec = ReportSpec("s", [Section("a"), Text("words"), Table("one", "one", frame), Section("b"),
                            Table("two", "two", frame), Finding(lambda run: "found.")])
    run = Run(pd.DataFrame({"x": [1]}), {})
    render(spec, run, Document("t", "simulation", []))
    assert run.items == 3 and run.broken == [] and run.failures == []


def test_the_design_lists_four_levels_and_counts_five():
    assert design_text({"factors": {"mu": [0.2, 0.4, 0.6, 0.8]}}) == "mu 0.2, 0.4, 0.6, 0.8"
    assert design_text({"factors": {"mu": [0.2, 0.4, 0.6, 0.8, 1.0]}}) == "mu (5 levels)"


def test_a_schedule_without_factor_levels_has_no_design_line():
    """A protocol's schedule (no factor lists) says nothing of seeds or repeats: "" (no Design line)."""
    assert design_text({"seeds": 3, "repeats": 2}) == ""
    assert design_text({"factors": {"mu": [0.2]}, "seeds": 3}) == "mu 0.2; seeds 3"


def test_each_other_config_of_a_drifted_run_is_named_once_in_order():
    manifest = {"config_hash": "a", "sessions": [{"config_hash": h} for h in "abbcbc"]}
    assert drifted(manifest) == ["b", "c"]


def test_records_with_two_indenter_radii_are_refused_naming_both():
    run = Run(pd.DataFrame({"indenter_radius_mm": [5.0, 6.0, 5.0]}), {})
    with pytest.raises(ValueError, match=r"more than one indenter radius: \[5.0, 6.0\] mm"):
        _ = run.radius_mm


def test_a_missing_column_pandas_names_as_a_list_is_named_alone():
    """pandas' own KeyError for a missing column list ("None of [Index(['success'], ...)] are in the
    [columns]") reads as the one column's sentence."""
    with pytest.raises(KeyError) as caught:
        pd.DataFrame({"a": [1]})[["success"]]
    assert reason(caught.value) == "the records have no `success` column"


# --- report/spec.py -----------------------------------------------------------------------------

def test_a_second_run_of_claims_is_the_second_paper_comparison():
    spec = ReportSpec("s", [Value("a", "§1", lambda run: 1.0), Section("b"),
                            Value("c", "§2", lambda run: 2.0), Section("d"),
                            Value("e", "§3", lambda run: 3.0)])
    assert [i.name for i in spec.items if isinstance(i, Table)] == [
        "paper_comparison", "paper_comparison2", "paper_comparison3"]


def test_a_p_value_row_is_compared_at_three_decimals():
    """A p-value is compared with the paper's at 3 decimals: 0.049 against 0.047 differs by 0.002
    (two printed digits of the third decimal), though both print 0.05 at two."""
    table = Claims("c", "claims", [Value("p of the test", "§1", lambda run: 0.049, lambda paper: 0.047,
                                         digits=fmt.P)])
    frame = table.render(Run(pd.DataFrame({"x": [1]}), {}, paper=object()))[0].frame
    assert frame["differs"].tolist() == [True]
    assert frame["verdict"].iloc[0].startswith("differs by +0.002")
