"""Figures of the ``test2_grasp`` and ``test3_disturbance`` reports (Figs. 28-31 and 33-36), drawn
from the reduced virtual-rig runs of the shared results tree (conftest.py): legends clear of the
marks, panels lettered once, virtual-rig data never labelled measured, readable schematic axes.
"""

from __future__ import annotations

import numpy as np
import pytest

from graspcampaign.campaign.records import RunStore


def _drawn(root, study: str, name: str, records=None):
    """Figure ``name`` of the run (its ``records`` if given, an Arrow table), drawn on an Agg canvas (the
    report's tables rendered first)."""
    import matplotlib as mpl
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from graspcampaign.campaign.paper import study_paper
    from graspcampaign.report import style
    from graspcampaign.report.build import spec_for
    from graspcampaign.report.document import Document
    from graspcampaign.report.render import Run, render

    store = RunStore(root / study / "default")
    run = Run((store.read() if records is None else records).to_pandas(), store.check(), study_paper(study),
              store)
    spec = spec_for(study, "")
    render(spec, run, Document("", run.source, []))
    item = next(i for i in spec.items if getattr(i, "name", None) == name)
    with mpl.rc_context(style.RC):
        fig = Figure(figsize=item.size, layout="constrained")
        FigureCanvasAgg(fig)
        item.draw(run, fig)
        fig.canvas.draw()
    return run, fig


FIGURES = {"test2_grasp": ["fig28_outcomes", "fig29_prediction_accuracy", "fig31_planner_comparison"],
           "test3_disturbance": ["fig33_thresholds", "fig34_threshold_prediction", "fig36_robustness"]}


@pytest.mark.parametrize(("study", "name"), [(s, f) for s, fs in FIGURES.items() for f in fs])
def test_no_legend_covers_a_mark_or_line_and_panels_are_lettered_once(sim_root, study, name):
    """Every legend box is clear of the lines and markers drawn in its axes (the paper's marks, our
    whiskers, reference lines), and the panel letters (a), (b), ... are each used once."""
    from matplotlib.collections import LineCollection
    from matplotlib.lines import Line2D

    _, fig = _drawn(sim_root, study, name)
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is None:
            continue
        box = legend.get_window_extent(renderer).shrunk(0.98, 0.9)
        paths = [a.get_transform().transform_path(a.get_path()) for a in ax.get_children()
                 if isinstance(a, Line2D) and a.get_visible() and len(a.get_xdata())]
        paths += [ax.transData.transform_path(p) for c in ax.collections if isinstance(c, LineCollection)
                  for p in c.get_paths()]
        hits = [p for p in paths if p.intersects_bbox(box, filled=False)
                or any(box.contains(*v) for v in p.vertices)]
        assert not hits, f"{name}, {ax.get_title('left')}: the legend covers {len(hits)} drawn lines or marks"
        texts = [t for t in (*ax.get_xticklabels(), ax.xaxis.label) if t.get_text()]
        assert not [t for t in texts if box.overlaps(t.get_window_extent(renderer))], ax.get_title("left")
        # a rate panel's legend sits below its axes: inside, a rate or paper mark near 100 % (a reduced
        # run's force balance at 75 % of 4, whisker to 95 %) lay under it whatever these runs draw
        if ax.get_ylabel() in ("success rate [%]", "share of trials [%]"):
            assert box.y1 <= ax.get_window_extent(renderer).y0, f"{name}, {ax.get_title('left')}"
    letters = [t.split(")")[0] for t in (ax.get_title("left") for ax in fig.axes) if t.startswith("(")]
    assert len(letters) == len(set(letters)), letters


@pytest.mark.parametrize("study", sorted(FIGURES))
def test_virtual_rig_figures_are_not_labelled_measured(sim_root, study):
    """A virtual run's axes and captions call its data virtual-rig data, never measured."""
    run, texts = None, []
    for name in FIGURES[study]:
        run, fig = _drawn(sim_root, study, name)
        texts += [t for ax in fig.axes for t in (ax.get_xlabel(), ax.get_ylabel(), ax.get_title("left"))]
    assert run.source == "virtual"
    md = (sim_root / study / "default" / "report" / "report.md").read_text()
    texts += [line for line in md.splitlines() if line.startswith("*Fig.")]
    assert not [t for t in texts if "measured" in t]
    assert any("virtual-rig" in t for t in texts)


def test_fig29c_marks_the_errors_over_a_measured_deformation_below_the_vision_step(sim_root):
    """Fig. 29c's tail ran to 10^4 % with nothing saying why: the trials whose recorded mean deformation
    (the error's denominator) lies above 0 but below the 0.1 mm vision quantisation (§8.1), counted here
    from the records, are drawn dark over the histogram, one bar height per trial, and the legend gives n."""
    from matplotlib.colors import to_hex

    from graspcampaign.report import style

    run, fig = _drawn(sim_root, "test2_grasp", "fig29_prediction_accuracy")
    r = run.records[(run.records["status"] == "ok") & ~run.records["aborted"].astype(bool)]
    n = int(r["deformation_mean_mm"].between(0.0, 0.1, inclusive="neither").sum())
    ax = fig.axes[2]
    dark = [p for p in ax.patches if to_hex(p.get_facecolor()) == to_hex(style.CRITERION)]
    assert n > 0 and sum(p.get_height() for p in dark) == n
    assert f"denominator < 0.1 mm, n={n}" in [t.get_text() for t in ax.get_legend().get_texts()]


@pytest.mark.parametrize(("study", "name"), [("test2_grasp", "fig30_representative_grasp"),
                                             ("test3_disturbance", "fig35_representative_pull")])
def test_schematic_slip_axis_has_readable_ticks_and_no_finger_hides_another(sim_root, study, name):
    """Fig. 35's slip axis had a single tick label (10¹) and Fig. 30's finger 1 lay hidden under finger 3
    (0.51 and 0.52 N): the slip axis now labels at least three plain values in view (the 2 mm criterion
    among them), and of two finger lines less than 5 % of the axis apart the later drawn is thinner, so
    both show; each finger's legend entry gives its recorded force."""
    run, fig = _drawn(sim_root, study, name)
    slip = fig.axes[1]
    low, high = slip.get_ylim()
    shown = [t.get_text() for t in slip.get_yticklabels()
             if t.get_text() and low <= t.get_position()[1] <= high]
    assert len(shown) >= 3 and "2" in shown and not any("^" in s for s in shown), shown
    if study == "test2_grasp":
        force = fig.axes[0]
        fingers = [line for line in force.get_lines() if line.get_label().startswith("finger ")]
        assert len(fingers) == 3
        span = np.diff(force.get_ylim())[0]
        for i, under in enumerate(fingers):
            for over in fingers[i + 1:]:
                if abs(under.get_ydata()[0] - over.get_ydata()[0]) < 0.05 * span:
                    assert over.get_linewidth() < under.get_linewidth()
        for line in fingers:
            assert f"({line.get_ydata()[0]:#.3g} N)" in line.get_label()  # 0.510 N: 3 digits, as 0.245 N


def test_fig30_draws_the_recorded_hold_values_over_the_hold(sim_root):
    """The trial's recorded normal forces and its prediction are the hold's (§8.1: the forces "settle to
    a steady hold"), as its peak slip is: Fig. 30 drew the forces from the start of the lift, the slip from
    the start of the hold. Every recorded level now spans the shaded hold phase exactly."""
    _, fig = _drawn(sim_root, "test2_grasp", "fig30_representative_grasp")
    force, slip = fig.axes
    hold = [p for p in force.patches if p.get_label() == "hold"]
    assert len(hold) == 1
    x = hold[0].get_x(), hold[0].get_x() + hold[0].get_width()
    levels = [line for line in force.get_lines() if line.get_label().startswith(("finger ", "predicted"))]
    levels += [line for line in slip.get_lines() if line.get_label().startswith("peak slip")]
    assert len(levels) == 5
    for line in levels:
        assert tuple(line.get_xdata()) == pytest.approx(x, rel=1e-12), line.get_label()


def test_fig30_leaves_out_a_finger_without_a_recorded_force_and_says_so(sim_root):
    """An ingested file may leave a finger's force empty (null in the records): Fig. 30 drew it as a NaN
    line, "finger 2, recorded (nan N)". Here finger 2 of the trial the figure draws is emptied (its mean
    force, which chose the trial, kept): fingers 1 and 3 are drawn and the caption says one was not; with
    every finger read the caption has no such sentence."""
    import pyarrow as pa
    import pyarrow.compute as pc
    from matplotlib.colors import to_hex

    from graspcampaign.report.studies import test2

    run, fig = _drawn(sim_root, "test2_grasp", "fig30_representative_grasp")
    trial = fig.axes[0].get_title("left").split(":")[0]
    assert "not drawn" not in test2.fig30_caption(run)
    records = RunStore(sim_root / "test2_grasp" / "default").read()
    column = records["normal_force_2_n"]
    emptied = pc.if_else(pc.equal(records["rig_trial_id"], trial), pa.scalar(None, column.type), column)
    at = records.schema.get_field_index("normal_force_2_n")
    records = records.set_column(at, "normal_force_2_n", emptied)
    run, fig = _drawn(sim_root, "test2_grasp", "fig30_representative_grasp", records)
    assert fig.axes[0].get_title("left").startswith(f"{trial}:")  # the same trial
    fingers = [line.get_label() for line in fig.axes[0].get_lines() if line.get_label().startswith("finger ")]
    assert [f.split(",")[0] for f in fingers] == ["finger 1", "finger 3"]
    assert not any("nan" in f for f in fingers)
    # each finger in its vocabulary colour, as in Figs. 12-13 (it drew matplotlib's C2 and C4 here)
    assert [to_hex(line.get_color()) for line in fig.axes[0].get_lines()
            if line.get_label().startswith("finger ")] == ["#332288", "#aa4499"]
    assert test2.fig30_caption(run).endswith("; 1 of 3 fingers not drawn (finger 2: no force recorded)")


def _emptied(root, study: str, trial: str, column: str):
    """The run's records (an Arrow table, as Parquet gives them) with ``column`` of ``trial`` null."""
    import pyarrow as pa
    import pyarrow.compute as pc

    records = RunStore(root / study / "default").read()
    values = records[column]
    emptied = pc.if_else(pc.equal(records["rig_trial_id"], trial), pa.scalar(None, values.type), values)
    return records.set_column(records.schema.get_field_index(column), column, emptied)


def test_fig30_predicts_over_the_fingers_it_draws(sim_root):
    """Fig. 30 drew the predicted level from the three-finger ``normal_force_pred_mean_n`` beside a finger
    left out for want of a recorded force, while the parity and the errors (Fig. 29) predict over the
    fingers read: the level is the mean prediction of the fingers drawn (by hand from the records)."""
    run, fig = _drawn(sim_root, "test2_grasp", "fig30_representative_grasp")
    trial = fig.axes[0].get_title("left").split(":")[0]
    records = _emptied(sim_root, "test2_grasp", trial, "normal_force_2_n")
    row = records.filter(records["rig_trial_id"].to_numpy(zero_copy_only=False) == trial).to_pylist()[0]
    pred = [line for line in fig.axes[0].get_lines() if line.get_label().startswith("predicted")]
    assert pred[0].get_ydata()[0] == pytest.approx(row["normal_force_pred_mean_n"], rel=1e-12)
    assert pred[0].get_label().startswith("predicted, mean (")
    _, fig = _drawn(sim_root, "test2_grasp", "fig30_representative_grasp", records)
    by_hand = (row["normal_force_pred_1_n"] + row["normal_force_pred_3_n"]) / 2
    assert by_hand != pytest.approx(row["normal_force_pred_mean_n"], rel=1e-6)  # the test can tell
    pred = [line for line in fig.axes[0].get_lines() if line.get_label().startswith("predicted")]
    assert pred[0].get_ydata()[0] == pytest.approx(by_hand, rel=1e-12)
    assert pred[0].get_label() == f"predicted, mean of the fingers drawn ({by_hand:#.3g} N)"


@pytest.mark.parametrize(("study", "name"), [("test2_grasp", "fig30_representative_grasp"),
                                             ("test3_disturbance", "fig35_representative_pull")])
def test_a_schematic_leaves_out_a_peak_slip_not_recorded_and_says_so(sim_root, study, name):
    """Figs. 30 and 35 drew a trial's missing ``peak_slip_mm`` (null in the records) as a NaN line whose
    legend read "(nan mm)": with the drawn trial's peak slip emptied it is not drawn and the caption says
    so; with it recorded, one peak-slip line and no such sentence."""
    from graspcampaign.report.build import spec_for

    item = next(i for i in spec_for(study, "").items if getattr(i, "name", None) == name)

    def caption(run):  # a caption is a sentence or a function of the run
        return item.caption(run) if callable(item.caption) else item.caption

    def slips(fig):
        return [line.get_label() for line in fig.axes[1].get_lines() if "peak slip" in line.get_label()]

    run, fig = _drawn(sim_root, study, name)
    trial = fig.axes[0].get_title("left").split(":")[0]
    assert len(slips(fig)) == 1 and "not drawn" not in caption(run)
    run, fig = _drawn(sim_root, study, name, _emptied(sim_root, study, trial, "peak_slip_mm"))
    assert fig.axes[0].get_title("left").startswith(f"{trial}:")  # the same trial
    assert slips(fig) == []
    assert caption(run).endswith("recorded peak slip" * (study == "test3_disturbance")
                                 + "; peak slip not drawn (not recorded)")


@pytest.mark.parametrize(("study", "name"), [("test2_grasp", "fig30_representative_grasp"),
                                             ("test3_disturbance", "fig35_representative_pull")])
def test_every_level_in_a_schematic_legend_gives_its_value(sim_root, study, name):
    """Fig. 30's legend read "paper: slip below" with no value and gave none for the predicted force,
    the recorded slip or the paper's hold band, nor did Fig. 35's for the threshold, the prediction or
    the paper's median, while the fingers' entries gave theirs: every horizontal line and band of a
    legend names a number, the paper's the value its paper record holds."""
    import re

    from matplotlib.lines import Line2D
    from matplotlib.patches import Polygon, Rectangle

    from graspcampaign.campaign.paper import study_paper

    _, fig = _drawn(sim_root, study, name)
    levels = []
    for ax in fig.axes:
        for artist in ax.get_children():
            what = (artist.get_label() if isinstance(artist, Line2D | Polygon | Rectangle) else None) or "_"
            if what.startswith("_"):
                continue
            if isinstance(artist, Line2D) and len(set(artist.get_ydata())) == 1:
                levels.append(what)
            elif not isinstance(artist, Line2D) and what.startswith("paper"):  # the paper's band
                levels.append(what)
    assert len(levels) >= 5, levels
    assert not [w for w in levels if not re.search(r"\d", w)], levels
    paper = study_paper(study)
    expected = ([f"paper: slip below {paper.hold_slip_max_mm:g} mm",
                 "paper: steady hold ({:g}–{:g} N)".format(*paper.hold_force_per_finger_n)]
                if study == "test2_grasp" else
                [f"paper: natural-friction median ({paper.lateral_threshold_median_n:g} N)"])
    assert set(expected) <= set(levels), levels


def _panel(draw, run, size=(4.0, 3.0)):
    """``draw(run, ax)`` on one Agg axes in the report's style."""
    import matplotlib as mpl
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from graspcampaign.report import style

    with mpl.rc_context(style.RC):
        fig = Figure(figsize=size, layout="constrained")
        FigureCanvasAgg(fig)
        ax = fig.add_subplot()
        draw(run, ax)
        fig.canvas.draw()
    return ax


@pytest.mark.parametrize(("study", "name"), [("test2_grasp", "fig31_planner_comparison"),
                                             ("test3_disturbance", "fig36_robustness")])
def test_the_flag_panel_says_in_words_what_the_flag_predicts(study, name):
    # Figs. 31c and 36c were labelled with the raw column name `predicted_stable`; the caption
    # still names the column the label describes

    import pandas as pd

    from graspcampaign.report.build import spec_for
    from graspcampaign.report.render import Run

    flags = pd.DataFrame({"belief_error": "paper", "planner": "heuristic", "source": "virtual",
                          "predicted_stable": [True, True, False, False, True],
                          "success": [True, False, False, True, True]})
    run = Run(flags, {"study": study, "source": "virtual"})
    run.memo("hardware", lambda: flags)
    figure = next(i for i in spec_for(study, "").items if getattr(i, "name", None) == name)
    confusion = figure.draw.specs[-1]  # style.panels' last panel
    ax = _panel(confusion, run)
    assert ax.get_ylabel() == {"test2_grasp": "predicted stable: believed SF > 1",
                               "test3_disturbance": "predicted to retain: believed margin > 1"}[study]
    assert [t.get_text() for t in ax.texts] == ["1", "1", "1", "2"]  # tn, fn / fp, tp of the flags above
    caption = figure.caption(run) if callable(figure.caption) else figure.caption
    assert "(c) " in caption and "`predicted_stable`" in caption.split("(c) ")[1]


def test_a_pull_direction_without_a_threshold_says_why_in_fig_33c():
    # the line broke at 180° (1 trial, no uncensored ramp) and ran straight over 45° (no trial) with
    # nothing saying why; each such direction now breaks the line and is marked where it lies
    import numpy as np
    import pandas as pd

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.test3 import directions

    run = Run(pd.DataFrame(), {"study": "test3_disturbance"})
    run.tables["test3_directions"] = pd.DataFrame({
        "direction_deg": [0.0, 90.0, 180.0, 270.0, 315.0], "n": [2, 2, 1, 3, 2],
        "success_pct": 0.0, "lat_threshold_n": [1.2, 2.7, np.nan, 1.5, 0.8],
        "n_lat_threshold": [1, 1, 0, 2, 1]})
    ax = _panel(directions, run)
    marks = {t.xy[0]: t.get_text() for t in ax.texts}
    assert marks == {45.0: "no trial", 135.0: "no trial", 180.0: "1 trial, no threshold",
                     225.0: "no trial"}
    line = next(line for line in ax.get_lines() if line.get_label() == "ours")
    drawn = dict(zip(line.get_xdata(), line.get_ydata(), strict=True))
    assert [a for a, v in drawn.items() if np.isnan(v)] == [45.0, 135.0, 180.0, 225.0]
    assert [t.get_text() for t in ax.get_xticklabels()] == [f"{a}" for a in range(0, 360, 45)]


def test_every_line_style_of_the_bland_altman_panel_has_its_legend_entry(sim_root):
    """Fig. 34b drew the 95% limits dashed (ours) and dotted (the paper's) under one solid legend
    entry "bias, 95% limits" each: every (colour, style) of a horizontal line drawn in the panel has a
    legend entry of that colour and style."""
    import matplotlib as mpl
    from matplotlib.lines import Line2D

    _, fig = _drawn(sim_root, "test3_disturbance", "fig34_threshold_prediction")
    ax = next(a for a in fig.axes if a.get_title("left").startswith("(b)"))
    drawn = {(mpl.colors.to_hex(line.get_color()), line.get_linestyle()) for line in ax.lines
             if np.ptp(line.get_ydata()) == 0 and np.isfinite(line.get_ydata()).all()}
    shown = {(mpl.colors.to_hex(h.get_color()), h.get_linestyle()) for h in ax.get_legend().legend_handles
             if isinstance(h, Line2D) and h.get_linestyle() != "None"}
    assert {"--", ":"} <= {ls for _, ls in drawn}  # both kinds of limits drawn
    assert drawn <= shown, drawn - shown


def test_fig30_says_why_its_hold_lies_below_the_papers_band(sim_root):
    """Fig. 30 drew the paper's steady hold (1.4–1.7 N per finger, the paper's text on Fig. 30) far
    above the recorded forces and its caption said nothing of it. The caption now gives the trial's mean
    hold and, for the commanded grip, the paper's band as multiples of it (numbers by hand from the drawn
    trial's record); inside the band, or with no commanded grip (the ``paper`` law), no cause is given."""
    from graspcampaign.report.studies import test2

    run, fig = _drawn(sim_root, "test2_grasp", "fig30_representative_grasp")
    t = test2.representative(run)
    caption = test2.fig30_caption(run)
    assert t["normal_force_mean_n"] < 1.4  # the reduced virtual run grips lighter than the paper's hand
    grip = t["grip_force_n"]
    assert caption.endswith(  # no reading left out: the clause ends the caption
        f"; its mean hold, {t['normal_force_mean_n']:.3g} N per finger, is below the paper's steady hold "
        f"(1.4–1.7 N): the grip law commands {grip:.3g} N per finger, safety factor {t['sf_predicted']:g} "
        f"for this {t['mass_kg']:g} kg object, and the paper's band is {1.4 / grip:.1f}–{1.7 / grip:.1f} "
        "times that")
    inside = t.copy()
    inside["normal_force_mean_n"] = 1.5
    assert test2.hold_gap(run, inside) == ""
    paper_law = t.copy()
    paper_law["grip_force_n"] = float("nan")
    assert test2.hold_gap(run, paper_law).endswith("is below the paper's steady hold (1.4–1.7 N)")


def test_a_surface_without_a_threshold_says_why_in_fig_33a():
    """Fig. 33a left the low surface's slot empty (no uncensored ramp, n = 0) with nothing saying why,
    where 33c marks such a direction: each surface without a median threshold now says so where its bar
    would stand, its trials counted from table test3_coating."""
    import numpy as np
    import pandas as pd

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.test3 import thresholds

    run = Run(pd.DataFrame(), {"study": "test3_disturbance"})
    run.tables["test3_coating"] = pd.DataFrame({
        "friction_level": ["natural", "high", "medium", "low"], "n": [20, 2, 1, 0],
        "lat_threshold_n": [1.22, 2.06, np.nan, np.nan], "n_lat_threshold": [11, 1, 0, 0],
        "paper_threshold_n": [4.34, 4.31, 0.84, 0.185]})
    ax = _panel(thresholds, run)
    assert {t.xy[0]: t.get_text() for t in ax.texts} == {2: "1 trial, no threshold", 3: "no trial"}
    assert [t.get_text() for t in ax.get_xticklabels()] == ["natural\nn=11", "high\nn=1", "medium\nn=0",
                                                            "low\nn=0"]


def test_fig29_draws_every_planners_pooled_trials_in_no_planners_colour(sim_root):
    """Fig. 29 pools every planner's trials (its parity points and fit, the histograms and their
    medians) but drew them in the proposed planner's blue, read as that planner's alone. Every coloured
    mark of ours in it (all but the paper's black, the identity's and the criterion's greys) lies
    outside the hues of the proposed planner's family (± 15°) and is no planner's colour."""
    import colorsys

    from matplotlib.colors import to_hex, to_rgb

    from graspcampaign.analysis.vocabulary import PLANNERS

    family = [colorsys.rgb_to_hsv(*to_rgb(PLANNERS[k].colour))[0]
              for k in ("heuristic", "no_s1", "no_s2", "no_s3", "no_pc", "no_pe", "no_pso")]
    band = (min(family) - 15 / 360, max(family) + 15 / 360)
    _, fig = _drawn(sim_root, "test2_grasp", "fig29_prediction_accuracy")
    colours = set()
    for ax in fig.axes:
        colours |= {to_hex(c) for coll in ax.collections for c in coll.get_facecolors()}
        colours |= {to_hex(p.get_facecolor()) for p in ax.patches}
        colours |= {to_hex(line.get_color()) for line in ax.get_lines()}
    planners = {to_hex(p.colour) for p in PLANNERS.values()}
    blue = [c for c in colours if colorsys.rgb_to_hsv(*to_rgb(c))[1] > 0.1
            and band[0] <= colorsys.rgb_to_hsv(*to_rgb(c))[0] <= band[1]]
    assert len(colours) >= 3, colours
    assert not blue and not colours & planners, (blue, colours & planners)
