"""The tick labels of every figure (report.style.tick, report.style.plain_log) and its rate bars
(report.style.bars)."""

import re

import matplotlib as mpl
import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from synthetic_runs import half_an_em

from graspcampaign.analysis.vocabulary import VOCABULARIES, label
from graspcampaign.report.style import RC, bars, plain_log, tick

WORDS = st.text(alphabet="abcdefghijklmnopqrstuvwxyz–-()2ε", min_size=1, max_size=14)


@given(st.lists(WORDS, min_size=1, max_size=5))
def test_tick_keeps_every_character_and_wraps_at_nine(words):
    text = " ".join(words)
    wrapped = tick(text)
    assert "".join(wrapped.split()) == "".join(text.split())  # nothing lost, nothing added
    for line in wrapped.split("\n"):  # a line over the width is one word that has no dash to break at
        assert len(line) <= 9 or (" " not in line and not re.search(r"[–-]\w", line)), line


def test_every_planner_label_fits_its_bar():
    """Labels of the vocabulary wrap to lines of at most nine characters or one unbreakable word
    (the Ferrari–Canny label ran into its neighbour in Fig. 18a)."""
    assert tick("Ferrari–Canny ε") == "Ferrari–\nCanny ε"
    for column, values in VOCABULARIES.items():
        for value in values:
            for line in tick(label(column, value)).split("\n"):
                assert len(line) <= 9 or " " not in line, (column, value, line)


def test_a_missing_rate_draws_no_whisker():
    """A group without a value (a dynamic_check shape whose grasps are all not settled by t_max, or
    not yet run) has no bar and no whisker; its caption says so. The whisker used to be drawn from
    0 to 0 with its caps, a mark at 0% on the axis that read as a measured 0%."""
    with mpl.rc_context(RC):  # the report's caps
        ax = Figure().subplots()
        bars(ax, [0, 1], [50.0, np.nan], [40.0, np.nan], [60.0, np.nan], ["C0", "C1"])
    points = np.vstack([line.get_xydata() for line in ax.lines]
                       + [seg for c in ax.collections for seg in c.get_segments()])
    drawn = points[np.isfinite(points).all(axis=1)]
    assert set(drawn[:, 0].round(1)) <= {-0.1, 0.0, 0.1}, drawn  # only the measured group's whisker
    assert drawn[:, 1].min() == 40.0 and drawn[:, 1].max() == 60.0


def _relative_luminance(colour) -> float:
    """WCAG 2 relative luminance of an sRGB colour (W3C's closed form)."""
    rgb = np.asarray(mpl.colors.to_rgb(colour))
    linear = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    return float(linear @ [0.2126, 0.7152, 0.0722])


def test_the_mu_lines_of_fig17_are_told_apart_by_lightness():
    # Fig. 17's three μ lines took neighbouring steps of one green ramp (WCAG contrast 1.5-1.7:
    # hard to tell apart); each pair now differs by at least 2:1
    from types import SimpleNamespace

    import pandas as pd

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.wrench import fig17

    mus = (0.1, 0.3, 0.5)
    records = pd.DataFrame({"trial_id": [f"t{m}" for m in mus], "status": "ok", "mu": mus})
    paper = SimpleNamespace(residual_settles_within_iterations=(30, 40), slip_margin_saturates_above=0.8,
                            slip_margin_saturates_from_mu=0.3, finger_force_command_n=65.0)
    run = Run(records, {"config": {"evaluator": {"tau_f_n": 0.5, "tau_t_nm": 0.025}}}, paper)
    run.memo("tables/iterations", lambda: pd.DataFrame(
        [{"trial_id": f"t{m}", "iteration": i, "residual_norm_n": 1.0, "torque_norm_nm": 0.0,
          "slip_margin_ratio": 0.5, "normal_force_1_n": 10.0} for m in mus for i in range(5)]))
    with mpl.rc_context(RC):
        fig = Figure()
        fig17(run, fig)
    lines = [line for line in fig.axes[0].lines if line.get_label().startswith("μ =")]
    assert [line.get_label() for line in lines] == [f"μ = {m:g}" for m in mus]
    light = sorted(_relative_luminance(line.get_color()) for line in lines)
    assert min((b + 0.05) / (a + 0.05) for a, b in zip(light, light[1:], strict=False)) >= 2.0


def test_a_near_zero_bar_stays_visible_under_the_papers_zero_mark():
    # Fig. 18 (grip_laws, baseline_grid): the paper's 0 % mark, a 2 pt black line over the bar, hid our
    # 1 % bar; the bar's own pixels (off its whisker) must show its colour
    with mpl.rc_context(RC):
        fig = Figure(figsize=(4.0, 3.0), dpi=100)
        FigureCanvasAgg(fig)
        ax = fig.add_subplot()
        bars(ax, [0.0], [1.0], [0.5], [2.0], ["#ff0000"], paper=[0.0])
        ax.set(ylim=(0, 105))
        fig.canvas.draw()
        pixels = np.asarray(fig.canvas.buffer_rgba())[..., :3]
        (x0, y0), (x1, y1) = ax.transData.transform([(0.15, 0.0), (0.3, 1.0)])  # right of the whisker
    height = pixels.shape[0]
    region = pixels[int(height - y1) - 1:int(np.ceil(height - y0)) + 1, int(x0):int(x1)]
    red = (region[..., 0] > 150) & (region[..., 1] < 150) & (region[..., 2] < 150)
    assert red.any(axis=0).mean() > 0.9  # the bar shows in (nearly) every pixel column


def _log_labels(low: float, high: float) -> list[str]:
    """The labels a log axis from ``low`` to ``high`` shows under :func:`plain_log`."""
    with mpl.rc_context(RC):
        fig = Figure(figsize=(3.0, 3.0))
        FigureCanvasAgg(fig)
        ax = fig.subplots()
        ax.set_yscale("log")
        ax.set_ylim(low, high)
        plain_log(ax.yaxis)
        fig.canvas.draw()
    return [t.get_text() for t in (*ax.yaxis.get_majorticklabels(), *ax.yaxis.get_minorticklabels())
            if t.get_text() and low <= t.get_position()[1] <= high]


def test_plain_log_labels_read_as_numbers():
    """Where matplotlib labels 0.53-1.7 as "6×10⁻¹" and "10⁰", and 1-7 as "2×10⁰" ... "6×10⁰": 1, 2 and 5
    of each decade, every tenth of the decade and 1.5 where fewer than three of those are in view. Without
    1.5 the top of Fig. 20d's 0.47-1.9 gap axis (from 1 up, 40 % of its height, where its largest gap
    lies) had no label."""
    assert _log_labels(0.3, 20.0) == ["0.5", "1", "2", "5", "10", "20"]
    assert _log_labels(1.0, 7.0) == ["1", "2", "5"]
    assert _log_labels(0.53, 1.7) == ["0.6", "0.7", "0.8", "0.9", "1", "1.5"]
    assert _log_labels(0.47, 1.9) == ["0.5", "0.6", "0.7", "0.8", "0.9", "1", "1.5"]
    assert _log_labels(5.3, 17.0) == ["6", "7", "8", "9", "10", "15"]


def test_plain_log_levels_closer_than_a_label_leave_the_later_one_blank():
    """Fig. 20a-b labelled a run's 356 and 390 nodes (0.04 decades apart) at their ticks, printed over
    each other as "356390": the drawn labels (matplotlib's own text extents) never overlap, the later of
    two touching levels keeps its tick mark without a label, every other level is labelled."""
    levels = [144, 250, 356, 390, 600, 900, 1300, 1750]
    with mpl.rc_context(RC):
        fig = Figure(figsize=(4.9, 3.0), layout="constrained")  # Fig. 20's panel width
        FigureCanvasAgg(fig)
        ax = fig.subplots()
        ax.plot(levels, levels)
        ax.set_xscale("log")
        plain_log(ax.xaxis, levels)
        fig.canvas.draw()
    shown = [t for t in ax.xaxis.get_majorticklabels() if t.get_text()]
    assert [t.get_text() for t in shown] == ["144", "250", "356", "600", "900", "1300", "1750"]
    assert list(ax.get_xticks()) == levels  # the 390 tick mark stays
    boxes = [t.get_window_extent(fig.canvas.get_renderer()) for t in shown]
    assert min(b.x0 - a.x1 for a, b in zip(boxes, boxes[1:], strict=False)) >= half_an_em(shown[0]), boxes


def test_grouped_bars_name_the_trials_under_each_group():
    """Fig. 16, Fig. 18 and dynamic_check drew success rates without the trials behind them (rate_bars'
    panels showed n): each group's tick reads its n, a range where its bars' n differ."""
    import pandas as pd

    from graspcampaign.report.style import grouped_bars

    t = pd.DataFrame({"planner": ["heuristic", "heuristic", "centroid", "centroid"],
                      "grip_law": ["paper", "slip", "paper", "slip"], "n": [50, 50, 40, 50],
                      "rate_pct": [10.0, 20.0, 30.0, 40.0], "wilson_low_pct": [5.0, 15.0, 25.0, 35.0],
                      "wilson_high_pct": [15.0, 25.0, 35.0, 45.0]})
    with mpl.rc_context(RC):
        ax = Figure().subplots()
        grouped_bars(ax, t, "planner", "grip_law")
    assert [x.get_text() for x in ax.get_xticklabels()] == ["proposed\nH(G)\nn=50", "centroid\nn=40–50"]


def test_a_legend_below_clears_the_tick_labels_of_a_short_axes():
    """Fig. 18a put its legend a fixed fraction of the axes' height below them (-0.14): on its short
    axes that ran into the three-line ticks ("Ferrari–/Canny ε/n=675"). The legend is placed in
    points below the ticks and x label, so its drawn box (matplotlib's extents) clears both."""
    import pandas as pd

    from graspcampaign.report.style import grouped_bars

    planners = ["heuristic", "antipodal", "centroid", "random", "epsilon"]
    t = pd.DataFrame({"planner": planners, "n": 675, "rate_pct": 10.0, "wilson_low_pct": 5.0,
                      "wilson_high_pct": 15.0, "paper_pct": 40.0})
    for height in (3.0, 3.8, 6.0):
        with mpl.rc_context(RC):
            fig = Figure(figsize=(10.0, height), layout="constrained")
            FigureCanvasAgg(fig)
            ax = fig.subplots(1, 2, width_ratios=[1, 2.2])[0]
            ax.set_xlabel("planner")
            grouped_bars(ax, t, "planner")
            fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        legend = ax.get_legend().get_window_extent(renderer)
        for text in [*ax.get_xticklabels(), ax.xaxis.label]:
            assert not text.get_window_extent(renderer).overlaps(legend), (height, text.get_text())
        assert legend.y1 > ax.get_window_extent(renderer).y0 - 80, height  # still under its axes


def test_fig17_residual_axis_reads_plain_one_two_five_newtons():
    """Fig. 17a's log residual axis, 0.5 N (τ_F) to ~17 N at paper scale, was labelled 10⁰ and 10¹ only:
    two labels for a panel read against 0.5 N. It reads 0.5, 1, 2, 5, 10, 20."""
    from types import SimpleNamespace

    import pandas as pd

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.wrench import fig17

    records = pd.DataFrame({"trial_id": ["t"], "status": "ok", "mu": [0.3]})
    paper = SimpleNamespace(residual_settles_within_iterations=(30, 40), slip_margin_saturates_above=0.8,
                            slip_margin_saturates_from_mu=0.3, finger_force_command_n=65.0)
    run = Run(records, {"config": {"evaluator": {"tau_f_n": 0.5, "tau_t_nm": 0.025}}}, paper)
    run.memo("tables/iterations", lambda: pd.DataFrame(
        [{"trial_id": "t", "iteration": i, "residual_norm_n": r, "torque_norm_nm": 0.0,
          "slip_margin_ratio": 0.5, "normal_force_1_n": 10.0} for i, r in enumerate((3.5, 8.0, 12.0))]))
    with mpl.rc_context(RC):
        fig = Figure(figsize=(9.0, 7.0), layout="constrained")
        FigureCanvasAgg(fig)
        fig17(run, fig)
        fig.canvas.draw()
    axis = fig.axes[0].yaxis
    low, high = axis.get_view_interval()
    shown = [t.get_text() for t in (*axis.get_majorticklabels(), *axis.get_minorticklabels())
             if t.get_text() and low <= t.get_position()[1] <= high]
    assert shown == ["0.5", "1", "2", "5", "10"], shown
