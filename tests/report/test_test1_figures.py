"""Figs. 23 and 26 of ``test1_bench``: their legends lie clear of the bars, lines and the paper's marks.

The tables are synthetic, shaped as the golden reduced run's (a CV of 128 % for b under the top
centre, a held-out error of 7.8 % as the second bar of panel (c)); the figure is drawn on an Agg
canvas and each legend box is checked against the drawn bars and lines in screen pixels.
"""

from __future__ import annotations

import matplotlib as mpl
import pandas as pd
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Rectangle
from synthetic_runs import draw_all

from graspcampaign.report import style
from graspcampaign.report.render import Run
from graspcampaign.report.studies.test1 import fig26

TABLE5 = pd.DataFrame({
    "parameter_label": ["λ1", "λ2", "n", "b", "k", "c"],
    "cv_pct": [1.7, 72.5, 2.9, 128.4, 47.8, 71.6], "paper_cv_pct": [56.1, 41.5, 20.7, 47.2, 48.0, 61.9],
    "mean": [2.0, 0.84, 0.45, 0.74, 0.13, 0.0097], "sd": [0.03, 0.61, 0.01, 0.95, 0.06, 0.007],
    "paper_mean": [0.333, 0.953, 0.48, 0.68, 0.15, 0.0027], "paper_sd": [0.19, 0.4, 0.1, 0.33, 0.07, 0.0012],
    "paper_simulation": [0.332, 0.88, 0.487, 0.646, 0.138, 0.00247]})
TRANSFER = pd.DataFrame({
    "quantity": ["normal_force"] * 3 + ["friction"] * 4 + ["relaxation", "curved"],
    "split": ["train", "unseen_specimen", "unseen_speed", "train", "unseen_specimen", "unseen_speed",
              "unseen_load", "extended_relaxation", "flat_to_curved"],
    "mean_error_pct": [2.03, 7.81, 1.26, 0.15, 2.12, 0.09, 0.11, 0.44, 6.12],
    "paper_pct": [2.58, 2.58, 3.65, 1.0, 1.0, 1.0, 1.0, 3.1, 4.3]}).assign(
    quantity_label=lambda t: t["quantity"].str.replace("_", " "),
    split_label=lambda t: t["split"].str.replace("_", " "))


def test_no_legend_of_fig26_covers_a_bar_or_a_paper_mark():
    # (a)'s legend sat at the top centre over b's 128 % bar, (c)'s at the top left over the 7.8 %
    # held-out bar; (a) now has it below its axes as (b), (c) where matplotlib finds room
    run = Run(pd.DataFrame(), {}, None)
    run.tables.update(table5=TABLE5, transfer=TRANSFER)
    with mpl.rc_context(style.RC):
        fig = Figure(figsize=(13.0, 4.8), layout="constrained")
        FigureCanvasAgg(fig)
        fig26(run, fig)
        fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in (fig.axes[0], fig.axes[2]):
        box = ax.get_legend().get_window_extent(renderer)
        bars = [p.get_window_extent(renderer) for p in ax.patches if isinstance(p, Rectangle)]
        marks = [line.get_window_extent(renderer) for line in ax.get_lines() if isinstance(line, Line2D)]
        assert len(bars) == len(TABLE5 if ax is fig.axes[0] else TRANSFER)
        covered = [b for b in bars + marks if box.overlaps(b)]
        assert not covered, f"{ax.get_title('left')}: the legend covers {len(covered)} bars or marks"


@pytest.mark.parametrize("families", [["gel"], ["gel", "silicone_soft"]])
def test_fig24c_draws_a_family_line_only_beside_other_families(monkeypatch, families):
    # with one family its mean line lay hidden under "ours, all" (the same means), yet had a legend entry
    from types import SimpleNamespace

    from graspcampaign.report.studies import test1

    angles = [0.0, 15.0, 30.0, 45.0]
    oblique = pd.DataFrame([{"material": m, "angle_deg": a, "margin_n": 0.3 - 0.008 * a + 0.01 * i + 1e-3 * k}
                            for i, m in enumerate(families) for a in angles for k in range(3)])
    sliding = pd.DataFrame({"material": families, "mu_s": 0.8, "mu_k": 0.5})
    monkeypatch.setitem(test1.FRAMES, "oblique", lambda run: oblique)
    monkeypatch.setitem(test1.FRAMES, "sliding", lambda run: sliding)
    law = SimpleNamespace(mu_s=0.77, mu_k=0.54)
    run = Run(pd.DataFrame(), {}, SimpleNamespace(table4=dict.fromkeys(families, law),
                                                  oblique_margin_n={"0": 0.45, "30": 0.05, "45": -0.16}))
    run.memo("fitted", lambda: pd.DataFrame(columns=["block", "event_id", "material", "speed_mm_per_s",
                                                     "load_level"]))
    with mpl.rc_context(style.RC):
        fig = Figure(figsize=(13.0, 4.6), layout="constrained")
        FigureCanvasAgg(fig)
        test1.fig24(run, fig)
    entries = fig.axes[2].get_legend_handles_labels()[1]
    expected = [] if len(families) == 1 else ["gel", "silicone, soft"]
    assert entries[:len(expected)] == expected and entries[len(expected):] == ["paper (mean)",
                                                                             "ours, all: mean ± SD"]
    means = oblique.groupby("angle_deg")["margin_n"].mean()  # pandas: the line "ours, all" draws
    overall = fig.axes[2].containers[0].lines[0]
    assert list(overall.get_ydata()) == pytest.approx(means.tolist())


def test_no_line_of_fig23c_runs_through_its_legend(sim_root):
    """Fig. 23c's legend sat at the upper right, where the 5% review line ran through its last entry:
    no vertical line of the panel (our mean, the paper's, the review threshold) crosses the legend box."""
    fig = draw_all(sim_root, "test1_bench")["fig23_normal_law"]
    ax = next(a for a in fig.axes if a.get_title("left").startswith("(c)"))
    renderer = fig.canvas.get_renderer()
    box = ax.get_legend().get_window_extent(renderer)
    lines = [line.get_window_extent(renderer) for line in ax.get_lines()]
    assert len(lines) == 3
    assert not [b for b in lines if box.overlaps(b)]


def _lines_in_legend(ax) -> list[str]:
    """The label of each line of ``ax`` once per drawn point of it inside the legend box (screen
    pixels; the segments too: a vertical drop has its two ends outside the box and its middle inside)."""
    import numpy as np
    box = ax.get_legend().get_window_extent(ax.figure.canvas.get_renderer())
    inside = []
    for line in ax.get_lines():
        xy = np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float)
        xy = ax.transData.transform(xy[np.isfinite(xy).all(axis=1)])
        steps = np.linspace(0.0, 1.0, 21)[:, None, None]
        points = (xy[:-1] + steps * (xy[1:] - xy[:-1])).reshape(-1, 2)
        within = ((points >= [box.x0, box.y0]) & (points <= [box.x1, box.y1])).all(axis=1)
        inside += [line.get_label()] * int(within.sum())
    return inside


def test_no_trace_of_fig24b_runs_through_its_legend(sim_root):
    """Fig. 24b's legend sat at the lower right, where the slide's tangential force drops back to zero at
    the end of the stroke: the drop ran through "virtual-rig ft (normal-lab)". No drawn point of any line
    of the panel lies inside the legend box (screen pixels)."""
    fig = draw_all(sim_root, "test1_bench")["fig24_tangential"]
    ax = next(a for a in fig.axes if a.get_title("left").startswith("(b)"))
    inside = _lines_in_legend(ax)
    assert len(ax.get_lines()) == 3 and not inside, set(inside)


def test_no_curve_of_fig23a_runs_through_its_legend(sim_root):
    """Fig. 23a's legend sat at the upper left, where the paper's Table 4 law, rising above our trace,
    ran through the box's right end beside "(RMSE 0.7%)" (the paper-scale run and the reduced one
    alike): no drawn point of the loading, unloading, fit or paper curve lies inside the legend box."""
    fig = draw_all(sim_root, "test1_bench")["fig23_normal_law"]
    ax = next(a for a in fig.axes if a.get_title("left").startswith("(a)"))
    inside = _lines_in_legend(ax)
    assert len(ax.get_lines()) == 4 and not inside, set(inside)


def test_fig23b_draws_each_violin_in_its_family_colour_and_names_its_lines(sim_root):
    """Fig. 23b's violins drew their median and min–max bars in matplotlib's first cycle colour (a blue
    no vocabulary gives), with caps a reader takes for the 95 % whiskers of every other figure, and no
    legend entry: each violin's lines take its family's colour, and the legend names them."""
    from graspcampaign.analysis.vocabulary import VOCABULARIES, colour, label

    fig = draw_all(sim_root, "test1_bench")["fig23_normal_law"]
    ax = next(a for a in fig.axes if a.get_title("left").startswith("(b)"))
    table = {label("material", v): mpl.colors.to_hex(colour("material", v)) for v in VOCABULARIES["material"]}
    families = [table[lab.get_text()] for lab in ax.get_xticklabels()]
    assert families
    bars = [c for c in ax.collections if type(c).__name__ == "LineCollection"
            and {mpl.colors.to_hex(rgba) for rgba in c.get_colors()} != {"#000000"}]  # not the paper's marks
    assert len(bars) == 4  # range bar, min and max caps, median
    for c in bars:
        assert [mpl.colors.to_hex(rgba) for rgba in c.get_colors()] == families
    assert "ours: median, min–max" in [t.get_text() for t in ax.get_legend().get_texts()]
