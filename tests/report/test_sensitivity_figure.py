"""Fig. 19 of the sensitivity report drawn from synthetic panels: category axes, legible cell text and
the paper's boundaries on cell edges."""

from __future__ import annotations

from types import SimpleNamespace

import matplotlib as mpl
import numpy as np
import pandas as pd
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from graspcampaign.report import style
from graspcampaign.report.document import Figure as ReportFigure
from graspcampaign.report.render import Run
from graspcampaign.report.studies.sensitivity import PANELS, SPEC, _figure, _panels, _supplement

PAPER = SimpleNamespace(stable_mu_min=0.2, stable_mass_max_kg=0.5, lambda1_stable_below=0.35,
                        nonconvergence_strip_lambda1_from=0.9)

FIG19 = next(i for i in SPEC.items if getattr(i, "name", None) == "fig19_sensitivity")


def _fig19(rows: list[dict]) -> Figure:
    """Fig. 19 of trials ``rows`` at the report's size, over table sensitivity_panels as the report
    computes it first (the |R_z| reading: the ‖R‖ one where the rows have none)."""
    frame = pd.DataFrame(rows)
    if "success_vertical" not in frame:
        frame["success_vertical"] = frame["success"]
    run = Run(frame, {}, PAPER)
    run.tables["sensitivity_panels"] = _panels(run)
    fig = Figure(figsize=FIG19.size, layout="constrained")
    _figure(run, fig)
    return fig


@pytest.mark.parametrize("levels", [2, 12, 40])
def test_fig19_draws_one_cell_per_level_with_legible_or_no_cell_text(levels):
    """Category axes (the tick labels are the swept levels, no axis beyond them), cell text ≥ 7 pt
    or none at all."""
    grid = np.linspace(0.1, 0.8, levels)
    rows = [{"panel": panel, "status": "ok", x: a, y: b, "success": a < 0.4, "runtime_ms": 1.0 + a,
             "delta_max_mm": 1.0, "loop_capped": False}
            for panel, (x, y, *_) in PANELS.items() for a in grid for b in grid]
    fig = _fig19(rows)
    fig.canvas.draw()
    heatmaps = [ax for ax in fig.axes if ax.get_xlabel()]
    assert len(heatmaps) == 3
    for ax in heatmaps:
        assert ax.get_xlim() == (-0.5, levels - 0.5) and ax.get_ylim() == (-0.5, levels - 0.5)
        labels = [float(t.get_text()) for t in ax.get_xticklabels()]
        assert 2 <= len(labels) <= 7 and labels[0] == pytest.approx(grid[0])
        assert all(np.isclose(grid, label, rtol=5e-3).any() for label in labels)  # each one a level
        sizes = [t.get_fontsize() for t in ax.texts]
        assert len(sizes) in (0, levels ** 2) and all(size >= 7 for size in sizes)
    assert any(ax.texts for ax in heatmaps) == (levels <= 12)


def test_fig19_paper_boundaries_run_between_cells_on_the_side_the_claims_count_them():
    """At the paper-scale grids (12 levels each) every cell lies wholly on one side of each paper
    boundary, the side the claims table counts it on (μ ≥ 0.2 and m ≤ 0.5 inside; λ1 ≤ 0.35 below;
    λ1 ≥ 0.9 in the strip); a line through a cell hid which side the μ = 0.2 column was on."""
    grids = {"mu": np.linspace(0.05, 0.6, 12), "mass_kg": np.linspace(0.1, 0.8, 12),
             "lambda1": np.linspace(0.1, 1.5, 12)}
    rows = [{"panel": panel, "status": "ok", x: a, y: b, "success": False, "runtime_ms": 1.0,
             "delta_max_mm": 1.0, "loop_capped": False}
            for panel, (x, y, *_) in PANELS.items() for a in grids.get(x, grids["lambda1"])
            for b in grids.get(y, grids["lambda1"])]
    fig = _fig19(rows)
    a, b = ([line for line in ax.lines if line.get_color() == style.PAPER]
            for ax in fig.axes if ax.get_xlabel() in (PANELS["mu_mass"][2], PANELS["lambda"][2]))

    def sides(levels, edge):  # the levels whose cell lies wholly below / above the line
        cells = np.arange(len(levels))
        return levels[cells + 0.5 <= edge], levels[cells - 0.5 >= edge]

    def check(levels, edge, below, above):
        low, high = sides(levels, edge)
        assert len(low) + len(high) == len(levels)  # no cell cut by the line
        assert below(low).all() and above(high).all()

    (stable,) = a
    check(grids["mu"], stable.get_xdata()[0], lambda v: v < 0.2, lambda v: v >= 0.2 - 1e-9)
    check(grids["mass_kg"], stable.get_ydata()[1], lambda v: v <= 0.5, lambda v: v > 0.5)
    boundary, strip = b
    check(grids["lambda1"], boundary.get_xdata()[0], lambda v: v <= 0.35, lambda v: v > 0.35)
    check(grids["lambda1"], strip.get_xdata()[0], lambda v: v < 0.9, lambda v: v >= 0.9)


def test_fig19_supplement_panels_carry_the_letters_its_caption_names_them_by():
    """Each supplement tile is titled (a)..(d), as every other multi-panel figure, and the caption names
    each of those letters with the tile's quantity (the titles had no letters)."""
    grid = [0.1, 0.8]
    rows = [{"panel": panel, "status": "ok", x: a, y: b, "success": True, "success_vertical": a < 0.4,
             "runtime_ms": 1.0, "delta_max_mm": 1.0, "loop_capped": False, "valid_geometry": True}
            for panel, (x, y, *_) in PANELS.items() for a in grid for b in grid]
    fig = Figure(figsize=(10.0, 8.6), layout="constrained")
    _supplement(Run(pd.DataFrame(rows), {}, PAPER), fig)
    titles = [ax.get_title() for ax in fig.axes if ax.get_xlabel()]
    assert [t[:4] for t in titles] == ["(a) ", "(b) ", "(c) ", "(d) "]
    (caption,) = [item.caption for item in SPEC.items
                  if isinstance(item, ReportFigure) and item.name == "fig19_supplement"]
    for letter, quantity in zip("abcd", ["|R_z|", "N_max", "fingertip radius", "|R_z|"], strict=True):
        named = caption.split(f"({letter}) ")[1].split("(")[0] if f"({letter}) " in caption else ""
        assert quantity in named, (letter, caption)


def _luminance(colour) -> float:
    """WCAG 2.1 relative luminance of an sRGB colour (W3C's closed form)."""
    rgb = np.asarray(mpl.colors.to_rgb(colour))
    return float(np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
                 @ [0.2126, 0.7152, 0.0722])


def test_fig19_cell_text_contrasts_with_its_cell():
    """Cell values were black on every cell: on viridis' dark end (Fig. 19c's runtimes at paper scale,
    1.1 ms of 5.8 ms) and RdYlGn's dark red and green (0 % and 100 %) they read at 1.6-3:1. Every cell
    value of Fig. 19 and its supplement contrasts with its cell's colour at least 4.5:1 (WCAG 2.1 AA
    for normal text; black or white reaches it on any colour)."""
    grid = np.linspace(0.1, 0.8, 12)
    rows = [{"panel": panel, "status": "ok", x: a, y: b, "success": a < 0.2 or b < 0.2,
             "success_vertical": a > 0.7, "runtime_ms": 1.0 + 5 * (a > 0.7 and b > 0.7),
             "delta_max_mm": 1.0, "loop_capped": b < 0.4, "valid_geometry": a < 0.5}
            for panel, (x, y, *_) in PANELS.items() for a in grid for b in grid]
    low = []
    supplement = Figure(figsize=(10.0, 8.6), layout="constrained")
    _supplement(Run(pd.DataFrame(rows), {}, PAPER), supplement)
    for fig in (_fig19(rows), supplement):
        FigureCanvasAgg(fig).draw()  # the cells' colours, mapped at drawing
        for ax in (ax for ax in fig.axes if ax.texts):
            cells = ax.collections[0].get_facecolors()  # row-major, one per cell, as pcolormesh lays them
            assert len(ax.texts) == len(cells) == grid.size ** 2
            for t in ax.texts:
                c, r = (round(v) for v in t.get_position())
                dark, bright = sorted((_luminance(t.get_color()), _luminance(cells[r * grid.size + c])))
                if (bright + 0.05) / (dark + 0.05) < 4.5:
                    low.append((ax.get_title()[:12], t.get_text(), t.get_color()))
    assert not low, low[:5]


def test_fig19_titles_the_share_deeper_than_r_that_table_sensitivity_panels_holds():
    """Each panel's title says the share of its trials with a contact deeper than the fingertip radius
    (r = 5 mm, Table 2), read from table sensitivity_panels, not counted again: here 1 of 4 trials of
    panel (a) (δmax 6 mm) and 3 of 4 of panel (b) (δmax 5.5, 7 and 9 mm; 5 mm is within r), counted by
    hand; panel (c) has none, so no caveat."""
    depths = {"mu_mass": [1.0, 6.0, 2.0, 5.0], "lambda": [5.5, 7.0, 5.0, 9.0], "n_b": [1.0] * 4}
    rows = [{"panel": panel, "status": "ok", x: a, y: b, "success": False, "runtime_ms": 1.0,
             "delta_max_mm": depths[panel][2 * i + j], "loop_capped": False}
            for panel, (x, y, *_) in PANELS.items() for i, a in enumerate([0.1, 0.8])
            for j, b in enumerate([0.1, 0.8])]
    titles = [ax.get_title() for ax in _fig19(rows).axes if ax.get_xlabel()]
    assert [t.split("\n")[1:] for t in titles] == [
        ["25% of trials deeper than r = 5 mm (non-physical)"],
        ["75% of trials deeper than r = 5 mm (non-physical)"], []]
