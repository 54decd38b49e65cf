"""A report's items and blocks (sections, paragraphs, tables, figures), one class each; the page writer."""

from __future__ import annotations

import base64
import html
import json
import math
import os
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Any

import pandas as pd

from graspcampaign.analysis.vocabulary import FACTOR_LABELS, UNITS, VOCABULARIES, label
from graspcampaign.campaign.paths import write_file
from graspcampaign.core.words import meant
from graspcampaign.errors import UserInputError
from graspcampaign.report import format as fmt
from graspcampaign.report import style

FORMATS = ("md", "csv", "json", "html")
FIGURE_FORMATS = ("png", "svg", "pdf")
SOURCE_LABEL = {"simulation": "simulation (this tool's numerical model)", "measured": "measured on hardware "
                "(ingested records)", "virtual": "VIRTUAL RIG: synthetic data from a stochastic model, not "
                "hardware measurements"}
NAV = [("Index", "index.html"), ("Table 1 headline", "headline.html")]
"""The navigation bar of every page (relative to the results root)."""
WIDE = 12
"""Columns from which a table is set compact in HTML (smaller type, tighter cells): at the page's 1,180 px
the reduced reports' tables of 12 columns and more (Tables 1, 6, 7) overflowed, none of 11 or fewer did."""
LONG = 20
"""Rows beyond which a table scrolls in a box of at most 90% of the window's height under a header row that
stays in view (on the page, the header of test2_classifier scrolled out of view above its rows 20-44)."""
# a printed number: a bound, a sign, digits or inf, an exponent, a unit sign, a range or an interval
# ("35.7 (25.5–47.4)"), the count a rate is over ("35.7 (25.5–47.4) of 40")
NUMBER = re.compile(r"[<>≤≥≈]? ?[+−-]?(\d[\d,]*(\.\d+)?(e[+−-]?\d+| ?× ?10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)?|inf) ?[%×]?"
                    r"(–[\d.]+)?( \([^()]*\))?( of \d+)?")


def check_formats(formats: Sequence[str] | str | None, allowed: Sequence[str] = FORMATS,
                  what: str = "report format", option: str = "--format", one: bool = False) -> list[str]:
    """Return the requested formats (comma-separated or a list; with ``one``, a single one) or
    raise naming an unknown one, or formats separated by spaces (or more than one) as the option
    ``option`` that gives them."""
    items = formats.split(",") if isinstance(formats, str) else ["md", "csv"] if formats is None else formats
    items = list(dict.fromkeys(f.strip().lower() for f in items if f and str(f).strip()))
    words = list(dict.fromkeys(w for f in items for w in f.split()))
    given = formats if isinstance(formats, str) else ",".join(items)
    if one and len(words) > 1:  # 'svg png' or 'svg,png': one format draws the figures
        raise UserInputError(f"{option} {given!r}: one {what} is taken, not {len(words)}; choose one "
                             f"of {', '.join(allowed)}.")
    if len(words) > len(items):  # 'md csv' is one item of two words, not csv misspelt
        raise UserInputError(f"{option} {given!r}: {what}s are separated by commas, not spaces; give "
                             f"{option} {','.join(words)}.")
    if not items or (bad := [f for f in items if f not in allowed]):
        raise UserInputError(f"{f'unknown {what} {bad[0]!r}' if items else f'no {what} given'}; "
                             f"{meant(bad[0], allowed) if items else ''}choose from {', '.join(allowed)}.")
    return items


@dataclass(frozen=True)
class Col:
    """A shown column: the CSV column ``key`` under ``label``, rounded once to ``digits`` decimals
    (or the CSV column holding each row's) or ``sig`` significant digits; ``low``/``high`` the
    interval columns in brackets (only the interval when ``low == key``); ``why`` the column whose
    text replaces a value not computed; ``share`` a percentage after a count, ``k (p%)``; ``link``
    the column holding a relative link to another page; ``of`` the column holding the count a rate is
    over, printed after it (``12.5 (5.1–27.4) of 40``) where it differs from the row's ``n``."""

    key: str
    label: str
    digits: int | str | None = None
    sig: int | None = None
    signed: bool = False
    low: str | None = None
    high: str | None = None
    why: str | None = None
    share: str | None = None
    link: str | None = None
    of: str | None = None

    @property
    def keys(self) -> list[str]:
        return list(dict.fromkeys(k for k in (self.key, self.low, self.high, self.share) if k))


def cols(*names: str, frame: pd.DataFrame | None = None, digits: int | None = None) -> list[Col]:
    """Shown columns of record-convention names ``<words>_<unit>``: header ``words [unit]``, ``digits``
    decimals when the quantity has a known precision, else 3 significant digits (1 decimal for %);
    factor levels and other columns (counts are ``n_<things>``) print as they are. With ``frame``,
    its interval ``<words>_low_<unit>``/``_high_<unit>`` (or ``<name>_low``/``_high``) and reason
    ``<name>_why`` (or ``<words>_why``) join a column when the frame has them."""
    out, has = [], (lambda c: frame is not None and c in frame)
    for name in names:
        words, _, suffix = name.rpartition("_")
        unit = UNITS.get(suffix) if words and name not in FACTOR_LABELS else None
        head = FACTOR_LABELS.get(name) or (f"{words.replace('_', ' ')} [{unit}]" if unit else
                                           name.replace("_", " "))
        low, high = (f"{words}_low_{suffix}", f"{words}_high_{suffix}") if unit else (f"{name}_low",
                                                                                       f"{name}_high")
        ci, why = has(low) and has(high), next((w for w in (f"{name}_why", f"{words}_why") if has(w)), None)
        fixed = digits if digits is not None else 1 if unit == "%" else None
        out.append(Col(name, head, fixed, sig=3 if unit and fixed is None else None,
                       low=low if ci else None, high=high if ci else None, why=why))
    return out


def pct_col(name: str, head: str, of: str | None = None) -> Col:
    """The rate ``<name>_pct`` under ``<head> % (Wilson 95%)`` with its ``_low_pct``/``_high_pct`` (and
    its count ``of``, see :class:`Col`)."""
    return Col(f"{name}_pct", f"{head} % (Wilson 95%)", 1, low=f"{name}_low_pct", high=f"{name}_high_pct",
               of=of)


def cell(row: Mapping[str, Any], col: Col) -> str:
    """Return the displayed text of ``row`` under ``col`` (the one formatting of every table); a
    p-value (:func:`~graspcampaign.report.format.is_p_value`, or a row whose digits are ``fmt.P``)
    by :func:`~graspcampaign.report.format.p_value`."""
    value = row.get(col.key)
    if fmt.is_missing(value):
        why = row.get(col.why) if col.why else None
        return str(why) if isinstance(why, str) and why else fmt.MISSING
    if col.key in VOCABULARIES:  # a level prints in the vocabulary's words, as a grouping column's does
        return label(col.key, value)
    # fmt.EACH: each value at col.sig significant digits, by the one formatter (fmt.number)
    digits = col.digits if col.digits == fmt.EACH else \
        row.get(col.digits) if isinstance(col.digits, str) else col.digits
    if fmt.is_p_value(col.key) or (digits == fmt.P and not col.signed):
        return fmt.p_value(value)
    # a p row's difference (signed) at the 3 decimals its verdict compares at
    digits = None if fmt.is_missing(digits) else 3 if digits == fmt.P else \
        digits if digits == fmt.EACH else int(digits)
    if col.low and col.low == col.key:
        return fmt.interval(value, row.get(col.high), digits, sig=col.sig)
    if col.low:
        k, n = row.get(col.of) if col.of else None, row.get("n")  # the rate's n, said unless the row's
        return fmt.estimate(value, row.get(col.low), row.get(col.high), digits, sig=col.sig) + (
            f" of {int(k)}" if not fmt.is_missing(k) and (fmt.is_missing(n) or k != n) else "")
    if col.share:
        return f"{fmt.number(value, digits)} ({fmt.number(row.get(col.share), 1)}%)"
    return fmt.number(value, digits, sig=col.sig, signed=col.signed)


def rounded(col: Col, frame: pd.DataFrame) -> Col:
    """``col`` with one rounding for the whole column (:func:`~graspcampaign.report.format.decimals`
    at its ``sig``, default 3: ``fmt.EACH`` value alone when they span more than two decades) unless
    its digits are fixed."""
    if col.digits is not None or col.share or fmt.is_p_value(col.key) or col.key not in frame:
        return col
    digits = fmt.decimals([v for k in col.keys if k in frame for v in frame[k]], col.sig or 3)
    return col if digits is None else replace(col, digits=digits, sig=col.sig if digits == fmt.EACH else None)


def labelled(frame: pd.DataFrame, by: Sequence[str]) -> tuple[pd.DataFrame, list[Col]]:
    """Add ``<column>_label`` (the vocabulary's words) for grouping columns; return the shown cols."""
    for c in (c for c in by if c in VOCABULARIES):
        frame[f"{c}_label"] = [label(c, v) for v in frame[c]]
    return frame, [Col(f"{c}_label", c.replace("_", " ")) if c in VOCABULARIES
                   else Col(c, FACTOR_LABELS.get(c, c.replace("_", " "))) for c in by]


def _text(text: str | Callable, run: Any) -> str:
    return text(run) if callable(text) else text


# A spec's items and the page's blocks are the same classes: ``render(run)`` turns an item of a
# ReportSpec into the blocks of the page (a Table's frame, a Figure's images); ``md``/``html`` write them.
@dataclass(frozen=True)
class Table:
    """Any table: ``compute(run)`` returns the full-precision frame (the CSV), or ``compute`` is the
    frame; ``cols`` the shown columns after the labels of the grouping columns ``by``: a :class:`Col`, or
    a column name shown by :func:`cols` (header and rounding from its unit, its interval and reason
    columns joined), or ``cols(run, frame)``; default every other column. ``csv``: its CSV path."""

    name: str
    caption: str | Callable[[Any], str]
    compute: Callable[[Any], pd.DataFrame] | pd.DataFrame
    cols: Sequence[Col | str] | Callable[[Any, pd.DataFrame], Sequence[Col | str]] | None = None
    by: Sequence[str] = ()
    empty: str | None = "no executed trial has its data"  # None: an empty table is left out
    csv: str | None = "tables/{name}.csv"
    title = property(lambda self: f"Table {self.name}")
    frame = property(lambda self: self.compute)
    anchor = property(lambda self: f"t-{self.name}")

    def render(self, run: Any) -> list:
        frame = self.compute(run) if callable(self.compute) else self.compute
        if frame is not None and not isinstance(frame, pd.DataFrame):
            raise TypeError(f"its compute returned a {type(frame).__name__}, not a DataFrame" + (
                " (a grouped result needs .reset_index())" if isinstance(frame, pd.Series) else ""))
        if frame is None or not len(frame):
            return [Text(f"Table {self.name} is empty: {self.empty}.", "note")] if self.empty else []
        frame, lead = labelled(frame.reset_index(drop=True), self.by)
        shown = self.cols(run, frame) if callable(self.cols) else self.cols if self.cols is not None else [
            c for c in frame if c not in self.by and not re.search(r"_(label|why|low|high)(_[a-z]+)?$", c)]
        shown = [c if isinstance(c, Col) else cols(c, frame=frame)[0] for c in shown]
        return [replace(self, caption=_text(self.caption, run), compute=frame, cols=[*lead, *shown], by=())]

    def absent(self) -> str:
        """The note on shown columns the frame lacks (a misspelt name, or a run recorded before the
        column existed): each named with the frame's nearest column, as each prints as the missing mark."""
        missing = [c.key for c in self.cols if c.key not in self.frame]
        if not missing:
            return ""
        near = {c: meant(c, self.frame.columns).strip() for c in missing}
        names = ", ".join(f"`{c}`" + (f" ({near[c]})" if near[c] else "") for c in missing)
        return f"Table {self.name} shows {names}, not in its frame: shown as {fmt.MISSING}."

    @cached_property
    def grid(self) -> tuple[list[list[tuple[str, str | None]]], list[bool]]:
        """Every row's ``(text, link target or None)`` per shown column, formatted once for every
        writer, and whether each column holds numbers (with an interval, unit sign or missing mark),
        besides which only yes/no or a reason standing for a value not computed (its ``why``): such a
        column is right-aligned, so digits line up as in a printed table (a claims table's "yes" or
        one "not computed: …" row left its numbers and ranges left-aligned)."""
        shown, records = [rounded(c, self.frame) for c in self.cols], self.frame.to_dict("records")
        rows = [[(cell(r, c), None if not c.link or fmt.is_missing(r.get(c.link)) else str(r[c.link]))
                 for c in shown] for r in records]

        def kind(r: dict, c: Col, text: str) -> str:
            return "number" if NUMBER.fullmatch(text) else "value" if text in (fmt.MISSING, "yes", "no") or (
                c.why and fmt.is_missing(r.get(c.key))) else "text"
        kinds = [[kind(r, c, row[i][0]) for i, c in enumerate(shown)] for r, row in zip(records, rows,
                                                                                       strict=True)]
        return rows, [any(k[i] == "number" for k in kinds) and all(k[i] != "text" for k in kinds)
                      for i in range(len(self.cols))]

    def md(self, figure_format: str) -> str:
        def line(cells: Sequence[str]) -> str:
            return "| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ") for c in cells) + " |"

        cells, numeric = self.grid
        rows = [[f"[{v}]({h.replace('.html', '.md')})" if h else v for v, h in r] for r in cells]
        rule = "|" + "".join("---:|" if n else "---|" for n in numeric)
        return "\n".join([f"**{self.caption}**" + (f" (`{self.csv.format(name=self.name)}`)" if self.csv
                                                   else "") + "\n", line([c.label for c in self.cols]),
                          rule, *map(line, rows)])

    def html(self) -> str:
        """A styled HTML table; each header names the CSV columns it shows (``data-cols``)."""
        head = "".join(f"<th data-cols='{' '.join(c.keys)}'>"
                       f"{html.escape(c.label)}</th>" for c in self.cols)
        # a line never breaks at an en dash: "35.7 (25.5–47.4)" wraps before its interval, not inside it;
        # it may after an underscore (a record name, "predicted_stable_residual", set a column's width)
        cells, numeric = self.grid
        td = ["<td class='num'>" if n else "<td>" for n in numeric]
        body = "".join("<tr>" + "".join(
            f"{td[i]}<a href='{html.escape(h, quote=True)}'>{html.escape(v)}</a></td>" if h else
            td[i] + re.sub(r"\S*–\S*", r"<span class='nb'>\g<0></span>", html.escape(v)).replace(
                "_", "_<wbr>") + "</td>"
            for i, (v, h) in enumerate(r)) + "</tr>" for r in cells)
        attrs = f" data-table='{self.name}'" if self.csv else ""
        csv = f" <span class='csv'>{self.csv.format(name=self.name)}</span>" if self.csv else ""
        # the caption above the table, not its <caption>: that one wraps to a narrow table's width
        kind = " wide" * (len(self.cols) >= WIDE) + " long" * (len(cells) > LONG)
        return (f"<div class='table{kind}' id='{self.anchor}'><p class='caption' id='c-{self.name}'>"
                f"{inline(self.caption)}{csv}</p><table{attrs} aria-labelledby='c-{self.name}'><thead><tr>"
                f"{head}</tr></thead><tbody>{body}</tbody></table></div>")


@dataclass(frozen=True)
class Text:
    """A paragraph: Markdown, or a function of the run returning it (empty: left out); ``kind`` is
    ``finding``, ``note`` (a reason) or ``text``."""

    markdown: str | Callable[[Any], str]
    kind: str = "text"
    title = "a paragraph"

    def render(self, run: Any) -> list:
        return [replace(self, markdown=text)] if (text := _text(self.markdown, run)) else []

    def md(self, figure_format: str) -> str:
        return self.markdown if self.kind != "note" else f"*{self.markdown}*"

    def html(self) -> str:
        return f"<p class='{self.kind}'>{inline(self.markdown)}</p>"


@dataclass(frozen=True)
class Section:
    """A heading; the HTML page's navigation lists every section."""

    title: str

    def render(self, run: Any) -> list:
        return [self]

    @property
    def anchor(self) -> str:
        return "s-" + "".join(c if c.isalnum() else "-" for c in self.title.lower()).strip("-")

    def md(self, figure_format: str) -> str:
        return f"## {self.title}"

    def html(self) -> str:
        return f"<h2 id='{self.anchor}'>{html.escape(self.title)}</h2>"


@dataclass(frozen=True)
class Figure:
    """A figure: ``draw(run, fig)`` draws on a figure of ``size`` inches in the one style; rendered, its
    ``images`` by format (``png`` always, for the HTML page) and the run's data ``source``."""

    name: str
    caption: str | Callable[[Any], str]
    draw: Callable[[Any, Any], None]
    size: tuple[float, float] = (6.4, 3.6)
    images: dict[str, bytes] | None = None
    source: str = ""
    title = property(lambda self: f"Figure {self.name}")
    anchor = property(lambda self: f"f-{self.name}")

    def render(self, run: Any) -> list:
        images = style.draw(lambda fig: self.draw(run, fig), self.size, run.source, (run.figure_format,))
        return [replace(self, caption=_text(self.caption, run), images=images, source=run.source)]

    def md(self, figure_format: str) -> str:
        path = f"figures/{self.name}.{figure_format}"
        link = f"![{self.caption}]({path})" if figure_format != "pdf" else f"[{self.name} (PDF)]({path})"
        return f"{link}\n\n*{self.caption}*"

    def html(self) -> str:
        """The figure fitted to the page, its caption under it; its alt text the caption as plain text
        and the data source the image is labelled with, so a screen reader hears both."""
        kind = "svg" if "svg" in self.images else "png"
        data = base64.b64encode(self.images[kind]).decode()
        # the page fits a figure to its width, a three-panel one's labels then at half size: a click on
        # the image toggles it to full size (scrolling inside the figure), with no link out of the page;
        # the checkbox is invisible, not hidden, so Tab reaches it and Space toggles it too
        zoom, source = f"zoom-{self.anchor}", style.SOURCE_SHORT.get(self.source, self.source)
        alt = re.sub(r"[*`]", "", self.caption) + (f" Data: {source}." if source else "")
        return (f"<figure id='{self.anchor}'><input type='checkbox' class='zoom' id='{zoom}' aria-label="
                f"'{html.escape(self.title)}: full size'><label for='{zoom}' title='click: full size / fit'>"
                f"<img src='data:image/{'svg+xml' if kind == 'svg' else 'png'};base64,{data}' alt='"
                f"{html.escape(alt, quote=True)}'></label><figcaption>{inline(self.caption)}"
                "</figcaption></figure>")


def _json(value: Any) -> Any:
    """Return ``value`` as strict JSON allows: nan and NA -> null, inf -> "inf"."""
    if value is pd.NA or value is pd.NaT or (isinstance(value, float) and math.isnan(value)):
        return None
    return ("inf" if value > 0 else "-inf") if isinstance(value, float) and math.isinf(value) else value


MISSING_MEANS = ("in a table, no value there: the paper reports none, or the run records none or does not "
                 "compare it (where a row has a verdict or reason, it says which)")
"""What the missing mark :data:`~graspcampaign.core.words.MISSING` in a table cell means, said once per
page."""


@dataclass
class Document:
    """One page: title, data source, provenance lines, blocks and the navigation bar."""

    title: str
    source: str
    provenance: list[tuple[str, str]]
    blocks: list[Any] = field(default_factory=list)
    nav: list[tuple[str, str]] = field(default_factory=lambda: list(NAV))

    @property
    def tables(self) -> dict[str, pd.DataFrame]:
        return {b.name: b.frame for b in self.blocks if isinstance(b, Table)}

    @property
    def lines(self) -> list[tuple[str, str]]:
        """The provenance lines, then what the missing mark means when a table on the page shows one:
        said once here for every table, not in each caption."""
        dashed = any(text == fmt.MISSING for b in self.blocks if isinstance(b, Table)
                     for row in b.grid[0] for text, _ in row)
        return [*self.provenance, *([(fmt.MISSING, MISSING_MEANS)] if dashed else [])]

    def write(self, out: Path, formats: Sequence[str], figure_format: str = "png") -> Path:
        """Write the requested formats under ``out``; return the main page (md, else html...)."""
        formats, written = check_formats(formats), {}
        for folder in (out, out / "figures", out / "tables"):  # mkdir says only "File exists"
            if os.path.lexists(folder) and not folder.is_dir():
                raise UserInputError(f"{folder} is a file where the report's directory belongs; "
                                     "move it aside and report again.")
        out.mkdir(parents=True, exist_ok=True)
        for b in (b for b in self.blocks if isinstance(b, Figure)):
            (out / "figures").mkdir(exist_ok=True)
            write_file(out / "figures" / f"{b.name}.{figure_format}", b.images[figure_format])
        if "csv" in formats:
            (out / "tables").mkdir(exist_ok=True)
            for name, frame in self.tables.items():
                write_file(out / "tables" / f"{name}.csv", frame.to_csv(index=False))
            written["csv"] = out / "tables"
        if "json" in formats:
            written["json"] = out / "tables.json"
            tables = {k: [{c: _json(v) for c, v in r.items()} for r in f.to_dict("records")]
                      for k, f in self.tables.items()}
            write_file(written["json"], json.dumps(tables, indent=1, default=str, allow_nan=False))
        for f in ("html", "md"):
            if f in formats:
                written[f] = out / f"report.{f}"
                write_file(written[f], self.html() if f == "html" else self.markdown(figure_format))
        return next(written[k] for k in ("md", "html", "json", "csv") if k in written)

    def markdown(self, figure_format: str = "png") -> str:
        out = [f"# {self.title}"]
        if self.source:
            out.append(f"> **Data source:** {SOURCE_LABEL.get(self.source, self.source)}")
        if lines := self.lines:
            out.append("\n".join(f"- **{k}:** {v}" for k, v in lines))
        return "\n\n".join([*out, *(b.md(figure_format) for b in self.blocks)]) + "\n"

    def contents(self) -> str:
        """The page's contents: a link to every table and figure by its caption's first clause
        (:func:`short`; two of one title add their names), "" for fewer than two."""
        listed = [b for b in self.blocks if isinstance(b, Table | Figure)]
        titles = [short(b.caption) for b in listed]
        titles = [f"{short(b.caption, 57 - len(b.name))} ({b.name})" if titles.count(t) > 1 else t
                  for b, t in zip(listed, titles, strict=True)]
        links = "".join(f"<li><a href='#{b.anchor}'>{html.escape(t)}</a></li>"
                        for b, t in zip(listed, titles, strict=True))
        return f"<div class='contents'><b>On this page</b><ul>{links}</ul></div>" if len(listed) > 1 else ""

    def html(self) -> str:
        """A complete self-contained page: navigation bar (the other pages and this page's sections),
        data-source banner, provenance, blocks and the contents before the first table or figure."""
        toc = "".join(f"<a href='#{b.anchor}'>{html.escape(b.title)}</a>" for b in self.blocks
                      if isinstance(b, Section))
        links = "".join(f"<a href='{html.escape(h, quote=True)}'>{html.escape(t)}</a>" for t, h in self.nav) \
            + (f"<span class='toc'>{toc}</span>" if toc else "")
        banner, title = html.escape(SOURCE_LABEL.get(self.source, self.source) or "see each row"), \
            html.escape(self.title)
        source = html.escape(self.source or "mixed")  # a page over several runs: each row says its own
        blocks = [b.html() for b in self.blocks]
        first = next((i for i, b in enumerate(self.blocks) if isinstance(b, Table | Figure)), 0)
        body = "\n".join(["<dl class='provenance'>" + "".join(f"<dt>{html.escape(k)}</dt><dd>{inline(v)}</dd>"
                                                              for k, v in self.lines) + "</dl>",
                          *blocks[:first], self.contents(), *blocks[first:]])
        return ("<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'><meta name='viewport' "
                f"content='width=device-width,initial-scale=1'><title>{title}</title><style>{style.CSS}</style>"
                f"</head><body><nav aria-label='pages and sections'>{links}</nav><div class='source "
                f"source-{source}'>Data: "
                f"{banner}</div><main><h1>{title}</h1>{body}</main><footer>Data: {banner}. Written by "
                "graspcampaign from the records only.</footer></body></html>\n")


#: where a caption's first clause ends: a colon, a sentence's full stop (not that of "Fig. 28"), an aside
CLAUSE = re.compile(r":|\.(?= [A-Z][a-z]|$)| \(")
#: a caption that opens with a bare label of the paper's: "Table 7", "Fig. 28", "Figs. 12-13"
LABEL = re.compile(r"(Table|Figs?\.) [\w.–-]+")


def short(caption: str, limit: int = 60) -> str:
    """A caption's first clause as plain text, at most ``limit`` characters (cut at a word: '…'); a bare
    label ("Table 7", "Fig. 28") with the clause after its colon ("Table 7: executed trials per …")."""
    caption = re.sub(r"[*`]", "", caption)
    text = CLAUSE.split(caption, maxsplit=1)[0].strip()
    if LABEL.fullmatch(text) and ":" in caption:
        shows = CLAUSE.split(caption.split(":", 1)[1], maxsplit=1)[0].strip()
        text += f": {shows}" if shows else ""
    return text if len(text) <= limit else text[:limit].rsplit(" ", 1)[0].rstrip(",;") + "…"


def inline(markdown: str) -> str:
    """Return escaped HTML of a Markdown paragraph: **bold**, *italic*, `code`, line breaks and
    ``[text](page.md)`` links between the pages of the results tree (to their ``.html``)."""
    text = html.escape(markdown)
    text = re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", text)
    text = re.sub(r"(?<![\w*])\*(?!\s)(.+?)(?<!\s)\*(?![\w*])", r"<i>\1</i>", text)
    text = re.sub(r"`(.+?)`", r"<code>\1</code>", text)
    text = re.sub(r"\[([^\]]+)\]\(([\w./-]+)\.md\)", r"<a href='\2.html'>\1</a>", text)
    return text.replace("\n- ", "<br>• ").replace("\n\n", "<br><br>")
