"""Report of ``wrench_balance`` (Sec. 6.4, Fig. 17): a fixed grip command, one trial per friction."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from graspcampaign.analysis.vocabulary import colour
from graspcampaign.report import style
from graspcampaign.report.document import Col
from graspcampaign.report.render import Run
from graspcampaign.report.spec import DesignLimit, Figure, Finding, GateRemoved, ReportSpec, Table, verdicts


def settle_iteration(residual: np.ndarray, iterations: np.ndarray, limit: float) -> float:
    """Return the first iteration from which ``residual`` stays below ``limit`` (nan if never)."""
    above = np.flatnonzero(residual >= limit)
    if above.size == 0:
        return float(iterations[0])
    return math.nan if above[-1] == residual.size - 1 else float(iterations[above[-1] + 1])


def _tau(run: Run) -> float:
    return float(run.config["evaluator"]["tau_f_n"])


def _traces(run: Run) -> pd.DataFrame:
    if not len(trace := run.aux("iterations")):
        raise ValueError("the run has no `iterations` trace table")
    return trace.merge(run.ok[["trial_id", "mu"]], on="trial_id").sort_values(["mu", "iteration"])


def _per_mu(run: Run) -> pd.DataFrame:
    p, tau, rows = run.paper, _tau(run), []
    for mu, tr in _traces(run).groupby("mu", sort=True):
        settle = settle_iteration(tr["residual_norm_n"].to_numpy(float), tr["iteration"].to_numpy(), tau)
        rec = run.ok[run.ok["mu"] == mu]
        rows += [{"mu": mu, "quantity": q, "paper": paper, "ours": ours, "digits": d, "n": len(rec),
                  "why": "never settles within the trace" if ours != ours else ""} for q, paper, ours, d in (
            (f"iteration from which ‖R‖ stays < {tau:g} N", p.residual_settles_within_iterations, settle, 0),
            ("final slip margin (μf_n − ‖f_t‖)/(μf_n) [–]", (p.slip_margin_saturates_above, 1.0)
             if mu >= p.slip_margin_saturates_from_mu else None, float(tr["slip_margin_rel"].iloc[-1]), 2),
            ("final finger-1 normal force [N]", p.finger_force_command_n,
             float(tr["normal_force_1_n"].iloc[-1]), 0),
            ("largest torque residual ‖τ‖ [N·m]", p.torque_residual_nm, float(tr["torque_norm_nm"].max()), 3),
            ("final residual ‖R‖ of the record [N]", (0.0, tau), float(rec["residual_norm_n"].median()), 2))]
    frame = verdicts(pd.DataFrame(rows), "ours", "paper", digits="digits")
    return frame.assign(paper=[f"{v[0]:g}–{v[1]:g}" if isinstance(v, tuple) else v for v in frame["paper"]])


def finding(run: Run) -> str:
    table, p = _per_mu(run), run.paper
    settle = table[table["quantity"].str.startswith("iteration")]
    return (f"Under the fixed {p.finger_force_command_n:g} N grip command the force residual settles below "
            f"τ_F = {_tau(run):g} N at {settle['ours'].notna().sum()} of {len(settle)} friction levels "
            f"(paper: by iteration {p.residual_settles_within_iterations[1]} at every level), and "
            f"{int((table['differs'] == True).sum())} of {len(table)} quantities differ from the paper's "  # noqa: E712
            f"statements. At Table 3's contact constants this command needs a penetration of "
            f"{run.ok['delta_max_mm'].max() / 1e3:.3g} m, far outside the contact law's range (the paper "
            "calls the study a robustness test outside the validated envelope, Sec. 6.4); we record it "
            "rather than rescale (`docs/decisions.md`, *Simulation studies (issue 4, campaign side)*: "
            "wrench_balance).")


PANELS = (("residual_norm_n", "(a) force residual ‖R‖ [N]"),
          ("torque_norm_nm", "(b) torque residual ‖τ‖ [N·m]"),
          ("slip_margin_rel", "(c) slip margin (μf_n − ‖f_t‖)/(μf_n) [–]"),
          ("normal_force_1_n", "(d) finger-1 normal force [N]"))


def fig17(run: Run, fig) -> None:
    axes, p, trace, tau = fig.subplots(2, 2, sharex=True).ravel(), run.paper, _traces(run), _tau(run)
    for ax, (col, title) in zip(axes, PANELS, strict=True):
        ax.set_title(title)
        for i, (mu, g) in enumerate(trace.groupby("mu", sort=True)):
            ax.plot(g["iteration"], g[col], color=colour("mu", mu, i), label=f"μ = {mu:g}")
    lo, hi = p.residual_settles_within_iterations
    axes[0].set_yscale("log")
    axes[0].axhline(tau, color=style.CRITERION, linestyle="--", label=f"τ_F {tau:g} N")
    axes[0].axvspan(lo, hi, color=style.PAPER, alpha=0.12, label=f"paper: settles in {lo}–{hi}")
    axes[2].axhline(p.slip_margin_saturates_above, color=style.PAPER, linestyle=":", label=f"paper: > "
                    f"{p.slip_margin_saturates_above:g} for μ ≥ {p.slip_margin_saturates_from_mu:g}")
    axes[2].axhline(0.0, color=style.CRITERION, linestyle="--", label="slip boundary")
    if trace["slip_margin_rel"].min() < -1.0:  # the seed contact can reach −100 and hides it
        axes[2].set(ylim=(-1.0, 1.1), title=PANELS[2][1] + ", clipped at −1")
    axes[3].axhline(p.finger_force_command_n, color=style.PAPER, linestyle=":",
                    label=f"paper: ≈{p.finger_force_command_n:g} N command")
    for ax in axes:
        ax.legend(loc="best")
    for ax in axes[2:]:
        ax.set_xlabel("iteration of Algorithm 2")


SPEC = ReportSpec("wrench_balance", [
    Finding(finding),
    Table("wrench_balance", "Wrench balance per friction level beside Sec. 6.4 (fixed grip command; one "
          "trial per μ; traces from tables/iterations)", _per_mu, [
              Col("mu", "μ"), Col("quantity", "quantity"), Col("paper", "paper", "digits"),
              Col("ours", "ours", "digits", why="why"),
              Col("difference", "difference", "digits", signed=True), Col("n", "n"),
              Col("verdict", "verdict")]),
    Figure("fig17_wrench", "Fig. 17 (ours): (a) force residual, (b) torque residual, (c) friction-cone slip "
           "margin, (d) finger-1 normal force per iteration; the paper's statements in black", fig17,
           (9.0, 6.0)),
    DesignLimit(["mu"], caption="Penetration against the paper's 1 mm design limit (Sec. 4); the paper notes "
                "this study's command lies far outside the validated envelope (Sec. 6.4)"),
    GateRemoved(["mu"]),
])
