"""An HTML report page's contents: one link per table and figure, by a short title, to its id.

A page with 16 tables and 4 figures listed only its two sections in the navigation bar; "Table 7"
could be found only by scrolling. Each page now lists, under its opening, every table and figure by
its caption's first clause (at most 60 characters) and links each to the block's stable id.
"""

from __future__ import annotations

import re
import subprocess
from collections import Counter
from html.parser import HTMLParser
from pathlib import Path

import pandas as pd
import pytest

from graspcampaign.report.document import Document, Figure, Section, Table, Text, short

CHROMIUM = Path("/usr/bin/chromium")


class Contents(HTMLParser):
    """A page's ids, its tables' and figures' ids with their caption texts (page order) and its
    contents links ``(target, text)``."""

    def __init__(self):
        super().__init__()
        self.ids, self.blocks, self.links = Counter(), [], []
        self._caption = self._link = None
        self._in_contents = False
        self._block = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.ids[a.get("id")] += 1
        if tag == "span" and a.get("class") == "csv":  # the CSV path after a table's caption
            self.handle_endtag("p")
        elif (tag == "div" and "table" in (a.get("class") or "").split()) or tag == "figure":  # "table wide"
            self._block = a.get("id")
        elif tag == "div" and a.get("class") == "contents":
            self._in_contents = True
        elif (tag == "p" and a.get("class") == "caption") or tag == "figcaption":
            self._caption = ""
        elif tag == "a" and self._in_contents:
            self._link = [a.get("href"), ""]

    def handle_endtag(self, tag):
        if tag in ("p", "figcaption") and self._caption is not None:
            self.blocks.append((self._block, self._caption))
            self._caption = None
        elif tag == "a" and self._link is not None:
            self.links.append(tuple(self._link))
            self._link = None
        elif tag == "ul" and self._in_contents:
            self._in_contents = False

    def handle_data(self, data):
        if self._caption is not None:
            self._caption += data
        if self._link is not None:
            self._link[1] += data


def check_contents(text: str) -> Contents:
    """Every table and figure of the page is linked once from its contents, in page order, by a
    distinct title of at most 60 characters that begins its caption; every link has its target."""
    page = Contents()
    page.feed(text)
    if len(page.blocks) < 2:
        assert page.links == [], page.links
        return page
    assert [target for target, _ in page.links] == [f"#{block}" for block, _ in page.blocks]
    assert all(page.ids[target[1:]] == 1 for target, _ in page.links), page.links
    titles = [title for _, title in page.links]
    assert len(set(titles)) == len(titles), titles
    for title, (block, caption) in zip(titles, page.blocks, strict=True):
        assert 0 < len(title) <= 60, title
        name = block.split("-", 1)[1]
        begins = title.removesuffix(f" ({name})").removesuffix("…")
        label = re.match(r"((?:Table|Figs?\.) [\w.–-]+): ", begins)
        if label and not caption.startswith(begins):  # "Fig. 28 (paper in black): proposed …"
            assert caption.startswith(label[1]), (title, caption)
            begins, caption = begins[label.end():], caption.split(":", 1)[1].lstrip()
        assert caption.startswith(begins), (title, caption)
        cut = title.removesuffix(f" ({name})").endswith("…")  # at a word; else where the clause ends
        ends = r"[ ,;]" if cut else r":|\. [A-Z]|\.?\s*$| \("
        assert re.match(ends, caption[len(begins):]), (title, caption)
    return page


def test_every_study_page_lists_each_table_and_figure_once(sim_root):
    checked = 0
    for path in sorted(sim_root.glob("*/*/report/report.html")):
        page = check_contents(path.read_text())
        checked += len(page.links)
    test2 = check_contents((sim_root / "test2_grasp" / "default" / "report" / "report.html").read_text())
    assert ("#t-table7", "Table 7: executed trials per planner and belief reading") in test2.links \
        and len(test2.links) >= 15
    assert checked > 100


def _figure(name: str, caption: str) -> Figure:
    return Figure(name, caption, draw=None, images={"png": b"\x89PNG"})


def test_contents_follow_the_opening_and_tell_equal_titles_apart():
    rates = pd.DataFrame({"planner": ["random"], "rate_pct": [35.7]})
    blocks = [Section("What this shows"), Text("The opening.", "finding"),
              *Table("matched", "Matched ablation: success per planner (§8.5)", rates).render(None),
              *Table("mcnemar", "Matched ablation (§8.5): McNemar, proposed against each",
                     rates).render(None),
              _figure("fig28", "Fig. 28 (paper in black): proposed success per shape")]
    text = Document("t", "simulation", [], blocks).html()
    page = check_contents(text)
    assert page.links == [("#t-matched", "Matched ablation (matched)"),
                          ("#t-mcnemar", "Matched ablation (mcnemar)"),
                          ("#f-fig28", "Fig. 28: proposed success per shape")]
    assert text.index("The opening.") < text.index("class='contents'") < text.index("id='t-matched'")
    one = Document("t", "simulation", [], Table("n", "One table", rates).render(None)).html()
    assert "class='contents'" not in one


@pytest.mark.parametrize("caption, title", [
    ("Trial counts beside the paper's (a reduced study has fewer)", "Trial counts beside the paper's"),
    # a bare label of the paper's says what it shows (the contents read "Table 6", "Table 7", "Fig. 28")
    ("Table 7: executed trials per planner and belief reading",
     "Table 7: executed trials per planner and belief reading"),
    ("Fig. 28 (paper in black): proposed success per shape", "Fig. 28: proposed success per shape"),
    ("Success per planner beside Fig. 18a. Intervals: Wilson 95% per row",
     "Success per planner beside Fig. 18a"),
    ("Figs. 12-13 (ours), one row per preset", "Figs. 12-13"),
    ("Fig. A.1 (ours): (a) ROC curves", "Fig. A.1"),
    ("Pre-execution flags against virtual-rig success (§8.4): `predicted_stable` is",
     "Pre-execution flags against virtual-rig success"),
    ("χ² of planner × success; Kruskal–Wallis of the force error across planners, the peak slip (§8.5)",
     "χ² of planner × success; Kruskal–Wallis of the force error…"),
])
def test_a_short_title_is_the_captions_first_clause(caption, title):
    assert short(caption) == title


@pytest.mark.slow
@pytest.mark.skipif(not CHROMIUM.exists(), reason="/usr/bin/chromium is not installed")
def test_chromium_shows_a_linked_table_below_the_sticky_bar(tmp_path):
    """Followed, a link put its table's caption under the sticky navigation bar."""
    frame = pd.DataFrame({"n": range(30)})
    tables = [b for k in range(8) for b in Table(f"t{k}", f"Table {k}", frame).render(None)]
    script = ("document.getElementById('t-t5').scrollIntoView(); document.body.dataset.gap = Math.round("
              "document.getElementById('t-t5').getBoundingClientRect().top - "
              "document.querySelector('nav').getBoundingClientRect().bottom);")
    page = tmp_path / "page.html"
    page.write_text(Document("t", "simulation", [], tables).html().replace(
        "</body>", f"<script>{script}</script></body>"))
    out = subprocess.run([str(CHROMIUM), "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                          f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1280,600",
                          "--dump-dom", page.as_uri()], capture_output=True, text=True, timeout=120)
    gap = re.search(r"<body data-gap=\"(-?\d+)\">", out.stdout)
    assert gap and int(gap.group(1)) >= 0, re.findall(r"<body[^>]*>", out.stdout)


def test_a_page_whose_tables_show_the_missing_mark_says_once_what_it_means():
    """Tables printed "—" (no paper value, no reading, not compared) and no caption or page said what
    it means: the page says it once, under its provenance, and only when one of its tables shows it."""
    from graspcampaign.report.document import Col

    def page(paper: float | None) -> Document:
        frame = pd.DataFrame({"quantity": ["a", "b"], "paper": [1.0, paper], "ours": [1.5, 2.5]})
        return Document("t", "simulation", [("Seed", "1")], [
            Table("one", "first", frame, [Col("quantity", "q"), Col("paper", "paper", 1)]),
            Table("two", "second", frame, [Col("quantity", "q"), Col("paper", "paper", 1)])])

    md, html = page(None).markdown(), page(None).html()
    assert "| b | — |" in md  # the mark the line explains
    line = "- **—:** in a table, no value there: the paper reports none, or the run records none or does " \
           "not compare it (where a row has a verdict or reason, it says which)"
    assert md.count(line) == 1 and md.index("- **Seed:** 1\n" + line) > 0  # once, with the provenance
    assert html.count("<dt>—</dt><dd>in a table, no value there") == 1
    assert "**—:**" not in page(2.0).markdown() and "<dt>—</dt>" not in page(2.0).html()  # no mark shown
