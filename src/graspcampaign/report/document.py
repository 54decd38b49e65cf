"""A study report being assembled: text, tables (Markdown + CSV) and figures (PNG)."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd


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


@dataclass
class Report:
    """Collects the parts of one run's report and writes them under ``<run>/report/``."""

    title: str
    out_dir: Path
    parts: list[str] = field(default_factory=list)
    tables: dict[str, pd.DataFrame] = field(default_factory=dict)

    def __post_init__(self):
        (self.out_dir / "tables").mkdir(parents=True, exist_ok=True)
        (self.out_dir / "figures").mkdir(parents=True, exist_ok=True)

    def text(self, markdown: str) -> None:
        self.parts.append(markdown.strip())

    def table(self, name: str, df: pd.DataFrame, caption: str) -> None:
        """Add a table: shown in Markdown and written to ``tables/<name>.csv``."""
        self.tables[name] = df
        df.to_csv(self.out_dir / "tables" / f"{name}.csv", index=False)
        self.parts.append(f"**{caption}** (`tables/{name}.csv`)\n\n{_md_table(df)}")

    def figure(self, name: str, fig, caption: str) -> None:
        """Add a matplotlib figure, saved as ``figures/<name>.png``."""
        import matplotlib.pyplot as plt

        path = self.out_dir / "figures" / f"{name}.png"
        fig.savefig(path, dpi=130, bbox_inches="tight")
        plt.close(fig)
        self.parts.append(f"![{caption}](figures/{name}.png)\n\n*{caption}*")

    def write(self, formats: list[str]) -> Path:
        md = f"# {self.title}\n\n" + "\n\n".join(self.parts) + "\n"
        path = self.out_dir / "report.md"
        path.write_text(md)
        if "json" in formats:
            data = {k: v.to_dict(orient="records") for k, v in self.tables.items()}
            (self.out_dir / "tables.json").write_text(json.dumps(data, indent=1, default=str))
        if "html" in formats:
            body = "".join(f"<h2>{k}</h2>{v.to_html(index=False)}" for k, v in self.tables.items())
            (self.out_dir / "report.html").write_text(
                f"<html><body><h1>{self.title}</h1>{body}</body></html>")
        return path
