"""A rendered report: blocks (headings, paragraphs, tables, figures) and the writers of each format.

A table is one DataFrame at full precision (written as ``tables/<name>.csv`` and in
``tables.json``) plus the columns shown: each shown column names the CSV column(s) it displays
(:class:`Col`), and every cell is :func:`cell` of its row -- rounded once, the missing mark or the
reason a value could not be computed. So a page's table always equals its CSV table.

Formats: ``md`` (``report.md``), ``csv`` (``tables/``), ``json`` (``tables.json``) and ``html``
(one self-contained ``report.html``: styles inline, figures embedded as data URIs, links only to
the other pages of the results tree). Figures are written as PNG, SVG or PDF (``figures/``).
"""

from __future__ import annotations

import base64
import html
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from graspcampaign.errors import UserInputError
from graspcampaign.report import format as fmt

FORMATS = ("md", "csv", "json", "html")
FIGURE_FORMATS = ("png", "svg", "pdf")
SOURCE_LABEL = {
    "simulation": "simulation (this tool's numerical model)",
    "virtual": "VIRTUAL RIG: synthetic data from a stochastic model, not hardware measurements",
    "measured": "measured on hardware (ingested records)",
}


def check_formats(formats: Sequence[str] | str | None) -> list[str]:
    """Return the requested formats as a list, or raise naming an unknown one."""
    if formats is None:
        return ["md", "csv"]
    items = formats.split(",") if isinstance(formats, str) else list(formats)
    items = [f.strip().lower() for f in items if f and f.strip()]
    unknown = [f for f in items if f not in FORMATS]
    if unknown or not items:
        raise UserInputError(f"unknown report format {unknown[0]!r}; choose from "
                             f"{', '.join(FORMATS)} (comma-separated)." if unknown else
                             f"no report format given; choose from {', '.join(FORMATS)}.")
    return list(dict.fromkeys(items))


def check_figure_format(figure_format: str) -> str:
    """Return the figure format, or raise naming the allowed ones."""
    value = str(figure_format).strip().lower()
    if value not in FIGURE_FORMATS:
        raise UserInputError(f"unknown figure format {figure_format!r}; choose from "
                             f"{', '.join(FIGURE_FORMATS)}.")
    return value


@dataclass(frozen=True)
class Col:
    """A shown column: the CSV column ``key`` under ``label``, rounded once.

    ``digits`` decimals (or the name of a CSV column holding each row's decimals), ``sig``
    significant digits instead; ``low``/``high`` name the interval columns printed in brackets
    (only the interval when ``key`` is ``low``);
    ``why`` names the column whose text replaces a value that could not be computed; ``share``
    names a percentage column printed after a count, ``k (p%)``.
    """

    key: str
    label: str
    digits: int | str | None = None
    sig: int | None = None
    signed: bool = False
    low: str | None = None
    high: str | None = None
    why: str | None = None
    share: str | None = None
    link: str | None = None  # column holding a relative link to another page (html/md)

    @property
    def keys(self) -> list[str]:
        return list(dict.fromkeys(k for k in (self.key, self.low, self.high, self.share) if k))


#: Unit suffixes of record columns (docs/records.md) and how their headers print them.
UNITS = {"pct": "%", "mm": "mm", "m": "m", "n": "N", "nm": "N·m", "s": "s", "ms": "ms",
         "kg": "kg", "j": "J", "mj": "mJ", "deg": "°", "rad": "rad", "kpa": "kPa"}


def cols(*names: str) -> list[Col]:
    """Shown columns for record-convention names ``<words>_<unit>``: header ``words [unit]``,
    values with 3 significant digits (1 decimal for %); factor levels and other columns print
    as they are."""
    from graspcampaign.analysis.vocabulary import FACTOR_LABELS

    out = []
    for name in names:
        if name in FACTOR_LABELS:  # design levels print as configured
            out.append(Col(name, FACTOR_LABELS[name]))
            continue
        words, _, suffix = name.rpartition("_")
        unit = UNITS.get(suffix) if words else None
        label = f"{words.replace('_', ' ')} [{unit}]" if unit else name.replace("_", " ")
        out.append(Col(name, label, 1 if unit == "%" else None, sig=3 if unit and unit != "%"
                       else None))
    return out


def cell(row: Mapping[str, Any], col: Col) -> str:
    """Return the displayed text of ``row`` under ``col`` (the one formatting of every table)."""
    value = row.get(col.key)
    if fmt.is_missing(value):
        why = row.get(col.why) if col.why else None
        return str(why) if isinstance(why, str) and why else fmt.MISSING
    digits = row.get(col.digits) if isinstance(col.digits, str) else col.digits
    digits = None if fmt.is_missing(digits) else int(digits)
    if col.low and col.low == col.key:
        return fmt.interval(value, row.get(col.high), digits, sig=col.sig)
    if col.low:
        return fmt.estimate(value, row.get(col.low), row.get(col.high), digits, sig=col.sig)
    if col.share:
        return f"{fmt.number(value, digits)} ({fmt.number(row.get(col.share), 1)}%)"
    return fmt.number(value, digits, sig=col.sig, signed=col.signed)


@dataclass
class Table:
    """A table block: full-precision frame, shown columns, caption."""

    name: str
    caption: str
    frame: pd.DataFrame
    cols: list[Col]
    legacy: list[list[str]] | None = None  # LEGACY PATH: a section's own display cells

    def rows(self) -> list[list[str]]:
        if self.legacy is not None:
            return self.legacy
        records = self.frame.to_dict("records")
        return [[cell(r, c) for c in self.cols] for r in records]

    def links(self) -> list[list[str | None]]:
        """The link target of every cell (None where the cell links nothing)."""
        records = self.frame.to_dict("records") if self.legacy is None else []
        return [[None if not c.link or fmt.is_missing(r.get(c.link)) else str(r[c.link])
                 for c in self.cols]
                for r in records] or [[None] * len(self.cols) for _ in self.rows()]


@dataclass
class Text:
    """A paragraph (Markdown); ``kind`` is ``finding``, ``note`` (a reason) or ``text``."""

    markdown: str
    kind: str = "text"


@dataclass
class Heading:
    title: str

    @property
    def anchor(self) -> str:
        return "s-" + "".join(c if c.isalnum() else "-" for c in self.title.lower()).strip("-")


@dataclass
class Figure:
    """A figure block: its images by format (``png`` always, for the HTML page)."""

    name: str
    caption: str
    images: dict[str, bytes]


def auto_cols(frame: pd.DataFrame) -> list[Col]:
    """Show every column of ``frame``; floats with 4 significant digits."""
    return [Col(c, c.replace("_", " ")) for c in frame.columns]


@dataclass
class Document:
    """One run's report: title, data source, provenance lines and blocks."""

    title: str
    source: str
    provenance: list[tuple[str, str]]
    blocks: list[Any] = field(default_factory=list)
    nav: list[tuple[str, str]] = field(default_factory=list)  # (label, relative href)

    @property
    def tables(self) -> dict[str, pd.DataFrame]:
        return {b.name: b.frame for b in self.blocks if isinstance(b, Table)}

    def write(self, out: Path, formats: Sequence[str], figure_format: str = "png") -> Path:
        """Write the requested formats under ``out``; return the main page (md, else html...)."""
        formats = check_formats(formats)
        out.mkdir(parents=True, exist_ok=True)
        figures = [b for b in self.blocks if isinstance(b, Figure)]
        if figures:
            (out / "figures").mkdir(exist_ok=True)
            for b in figures:
                (out / "figures" / f"{b.name}.{figure_format}").write_bytes(b.images[figure_format])
        written = {}
        if "csv" in formats:
            (out / "tables").mkdir(exist_ok=True)
            for name, frame in self.tables.items():
                frame.to_csv(out / "tables" / f"{name}.csv", index=False)
            written["csv"] = out / "tables"
        if "json" in formats:
            data = {k: [{c: _json(v) for c, v in r.items()} for r in f.to_dict("records")]
                    for k, f in self.tables.items()}
            written["json"] = out / "tables.json"
            written["json"].write_text(json.dumps(data, indent=1, default=str, allow_nan=False))
        if "html" in formats:
            written["html"] = out / "report.html"
            written["html"].write_text(self.html())
        if "md" in formats:
            written["md"] = out / "report.md"
            written["md"].write_text(self.markdown(figure_format))
        return next(written[k] for k in ("md", "html", "json", "csv") if k in written)

    # ---------------------------------------------------------------------------- Markdown
    def markdown(self, figure_format: str = "png") -> str:
        out = [f"# {self.title}"]
        if self.source:
            out.append(f"> **Data source:** {SOURCE_LABEL.get(self.source, self.source)}")
        if self.provenance:
            out.append("\n".join(f"- **{k}:** {v}" for k, v in self.provenance))
        for b in self.blocks:
            if isinstance(b, Heading):
                out.append(f"## {b.title}")
            elif isinstance(b, Text):
                out.append(b.markdown if b.kind != "note" else f"*{b.markdown}*")
            elif isinstance(b, Table):
                rows = [[f"[{v}]({h.replace('.html', '.md')})" if h else v
                         for v, h in zip(r, lk, strict=True)]
                        for r, lk in zip(b.rows(), b.links(), strict=True)]
                out.append(f"**{b.caption}** (`tables/{b.name}.csv`)\n\n" + markdown_table(
                    [c.label for c in b.cols], rows))
            else:
                path = f"figures/{b.name}.{figure_format}"
                link = f"![{b.caption}]({path})" if figure_format != "pdf" else \
                    f"[{b.name} (PDF)]({path})"
                out.append(f"{link}\n\n*{b.caption}*")
        return "\n\n".join(out) + "\n"

    # ---------------------------------------------------------------------------- HTML
    def html(self) -> str:
        toc = [(b.title, f"#{b.anchor}") for b in self.blocks if isinstance(b, Heading)]
        body = ["<dl class='provenance'>" + "".join(
                    f"<dt>{html.escape(k)}</dt><dd>{inline(v)}</dd>" for k, v in self.provenance)
                + "</dl>"]
        for b in self.blocks:
            if isinstance(b, Heading):
                body.append(f"<h2 id='{b.anchor}'>{html.escape(b.title)}</h2>")
            elif isinstance(b, Text):
                body.append(f"<p class='{b.kind}'>{inline(b.markdown)}</p>")
            elif isinstance(b, Table):
                body.append(html_table(b))
            else:
                data = base64.b64encode(b.images["svg" if "svg" in b.images else "png"]).decode()
                mime = "image/svg+xml" if "svg" in b.images else "image/png"
                body.append(f"<figure id='f-{b.name}'><img src='data:{mime};base64,{data}' "
                            f"alt='{html.escape(b.caption, quote=True)}'><figcaption>"
                            f"{inline(b.caption)}</figcaption></figure>")
        return page(self.title, self.source, "\n".join(body), self.nav, toc)


def _json(value: Any) -> Any:
    """Return ``value`` as strict JSON allows: nan and NA -> null, inf -> "inf"."""
    if value is pd.NA or value is pd.NaT:
        return None
    if isinstance(value, float) and not math.isfinite(value):
        return None if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """Return a GitHub Markdown table of already formatted cells."""
    def esc(text: str) -> str:
        return str(text).replace("|", "\\|").replace("\n", " ")

    lines = ["| " + " | ".join(map(esc, header)) + " |", "|" + "---|" * len(header)]
    return "\n".join(lines + ["| " + " | ".join(map(esc, r)) + " |" for r in rows])


def inline(markdown: str) -> str:
    """Return escaped HTML of a Markdown paragraph: **bold**, *italic*, `code` and line breaks."""
    import re

    text = html.escape(markdown)
    text = re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", text)
    text = re.sub(r"(?<![\w*])\*(?!\s)(.+?)(?<!\s)\*(?![\w*])", r"<i>\1</i>", text)
    text = re.sub(r"`(.+?)`", r"<code>\1</code>", text)
    return text.replace("\n- ", "<br>• ").replace("\n\n", "<br><br>")


def html_table(b: Table) -> str:
    """Return a styled HTML table; each header names the CSV columns it shows (data-cols)."""
    def td(text: str, href: str | None) -> str:
        inner = html.escape(text)
        return f"<td><a href='{html.escape(href, quote=True)}'>{inner}</a></td>" if href \
            else f"<td>{inner}</td>"

    head = "".join(f"<th data-cols='{' '.join(c.keys) if b.legacy is None else ''}'>"
                   f"{html.escape(c.label)}</th>" for c in b.cols)
    body = "".join("<tr>" + "".join(td(v, h) for v, h in zip(r, lk, strict=True)) + "</tr>"
                   for r, lk in zip(b.rows(), b.links(), strict=True))
    legacy = " data-legacy='1'" if b.legacy is not None else ""
    return (f"<div class='table' id='t-{b.name}'><table data-table='{b.name}'{legacy}><caption>"
            f"{inline(b.caption)} <span class='csv'>tables/{b.name}.csv</span></caption>"
            f"<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table></div>")


CSS = """
body{font:15px/1.5 system-ui,-apple-system,"Segoe UI",sans-serif;margin:0;color:#1d2327;
background:#fafafa}main{max-width:1180px;margin:0 auto;padding:0 24px 48px}
nav{position:sticky;top:0;background:#1f3a5f;color:#fff;padding:8px 24px;z-index:2;
font-size:14px}nav a{color:#fff;margin-right:14px;text-decoration:none}nav a:hover{
text-decoration:underline}nav .toc{opacity:.85}h1{font-size:26px;margin:18px 0 6px}
h2{font-size:19px;margin:34px 0 8px;border-bottom:1px solid #d5dbe1;padding-bottom:4px}
.source{padding:8px 24px;font-weight:600}.source-simulation{background:#e3edf7;color:#1f3a5f}
.source-virtual{background:#fff3cd;color:#7a4b00}.source-measured{background:#e3f4e6;
color:#1b5e20}dl.provenance{display:grid;grid-template-columns:max-content auto;gap:2px 14px;
font-size:13.5px;color:#444}dl.provenance dt{font-weight:600}dl.provenance dd{margin:0}
p.finding{font-size:16px;background:#fff;border-left:4px solid #1f5aa6;padding:10px 14px}
p.note{color:#8a4b00;font-style:italic}.table{overflow-x:auto;margin:14px 0}
table{border-collapse:collapse;background:#fff;font-size:13.5px}caption{text-align:left;
padding:6px 0;font-weight:600;caption-side:top}caption .csv{font-weight:400;color:#777;
font-family:monospace;font-size:12px}th,td{border:1px solid #d5dbe1;padding:4px 8px;
text-align:left;vertical-align:top}th{background:#eef2f6}tbody tr:nth-child(even){
background:#f6f8fa}figure{margin:18px 0;background:#fff;padding:10px;border:1px solid #e1e5ea}
figure img{max-width:100%;height:auto}figcaption{font-size:13.5px;color:#444;margin-top:6px}
footer{color:#666;font-size:13px;padding:12px 24px}code{background:#eef2f6;padding:0 3px}
"""


def page(title: str, source: str, body: str, nav: Sequence[tuple[str, str]] = (),
         toc: Sequence[tuple[str, str]] = ()) -> str:
    """Return a complete self-contained HTML page: navigation bar, data-source banner, body.

    ``nav`` and ``toc`` are (label, href) pairs: relative links to the other pages of the
    results tree and anchors of this page; nothing else is linked.
    """
    links = "".join(f"<a href='{html.escape(h, quote=True)}'>{html.escape(t)}</a>"
                    for t, h in nav)
    toc_html = ("<span class='toc'>" + "".join(
        f"<a href='{h}'>{html.escape(t)}</a>" for t, h in toc) + "</span>") if toc else ""
    banner = html.escape(SOURCE_LABEL.get(source, source) or "see each row")
    return ("<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'><meta name='viewport' "
            f"content='width=device-width,initial-scale=1'><title>{html.escape(title)}</title>"
            f"<style>{CSS}</style></head><body><nav>{links}{toc_html}</nav>"
            f"<div class='source source-{html.escape(source)}'>Data: {banner}</div><main>"
            f"<h1>{html.escape(title)}</h1>{body}</main><footer>Data: {banner}. Written by "
            "graspcampaign from the records only.</footer></body></html>\n")
