"""Reports of the dynamic MSD/RK4 studies: ``gravity_settle`` (Sec. 5.4, Fig. 10, and the
integrator audit Sec. 12 lists as missing) and ``friction_mass`` (Sec. 5.5, Figs. 12-13, with the
like-for-like checks of Sec. 6.1 / Sec. 12)."""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib.ticker import FixedLocator, NullFormatter

from graspcampaign.report import style
from graspcampaign.report.document import cols
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Figure, Finding, ReportSpec, Table, Text

DECISION = ("`docs/decisions.md`, *Dynamic studies (issue 6, campaign side)*: SI body constants "
            "from the object modulus; the paper's b, k, c are in unpublished internal units")


def _first(run: Run, table: str) -> pd.DataFrame:
    data = run.aux(table)
    if not len(data):
        raise ValueError(f"the run has no `{table}` table")
    return data[data["trial_id"] == run.ok["trial_id"].iloc[0]]


# --------------------------------------------------------------------------- gravity settle
def settle_finding(run: Run) -> str:
    ok, row = run.ok, run.ok.iloc[0]
    settled = bool(ok["settled"].all())
    what = "settles on the floor" if settled else "does **not** settle within the time budget"
    like = "as" if settled == run.paper.settles else "unlike"
    text = (f"The sphere {what} ({like} the paper's "
            f"Fig. 10): squash ratio {row['squash_ratio']:.3f}, final kinetic energy "
            f"{row['final_kinetic_energy_j']:.2g} J after {row['simulated_time_s']:.2f} s. ")
    if "rk4_observed_order" in ok:
        shrink = row["energy_balance_rel_error"] / row["energy_balance_rel_error_half_dt"]
        text += (f"The integrator audit the paper lists as missing (Sec. 12) gives an observed "
                 f"order {row['rk4_observed_order']:.2f} (RK4: 4); halving the step shrinks the "
                 f"energy-balance error {shrink:.1f}-fold. ")
    return text + f"Body constants are SI, not the paper's ({DECISION})."


def fig10(run: Run, fig) -> None:
    shape, trace = _first(run, "shape"), _first(run, "settle")
    a, b = fig.subplots(1, 2)
    a.scatter(1e3 * shape["x0_m"], 1e3 * shape["z0_m"], s=6, c="0.65", label="initial")
    a.scatter(1e3 * shape["x_m"], 1e3 * shape["z_m"], s=6, c=style.SOURCE_COLOUR["simulation"],
              label="settled")
    a.axhline(1e3 * shape["z_m"].min(), color=style.PAPER, linewidth=1.0, label="floor")
    a.set(xlabel="x [mm]", ylabel="z [mm]", aspect="equal",
          title=f"(a) side view, squash ratio {run.ok['squash_ratio'].iloc[0]:.3f}")
    a.legend(loc="upper right")
    b.semilogy(trace["time_s"], np.maximum(trace["kinetic_energy_j"], 1e-12),
               color=style.SOURCE_COLOUR["simulation"])
    b.set(xlabel="time [s]", ylabel="kinetic energy [J]", title="(b) settling")


def integrator_figure(run: Run, fig) -> None:
    conv = _first(run, "step_convergence").sort_values("dt_s")
    energy = _first(run, "energy_audit")
    a, b = fig.subplots(1, 2)
    dt_us = 1e6 * conv["dt_s"].to_numpy(float)
    err = conv["max_position_error_m"].to_numpy(float)
    a.loglog(dt_us, err, "o-", label="RK4")
    a.loglog(dt_us, err[-1] * (dt_us / dt_us[-1]) ** 4, "--", color=style.CRITERION,
             label="slope 4")
    a.xaxis.set_major_locator(FixedLocator(dt_us))
    a.xaxis.set_major_formatter(lambda v, _: f"{v:.3g}")
    a.xaxis.set_minor_formatter(NullFormatter())
    a.set(xlabel="step [µs]", ylabel="largest position error at t_end [m]",
          title="(a) step-size study (reference DOP853)")
    a.legend()
    for i, (step, rows) in enumerate(energy.groupby("step", sort=False)):
        b.plot(rows["time_s"], rows["balance_error_j"], color=f"C{i}", label=f"step {step}")
    b.set(xlabel="time [s]", ylabel="energy-balance error [J]",
          title="(b) energy audit (no contact, gravity on)")
    b.legend()


GRAVITY_SETTLE = ReportSpec("gravity_settle", [
    Finding(settle_finding),
    Table("settle", "Gravity settling beside Sec. 5.4 (the paper reports it qualitatively)",
          lambda run: run.ok.assign(paper_settles=run.paper.settles), [
              *cols("shape", "nodes", "mass_kg", "paper_settles", "settled", "squash_ratio",
                    "simulated_time_s", "final_kinetic_energy_j", "max_floor_penetration_mm",
                    "dt_s", "n_steps")]),
    Figure("fig10_settle", "Fig. 10 (ours): undeformed and settled sphere; kinetic-energy "
           "decay", fig10, (10.0, 4.0)),
    Table("integrator_audit", "RK4 step-size study and energy audit on the settle body (Sec. 12 "
          "lists both as missing from the paper; no paper values to compare)",
          lambda run: run.ok, [
              *cols("shape", "nodes", "dt_s", "rk4_error_at_settle_dt_m", "rk4_observed_order",
                    "energy_balance_rel_error", "energy_balance_rel_error_half_dt",
                    "energy_increases")]),
    Text("The energy-balance error at the settle step is RK4's own damping of the stiffest mesh "
         "modes; mechanical energy growing without external power would be a defect, and the "
         "table counts such steps (`docs/decisions.md`, energy audit)."),
    Figure("integrator_audit", "RK4 global error against step size (slope-4 guide) and "
           "energy-balance error over time", integrator_figure, (10.0, 3.8)),
])


# ---------------------------------------------------------------------------- friction mass
def mass_finding(run: Run) -> str:
    ok, p = run.ok, run.paper
    stable = int((ok["dynamic_status"] == "stable").sum())
    others = ", ".join(sorted(set(ok["dynamic_status"]) - {"stable"}))
    agree = int(((ok["dynamic_status"] == "stable") == ok["qs_success"].astype(bool)).sum())
    lp0 = int((ok["lp_status_mu0"] == "feasible").sum())
    text = (f"{stable} of {len(ok)} μ × m runs settle into a stable grasp (the paper ran six "
            "of the nine and reports all stable, Sec. 5.5)")
    if stable < len(ok):
        text += (f"; the others stop with {others}: with the SI contact law a fingertip passes "
                 f"the penetration limit (deepest {ok['delta_max_mm'].max():.1f} mm, radius "
                 f"5 mm), and the quasi-static evaluator on the same contacts needs "
                 f"{ok['qs_delta_max_mm'].min():.0f}–{ok['qs_delta_max_mm'].max():.0f} mm to "
                 f"carry the weight. Nothing is rescaled ({DECISION})")
    return text + (f". The dynamic and quasi-static labels agree on {agree} of {len(ok)} cases; "
                   f"the friction-cone LP is feasible at μ = 0 in {lp0} of {len(ok)} cases "
                   + ("(the paper's ideal-sphere argument says every case)" if lp0 < len(ok)
                      else "as the paper argues") + f", on the meshed sphere's face normals. "
                   f"Representative case μ = {p.representative_mu:g}, m = "
                   f"{p.representative_mass_kg:g} kg.")


def fig12_13(run: Run, fig) -> None:
    steps, p = run.aux("steps"), run.paper
    if not len(steps):
        raise ValueError("the run has no `steps` table")
    axes = fig.subplots(1, 3)
    for i, row in enumerate(run.ok.sort_values(["mu", "mass_kg"]).itertuples()):
        s = steps[steps["trial_id"] == row.trial_id]
        rep = np.isclose(row.mu, p.representative_mu) and np.isclose(row.mass_kg,
                                                                     p.representative_mass_kg)
        kw = {"linewidth": 2.0 if rep else 0.8, "alpha": 1.0 if rep else 0.5, "color": f"C{i}",
              "label": f"μ={row.mu:g}, m={row.mass_kg:g} kg"}
        axes[0].plot(s["time_s"], s["residual_z_n"], **kw)
        axes[1].plot(s["time_s"], 1e3 * s["total_penetration_m"], **kw)
        if rep:
            for j in (1, 2, 3):
                axes[2].plot(s["time_s"], s[f"normal_force_{j}_n"], label=f"finger {j}")
    axes[0].axhline(0.0, color=style.CRITERION, linestyle="--", linewidth=1)
    axes[0].set(xlabel="time [s]", ylabel="vertical residual R_z [N]", title="(a) Fig. 12 top")
    axes[1].axhline(1e3 * p.total_penetration_below_m, color=style.PAPER, linewidth=2,
                    label=f"paper: settles below {1e3 * p.total_penetration_below_m:g} mm")
    axes[1].set(xlabel="time [s]", ylabel="total penetration [mm]", title="(b) Fig. 12 bottom")
    axes[2].set(xlabel="time [s]", ylabel="normal force [N]",
                title=f"(c) Fig. 13: μ={p.representative_mu:g}, m={p.representative_mass_kg:g} kg")
    style.legend_below(axes[0], ncol=2)
    axes[1].legend(handles=axes[1].get_legend_handles_labels()[0][-1:], loc="upper right")
    if axes[2].lines:
        axes[2].legend()


FRICTION_MASS = ReportSpec("friction_mass", [
    Finding(mass_finding),
    Table("friction_mass", "Dynamic grasp at every μ × m beside Sec. 5.5 (the paper ran six of "
          "the nine and reports all stable); final six-component wrench residual (the paper "
          "checked only the vertical part)",
          lambda run: run.ok.sort_values(["mu", "mass_kg"]).assign(paper="stable"), [
              *cols("mu", "mass_kg", "paper", "dynamic_status", "simulated_time_s",
                    "delta_max_mm", "final_residual_z_n", "wrench_force_norm_n",
                    "wrench_torque_norm_nm", "normal_force_1_n", "normal_force_2_n",
                    "normal_force_3_n")]),
    Table("like_for_like", "Like-for-like checks on the dynamic pipeline's 45°/45°/−90° contact "
          "set (open items of Sec. 6.1 and Sec. 12): the quasi-static evaluator on the same "
          "contacts, and the friction-cone LP at μ and at μ = 0 (the paper: feasible at every μ "
          "and as μ → 0)", lambda run: run.ok.sort_values(["mu", "mass_kg"]), [
              *cols("mu", "mass_kg", "dynamic_status", "qs_success", "qs_failure_check",
                    "qs_residual_norm_n", "qs_delta_max_mm", "lp_status", "lp_status_mu0")]),
    Figure("fig12_13_dynamic", "Figs. 12-13 (ours): vertical residual and total penetration for "
           "every μ × m (thick: the paper's representative case), and the per-finger normal "
           "forces of the representative case", fig12_13, (15.0, 4.6)),
])
