"""A study report being assembled: text, tables (Markdown/HTML + CSV/JSON) and figures (PNG)."""

from __future__ import annotations

import html
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from graspcampaign.errors import UserInputError

#: Output formats of ``graspcampaign report --format``; PNG figures are always written.
FORMATS = ("md", "csv", "json", "html")


def check_formats(formats: list[str] | str | None) -> list[str]:
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


def _md_table(df: pd.DataFrame) -> str:
    """Render a DataFrame as a GitHub Markdown table (no extra dependency)."""
    def cell(v: Any) -> str:
        if isinstance(v, float):
            return "" if pd.isna(v) else f"{v:.4g}"
        return "" if v is None else str(v).replace("|", "\\|")

    head = "| " + " | ".join(map(str, df.columns)) + " |"
    rule = "|" + "|".join("---" for _ in df.columns) + "|"
    rows = ["| " + " | ".join(cell(v) for v in row) + " |" for row in df.itertuples(index=False)]
    return "\n".join([head, rule, *rows])


def _json_value(value: Any) -> Any:
    """Return ``value`` as strict JSON allows: nan and NA -> null, inf -> "inf"."""
    if value is pd.NA or value is pd.NaT:
        return None
    if isinstance(value, float) and not math.isfinite(value):
        return None if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


@dataclass
class Report:
    """Collects the parts of one run's report and writes them under ``<run>/report/``.

    A table is kept twice: at full precision (``tables/<name>.csv`` and ``tables.json``, what a
    notebook or a test checks) and, optionally, as displayed (rounded once, in Markdown/HTML).
    """

    title: str
    out_dir: Path
    parts: list[tuple[str, ...]] = field(default_factory=list)
    tables: dict[str, pd.DataFrame] = field(default_factory=dict)
    displays: dict[str, pd.DataFrame] = field(default_factory=dict)

    def __post_init__(self):
        (self.out_dir / "figures").mkdir(parents=True, exist_ok=True)

    def text(self, markdown: str) -> None:
        self.parts.append(("text", markdown.strip()))

    def table(self, name: str, df: pd.DataFrame, caption: str,
              display: pd.DataFrame | None = None) -> None:
        """Add a table: ``df`` goes to CSV/JSON, ``display`` (default ``df``) to Markdown/HTML."""
        self.tables[name] = df
        self.displays[name] = df if display is None else display
        self.parts.append(("table", name, caption))

    def figure(self, name: str, fig, caption: str) -> None:
        """Add a matplotlib figure, saved now as ``figures/<name>.png``."""
        path = self.out_dir / "figures" / f"{name}.png"
        fig.savefig(path, dpi=130, bbox_inches="tight")
        if getattr(fig.canvas, "manager", None) is not None:  # a pyplot figure: release it
            import matplotlib.pyplot as plt

            plt.close(fig)
        self.parts.append(("figure", name, caption))

    def markdown(self) -> str:
        out = [f"# {self.title}"]
        for kind, *rest in self.parts:
            if kind == "text":
                out.append(rest[0])
            elif kind == "table":
                name, caption = rest
                out.append(f"**{caption}** (`tables/{name}.csv`)\n\n{_md_table(self.displays[name])}")
            else:
                name, caption = rest
                out.append(f"![{caption}](figures/{name}.png)\n\n*{caption}*")
        return "\n\n".join(out) + "\n"

    def html(self) -> str:
        body = [f"<h1>{html.escape(self.title)}</h1>"]
        for kind, *rest in self.parts:
            if kind == "text":
                body.append(f"<div style='white-space:pre-wrap'>{html.escape(rest[0])}</div>")
            elif kind == "table":
                name, caption = rest
                body.append(f"<p><b>{html.escape(caption)}</b> (<code>tables/{name}.csv</code>)</p>"
                            + self.displays[name].to_html(index=False, na_rep=""))
            else:
                name, caption = rest
                body.append(f"<figure><img src='figures/{name}.png' alt='{html.escape(caption)}'>"
                            f"<figcaption>{html.escape(caption)}</figcaption></figure>")
        return ("<!DOCTYPE html><html><head><meta charset='utf-8'>"
                f"<title>{html.escape(self.title)}</title></head><body>"
                + "\n".join(body) + "</body></html>\n")

    def write(self, formats: list[str] | None = None) -> Path:
        """Write the requested formats; return the main document's path (md, else html/json)."""
        formats = check_formats(formats)
        written: dict[str, Path] = {}
        if "csv" in formats:
            (self.out_dir / "tables").mkdir(parents=True, exist_ok=True)
            for name, df in self.tables.items():
                df.to_csv(self.out_dir / "tables" / f"{name}.csv", index=False)
            written["csv"] = self.out_dir / "tables"
        if "json" in formats:
            data = {k: [{c: _json_value(x) for c, x in row.items()}
                        for row in v.to_dict(orient="records")] for k, v in self.tables.items()}
            path = self.out_dir / "tables.json"
            path.write_text(json.dumps(data, indent=1, default=str, allow_nan=False))
            written["json"] = path
        if "html" in formats:
            path = self.out_dir / "report.html"
            path.write_text(self.html())
            written["html"] = path
        if "md" in formats:
            path = self.out_dir / "report.md"
            path.write_text(self.markdown())
            written["md"] = path
        for key in ("md", "html", "json", "csv"):
            if key in written:
                return written[key]
        raise AssertionError("check_formats returned no format")
