"""The one figure style: rcParams, the data-source label, the paper's marks, rate bars, panels, parity,
confusion matrices, one trial's schematic; the HTML page's style sheet."""

from __future__ import annotations

import io
import math
import re
from collections.abc import Callable, Sequence

import matplotlib as mpl
import numpy as np
import pandas as pd
from cycler import cycler
from matplotlib import patheffects
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.ticker import Formatter, FuncFormatter, LogLocator, NullFormatter, SymmetricalLogLocator
from matplotlib.transforms import ScaledTranslation

from graspcampaign.analysis.vocabulary import OTHER_COLOURS, colour, label
from graspcampaign.report import format as fmt

RC = {
    "font.size": 9, "axes.titlesize": 9.5, "axes.titlelocation": "left", "axes.labelsize": 9,
    "legend.fontsize": 7.5, "xtick.labelsize": 8, "ytick.labelsize": 8, "axes.grid": True,
    "grid.alpha": 0.3, "grid.linewidth": 0.6, "axes.spines.top": False,
    "axes.spines.right": False, "legend.frameon": False, "lines.linewidth": 1.5,
    "errorbar.capsize": 3, "figure.dpi": 100, "savefig.dpi": 130, "image.cmap": "viridis",
    "svg.hashsalt": "graspcampaign", "svg.fonttype": "none", "font.family": "DejaVu Sans",
    # a line drawn without a colour of its own takes the levels' ramp, never matplotlib's tab10, whose
    # C0 blue read as the proposed planner's (Figs. 12-13's μ × m cases, drawn in C0, C1, ...); the
    # ramp's steps alternate dark and light, as adjacent steps are hard to tell apart
    "axes.prop_cycle": cycler(color=[OTHER_COLOURS[i] for i in (0, 3, 1, 4, 2, 5)]),
}
"""The report's rcParams (every figure of every study)."""
PAPER = "black"
"""Colour of the paper's values in every figure."""
CRITERION = "#555555"
"""Colour of a criterion or reference line of ours (0.5 N, the slip boundary)."""
SOURCE_SHORT = {"simulation": "simulation", "virtual": "VIRTUAL RIG (synthetic data)",
                "measured": "measured on hardware"}
SOURCE_COLOUR = {"simulation": "#1f3a5f", "virtual": "#b35900", "measured": "#1b5e20"}
FINGER_LINES = ((1, "-", 3.2), (2, "--", 2.2), (3, "-.", 1.4))
"""A finger's line style and width in every per-finger force plot (Figs. 13 and 30): each drawn thinner
over the one before, so fingers with equal or near-equal forces all stay visible."""


def save(fig: Figure, source: str, formats: Sequence[str] = ("png",)) -> dict[str, bytes]:
    """Label ``fig`` with its data source; return its PNG and each of ``formats`` (SVG and PDF
    without a creation date, so they are reproducible)."""
    if getattr(fig, "_suptitle", None) is None:
        fig.suptitle(f"data: {SOURCE_SHORT.get(source, source)}", x=0.995, ha="right",
                     fontsize=7.5, color=SOURCE_COLOUR.get(source, "#333333"))
    out = {}
    for f in dict.fromkeys(("png", *formats)):
        buf = io.BytesIO()
        fig.savefig(buf, format=f, dpi=RC["savefig.dpi"], bbox_inches="tight", metadata=(
            {"Software": "graspcampaign"} if f == "png" else {"Date": None, "Creator": "graspcampaign"}))
        out[f] = buf.getvalue()
    return out


def draw(build: Callable[[Figure], None], size: tuple[float, float], source: str,
         formats: Sequence[str] = ("png",)) -> dict[str, bytes]:
    """Build a figure of ``size`` inches with ``build(fig)`` under :data:`RC`; return its images."""
    with mpl.rc_context(RC):
        fig = Figure(figsize=size, layout="constrained")
        build(fig)
        return save(fig, source, formats)


def level_colours(n: int) -> list[str]:
    """Colours of ``n`` ordered levels outside every vocabulary (μ, node counts), dark to light: the
    ramp ``OTHER_COLOURS`` spread over its whole length, since its adjacent steps are hard to tell
    apart as lines; more levels than the ramp holds cycle it."""
    steps = np.linspace(0, len(OTHER_COLOURS) - 1, n).round() if n <= len(OTHER_COLOURS) else range(n)
    return [OTHER_COLOURS[int(i) % len(OTHER_COLOURS)] for i in steps]


COUNTS = mpl.colors.LinearSegmentedColormap.from_list("counts", ["#ffffff", *OTHER_COLOURS[::-1]])
"""Colour scale of a count (a confusion matrix's cells), white at 0 to the levels' ramp's darkest: a
count is a level outside every vocabulary; matplotlib's ``Blues`` read as the proposed planner's
family beside its bars (Figs. 31c, 36c)."""
POOLED, POOLED_FILL = OTHER_COLOURS[1], OTHER_COLOURS[4]
"""Colours of data pooled over every planner (Fig. 29: points and lines, histogram bars): a dark and a
light step of the levels' ramp, no planner's colour; drawn in the proposed planner's blue, the pooled
trials read as the proposed planner's alone."""


def ink(fill) -> str:
    """Black or white, whichever contrasts more with ``fill`` (a cell's colour): the text on a heatmap
    cell (W3C WCAG 2.1 contrast ratio, (L1 + 0.05)/(L2 + 0.05) of relative luminances; black text on
    viridis' dark end read at 1.6:1)."""
    rgb = np.asarray(mpl.colors.to_rgb(fill))
    lum = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4) @ [0.2126, 0.7152, 0.0722]
    return "black" if (lum + 0.05) / 0.05 >= 1.05 / (lum + 0.05) else "white"


def paper_handle(label: str = "paper's value") -> Line2D:
    """Legend entry of the paper's marks."""
    return Line2D([], [], color=PAPER, marker="D", markersize=5, markerfacecolor="none", linewidth=1.2,
                  label=label)


def interval_handle(label: str = "95% interval") -> Line2D:
    """Legend entry of our error bars."""
    return Line2D([], [], color="#333333", marker="|", linestyle="none", markersize=8, label=label)


HALO = [patheffects.withStroke(linewidth=3.2, foreground="white")]
"""A white outline under the paper's black marks: black on white has the highest contrast of any pair
(WCAG 2.1: 21:1), so the mark reads over every bar colour, the darkest planner's blue as the lightest."""


def paper_marks(ax, x: Sequence[float], values: Sequence, width: float) -> bool:
    """Draw the paper's values as black lines with a hollow diamond on them, over our bars and
    whiskers, each outlined in white (:data:`HALO`): drawn behind a bar, a paper value inside it (the
    centroid planner's 44.9 % in Fig. 31a) showed only its diamond. A paper 0 lies on the bars' base: its
    line stays behind them, where a line over a near-zero bar of ours (1 % on a paper 0 %, Fig. 18)
    hid it. Return whether any was drawn."""
    shown = [(xi, float(p)) for xi, p in zip(x, values, strict=True) if not fmt.is_missing(p)]
    for xi, p in shown:
        ax.hlines(p, xi - width * 0.45, xi + width * 0.45, colors=PAPER, linewidth=1.2,
                  **({"zorder": 5, "path_effects": HALO} if p else {"zorder": 0.9}))
        ax.plot([xi], [p], marker="D", color=PAPER, markerfacecolor="none", markersize=5, zorder=6,
                path_effects=HALO)
    return bool(shown)


def bars(ax, x: Sequence[float], values, low, high, colours, width: float = 0.7,
         paper: Sequence | None = None, label: str | None = None) -> bool:
    """Bars with interval whiskers (none for a missing value or bound; ``low``, ``high`` None: none)
    and, optionally, the paper's marks; return whether a paper mark was drawn."""
    x, v = np.asarray(x, dtype=float), np.asarray(values, dtype=float)
    lo, hi = (np.full_like(v, np.nan) if a is None else np.asarray(a, dtype=float) for a in (low, high))
    ax.bar(x, np.nan_to_num(v), width, color=colours, edgecolor="white", label=label)
    shown = np.isfinite(v) & np.isfinite(lo) & np.isfinite(hi)  # a missing value: no mark at 0
    ax.errorbar(x[shown], v[shown], yerr=np.vstack([v - lo, hi - v])[:, shown], fmt="none",
                ecolor="#333333", elinewidth=1.0)
    return paper_marks(ax, x, list(paper), width) if paper is not None else False


def rate_axes(ax, ylabel: str = "success rate [%]") -> None:
    """Axis of a rate in percent, 0-100 with room for the whiskers."""
    ax.set(ylim=(0, 105), ylabel=ylabel)


def legend_below(ax, handles=None, ncol: int = 3) -> None:
    """A legend under the axes (never over the data), below their tick labels and x label: placed in
    points from the axes' edge, as the labels are (a fraction of the axes' height put it over the
    three-line "Ferrari–/Canny ε/n=675" ticks of Fig. 18's shorter axes)."""
    ticks = ax.get_xticklabels()  # the text set_xticks gave; '' until drawn otherwise, one line
    lines = max([t.get_text().count("\n") + 1 for t in ticks], default=1)
    size = max([t.get_fontsize() for t in ticks], default=mpl.rcParams["font.size"])
    xlabel = ax.xaxis.label
    below = (mpl.rcParams["xtick.major.size"] + mpl.rcParams["xtick.major.pad"] + 1.2 * lines * size
             + (ax.xaxis.labelpad + 1.2 * xlabel.get_fontsize() if xlabel.get_text() else 0.0))
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=ncol,
              bbox_transform=ax.transAxes + ScaledTranslation(0.0, -below / 72, ax.figure.dpi_scale_trans))


class OneTwoFive(LogLocator):
    """Log ticks at 1, 2 and 5 of each decade, or at every whole multiple (0.6, 0.7, 0.8) and 1.5 where
    fewer than three of those fall in view, so a narrow axis still reads (1.5: the widest step, 1 to 2,
    otherwise leaves an axis ending below 2 unlabelled from 1 up)."""

    def __init__(self) -> None:
        super().__init__(subs=(1.0, 2.0, 5.0))

    def tick_values(self, vmin, vmax):
        ticks, (lo, hi) = super().tick_values(vmin, vmax), sorted((vmin, vmax))
        if np.count_nonzero((ticks >= lo) & (ticks <= hi)) >= 3:
            return ticks
        return LogLocator(subs=np.r_[1.0, 1.5, 2.0:10.0]).tick_values(vmin, vmax)


class Uncrowded(Formatter):
    """Plain numbers ("356", "0.6") at given ticks, a label left blank where it would run into the one
    labelled before it (its tick mark stays): a run's levels can sit closer than a label's width on a
    log axis (Fig. 20's 356 and 390 nodes, 0.04 decades apart, printed as "356390")."""

    def __call__(self, x, pos=None) -> str:
        return fmt.number(x)

    def format_ticks(self, values) -> list[str]:
        labels, axis = [fmt.number(v) for v in values], self.axis
        if axis is None or not len(values):
            return labels
        along = 1 if axis.axis_name == "y" else 0
        at = axis.axes.transData.transform(np.c_[values, values])[:, along]  # display px
        size = mpl.font_manager.FontProperties(size=mpl.rcParams[f"{axis.axis_name}tick.labelsize"])
        em = size.get_size_in_points() * axis.figure.dpi / 72
        # half a label across (digits are 0.64 em wide in DejaVu Sans) or up, and half an em apart (a
        # word space is 0.32 em: closer, two labels read as one number)
        half = [(0.5 if along else 0.32 * len(t)) * em for t in labels]
        last = None
        for i in np.argsort(at):
            if last is not None and abs(at[i] - at[last]) < half[i] + half[last] + 0.5 * em:
                labels[i] = ""
            else:
                last = i
        return labels


def plain_log(axis, at: Sequence[float] | None = None) -> None:
    """Label a log ``axis`` (an ``Axis``, a colorbar's too) in plain numbers, "0.6" and "20", never
    "6×10⁻¹": at the values ``at`` (the levels a run used, labels that would touch thinned by
    :class:`Uncrowded`) or at :class:`OneTwoFive`; no minor labels (matplotlib labels minor ticks as
    a×10ᵇ where an axis spans less than a decade)."""
    if at is None:
        axis.set_major_locator(OneTwoFive())
        axis.set_major_formatter(FuncFormatter(lambda v, _: fmt.number(v)))
    else:
        axis.set_ticks(list(at))
        axis.set_major_formatter(Uncrowded())
    axis.set_minor_formatter(NullFormatter())


def tick(text: str, width: int = 9) -> str:
    """A tick label wrapped at ``width`` characters, a longer word broken after its dash
    ("Ferrari–Canny ε" -> "Ferrari–" / "Canny ε"), so neighbouring labels never overlap."""
    lines: list[str] = []
    for word in text.replace("_", " ").split():
        parts = re.split(r"(?<=[–-])(?=\w)", word) if len(word) > width else [word]
        for i, part in enumerate(parts):
            glue = "" if i else " "
            if lines and len(lines[-1]) + len(glue) + len(part) <= width:
                lines[-1] += glue + part
            else:
                lines.append(part)
    return "\n".join(lines)


def n_text(n: Sequence[int]) -> str:
    """The trials behind a group's rates, "n=50", or "n=40–50" where its bars' (or budgets') differ."""
    n = [int(k) for k in n]
    return f"n={min(n)}" + (f"–{max(n)}" if max(n) > min(n) else "")


def tick_n(text: str, n: Sequence[int]) -> str:
    """A group's :func:`tick` label over :func:`n_text` of ``n``; the label alone without ``n``."""
    return tick(text) + (f"\n{n_text(n)}" if len(n) else "")


def rate_bars(ax, f: pd.DataFrame, key: str, title: str, ylabel: str = "success rate [%]") -> None:
    """Rates [%] of ``f`` per ``key`` (its vocabulary) with Wilson whiskers, the paper's in black."""
    f = f.rename(columns=lambda c: c.replace("rate_pct", "success_pct").replace("wilson", "success")
                 .replace("paper_pct", "paper_success_pct"))
    x = np.arange(len(f))
    marked = bars(ax, x, f["success_pct"], f["success_low_pct"], f["success_high_pct"],
                  [colour(key, k, i) for i, k in enumerate(f[key])], paper=list(f["paper_success_pct"]))
    ax.set_xticks(x, [f"{tick(label(key, k))}\nn={n}"
                      for k, n in zip(f[key], f["n"], strict=True)], fontsize=7)
    rate_axes(ax, ylabel)
    ax.set_title(title)
    # below the axes: inside, over rates up to 100 %, it covered bars and the paper's marks
    legend_below(ax, [interval_handle(), *[paper_handle()] * marked], ncol=2)


def grouped_bars(ax, t: pd.DataFrame, x: str, hue: str | None = None,
                 rate: tuple[str, str, str] = ("rate_pct", "wilson_low_pct", "wilson_high_pct")) -> None:
    """Rates (the ``rate`` columns: value, Wilson low, high) per ``x`` (and ``hue``) level with their
    whiskers, the paper's marks (``paper_pct``, if any) and each level's trials (``n``, if any)."""
    xs, hues = list(dict.fromkeys(t[x])), list(dict.fromkeys(t[hue])) if hue else [None]
    width, marked = 0.8 / len(hues), False
    for i, h in enumerate(hues):
        sub = (t[t[hue] == h] if hue else t).set_index(x).reindex(xs)
        marked |= bars(
            ax, np.arange(len(xs)) + (i - (len(hues) - 1) / 2) * width, *(sub[c] for c in rate),
            colour(hue, h, i) if hue else [colour(x, v, j) for j, v in enumerate(xs)], width,
            sub["paper_pct"].tolist() if "paper_pct" in sub else None, label(hue, h) if hue else None)
    ax.set_xticks(np.arange(len(xs)), [tick_n(label(x, v), t.loc[t[x] == v, "n"] if "n" in t else ())
                                       for v in xs])
    rate_axes(ax)
    handles = [*ax.get_legend_handles_labels()[0], interval_handle("ours, Wilson 95%"),
               *([paper_handle()] if marked else [])]
    legend_below(ax, handles, ncol=min(len(handles), 5))


def two_per_row(fig, n: int) -> list:
    """``n`` axes two to a row, an odd last one centred under them: three in one row were ~4-5 in wide
    each, their text 7.6-9.5 px at the HTML page's width (docs/decisions.md, *Figure text legible at the
    page's width*)."""
    grid = fig.add_gridspec(math.ceil(n / 2), 4)
    first = [1 if i == n - 1 and n % 2 else 2 * (i % 2) for i in range(n)]  # of the axes' two columns
    return [fig.add_subplot(grid[i // 2, c:c + 2]) for i, c in enumerate(first)]


def panels(*specs):
    """A figure with a panel per spec: ``(table, query, key, title[, ylabel])``, :func:`rate_bars` of a
    table the run has rendered, or ``draw(run, ax)``; the specs stay readable as ``draw.specs``."""
    def draw(run, fig) -> None:
        for ax, s in zip(two_per_row(fig, len(specs)), specs, strict=True):
            if callable(s):
                s(run, ax)
            else:
                rate_bars(ax, run.tables[s[0]].query(s[1] or "index == index"), *s[2:])
    draw.specs = specs
    return draw


def parity(ax, x, y, lines, xlabel: str, title: str, observed: str, points: str) -> None:
    """Parity panel: ``y`` (``observed``: "measured" or "virtual-rig") against ``x``, the predicted,
    drawn in ``points`` (a planner's colour, or :data:`POOLED` for trials of every planner), with the
    identity and lines ``(intercept, slope, label, style)``."""
    ax.scatter(x, y, s=7, alpha=0.5, color=points, label=f"ours, n={len(x)}", rasterized=True)
    grid = np.array([0.0, np.nanmax(np.r_[1.0, np.asarray(x, float), np.asarray(y, float)])])
    for a, b, what, kw in [(0.0, 1.0, "identity", {"ls": ":", "color": "#777777"}), *lines]:
        ax.plot(grid, (a or 0.0) + (np.nan if b is None else b) * grid, label=what, **kw)
    ax.set(xlabel=f"predicted {xlabel}", ylabel=f"{observed} {xlabel}", title=title)
    ax.legend(loc="upper left")


def confusion(ax, cells, rows: Sequence[str], columns: Sequence[str], xlabel: str, ylabel: str) -> None:
    """A confusion matrix: the counts ``cells`` (``rows`` × ``columns``) shaded on :data:`COUNTS` from 0
    to the largest, each printed in its cell's :func:`ink`."""
    cells = np.asarray(cells, dtype=int)
    image = ax.imshow(cells, cmap=COUNTS, vmin=0, vmax=max(1, cells.max()))
    for (i, j), v in np.ndenumerate(cells):
        ax.text(j, i, str(v), ha="center", va="center", color=ink(image.to_rgba(v)))
    ax.set(xticks=range(len(columns)), xticklabels=columns, yticks=range(len(rows)), yticklabels=rows,
           xlabel=xlabel, ylabel=ylabel)
    ax.grid(False)


def schematic(fig, t: pd.Series, spans, top, bottom, title: str) -> None:
    """Fig. 30/35: one recorded trial over its commanded phases ``(start, end, name, colour)``, lines
    ``(x, y, label, style)`` on ``top``/``bottom`` (x None: the band y); no time series is recorded."""
    axes = fig.subplots(2, 1, sharex=True)
    for ax, lines in zip(axes, (top, bottom), strict=True):
        for a, b, what, c in spans:
            ax.axvspan(a, b, color=c, zorder=0, label=what if ax is axes[0] else None)
        for x, y, what, kw in lines:
            ax.axhspan(*y, label=what, **kw) if x is None else ax.plot(x, y, label=what, **kw)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[0].set_title(f"{t['rig_trial_id']}: {title}")
    axes[1].set_yscale("symlog", linthresh=1.0)  # millimetres of slip beside tens of lift: 1-2-5 ticks
    axes[1].yaxis.set_major_locator(SymmetricalLogLocator(base=10, linthresh=1.0, subs=(1.0, 2.0, 5.0)))
    axes[1].yaxis.set_major_formatter(FuncFormatter(lambda v, _: fmt.number(v)))


#: The HTML page's style sheet, self-contained (no font or file fetched). Text colours meet WCAG 2.1's
#: 4.5:1 against their backgrounds (tests/report/test_html.py); wide tables (``.wide``) are set compact,
#: long ones (``.long``) scroll in a box under their header row;
#: in print (landscape: at A4 portrait's 718 px, 12 of test2_grasp's 15 tables ran past the edge, in
#: landscape only Table 9's 21 columns do) the navigation and zoom control go, nothing is cut in two.
CSS = """
body{font:15px/1.5 system-ui,-apple-system,"Segoe UI",sans-serif;margin:0;color:#1d2327;background:#fafafa}
main{max-width:1180px;margin:0 auto;padding:0 24px 48px}nav{position:sticky;top:0;background:#1f3a5f;
color:#fff;padding:8px 24px;z-index:2;font-size:14px}nav a{color:#fff;margin-right:14px;text-decoration:none}
nav a:hover{text-decoration:underline}nav .toc{opacity:.85}h1{font-size:26px;margin:18px 0 6px}
h2{font-size:19px;margin:34px 0 8px;border-bottom:1px solid #d5dbe1;padding-bottom:4px}
.source{padding:8px 24px;font-weight:600}.source-simulation{background:#e3edf7;color:#1f3a5f}
.source-virtual{background:#fff3cd;color:#7a4b00}.source-measured{background:#e3f4e6;color:#1b5e20}
.source-mixed{background:#eef2f6;color:#1d2327}
dl.provenance{display:grid;grid-template-columns:max-content auto;gap:2px 14px;font-size:13.5px;color:#444}
dl.provenance dt{font-weight:600}dl.provenance dd{margin:0}p.finding{font-size:16px;background:#fff;
border-left:4px solid #1f3a5f;padding:10px 14px}p.note{color:#8a4b00;font-style:italic}
.table{overflow-x:auto;margin:14px 0}table{border-collapse:collapse;background:#fff;font-size:13.5px}
p.caption{margin:0;padding:6px 0;font-weight:600;font-size:14px}p.caption .csv{font-weight:400;
color:#666;font-family:monospace;font-size:12px}th,td{border:1px solid #d5dbe1;padding:4px 8px;
text-align:left;vertical-align:top}th{background:#eef2f6}tbody tr:nth-child(even){background:#f6f8fa}
th:first-child,td:first-child,.table p.caption{position:sticky;left:0;z-index:1}
th:first-child,td:first-child{box-shadow:1px 0 0 #d5dbe1}
td:first-child{background:#fff}tbody tr:nth-child(even) td:first-child{background:#f6f8fa}
figure{margin:18px 0;background:#fff;padding:10px;border:1px solid #e1e5ea;overflow-x:auto}figure img{
max-width:100%;height:auto;cursor:zoom-in}.zoom:checked+label img{max-width:none;cursor:zoom-out}
.zoom{position:absolute;opacity:0;width:1px;height:1px}
.zoom:focus-visible+label img{outline:3px solid #1f3a5f;outline-offset:2px}
figcaption{font-size:13.5px;color:#444;margin-top:6px}footer{color:#666;font-size:13px;
padding:12px 24px}code{background:#eef2f6;padding:0 3px}.nb{white-space:nowrap}
td.num{text-align:right;font-variant-numeric:tabular-nums}th[data-cols=verdict]{min-width:10em}
.wide table{font-size:12.5px}.wide th,.wide td{padding:3px 5px}.long{max-height:90vh;overflow:auto}
.long thead th{position:sticky;top:0;z-index:2;box-shadow:0 1px 0 #d5dbe1}
.long thead th:first-child{z-index:3}
.contents{background:#fff;border:1px solid #e1e5ea;padding:8px 14px;margin:14px 0;font-size:13.5px}
.contents ul{columns:2 26em;margin:4px 0 0;padding:0;list-style:none}.contents li{break-inside:avoid}
.contents a{color:#1f5aa6;text-decoration:none}.contents a:hover{text-decoration:underline}
[id]{scroll-margin-top:48px}
@page{size:landscape;margin:12mm}@media print{body{background:#fff;font-size:11pt}.long{max-height:none}
.long thead th{position:static}nav,.zoom{display:none}main{max-width:none;padding:0}
.source{border:1px solid #999}.table,figure{overflow:visible}figure,tr,.contents li{break-inside:avoid}
th:first-child,td:first-child,.table p.caption{position:static;box-shadow:none}
thead{display:table-header-group}h2,p.caption{break-after:avoid}
figure img,.zoom:checked+label img{max-width:100%}.wide table{font-size:8pt}}
"""
