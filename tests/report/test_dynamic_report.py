"""friction_mass report: the case Figs. 12-13 (ours) single out, when the paper's is not run;
gravity_settle's figures against their records.

A small synthetic run (records and the ``steps`` trace as docs/records.md specifies) is rendered
through the report's own figure function; the expected case is the paper's Sec. 5.5 values.
"""

from __future__ import annotations

from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
from matplotlib.colors import to_hex
from synthetic_runs import md_table

from graspcampaign.analysis.vocabulary import label
from graspcampaign.report.document import Document
from graspcampaign.report.render import Run, render
from graspcampaign.report.studies.dynamic import (
    FRICTION_MASS,
    GRAVITY_SETTLE,
    TOTAL,
    fig10,
    fig12_13,
    integrator_figure,
    shown_case,
)

PAPER = SimpleNamespace(representative_mu=0.1, representative_mass_kg=0.4,  # Sec. 5.5, Figs. 12-13
                        total_penetration_below_m=5e-4, settle_within_iterations=50,
                        residual_amplitude_internal_units=0.1,
                        finger_forces_internal_units={"finger1": 5.0, "finger2": 0.4, "finger3": 12.0})


def friction_mass_run(mus, points=5) -> Run:
    rows = [{"trial_id": f"{p}-{mu}-{m}", "status": "ok", "model_preset": p, "mu": mu, "mass_kg": m,
             "lift_start_s": 0.2, "lift_end_s": 0.3, "simulated_time_s": 0.4, "hold_start_s": 0.3,
             "hold_end_s": 0.4, "dt_s": 1e-4, "normal_force_1_n": 0.05, "normal_force_2_n": 0.0,
             "normal_force_3_n": 3.95, "wrench_force_norm_n": 0.935, "fingertip_radius_mm": 5.0,
             "qs_delta_max_mm": 1.2, "delta_max_mm": 1.0, "final_phase": "hold"}
            for p in ("table2", "firm") for mu in mus for m in (0.2, 0.4, 0.6)]
    t = np.linspace(0.0, 0.4, points)
    steps = pd.DataFrame([{"trial_id": r["trial_id"], "time_s": x, "residual_z_n": -x,
                           "total_penetration_m": 1e-3 * x,
                           **{f"normal_force_{j}_n": j * x for j in (1, 2, 3)}}
                          for r in rows for x in t])
    run = Run(pd.DataFrame(rows), {"config": {"factors": {"model_preset": ["table2", "firm"]}}}, PAPER)
    run.memo("tables/steps", lambda: steps)
    return run


def test_the_papers_case_is_shown_when_the_run_has_it():
    assert shown_case(friction_mass_run([0.1, 0.3])) == (0.1, 0.4, True)


def test_a_run_without_the_papers_case_says_so_and_draws_its_nearest():
    run = friction_mass_run([0.3])
    assert shown_case(run) == (0.3, 0.4, False)
    fig = plt.figure()
    fig12_13(run, fig)
    right = [ax for ax in fig.axes if "Fig. 13" in ax.get_title()]
    titles = [ax.get_title() for ax in right]
    plt.close(fig)
    assert len(right) == 2 and all(len(ax.lines) == 3 for ax in right)  # three fingers, not empty
    # each finger in its vocabulary colour (Tol's muted indigo, wine, purple), not matplotlib's cycle
    assert all([to_hex(line.get_color()) for line in ax.lines] == ["#332288", "#882255", "#aa4499"]
               for ax in right)
    assert all("μ=0.3, m=0.4 kg" in t and "nearest the paper's μ=0.1, m=0.4 kg" in t for t in titles)
    assert titles[0].startswith(label("model_preset", "table2"))  # one label for a preset


def test_fig13_draws_each_finger_thinner_over_the_one_before_in_its_own_style():
    # Fig. 13 drew three solid lines of one width: fingers 1 and 3, with near-equal forces, hid each other
    fig = plt.figure()
    fig12_13(friction_mass_run([0.1]), fig)
    right = [ax for ax in fig.axes if "Fig. 13" in ax.get_title()]
    plt.close(fig)
    assert len(right) == 2
    for ax in right:
        widths = [line.get_linewidth() for line in ax.lines]
        assert len(widths) == 3 and widths[0] > widths[1] > widths[2]
        assert len({line.get_linestyle() for line in ax.lines}) == 3


def test_the_figure_caption_names_the_case_it_shows():
    # the opening named it too ("Representative case of Figs. 12-13: ..."); the caption is its one place
    run = friction_mass_run([0.3])
    ok = run.ok.assign(dynamic_status="stable", final_phase="hold", delta_max_mm=1.0, success=True,
                       qs_success=True, qs_success_unbounded=True, lp_status="feasible",
                       lp_status_mu0="feasible", lp_status_mu0_ideal="feasible", lp_mu0_reason="",
                       normal_off_radial_max_deg=1.0)
    run.__dict__["ok"] = ok  # the executed trials with their outcome columns
    text = finding(run)
    figure = next(i for i in FRICTION_MASS.items if getattr(i, "name", "") == "fig12_13_dynamic")
    assert ("the case nearest the paper's representative μ = 0.1, m = 0.4 kg (not run), μ = 0.3, "
            "m = 0.4 kg") in figure.caption(run)
    assert f"{label('model_preset', 'table2')} 3 of 3" in text and "table2 " not in text


def test_the_caption_shades_no_lift_off_when_the_case_never_lifts():
    # a run whose every preset stops before lift-off read "grey: its lift-off (in 0 of 2 presets;
    # the others never lift)", while the figure has no grey at all
    run = friction_mass_run([0.1])
    run.__dict__["ok"] = run.ok.assign(lift_start_s=np.nan, lift_end_s=np.nan)
    fig = plt.figure()
    fig12_13(run, fig)
    shaded = sum(len(ax.patches) for ax in fig.axes)
    plt.close(fig)
    figure = next(i for i in FRICTION_MASS.items if getattr(i, "name", "") == "fig12_13_dynamic")
    caption = figure.caption(run)
    assert shaded == 0 and "grey" not in caption and "0 of" not in caption
    assert caption.endswith("μ = 0.1, m = 0.4 kg; it never lifts off")
    run.__dict__["ok"] = run.ok.assign(lift_start_s=np.where(run.ok.model_preset == "firm", 0.2, np.nan))
    assert figure.caption(run).endswith("grey: its lift-off (in 1 of 2 presets; the others never lift)")


def test_the_paper_limit_legend_does_not_cover_the_paper_limit_line():
    # on a run whose penetration stays below 0.5 mm, the legend pinned upper right sat on that line
    run = friction_mass_run([0.1])
    fig = plt.figure(figsize=(15.0, 8.8))
    fig12_13(run, fig)
    fig.canvas.draw()
    for ax in (ax for ax in fig.axes if ax.get_title().endswith("Fig. 12 bottom")):
        box = ax.get_legend().get_window_extent()
        line_y = ax.transData.transform((0.0, 1e3 * PAPER.total_penetration_below_m))[1]
        assert not box.y0 <= line_y <= box.y1
    plt.close(fig)


def test_the_finding_reports_the_lp_at_the_runs_own_mu_not_only_at_zero():
    # the finding gave only the μ = 0 LP, while the table showed it infeasible at μ = 0.1 too,
    # against the paper's 'feasible at every μ'
    run = friction_mass_run([0.1, 0.3])
    ok = run.ok.assign(dynamic_status="stable", final_phase="hold", delta_max_mm=1.0, success=True,
                       qs_success=True, qs_success_unbounded=True, lp_status_mu0="infeasible",
                       lp_mu0_reason="torque_balance", lp_status_mu0_ideal="feasible",
                       normal_off_radial_max_deg=6.7)
    run.__dict__["ok"] = ok.assign(lp_status=np.where(ok.mu == 0.1, "infeasible", "feasible"))
    text = finding(run)
    assert (f"the friction-cone LP at μ = 0 is feasible in 0 of {len(ok)} on the meshed sphere and "
            f"{len(ok)} on the ideal one (table friction_cone)") in text
    cone = rendered_tables(run)["friction_cone"]  # the LP at the run's own μ: the table's
    assert cone["LP at μ"].tolist() == ["infeasible" if float(m) == 0.1 else "feasible" for m in cone["μ"]]


def test_the_finding_says_how_and_when_the_unheld_runs_ended_in_words():
    # "2 end `not_settled` (in closure)": a record token, and no word of the 0.03 s the run had
    run = friction_mass_run([0.1])
    ok = run.ok.assign(dynamic_status="not_settled", final_phase="closure", delta_max_mm=0.0,
                       success=False, qs_success=False, qs_success_unbounded=True, lp_status="feasible",
                       lp_status_mu0="feasible", lp_status_mu0_ideal="feasible", lp_mu0_reason="",
                       normal_off_radial_max_deg=1.0, simulated_time_s=0.03)
    run.__dict__["ok"] = ok
    text = finding(run)
    assert f"All {len(ok)} end: not settled by t_max (table friction_mass)" in text  # none held
    assert "`not_settled`" not in text


def finding(run: Run) -> str:
    """The friction_mass finding as the report computes it: last, after the tables it reads."""
    return next(b.markdown for b in render(FRICTION_MASS, run, Document("", "", [])).blocks
                if getattr(b, "kind", "") == "finding")


def rendered_tables(run: Run) -> dict[str, pd.DataFrame]:
    """Each friction_mass table as its Markdown page shows it (text cells, synthetic_runs.md_table)."""
    return {item.name: md_table(item.render(run)[0].md("png"), item.name)
            for item in FRICTION_MASS.items if type(item).__name__ == "Table"}


def test_the_tables_show_words_not_record_names():
    # the friction-cone table was headed `lp status mu0`, `lp mu0 reason` ... and showed `torque_balance`
    run = friction_mass_run([0.1])
    run.__dict__["ok"] = run.ok.assign(
        dynamic_status="not_settled", lp_status="feasible", lp_status_mu0="infeasible",
        lp_mu0_reason=np.where(run.ok.mass_kg == 0.2, "force_balance", "torque_balance"),
        lp_mu0_force_only_status="feasible", lp_status_mu0_ideal="feasible", qs_success=True,
        qs_success_unbounded=True, qs_failure_check="none", success=False)
    tables = rendered_tables(run)
    record_words = {"lp", "qs", "mu0", "unbounded", "wrench"}  # docs/records.md abbreviations
    for name, table in tables.items():
        assert not [h for h in table.columns if record_words & set(h.split())], name
    reasons = tables["friction_cone"]["at μ = 0 fails"]
    expected = {"force_balance": "force balance", "torque_balance": "torque balance"}  # docs/records.md
    assert sorted(reasons) == sorted(expected[v] for v in run.ok.lp_mu0_reason)
    assert set(tables["like_for_like"]["dynamic status"]) == {label("dynamic_status", "not_settled")}


def test_every_case_stays_visible_where_curves_coincide():
    # every μ × m case has the same trace here (as μ = 0.1 and 0.5 before slip): μ = 0.5 hid under 0.1
    run = friction_mass_run([0.1, 0.5], points=200)
    fig = plt.figure()
    fig12_13(run, fig)
    panels = [ax for ax in fig.axes if "Fig. 12" in ax.get_title()]
    for ax in panels:
        cases = [line for line in ax.lines if line.get_label().startswith("μ=")]
        assert len(cases) == 6  # two μ × three m
        shown = []
        for line in cases:
            start, step = line.get_markevery() or (0, 1)  # none: a marker at every point
            shown.append((line.get_marker(), set(line.get_xdata()[start::step])))
        assert len({marker for marker, _ in shown}) == len(cases)  # a marker shape per case
        for i, (_, times) in enumerate(shown):  # each case's markers at times no other case marks
            assert times and not times & set().union(*(t for j, (_, t) in enumerate(shown) if j != i))
    plt.close(fig)


def gravity_settle_run(steps: dict[str, list[float]] | None = None) -> tuple[Run, dict[str, list[float]]]:
    """A run of two integrators and their step sizes [s]: a step-size study at steps that are not
    1-2-5 µs, a settle trace released at rest (zero kinetic energy at t = 0) and a two-node shape."""
    settle = pd.DataFrame({"trial_id": ["rk4", "implicit"], "integrator": ["rk4", "implicit"],
                           "expected_order": [4, 2], "settled": True, "squash_ratio": 0.9})
    steps = steps or {"rk4": [23.6e-6, 47.2e-6, 94.3e-6, 189e-6], "implicit": [31.2e-6, 62.5e-6, 250e-6]}
    run = Run(pd.DataFrame(), {})
    run.tables["settle"] = settle
    run.memo("tables/step_convergence", lambda: pd.DataFrame(
        [{"trial_id": t, "dt_s": dt, "max_position_error_m": dt ** 2}
         for t, dts in steps.items() for dt in dts]))
    run.memo("tables/energy_audit", lambda: pd.DataFrame(
        [{"trial_id": t, "step": s, "time_s": x, "balance_error_j": x} for t in steps for s in ("dt", "dt/2")
         for x in (0.0, 0.1)]))
    run.memo("tables/settle", lambda: pd.DataFrame(
        [{"trial_id": t, "time_s": x, "kinetic_energy_j": 0.0 if x == 0 else x * 1e-3} for t in steps
         for x in np.linspace(0.0, 0.2, 11)]))
    run.memo("tables/shape", lambda: pd.DataFrame(
        [{"trial_id": t, "node": n, "x0_m": 0.0, "z0_m": n * 0.1, "x_m": 0.0, "y_m": 0.0, "z_m": n * 0.09}
         for t in steps for n in (0, 1)]))
    return run, steps


def _step_labels(fig):
    """Panel (a)'s step tick labels per axis (bottom, then the top one), drawn."""
    fig.canvas.draw()
    axis = fig.axes[0]
    return [[t for t in ax.get_xticklabels() if t.get_text()] for ax in (axis, *axis.child_axes)]


def test_the_step_axes_label_every_step_size_run_per_integrator():
    # the axis labelled only 50/100/200 µs, none of which the run used
    run, steps = gravity_settle_run()
    fig = plt.figure()
    integrator_figure(run, fig)
    labels = [[float(t.get_text()) for t in axis] for axis in _step_labels(fig)]
    plt.close(fig)
    assert labels == [pytest.approx([1e6 * dt for dt in steps[name]], rel=5e-3) for name in steps]


def test_the_step_ticks_read_as_the_report_writes_numbers():
    # 31.25 µs (the implicit settle step / 8) was labelled "31.2" (f"{v:.3g}"): ticks take the
    # report's number format, 4 significant digits or the exact value when shorter
    run, _ = gravity_settle_run({"rk4": [15.625e-6, 47.2e-6], "implicit": [31.25e-6, 62.5e-6, 250e-6]})
    fig = plt.figure()
    integrator_figure(run, fig)
    labels = [[t.get_text() for t in axis] for axis in _step_labels(fig)]
    plt.close(fig)
    assert labels == [["15.62", "47.2"], ["31.25", "62.5", "250"]]


def test_the_step_labels_of_the_two_integrators_do_not_overprint():
    # the paper-scale steps interleave (RK4 13.51-108.1 µs, implicit 31.25-250 µs): on one axis
    # "27.03" and "31.25" printed over each other, as did 54.05/62.5 and 108.1/125
    run, _ = gravity_settle_run({"rk4": [13.51e-6, 27.03e-6, 54.05e-6, 108.1e-6],
                                 "implicit": [31.25e-6, 62.5e-6, 125e-6, 250e-6]})
    fig = plt.figure(figsize=(10.0, 4.0))
    integrator_figure(run, fig)
    boxes = [t.get_window_extent() for axis in _step_labels(fig) for t in axis]
    plt.close(fig)
    assert len(boxes) == 8
    assert not [(i, j) for i in range(8) for j in range(i) if boxes[i].overlaps(boxes[j])]


def test_the_relative_energy_error_is_marked_dimensionless_and_the_plotted_one_absolute():
    # the table's "energy balance rel error" columns had no unit mark while panel (b) plots the absolute
    # error in J; docs/records.md: the rel error is the largest |balance error| over the largest energy
    run, _ = gravity_settle_run()
    run.tables["settle"] = run.tables["settle"].assign(
        dt_s=1e-4, energy_balance_rel_error=3.5e-4, energy_balance_rel_error_half_dt=2e-5)
    table, figure = (next(i for i in GRAVITY_SETTLE.items if type(i).__name__ == kind
                          and i.name == "integrator_audit") for kind in ("Table", "Figure"))
    shown = md_table(table.render(run)[0].md("png"), "integrator_audit")
    assert {"energy balance rel error [–]", "energy balance rel error half dt [–]"} <= set(shown.columns)
    fig = plt.figure()
    integrator_figure(run, fig)
    assert fig.axes[1].get_ylabel().endswith("[J]")
    plt.close(fig)
    assert "(b) plots the absolute error in J" in figure.caption


def test_the_kinetic_energy_plot_starts_at_the_first_moving_step():
    # the log plot clipped zero energy at 1e-12 J, drawing a plunge at t = 0 that no record holds
    run, _ = gravity_settle_run()
    fig = plt.figure()
    fig10(run, fig)
    lines = fig.axes[1].get_lines()
    plt.close(fig)
    trace = run.aux("settle")
    moving = trace[(trace.trial_id == "rk4") & (trace.kinetic_energy_j > 0)]
    assert len(lines) == 2
    assert list(lines[0].get_xdata()) == list(moving.time_s)
    assert list(lines[0].get_ydata()) == list(moving.kinetic_energy_j)


def held_run() -> Run:
    """Every run held (Eq. 19) at δmax 1.21 mm, its total penetration ending at 0.4 mm (the trace)."""
    run = friction_mass_run([0.1])
    run.__dict__["ok"] = run.ok.assign(
        dynamic_status="stable", final_phase="hold", delta_max_mm=1.21, success=True, qs_success=True,
        qs_success_unbounded=True, lp_status="feasible", lp_status_mu0="feasible",
        lp_status_mu0_ideal="feasible", lp_mu0_reason="", normal_off_radial_max_deg=1.0)
    return run


def test_the_papers_penetration_and_force_values_are_rows_beside_ours():
    # the paper's 0.5 mm total penetration was only a line on the figure, its settle steps, residual
    # amplitude and finger forces nowhere; δmax 1.21 mm passed as 'consistent' beside a 1 mm limit.
    # Each bound is worded as Sec. 5.5 has it: the total penetration "stabilises below 5×10^{-4} m"
    # (observed), "the design limit of 10^{-3} m per contact" (a limit); both were "the paper's target"
    values = rendered_tables(held_run())["paper_values"].set_index("quantity")
    verdict = values["verdict"]
    firm = label("model_preset", "firm")
    assert verdict[f"{firm}: final total penetration Σδ, largest over its lifted runs"] == \
        "within the paper's observed bound ≤ 0.50 mm"  # the trace ends at 1e-3 * 0.4 m = 0.4 mm
    assert verdict[f"{firm}: deepest contact δmax, largest over its lifted runs (paper: the design "
                   "limit per contact)"] == "differs: above the paper's design limit ≤ 1.00 mm"
    case = f"{firm}, μ = 0.1, m = 0.4 kg"
    assert verdict[f"{case}: steps before the settled window"].startswith("not compared: steps of another")
    assert values.loc[f"{case}: steps before the settled window", "ours"] == "3000"  # 0.3 s / 100 µs
    for j, paper in ((1, "5.000"), (2, "0.400"), (3, "12.000")):
        row = values.loc[f"{case}: finger {j} normal force at the end (paper: internal units)"]
        assert row["paper"] == paper and "internal units" in row["verdict"]


def test_the_finding_compares_penetration_and_says_what_a_hold_leaves():
    # "2 of 2 hold at δ_max 1.21 mm", no word of the 1 mm limit, of the 0.935 N left (16 % of
    # 0.6 kg × 9.81 to 48 % of 0.2 kg × 9.81) or of one finger carrying 3.95 of 4.0 N (98.75 %)
    run = held_run()
    text, tables = finding(run), rendered_tables(run)
    values = tables["paper_values"]
    verdicts = values["verdict"].str.split(":").str[0].str.split(" ").str[0].tolist()
    differ, judged = verdicts.count("differs"), verdicts.count("differs") + verdicts.count("within")
    assert f"{differ} of {judged} values compared with Sec. 5.5 differ (table paper_values)" in text
    # the trace's 0.4 mm as the paper_values table prints it (2 decimals), not "0.4"
    firm = label("model_preset", "firm")
    assert values.loc[values["quantity"] == f"{firm}: {TOTAL}", "ours"].tolist() == ["0.40"]
    # ‖F‖ sums the friction forces too, and it is the last step's value of a force that may swing from
    # step to step (a held 0.4 kg body cannot carry a steady 0.935 N: 0.12 m/s in the 0.05 s window)
    table = next(i for i in FRICTION_MASS.items if getattr(i, "name", "") == "friction_mass")
    assert ("the contact forces (normal and friction) plus the weight at the last step (one step's value: a "
            "centroid at rest over the settled window bounds the force's mean there, not its swing from "
            "step to step)") in table.caption
    assert {"final R_z [N]", "final ‖F‖ [N]", "final ‖τ‖ [N·m]"} <= set(tables["friction_mass"].columns)


def test_a_depth_not_computed_leaves_the_finding_without_penetration_words():
    # δmax missing in every lifted run: the table's row is "not computed"; the finding read that row's
    # empty verdict as a key and failed whole ("the records have no `None` column")
    run = held_run()
    run.__dict__["ok"] = run.ok.assign(delta_max_mm=np.nan)
    text = finding(run)
    # no item raised (the failures are only the notes on columns this synthetic run predates)
    assert f"{label('model_preset', 'firm')} 3 of 3" in text
    assert all("not in its frame" in f for f in run.failures)


def unexecuted_run() -> Run:
    """held_run with no executed trial, rendered."""
    run = held_run()
    run.__dict__["ok"] = run.ok.iloc[:0]
    render(FRICTION_MASS, run, Document("", "", []))
    return run


def test_a_run_without_an_executed_trial_says_so_in_its_figure():
    # Figs. 12-13 now read ends(), which took the arithmetic of an empty text column first:
    # "TypeError: Can only string multiply by an integer"
    assert "Figure fig12_13_dynamic: no executed trial" in unexecuted_run().failures


def test_a_finding_reading_a_table_not_computed_says_so():
    # the finding read the paper_values table, which its note says was not computed, and blamed a
    # column: "the records have no `paper_values` column"
    failures = unexecuted_run().failures
    assert "Table paper_values: no executed trial" in failures
    assert "The main finding: its table paper_values was not computed" in failures


def test_a_quasi_static_depth_beyond_the_fingertip_is_called_non_physical():
    run = held_run()
    table2 = run.ok.model_preset == "table2"
    run.__dict__["ok"] = run.ok.assign(qs_delta_max_mm=np.where(table2, 1693.0, 1.17), qs_success=~table2)
    like = rendered_tables(run)["like_for_like"]  # the table prints it; its caption names it
    deep = like.loc[like["model preset"] == label("model_preset", "table2"), "quasi-static δmax [mm]"]
    assert deep.tolist() == ["1693"] * int(table2.sum())
    table = next(i for i in FRICTION_MASS.items if getattr(i, "name", "") == "like_for_like")
    assert "a quasi-static δmax beyond the fingertip radius is non-physical" in table.caption


def test_the_figure_legend_lists_the_cases_before_the_lift_off_shading():
    fig = plt.figure()
    fig12_13(friction_mass_run([0.1, 0.5]), fig)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    plt.close(fig)
    assert labels[-1] == "lift-off" and labels.count("lift-off") == 1


def test_the_phases_a_status_ended_in_are_named_in_one_order():
    # the phases were joined from a set of strings, whose order changes with the hash seed, so two
    # reports of the same records could differ; and "2 end penetration limit" read as broken English
    run = friction_mass_run([0.1])
    ok = run.ok.assign(dynamic_status="penetration_limit", simulated_time_s=0.4, delta_max_mm=6.0,
                       final_phase=["lift" if i % 2 else "closure" for i in range(len(run.ok))],
                       success=False, qs_success=False, qs_success_unbounded=True, lp_status="feasible",
                       lp_status_mu0="feasible", lp_status_mu0_ideal="feasible", lp_mu0_reason="",
                       normal_off_radial_max_deg=1.0)
    run.__dict__["ok"] = ok
    assert f"All {len(ok)} end: penetration limit (table friction_mass)" in finding(run)
    phases = rendered_tables(run)["friction_mass"]["final phase"]  # each run's phase, in design order
    assert phases.tolist() == list(ok.final_phase)


def test_a_preset_without_the_shown_case_says_so_row_by_row():
    # the firm preset's μ = 0.1, m = 0.4 kg run errored: the table raised IndexError and was lost
    run = held_run()
    firm = label("model_preset", "firm")
    run.__dict__["ok"] = run.ok[~((run.ok.model_preset == "firm") & (run.ok.mass_kg == 0.4))]
    verdict = rendered_tables(run)["paper_values"].set_index("quantity")["verdict"]
    case = f"{firm}, μ = 0.1, m = 0.4 kg"
    assert verdict[f"{case}: steps before the settled window"] == \
        "not compared: this preset has no executed run of this case"
    assert verdict[f"{case}: finger 1 normal force at the end (paper: internal units)"] == \
        "not compared: this preset has no executed run of this case"


def test_labels_agree_only_where_the_dynamic_grasp_settled():
    # "Quasi-static and dynamic labels agree on 2 of 4" counted runs never settled by t_max, whose
    # dynamic success is False for want of a label, as agreeing with a quasi-static failure
    # (dynamic_check leaves them out); counted here outside the report: runs with a dynamic label only
    # (held or ended at a penetration limit; this is the paper-scale run's table2 preset)
    run = friction_mass_run([0.1])
    out = len(run.ok) - 2  # the first two have a dynamic label: held, and ended at the limit
    ok = run.ok.assign(dynamic_status=["stable", "penetration_limit"] + ["not_settled"] * out,
                       success=[True] + [False] * (out + 1), qs_success=[True, True] + [False] * out,
                       qs_success_unbounded=True,
                       lp_status="feasible", lp_status_mu0="feasible", lp_status_mu0_ideal="feasible",
                       lp_mu0_reason="", normal_off_radial_max_deg=1.0)
    run.__dict__["ok"] = ok
    assert (f"Quasi-static and dynamic labels agree on 1 of the 2 runs with a dynamic label ({out} not "
            "settled by t_max, left out; table like_for_like)") in finding(run)
    agree = rendered_tables(run)["like_for_like"]["labels agree"].tolist()
    assert agree == ["yes", "no"] + ["—"] * out
    fresh = friction_mass_run([0.1])  # a run memoises its tables
    fresh.__dict__["ok"] = ok.assign(dynamic_status="not_settled", success=False)
    assert ("No run has a dynamic label to set beside the quasi-static one: none settled by t_max "
            "(table like_for_like)") in finding(fresh)
    one = friction_mass_run([0.1])  # one run with a label read "agree on 1 of the 1 runs"
    one.__dict__["ok"] = ok.assign(dynamic_status=["stable"] + ["not_settled"] * (out + 1))
    assert (f"Quasi-static and dynamic labels agree on 1 of the 1 run with a dynamic label ({out + 1} not "
            "settled by t_max, left out; table like_for_like)") in finding(one)


def test_figs12_13_draw_their_cases_in_the_level_ramp_steps_spread_over_its_length():
    """Figs. 12-13 drew the μ × m cases in ``C{i}``, whatever the colour cycle held (matplotlib's tab10
    outside the report's style, whose C0 is a planner-like blue): each case is now the i-th of
    ``style.level_colours(n)``, the ramp ``OTHER_COLOURS`` spread dark to light over the n cases."""
    from graspcampaign.analysis.vocabulary import OTHER_COLOURS

    run = friction_mass_run([0.1, 0.3])  # two μ × three masses
    fig = plt.figure()
    fig12_13(run, fig)
    residual = [ax for ax in fig.axes if "Fig. 12 top" in ax.get_title()]
    drawn = [[to_hex(line.get_color()) for line in ax.lines if line.get_label().startswith("μ=")]
             for ax in residual]
    plt.close(fig)
    cases = len(run.ok) // 2  # per preset, two presets
    assert len(residual) == 2 and cases == 6
    spread = [OTHER_COLOURS[i] for i in (0, 1, 2, 3, 4, 5)]  # six levels: the whole ramp, one step each
    assert drawn == [spread, spread]
