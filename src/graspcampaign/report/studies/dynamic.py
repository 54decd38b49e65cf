"""Reports of the dynamic MSD studies: ``gravity_settle`` (Sec. 5.4, Fig. 10; RK4 against the implicit
midpoint rule with the integrator audit Sec. 12 lists as missing) and ``friction_mass`` (Sec. 5.5,
Figs. 12-13, per material preset, with the like-for-like checks of Sec. 6.1 / 12)."""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib.ticker import NullFormatter

from graspcampaign.analysis.dynamic_check import UNDETERMINED
from graspcampaign.analysis.records import DESIGN_LIMIT_MM
from graspcampaign.analysis.vocabulary import FINGERS, colour, label, ordered
from graspcampaign.core.words import counted
from graspcampaign.report import format as fmt
from graspcampaign.report import style
from graspcampaign.report.document import Col, cols
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Claims, Figure, Finding, Rates, ReportSpec, Table, Text, Value

#: order of accuracy of each integrator: classical RK4; the implicit midpoint rule (theta = 1/2)
ORDER = {"rk4": 4, "implicit": 2}
#: the level of a factor in runs recorded before it existed (issues 13, 17)
BEFORE = {"integrator": "rk4", "model_preset": "table2"}


def in_order(run: Run, by: list[str], frame: pd.DataFrame | None = None, first=()) -> pd.DataFrame:
    """Rows of ``frame`` (the executed trials) sorted by the ``first`` ranks, then the design's order
    of ``by`` (a factor missing from older runs takes its old level, ``BEFORE``)."""
    t = run.ok if frame is None else frame
    t = t.assign(**{c: BEFORE[c] for c in by if c not in t and c in BEFORE})
    ranks = [t[c].map({v: i for i, v in enumerate(ordered(c, t[c], run.order.get(c, ())))}) for c in by]
    return t.iloc[np.lexsort([*first, *ranks][::-1])].reset_index(drop=True)


def _trial(run: Run, table: str, trial_id: str) -> pd.DataFrame:
    data = run.stored(f"tables/{table}")
    return data[data["trial_id"] == trial_id]


# --------------------------------------------------------------------------- gravity settle
def _settle(run: Run) -> pd.DataFrame:
    """Settle rows per integrator; each settled shape's largest node distance from the first's."""
    ok = in_order(run, ["integrator"])
    xyz = [_trial(run, "shape", t).set_index("node")[["x_m", "y_m", "z_m"]] for t in ok.trial_id]
    return ok.assign(paper_settles=run.paper.settles, expected_order=ok.integrator.map(ORDER),
                     shape_difference_max_mm=[1e3 * np.linalg.norm(s - xyz[0], axis=1).max() for s in xyz],
                     final_kinetic_energy_uj=1e6 * ok.final_kinetic_energy_j,
                     error_at_settle_dt_um=1e6 * ok.error_at_settle_dt_m, dt_us=1e6 * ok.dt_s)


def settle_finding(run: Run) -> str:
    t = run.tables["settle"]
    seconds = fmt.decimals(t.simulated_time_s)  # as the table prints them
    like = "as" if t["settled"].all() == run.paper.settles else "unlike"
    text = f"The sphere on the floor, {like} the paper's Fig. 10: " + "; ".join(
        f"{label('integrator', r.integrator)} {'settles' if r.settled else '**does not settle**'} within "
        f"{fmt.number(r.simulated_time_s, seconds)} s at {fmt.number(r.dt_over_rk4_limit, 2)}× RK4's "
        "stable step" for r in t.itertuples()) + " (table settle)"
    if len(t) > 1:  # the one formatter: plain decimals, as the tables print them
        shapes = fmt.number(t.shape_difference_max_mm.max(), sig=3)
        text += f"; the final shapes differ by at most {shapes} mm"
    return text + (f". The integrator audit (Sec. 12 lists it as missing) finds {t.energy_increases.sum()} "
                   "energy increases (table integrator_audit). One settle step per integrator; body "
                   "constants are SI, not the paper's internal units (`docs/decisions.md`, *Dynamic "
                   "studies* and *Classical references: implicit integrator and original Hunt–Crossley "
                   "damping*).")


def fig10(run: Run, fig) -> None:
    t = run.tables["settle"]
    a, b = fig.subplots(1, 2)
    shape0 = _trial(run, "shape", t.trial_id[0])
    a.scatter(1e3 * shape0["x0_m"], 1e3 * shape0["z0_m"], s=6, c="0.75", label="initial")
    for i, r in enumerate(t.itertuples()):
        shape, trace = _trial(run, "shape", r.trial_id), _trial(run, "settle", r.trial_id)
        c = colour("integrator", r.integrator, i)
        a.scatter(1e3 * shape["x_m"], 1e3 * shape["z_m"], s=12, c=c, marker="o+x"[i % 3],
                  label=f"{'settled' if r.settled else 'unsettled'}, {label('integrator', r.integrator)} "
                  f"(ratio {fmt.number(r.squash_ratio, 3)})")
        moving = trace[trace["kinetic_energy_j"] > 0]  # a log axis has no zero (the release at rest)
        b.semilogy(moving["time_s"], moving["kinetic_energy_j"], color=c,
                   label=label("integrator", r.integrator))
    a.axhline(1e3 * shape0["z0_m"].min(), color=style.PAPER, linewidth=1.0, label="floor")  # lowest rest node
    a.set(xlabel="x [mm]", ylabel="z [mm]", aspect="equal", title="(a) side view")
    b.set(xlabel="time [s]", ylabel="kinetic energy [J]", title="(b) settling")
    style.legend_below(a, ncol=2), b.legend()


def integrator_figure(run: Run, fig) -> None:
    a, b = fig.subplots(1, 2)
    a.set(xscale="log", yscale="log")  # once: a later loglog() would reset the ticks set below
    for i, r in enumerate(run.tables["settle"].itertuples()):
        conv = _trial(run, "step_convergence", r.trial_id).sort_values("dt_s")
        dt_us, err = 1e6 * conv["dt_s"].to_numpy(float), conv["max_position_error_m"].to_numpy()
        c = colour("integrator", r.integrator, i)
        a.plot(dt_us, err, "o-", color=c, label=label("integrator", r.integrator))
        a.plot(dt_us, err[0] * (dt_us / dt_us[0]) ** r.expected_order, "--", linewidth=1, color=c,
               label=f"slope {r.expected_order}")
        # every step size run, labelled on its integrator's own axis (the first below, the other
        # above): the two sets interleave (27.03 and 31.25 µs) and would overprint on one axis
        steps = a if i == 0 else a.secondary_xaxis("top")
        steps.set_xticks(dt_us, [fmt.number(v) for v in dt_us])
        steps.xaxis.set_minor_formatter(NullFormatter())
        steps.set_xlabel(f"{label('integrator', r.integrator)}: step [µs]", color=c)
        steps.tick_params(axis="x", labelcolor=c)
        for j, (step, rows) in enumerate(_trial(run, "energy_audit", r.trial_id).groupby("step", sort=False)):
            b.plot(rows["time_s"], rows["balance_error_j"], color=c, linestyle="-:"[j % 2],
                   label=f"{label('integrator', r.integrator)}, step {step}")
    a.set(ylabel="largest position error at t_end [m]",
          title="(a) step-size study (reference DOP853)")
    b.set(xlabel="time [s]", ylabel="energy-balance error [J]",
          title="(b) energy audit (no contact, gravity on)")
    a.legend(), b.legend()


STEP = [Col("dt_us", "dt [µs]", sig=3), Col("dt_over_rk4_limit", "dt / RK4's stable step", 2),
        Col("n_steps", "steps"), Col("newton_iterations_per_step", "Newton iterations per step", 2),
        Col("lu_factorizations", "LU factorisations")]
GRAVITY_SETTLE = ReportSpec("gravity_settle", [
    Finding(settle_finding),
    Table("settle", "Gravity settling per integrator beside Sec. 5.4 (the paper reports it qualitatively); "
          "squash ratio: final height over undeformed height; shape difference: largest distance of a node "
          "from its place in the first integrator's final shape", _settle, [
              *cols("nodes", "mass_kg", "paper_settles", "settled", "squash_ratio", "shape_difference_max_mm",
                    "simulated_time_s"), Col("final_kinetic_energy_uj", "final kinetic energy [µJ]", sig=3),
              *cols("max_floor_penetration_mm"), *STEP], by=["integrator"]),
    Figure("fig10_settle", "Fig. 10 (ours): undeformed and final sphere per integrator; kinetic-energy "
           "decay (log scale: the release at rest, zero energy, is not drawn)", fig10, (10.0, 4.4)),
    Table("integrator_audit", "Step-size study and energy audit of each integrator on the settle body (Sec. "
          "12 lists both as missing from the paper; no paper values to compare); expected order: RK4 4, "
          "implicit midpoint 2; energy balance rel error: the largest |energy-balance error| over the "
          "largest energy, dimensionless", lambda run: run.tables["settle"], [
              STEP[0], *cols("expected_order", "observed_order"),
              Col("error_at_settle_dt_um", "error at the settle step [µm]", sig=3),
              *cols("energy_audit_steps", "energy_audit_span_s"),
              Col("energy_balance_rel_error", "energy balance rel error [–]"),
              Col("energy_balance_rel_error_half_dt", "energy balance rel error half dt [–]"),
              *cols("energy_increases")], by=["integrator"]),
    Text("The energy-balance error at the settle step is each integrator's own truncation of the stiffest "
         "mesh modes; mechanical energy growing without external power would be a defect, and the table "
         "counts such steps (`docs/decisions.md`, *Dynamic MSD simulator*)."),
    Figure("integrator_audit", "Global error against step size (dashed: the expected order's slope) and "
           "energy-balance error over time, per integrator; (b) plots the absolute error in J, the table "
           "integrator_audit its largest value relative to the largest energy [–]", integrator_figure,
           (10.0, 4.0)),
])


# ---------------------------------------------------------------------------- friction mass
FM = ["model_preset", "mu", "mass_kg"]


def shown_case(run: Run) -> tuple[float, float, bool]:
    """The μ and m Figs. 12-13 (ours) single out: the paper's representative case if the run has it,
    else the run's nearest case (relative distance in μ and m); and whether it is the paper's."""
    p, ok = run.paper, run.ok
    paper = np.array([p.representative_mu, p.representative_mass_kg], dtype=float)
    cases = ok[["mu", "mass_kg"]].drop_duplicates().to_numpy(float)
    if not len(cases):
        raise ValueError("no executed trial")
    best = cases[np.argmin(np.abs(cases / paper - 1.0).sum(axis=1))]
    return float(best[0]), float(best[1]), bool(np.isclose(best, paper).all())


def ends(run: Run) -> pd.DataFrame:
    """The runs in design order with what Figs. 12-13 (ours) end on: the last total penetration Σδ
    [mm], the largest |R_z| [N] over the recorded steps of the settled window and the steps before
    it, and the share [%] of the summed normal force on the most loaded finger (once per run)."""
    def compute() -> pd.DataFrame:
        steps = run.stored("tables/steps")
        t, by = in_order(run, FM), steps.sort_values("time_s").groupby("trial_id")
        if not len(t):
            raise ValueError("no executed trial")
        hold = steps.merge(t[["trial_id", "hold_start_s", "hold_end_s"]], on="trial_id")
        hold = hold[hold.time_s.between(hold.hold_start_s, hold.hold_end_s)].groupby("trial_id")
        forces = t[[f"normal_force_{j}_n" for j in (1, 2, 3)]]
        return t.assign(total_penetration_mm=1e3 * t.trial_id.map(by.total_penetration_m.last()),
                        settled_amplitude_n=t.trial_id.map(hold.residual_z_n.apply(lambda r: r.abs().max())),
                        steps_to_settle=(t.hold_start_s / t.dt_s).round(),
                        top_finger_pct=100 * forces.max(axis=1) / forces.sum(axis=1))
    return run.memo("ends", compute)


TOTAL = "final total penetration Σδ, largest over its lifted runs"
DEEPEST = "deepest contact δmax, largest over its lifted runs (paper: the design limit per contact)"
#: Whose and what each penetration bound is (Sec. 5.5): "the total penetration stabilises below 5×10^{-4} m"
#: is what the paper observed, "well within the design limit of 10^{-3} m per contact" its limit
OBSERVED, LIMIT = "the paper's observed bound", "the paper's design limit"
UNITS = "not compared: the paper's forces are in its internal units, not commensurate with mg (Sec. 5.5)"


def paper_rows(run: Run):
    """Sec. 5.5's values beside ours per preset: the penetrations over every μ × m run past closure
    (the paper: the same behaviour "for all tested combinations"), the rest at the case Figs. 12-13
    (ours) show, if it held; ours is left empty, and the verdict says why, where there is none."""
    mu, mass, _ = shown_case(run)
    for preset, g in ends(run).groupby("model_preset", sort=False):
        name = label("model_preset", preset)
        at = g[np.isclose(g.mu, mu) & np.isclose(g.mass_kg, mass)]
        rep = at.iloc[0] if len(at) else None
        case = f"{name}, μ = {fmt.number(mu)}, m = {fmt.number(mass)} kg"
        lifted = g[g.final_phase != "closure"]
        never = "" if len(lifted) else "not compared: no run got past closure"
        yield Value(f"{name}: {TOTAL}", "Sec. 5.5", lambda run, g=lifted: g.total_penetration_mm.max(),
                    lambda p: (None, 1e3 * p.total_penetration_below_m), "mm", because=never,
                    bound=OBSERVED)
        yield Value(f"{name}: {DEEPEST}", "Sec. 5.5", lambda run, g=lifted: g.delta_max_mm.max(),
                    lambda p: (None, DESIGN_LIMIT_MM), "mm", because=never, bound=LIMIT)
        held = rep is not None and rep.dynamic_status == "stable"
        unheld = ("not compared: this preset has no executed run of this case" if rep is None else
                  f"not compared: no settled hold ({label('dynamic_status', rep.dynamic_status)})")
        steps = (f"not compared: steps of another size (ours {fmt.number(1e6 * rep.dt_s, sig=3)} µs; the "
                 "paper's is not published)") if held else ""
        settled = [("steps before the settled window", "steps_to_settle",
                    lambda p: p.settle_within_iterations, "", steps),
                   ("largest |R_z| in the settled window (paper: internal units)", "settled_amplitude_n",
                    lambda p: p.residual_amplitude_internal_units, "N", UNITS)]
        settled += [(f"finger {j} normal force at the end (paper: internal units)", f"normal_force_{j}_n",
                     lambda p, finger=finger: p.finger_forces_internal_units[finger], "N", UNITS)
                    for j, finger in enumerate(FINGERS, 1)]
        for quantity, column, paper, unit, why in settled:
            yield Value(f"{case}: {quantity}", "Sec. 5.5", lambda run, v=rep[column] if held else np.nan: v,
                        paper, unit, 3 if unit else 0, because=why if held else unheld)


def mass_finding(run: Run) -> str:
    values = run.tables["paper_values"]  # first: a table not computed is named as the reason
    g = ends(run)
    held = g.dynamic_status == "stable"
    presets = ", ".join(f"{label('model_preset', k)} {held[p.index].sum()} of {len(p)}"
                        for k, p in g.groupby("model_preset", sort=False))
    differ, judged = fmt.differing(values)
    compared = (f"{differ} of {judged} values compared with Sec. 5.5 differ" if judged
                else "no value of Sec. 5.5 is compared")
    text = (f"{held.sum()} of {len(g)} μ × m runs hold (`stable`) where the paper reports every run it "
            f"made stable (Sec. 5.5): {presets} (table stable_by_preset); {compared} (table paper_values). ")
    if (~held).any():
        ended = g[~held].dynamic_status.value_counts()
        how = [label("dynamic_status", k) + f" ({v})" * (len(ended) > 1) for k, v in ended.items()]
        beyond = g[~held & (g.get("delta_required_mm", np.nan) > g.fingertip_radius_mm)]
        text += f"{'The other' if held.any() else 'All'} {(~held).sum()} end: {fmt.listed(how)}" + (
            f"; in {len(beyond)} one fingertip alone would carry the weight only at δ = (mg/K)^(1/n) of "
            f"{fmt.span(beyond.delta_required_mm, ' mm')}, beyond the fingertip radius"
            if len(beyond) else "") + " (table friction_mass). "
    feasible = [(run.ok[c] == "feasible").sum() for c in ("lp_status_mu0", "lp_status_mu0_ideal")]
    labelled = g[g.dynamic_status != UNDETERMINED]  # unsettled: no dynamic label
    out = f"{len(g) - len(labelled)} not settled by t_max, left out; " if len(labelled) < len(g) else ""
    agree = (f"Quasi-static and dynamic labels agree on {(labelled.success == labelled.qs_success).sum()} of "
             f"the {counted(len(labelled), 'run')} with a dynamic label ({out}" if len(labelled) else
             "No run has a dynamic label to set beside the quasi-static one: none settled by t_max (")
    return text + (f"{agree}table like_for_like); the friction-cone LP at μ = 0 is feasible in "
                   f"{feasible[0]} of {len(run.ok)} on the meshed sphere and {feasible[1]} on the ideal one "
                   "(table friction_cone). Body constants are SI, not the paper's internal units "
                   "(`docs/decisions.md`, *Dynamic studies* and *Dynamic grasp in the paper's order*).")


def _thick(run: Run) -> str:
    """What the figure's thick case is and where its lift-off is shaded."""
    mu, mass, exact = shown_case(run)
    lifted = run.ok[np.isclose(run.ok.mu, mu) & np.isclose(run.ok.mass_kg, mass)].lift_start_s.notna()
    some = "" if lifted.all() else f" (in {lifted.sum()} of {len(lifted)} presets; the others never lift)"
    return (("the paper's representative case" if exact else "the case nearest the paper's representative μ "
             f"= {fmt.number(run.paper.representative_mu)}, m = "
             f"{fmt.number(run.paper.representative_mass_kg)} kg (not run)")
            + f", μ = {fmt.number(mu)}, m = {fmt.number(mass)} kg; "
            + (f"grey: its lift-off{some}" if lifted.any() else "it never lifts off"))


def fig12_13(run: Run, fig) -> None:
    steps, p, ok = run.aux("steps"), run.paper, ends(run)
    mu, mass, exact = shown_case(run)
    case = f"μ={fmt.number(mu)}, m={fmt.number(mass)} kg" + ("" if exact else (
        f"\n(nearest the paper's μ={fmt.number(p.representative_mu)}, "
        f"m={fmt.number(p.representative_mass_kg)} kg)"))
    axes = fig.subplots(ok.model_preset.nunique(), 3, squeeze=False)
    for ax, (preset, g) in zip(axes, ok.groupby("model_preset", sort=False), strict=True):
        colours = style.level_colours(len(g))  # the cases are levels outside every vocabulary
        for i, row in enumerate(g.itertuples()):
            s = steps[steps["trial_id"] == row.trial_id]
            rep = np.isclose([row.mu, row.mass_kg], [mu, mass]).all()
            every = max(len(g), len(s) // 8)  # markers staggered per case: coinciding curves stay visible
            kw = {"linewidth": 2.0 if rep else 0.8, "alpha": 1.0 if rep else 0.5, "color": colours[i],
                  "marker": "os^Dv<>ph*"[i % 10], "markevery": (i * every // len(g), every),
                  "label": f"μ={fmt.number(row.mu)}, m={fmt.number(row.mass_kg)} kg"}
            ax[0].plot(s["time_s"], s["residual_z_n"], **kw)
            ax[1].plot(s["time_s"], 1e3 * s["total_penetration_m"], **kw)
            if rep:
                for j, ls, lw in style.FINGER_LINES:
                    ax[2].plot(s["time_s"], s[f"normal_force_{j}_n"], label=label("finger", f"finger{j}"),
                               color=colour("finger", f"finger{j}"), ls=ls, lw=lw)
                end = row.simulated_time_s if np.isnan(row.lift_end_s) else row.lift_end_s
                for a in ax if not np.isnan(row.lift_start_s) else ():
                    a.axvspan(row.lift_start_s, end, color="0.9", zorder=0, label="lift-off")
        ax[0].axhline(0.0, color=style.CRITERION, linestyle="--", linewidth=1)
        preset = label("model_preset", preset)
        ax[0].set(xlabel="time [s]", ylabel="vertical residual R_z [N]",
                  title=f"{preset}\nvertical force residual R_z, Fig. 12 top")
        ax[1].axhline(1e3 * p.total_penetration_below_m, color=style.PAPER, linewidth=2,
                      label=f"paper: settles below {fmt.number(1e3 * p.total_penetration_below_m)} mm")
        ax[1].set(xlabel="time [s]", ylabel="total penetration Σδ [mm]",
                  title=f"{preset}\ntotal penetration, Fig. 12 bottom")
        ax[2].set(xlabel="time [s]", ylabel="normal force [N]",
                  title=f"{preset}\nper-finger normal force, Fig. 13\n{case}")
        ax[1].legend(handles=ax[1].get_legend_handles_labels()[0][-1:], loc="best")
        if ax[2].lines:
            ax[2].legend()
    handles = axes[0, 0].get_legend_handles_labels()[0]  # the cases in design order, then the shading
    fig.legend(handles=sorted(handles, key=lambda h: h.get_label() == "lift-off"), loc="outside lower center",
               ncol=6)


def _fm_table(name: str, caption: str, *columns: Col | str, **extra) -> Table:
    """A table of every preset × μ × m run in design order (``extra``: columns added first)."""
    return Table(name, caption, lambda run: in_order(run, FM).assign(**extra), columns, by=FM)


DELTA_MAX, QS = Col("delta_max_mm", "δmax [mm]", sig=3), "quasi-static"
FRICTION_MASS = ReportSpec("friction_mass", [
    Finding(mass_finding),
    Rates("stable_by_preset", "Stable, physically valid grasps per material preset beside Sec. 5.5 (the "
          "paper ran six of the nine μ × m and reports every one stable)", ["model_preset"],
          lambda p, key: 100.0, bootstrap=False),
    Claims("paper_values", "Sec. 5.5's numbers beside ours per preset (penetrations: the largest over its "
           "μ × m runs that got past closure, Fig. 12 bottom's last value; the rest at the case Figs. 12-13 "
           "(ours) show; Σδ: the sum of the three contact depths)", paper_rows),
    _fm_table("friction_mass", "Dynamic grasp at every preset × μ × m beside Sec. 5.5; stable: |R_z| < "
              "τ_F over the settled window (the paper's rule, Eq. 19 along z; Sec. 3.7); δ required: the "
              "closed form (mg/K)^(1/n) at which one fingertip alone carries the weight, beside the "
              "fingertip radius (the validity limit); final six-component wrench residual (the paper checked "
              "only the vertical part): ‖F‖ and ‖τ‖ of the contact forces (normal and friction) plus the "
              "weight at the last step (one step's value: a centroid at rest over the settled window bounds "
              "the force's mean there, not its swing from step to step); finger forces: the paper's fingers "
              "1 and 3 pinch, finger 2 nearly unloaded", "paper", "dynamic_status", "final_phase", "success",
              DELTA_MAX,
              Col("delta_required_mm", "δ required [mm]", sig=3), "fingertip_radius_mm",
              Col("final_residual_z_n", "final R_z [N]", sig=3),
              Col("wrench_force_norm_n", "final ‖F‖ [N]", sig=3),
              Col("wrench_torque_norm_nm", "final ‖τ‖ [N·m]", sig=3),
              *(Col(f"normal_force_{j}_n", f"finger {j} normal force [N]", sig=3) for j in (1, 2, 3)),
              paper="stable"),
    _fm_table("phases", "Phase timings in the order of Fig. 11: closure on the held object (first touch of "
              "each finger), lift-off, the settled window of Eq. 19 (— unless stable)", "closure_start_s",
              *(Col(f"touch_{j}_s", f"finger {j} touches [s]", sig=3) for j in (1, 2, 3)), "closure_end_s",
              "lift_end_s", "hold_start_s", "hold_end_s", "simulated_time_s"),
    _fm_table("like_for_like", "Like-for-like labels on the dynamic pipeline's 45°/45°/−90° contact set "
              "(Sec. 6.1, Sec. 12): the dynamic label and Algorithms 1-2 on the same contacts under the same "
              "preset, with and without the validity gate (δ ≤ fingertip radius); a quasi-static δmax beyond "
              "the fingertip radius is non-physical (the fingertip centre inside the object) and a failure; "
              "‖R‖ is the normal-only residual after Algorithm 2 has balanced R_z: it moves the three depths "
              "together, so each contact carries the same force, set by the weight, and ‖R‖ is the contact "
              "normals' horizontal imbalance, the same at every μ and preset; labels agree: — where the "
              "dynamic grasp did not settle by t_max (no dynamic label)", "dynamic_status",
              Col("success", "dynamic success"), Col("qs_success", f"{QS} success"), "labels_agree",
              Col("qs_success_unbounded", f"{QS} success without the gate"),
              Col("qs_failure_check", f"{QS} failing check"),
              Col("qs_residual_norm_n", f"{QS} ‖R‖ [N]", sig=3),
              Col("qs_delta_max_mm", f"{QS} δmax [mm]", sig=3),
              labels_agree=lambda d: (d.success == d.qs_success).where(d.dynamic_status != UNDETERMINED),
              ),
    _fm_table("friction_cone", "Friction-cone LP on the same contacts at μ and at μ = 0 (the paper: feasible "
              "at every μ and as μ → 0 on the sphere): why μ = 0 fails on the meshed sphere (force or torque "
              "balance), the force-only LP's torque residual, the facet normals' largest angle off radial, "
              "and the ideal sphere along the same directions", Col("lp_status", "LP at μ"),
              Col("lp_status_mu0", "LP at μ = 0"), Col("lp_mu0_reason", "at μ = 0 fails"),
              Col("lp_mu0_force_only_status", "force-only LP at μ = 0"),
              Col("lp_mu0_torque_residual_nm", "its torque residual [N·m]", sig=3),
              Col("normal_off_radial_max_deg", "largest normal off radial [°]", sig=3),
              Col("lp_status_mu0_ideal", "ideal sphere: LP at μ = 0")),
    Figure("fig12_13_dynamic", lambda run: "Figs. 12-13 (ours), one row per preset: vertical residual "
           "and total penetration for every μ × m (each its own marker, at staggered times, so curves that "
           "coincide stay visible), and the per-finger normal forces of the case drawn with a thick line, "
           + _thick(run), fig12_13, (11.0, 8.8)),
])
