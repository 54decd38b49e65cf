"""Fig. 26 of ``test1_bench``: its legends lie clear of the bars and the paper's marks.

The tables are synthetic, shaped as the golden reduced run's (a CV of 128 % for b under the top
centre, a held-out error of 7.8 % as the second bar of panel (c)); the figure is drawn on an Agg
canvas and each legend box is checked against the drawn bars and lines in screen pixels.
"""

from __future__ import annotations

import matplotlib as mpl
import pandas as pd
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Rectangle

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
