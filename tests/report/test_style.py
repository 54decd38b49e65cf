"""The tick labels of every figure (report.style.tick, report.style.plain_log), its rate bars
(report.style.bars), its colour cycle and the HTML page's style sheet (report.style.CSS)."""

import re

import matplotlib as mpl
import numpy as np
import pytest
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


def test_a_line_drawn_without_a_colour_takes_the_level_ramp_not_a_planners_blue():
    """Figs. 12-13 drew their μ × m cases in matplotlib's C0, C1 (tab10): C0 #1f77b4 read as the
    proposed planner's blue (#1f5aa6). Under the report's style an uncoloured line takes the ramp of
    levels outside every vocabulary, and no step of the cycle is any vocabulary's colour."""
    from graspcampaign.analysis.vocabulary import OTHER_COLOURS

    with mpl.rc_context(RC):
        fig = Figure()
        ax = fig.subplots()
        drawn = [mpl.colors.to_hex(ax.plot([0, 1])[0].get_color()) for _ in range(6)]
    assert drawn[:2] == [OTHER_COLOURS[0], OTHER_COLOURS[3]] and sorted(drawn) == sorted(OTHER_COLOURS)
    named = {t.colour.lower() for v in VOCABULARIES.values() for t in v.values() if t.colour}
    assert named.isdisjoint(drawn)


def css_rules(media: str = "screen") -> dict[str, dict[str, str]]:
    """The page's style sheet as ``{selector: {property: value}}`` on screen, or (``print``) with the
    print rules over it."""
    from graspcampaign.report.style import CSS

    screen = re.sub(r"@media print\{((?:[^{}]*\{[^{}]*\})*)[^{}]*\}", "", CSS)
    printed = re.search(r"@media print\{((?:[^{}]*\{[^{}]*\})*)[^{}]*\}", CSS)
    rules: dict[str, dict[str, str]] = {}
    for sheet in [screen] + ([printed.group(1)] if media == "print" and printed else []):
        for selectors, body in re.findall(r"([^{}]+)\{([^{}]*)\}", sheet):
            for sel in selectors.split(","):
                rules.setdefault(sel.strip(), {}).update(
                    dict(d.strip().split(":", 1) for d in body.split(";") if d.strip()))
    return rules


def test_a_wide_tables_row_labels_and_caption_stay_in_view_when_it_scrolls():
    # the first column scrolled out of view with the rest of a wide table (Tables 6-9): it is sticky
    # on an opaque background (each row stripe's), as is the caption above the table
    rules = css_rules()
    for cell in ("th:first-child", "td:first-child", ".table p.caption"):
        assert (rules[cell]["position"], rules[cell]["left"]) == ("sticky", "0"), cell
    stripe = "tbody tr:nth-child(even)"
    assert rules["th"]["background"] and rules["td:first-child"]["background"] == "#fff"
    assert rules[f"{stripe} td:first-child"]["background"] == rules[stripe]["background"]


def _contrast(fore: str, back: str) -> float:
    """W3C WCAG 2.1 contrast ratio (L1 + 0.05) / (L2 + 0.05) of two #rrggbb colours, from the relative
    luminance its definition of "relative luminance" gives (sRGB, threshold 0.03928)."""
    def luminance(colour: str) -> float:
        rgb = [int(colour.lstrip("#")[i:i + 2], 16) / 255 for i in (0, 2, 4)]
        r, g, b = (c / 12.92 if c <= 0.03928 else ((c + 0.055) / 1.055) ** 2.4 for c in rgb)
        return 0.2126 * r + 0.7152 * g + 0.0722 * b

    hi, lo = sorted((luminance(fore), luminance(back)), reverse=True)
    return (hi + 0.05) / (lo + 0.05)


def _hex(colour: str) -> str:
    """``#rgb`` or ``#rrggbb`` as ``#rrggbb``."""
    c = colour.strip().lstrip("#")
    return "#" + (c if len(c) == 6 else "".join(2 * x for x in c))


def test_contrast_checker_matches_known_ratios():
    # WebAIM's contrast checker: #777777 on #ffffff 4.48:1, #767676 on #ffffff 4.54:1, black on white 21:1
    assert round(_contrast("#777777", "#ffffff"), 2) == 4.48
    assert round(_contrast("#767676", "#ffffff"), 2) == 4.54
    assert _contrast("#000000", "#ffffff") == pytest.approx(21.0)


def test_every_text_colour_of_the_page_reads_at_wcag_aa_contrast():
    """Each text colour of the style sheet against the background it sits on meets WCAG 2.1 AA's
    4.5:1 for normal text (the caption's CSV path, #777 on the page's #fafafa, read 4.3:1)."""
    rules = css_rules()
    page = _hex(rules["body"]["background"])
    colour = {sel: _hex(rules[sel]["color"]) for sel in rules if "color" in rules[sel]}
    fill = {sel: _hex(rules[sel]["background"]) for sel in rules if "background" in rules[sel]}
    # the navigation's section links: white at 85% opacity over the bar
    bar = [int(fill["nav"][i:i + 2], 16) for i in (1, 3, 5)]
    toc = "#" + "".join(f"{round(0.85 * 255 + 0.15 * c):02x}" for c in bar)
    pairs = {"body text": (colour["body"], page), "CSV path": (colour["p.caption .csv"], page),
             "note": (colour["p.note"], page), "provenance": (colour["dl.provenance"], page),
             "footer": (colour["footer"], page), "figure caption": (colour["figcaption"], fill["figure"]),
             "header cell": (colour["body"], fill["th"]),
             "striped row": (colour["body"], fill["tbody tr:nth-child(even)"]),
             "navigation": (colour["nav a"], fill["nav"]), "sections in the bar": (toc, fill["nav"]),
             "contents link": (colour[".contents a"], fill[".contents"]),
             **{f"{s} banner": (colour[f".source-{s}"], fill[f".source-{s}"])
                for s in ("simulation", "virtual", "measured", "mixed")}}
    low = {what: round(_contrast(*p), 2) for what, p in pairs.items() if _contrast(*p) < 4.5}
    assert low == {}


def test_the_printed_page_drops_the_controls_and_keeps_tables_and_figures_whole():
    """In print the navigation and zoom checkboxes go, nothing is sticky or scrolls (a scrolled wide
    table printed cut at the page edge), and figures and table rows are not split across pages."""
    from graspcampaign.report.style import CSS

    screen, printed = css_rules(), css_rules("print")
    assert screen["nav"]["position"] == "sticky" and printed["nav"]["display"] == "none"
    assert printed[".zoom"]["display"] == "none"
    assert screen[".table"]["overflow-x"] == "auto" and printed[".table"]["overflow"] == "visible"
    assert all(printed[s]["position"] == "static" for s in ("th:first-child", "td:first-child"))
    assert printed["figure"]["break-inside"] == printed["tr"]["break-inside"] == "avoid"
    assert printed["thead"]["display"] == "table-header-group"
    assert screen[".zoom:focus-visible+label img"]["outline"].startswith("3px solid")  # Tab reaches it
    assert re.search(r"@page\{size:landscape;", CSS)  # 14-17 columns do not fit A4 portrait


def test_a_long_tables_header_row_stays_in_view_and_a_wide_table_is_compact():
    """A long table (class ``long``) scrolls in a box under a sticky header row (test2_classifier's
    header scrolled out of view above 44 rows); in print it is whole. A wide one is set compact."""
    screen, printed = css_rules(), css_rules("print")
    assert (screen[".long"]["max-height"], screen[".long"]["overflow"]) == ("90vh", "auto")
    assert (screen[".long thead th"]["position"], screen[".long thead th"]["top"]) == ("sticky", "0")
    assert printed[".long"]["max-height"] == "none" and printed[".long thead th"]["position"] == "static"
    assert screen[".wide table"]["font-size"] == "12.5px"


def _confusion_axes(study: str) -> list:
    """The confusion-matrix axes of ``study``'s figure (test2_grasp: Fig. 31c; dynamic_check: one
    per preset and label pair) over counts 0, 1, 9 and 20, drawn on an Agg canvas in the report's
    style."""
    import pandas as pd

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies import dynamic_check, flags

    with mpl.rc_context(RC):
        fig = Figure(figsize=(6.0, 3.0), layout="constrained")
        FigureCanvasAgg(fig)
        if study == "test2_grasp":  # tn 0, fn 1 / fp 9, tp 20
            outcomes = [(False, True)] + [(True, False)] * 9 + [(True, True)] * 20
            records = pd.DataFrame({"belief_error": "paper", "planner": "heuristic", "source": "virtual",
                                    "predicted_stable": [p for p, _ in outcomes],
                                    "success": [s for _, s in outcomes]})
            run = Run(records, {"study": study, "source": "virtual"})
            run.memo("hardware", lambda: records)
            flags.confusion(None, "predicted stable")(run, fig.add_subplot())
        else:
            run = Run(pd.DataFrame(), {"study": study})
            run.tables["kappa"] = pd.DataFrame({
                "comparison": ["source", "preset"], "scope": dynamic_check.CLAIM_SHAPE,
                "model_preset": "table2", "both_success": [0, 20], "qs_only": [1, 9],
                "dynamic_only": [9, 1], "both_failure": [20, 0], "not_settled": 0})
            dynamic_check.confusion_figure(run, fig)
        fig.canvas.draw()
        pixels = np.asarray(fig.canvas.buffer_rgba())
    return [(ax, pixels) for ax in fig.axes if ax.images]


@pytest.mark.parametrize("study", ["test2_grasp", "dynamic_check"])
def test_confusion_cells_belong_to_no_planner_and_their_counts_read_at_wcag_aa(study):
    """Figs. 31c/36c and dynamic_check's matrices were shaded in matplotlib's Blues, the proposed
    planner's family beside its bars, their counts white above 0.6 × or 1/2 × the largest count. Both
    draw one way now: every cell's rendered colour (read back from the canvas) lies outside the hues of
    the proposed planner and its ablations, and its count reads at WCAG 2.1 AA, 4.5:1 or more."""
    import colorsys

    from graspcampaign.analysis.vocabulary import PLANNERS

    blues = [colorsys.rgb_to_hsv(*mpl.colors.to_rgb(PLANNERS[k].colour))[0]
             for k in ("heuristic", "no_s1", "no_s2", "no_s3", "no_pc", "no_pe", "no_pso")]
    band = (min(blues) - 15 / 360, max(blues) + 15 / 360)
    drawn = _confusion_axes(study)
    assert len(drawn) == {"test2_grasp": 1, "dynamic_check": 2}[study]
    counts, low, planner_hue = [], [], []
    for ax, pixels in drawn:
        for t in ax.texts:
            x, y = ax.transData.transform(t.get_position())
            rgb = pixels[pixels.shape[0] - int(round(y)) + 6, int(round(x)) - 12, :3] / 255  # beside the text
            cell = mpl.colors.to_hex(rgb)
            counts.append(t.get_text())
            if _contrast(mpl.colors.to_hex(t.get_color()), cell) < 4.5:
                low.append((t.get_text(), t.get_color(), cell))
            hue, saturation, _ = colorsys.rgb_to_hsv(*rgb)
            if saturation > 0.1 and band[0] <= hue <= band[1]:
                planner_hue.append((t.get_text(), cell))
    assert sorted(counts, key=int) == sorted(["0", "1", "9", "20"] * len(drawn), key=int)
    assert not low, low
    assert not planner_hue, planner_hue


def test_the_papers_mark_inside_a_bar_is_drawn_over_it_on_every_planners_colour():
    """Fig. 31a's centroid bar (ours 60 %) hid the paper's 44.9 % line behind it, only the diamond
    showing (Fig. 25a's inset, Fig. 26a and c alike). Drawn over a bar of each planner's colour, the
    paper's line inside it shows, off its diamond, as near-black pixels on the canvas, beside pixels that
    contrast with the bar at 3:1 or more (WCAG 2.1's least for graphics), dark bars as light."""
    from graspcampaign.analysis.vocabulary import PLANNERS

    hidden = []
    for key, planner in PLANNERS.items():
        with mpl.rc_context(RC):
            fig = Figure(figsize=(3.0, 3.0), dpi=100)
            FigureCanvasAgg(fig)
            ax = fig.add_subplot()
            bars(ax, [0.0], [80.0], [70.0], [90.0], [planner.colour], paper=[45.0])
            ax.set(ylim=(0, 105))
            fig.canvas.draw()
            pixels = np.asarray(fig.canvas.buffer_rgba())[..., :3]
            x, y = ax.transData.transform((0.2, 45.0))  # right of the diamond and the whisker
        row = pixels.shape[0] - int(round(y))
        column = pixels[row - 6:row + 7, int(round(x))]
        darkest = column[column.sum(axis=1).argmin()]
        ratios = [_contrast(mpl.colors.to_hex(p / 255), planner.colour) for p in column]
        if darkest.max() > 60 or max(ratios) < 3.0:
            hidden.append((key, planner.colour, darkest.tolist(), round(max(ratios), 2)))
    assert not hidden, hidden
