"""The text of every figure of every study, drawn from the reduced runs of the shared results tree
(conftest.py): tick labels a researcher reads as numbers, the levels a run used on its axes."""

from __future__ import annotations

import pytest
from synthetic_runs import draw_all, half_an_em, page_image_px

from graspcampaign.campaign.records import RunStore


def _labels_in_view(axis) -> list[str]:
    """The tick labels ``axis`` shows (major and minor, inside its view)."""
    low, high = sorted(axis.get_view_interval())
    along = 1 if axis.axis_name == "y" else 0
    return [t.get_text() for t in (*axis.get_majorticklabels(), *axis.get_minorticklabels())
            if t.get_text() and t.get_visible() and low <= t.get_position()[along] <= high]


def test_no_tick_label_reads_a_times_ten_to_the(sim_root):
    """matplotlib labels a log axis spanning less than a decade with minor ticks as "6×10⁻¹" and
    "2×10⁰" (the H–ε figure's candidate counts, Fig. 20d's H gap): every tick label of every figure
    of every study is a plain number or a power of ten."""
    studies = sorted(p.parent.name for p in sim_root.glob("*/default"))
    assert len(studies) == 17
    bad = [(study, name, ax.get_title("left") or ax.get_ylabel(), axis.axis_name, label)
           for study in studies for name, fig in draw_all(sim_root, study).items() for ax in fig.axes
           for axis in (ax.xaxis, ax.yaxis) for label in _labels_in_view(axis) if "times" in label]
    assert not bad, bad


def test_fig20_budget_axes_label_the_budgets_run(sim_root):
    """Fig. 20c-d's N_cand axes read 10⁰ and 10¹ where the run used budgets 1 and 30: they label the
    budgets of the run's config."""
    config = RunStore(sim_root / "mesh_resolution" / "default").check()["config"]
    expected = [f"{b:g}" for b in sorted(config["params"]["budgets"])]
    assert expected == ["1", "30"]  # conftest.REDUCED
    fig = draw_all(sim_root, "mesh_resolution")["fig20_mesh_resolution"]
    panels = [ax for ax in fig.axes if ax.get_xlabel().startswith("candidate budget")]
    assert len(panels) == 2
    for ax in panels:
        assert _labels_in_view(ax.xaxis) == expected, ax.get_title("left")


def test_fig20c_names_the_trials_behind_its_rates(sim_root):
    """Fig. 20c showed success rates per budget without the trials behind them: each series' legend
    entry reads the trials per budget of the run's table."""
    import pandas as pd

    tables = sim_root / "mesh_resolution" / "default" / "report" / "tables"
    table = pd.read_csv(tables / "success_vs_n_cand.csv")
    fig = draw_all(sim_root, "mesh_resolution")["fig20_mesh_resolution"]
    ax = next(a for a in fig.axes if a.get_title("left").startswith("(c)"))
    entries = [t.get_text() for t in ax.get_legend().get_texts() if "check" in t.get_text()]
    ours = table[table["planner"] != "reference"]
    assert entries == [f"{nodes} nodes, ‖R‖ check (Wilson 95%, n={g['trials'].iloc[0]} per budget)"
                       for nodes, g in ours.groupby("nodes")]


def test_neighbouring_tick_labels_lie_half_an_em_apart(sim_root):
    """Fig. 18a printed its planners "proposed" and "antipodal" 2.8 px apart (a quarter em at 8 pt), read
    as one phrase: no overlap, yet crowded. In every figure of every study, two neighbouring horizontal
    tick labels in view are at least half an em apart (matplotlib's drawn extents)."""

    crowded = []
    for study in sorted(p.parent.name for p in sim_root.glob("*/default")):
        for name, fig in draw_all(sim_root, study).items():
            renderer = fig.canvas.get_renderer()
            for ax in fig.axes:
                low, high = sorted(ax.get_xlim())
                shown = sorted((t for t in ax.get_xticklabels() if t.get_text() and t.get_visible()
                                and t.get_rotation() == 0 and low <= t.get_position()[0] <= high),
                               key=lambda t: t.get_position()[0])
                boxes = [t.get_window_extent(renderer) for t in shown]
                crowded += [(study, name, ax.get_title("left"), a.get_text(), b.get_text())
                            for a, b, ba, bb in zip(shown, shown[1:], boxes, boxes[1:], strict=False)
                            if bb.x0 - ba.x1 < half_an_em(a)]
    assert not crowded, crowded


COUNTED = ("nodes", "features", "evaluations", "events", "candidates", "trials", "triples", "budget")
"""Things a count axis counts (mesh nodes, sharp features, function evaluations, candidate triples)."""


def _counts(named: str) -> bool:
    """Whether an axis label names a count: its quantity (the words before its unit) ends in one of
    :data:`COUNTED` (a symbol such as "n" or "N_cand" may follow it), or its unit is one of them
    ("[triples]"); a statistic or ratio of counts ("Spearman ρ of H and ε over one trial's candidates",
    "identified value / mean over runs") is none."""
    import re

    quantity, unit = re.match(r"(.*?)\s*\[([^\]]*)\]", named).groups()
    words = quantity.split()
    if unit in COUNTED:
        return True
    if re.search(r"\b(of|over|per)\b|/", quantity) or not words:
        return False
    if re.fullmatch(r"[A-Za-z](_\w+)?", words[-1]):  # a symbol: "n", "N_cand"
        words = words[:-1]
    return bool(words) and words[-1] in COUNTED


def test_every_numeric_axis_names_its_unit(sim_root):
    """The H–ε histogram read "trials" over "Spearman ρ of H and ε over one trial's candidates", its
    colour bar "candidates", Fig. 23c "normal-indentation events", Fig. 17 "iteration of Algorithm 2":
    axes without a unit, where every other axis gives one ("[–]", "[count]", "[N]"). Every axis of every
    figure of every study whose tick labels are numbers names its unit in brackets: in its label, or,
    where it has none (Figs. 15 and 17 title each panel by its quantity), in its panel's title. A count
    reads "[count]" (docs/decisions.md): smoke's "requested mesh nodes [–]" and "sharp features [–]",
    Fig. 20's "mesh nodes n [–]" and "N_cand [triples]", Fig. 9's "function evaluations [–]" read three
    ways."""
    import re

    number = re.compile(r"[−+\-]?[\d.,]+|\$\\mathdefault\{10\^\{[−\-]?\d+\}\}\$")
    bare, uncounted = [], []
    for study in sorted(p.parent.name for p in sim_root.glob("*/default")):
        for name, fig in draw_all(sim_root, study).items():
            for ax in fig.axes:
                for axis, words in ((ax.xaxis, ax.get_xlabel()), (ax.yaxis, ax.get_ylabel())):
                    labels = _labels_in_view(axis)
                    if labels and all(number.fullmatch(t) for t in labels):
                        named = words or ax.get_title("left") or ax.get_title()
                        if not re.search(r"\[[^\]]+\]", named):
                            bare.append((study, name, axis.axis_name, named))
                        elif _counts(named) and "[count]" not in named:
                            uncounted.append((study, name, axis.axis_name, named))
    assert not bare, bare
    assert not uncounted, uncounted


LEGIBLE_PX = 10.0
"""The least em [px] of a figure's text at the page's width: 8 px (Figs. 12-13 and 19, 15 in wide, at
1110 px) read as footnotes beside the page's 13.5-15 px text; 10 px is the smallest its captions'
12-13.5 px rounds down to by one step (docs/decisions.md, *Figure text legible at the page's width*)."""


@pytest.mark.parametrize(("study", "name"), [
    ("friction_mass", "fig12_13_dynamic"), ("sensitivity", "fig19_sensitivity"),
    ("surrogate", "figA1_surrogate"), *(("test1_bench", f) for f in (
        "fig23_normal_law", "fig24_tangential", "fig25_relaxation_cycling", "fig26_identification")),
    *(("test2_grasp", f) for f in ("fig28_outcomes", "fig29_prediction_accuracy",
                                   "fig31_planner_comparison")),
    *(("test3_disturbance", f) for f in ("fig33_thresholds", "fig34_threshold_prediction",
                                         "fig36_robustness"))])
def test_wide_figures_text_reads_at_least_ten_px_at_the_pages_width(sim_root, study, name):
    """Figs. 12-13 and 19 were 15 in wide: saved at 130 dpi (1950 px) and shown at the page's 1110 px,
    their 7.5 pt legend text was 7.7 px high (Fig. A1's 6.5 pt legends, 12 in wide, 8.3 px; Fig. 33,
    15 in, 7 pt at 7.1 px; Figs. 23-26, 28-29, 31, 34 and 36, three panels in a 12-13 in row, 6-7.5 pt
    at 7.1-9.5 px). Every
    visible text of theirs is at least 10 px (its font size, an em) in the image as the page shows it:
    the saved PNG's width (its tight box and 0.1 in of padding at the saving dpi) scaled down to the
    page's, never up."""
    from matplotlib.text import Text

    from graspcampaign.report.style import RC

    fig = draw_all(sim_root, study)[name]
    dpi = RC["savefig.dpi"]
    saved_px = (fig.get_tightbbox(fig.canvas.get_renderer()).width + 2 * 0.1) * dpi
    scale = min(1.0, page_image_px() / saved_px)
    small = sorted({(round(t.get_fontsize() * dpi / 72 * scale, 1), t.get_text()[:30])
                    for t in fig.findobj(Text) if t.get_text().strip() and t.get_visible()
                    and t.get_fontsize() * dpi / 72 * scale < LEGIBLE_PX})
    assert page_image_px() == 1110.0
    assert not small, (round(saved_px), small[:8])
