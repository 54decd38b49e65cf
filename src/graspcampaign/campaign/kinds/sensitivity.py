"""``sensitivity``: the three parameter sweeps of Sec. 6.6 (Fig. 19) as one trial list.

Panels (the ``panel`` column):

``mu_mass``
    friction mu x object mass m; each soft body (shape x nodes x m x mu) is identified by PSO
    (Sec. 4) exactly as in the ``quasi_static`` kind, and the planner is judged under it.
``lambda``
    Hunt-Crossley scale factors lambda1 x lambda2 set directly (no identification), exponent n
    from the configured model (Table 3), at a fixed mass and friction.
``n_b``
    exponent n x nodal damping b (in the simulator's internal units, as Sec. 11's PSO bound), lambda1
    and lambda2 from the configured model, at the same fixed mass and friction; the runtime panel of
    Fig. 19c. ``b`` is an MSD constant (Sec. 2): the quasi-static evaluator never reads it, so this
    axis is inert by construction (recorded, not hidden).

One trial plans one grasp with ``params.planner`` (heuristic by default) on ``params.shape`` (the
390-node sphere by default, Sec. 6.2) and evaluates it with Algorithms 1-2. Grid levels are
``params.levels`` equally spaced values over each axis range (the paper's ranges by default);
``study.seeds`` seeds per cell.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common, quasi_static
from graspcampaign.campaign.schema import NODES, config_field
from graspcampaign.core.plausible import PLAUSIBLE
from graspcampaign.core.words import meant
from graspcampaign.errors import ConfigError

PANELS = ("mu_mass", "lambda", "n_b")
"""Sweep panels of Fig. 19 (a), (b), (c)."""

PANEL_AXES = {
    "mu_mass": ("mu", "mass_kg"),
    "lambda": ("lambda1", "lambda2"),
    "n_b": ("n_exp", "b"),
}
"""Panel -> (x factor, y factor) as recorded."""


def check_range(key: str, values: list[float], lower: float = 0.0) -> tuple[float, float]:
    """Return ``(low, high)`` of a two-element range, or raise a ConfigError naming ``key``."""
    if len(values) != 2 or not float(values[0]) < float(values[1]) or float(values[0]) < lower:
        raise ConfigError(f"{key} must be [low, high] with {lower} <= low < high, got {values!r}.")
    return float(values[0]), float(values[1])


def levels(low: float, high: float, n: int) -> list[float]:
    """Return ``n`` equally spaced grid values from ``low`` to ``high`` (rounded to 1e-4)."""
    return [round(float(v), 4) for v in np.linspace(low, high, n)]


@dataclass
class SensitivityParams:
    """Fixed parameters and grid of the sensitivity sweeps (Sec. 6.6)."""

    nodes: int = config_field(common.DEFAULT_NODES, **NODES)
    shape: str = config_field("sphere", choices="shape")
    planner: str = config_field("heuristic", choices="planner")
    levels: int = config_field(12, ge=2)  # grid values per axis
    panels: list[str] = config_field(list(PANELS))
    mu_range: list[float] = config_field([0.05, 0.6], **PLAUSIBLE["mu"].meta())  # Sec. 6.6
    mass_range_kg: list[float] = config_field([0.1, 0.8], **PLAUSIBLE["mass_kg"].meta())  # Sec. 6.6
    lambda_range: list[float] = config_field([0.1, 1.5])  # Sec. 6.6
    n_range: list[float] = config_field([0.1, 1.0])  # Sec. 11 PSO bounds
    b_range: list[float] = config_field([0.1, 2.0])  # Sec. 11 PSO bounds (internal units)
    fixed_mass_kg: float = config_field(0.4, gt=0.0)  # panels b, c
    fixed_mu: float = config_field(0.3, ge=0.0)  # panels b, c

    def __post_init__(self) -> None:
        unknown = [p for p in self.panels if p not in PANELS]
        if unknown or not self.panels:
            raise ConfigError(f"params.panels has unknown panel {unknown[0]!r}; "
                              f"{meant(unknown[0], PANELS)}allowed: {', '.join(PANELS)}." if unknown else
                              "params.panels must name at least one panel.")
        check_range("params.mu_range", self.mu_range)
        check_range("params.mass_range_kg", self.mass_range_kg, lower=1e-9)
        check_range("params.lambda_range", self.lambda_range, lower=1e-9)
        check_range("params.n_range", self.n_range, lower=1e-9)
        check_range("params.b_range", self.b_range)


def design(study, params: SensitivityParams) -> list[dict[str, Any]]:
    """Return every trial of the selected panels: cell x seed, panel by panel."""
    grids = {
        "mu_mass": (levels(*params.mu_range, params.levels),
                    levels(*params.mass_range_kg, params.levels)),
        "lambda": (levels(*params.lambda_range, params.levels),) * 2,
        "n_b": (levels(*params.n_range, params.levels), levels(*params.b_range, params.levels)),
    }
    rows = []
    for panel in params.panels:
        x_name, y_name = PANEL_AXES[panel]
        xs, ys = grids[panel]
        for y in ys:
            for x in xs:
                for seed in range(study.seeds):
                    row = {"panel": panel, "shape": params.shape, "planner": params.planner,
                           "mass_kg": params.fixed_mass_kg, "mu": params.fixed_mu}
                    row.update({x_name: x, y_name: y, "seed": seed})
                    rows.append(row)
    return rows


def body_key(factors: dict[str, Any]) -> dict[str, Any]:
    """One soft body per (shape, m, mu); identified only in the mu x m panel."""
    return {"shape": factors["shape"], "nodes": factors.get("nodes"),
            "mass_kg": factors["mass_kg"], "mu": factors["mu"],
            "contact": "identified" if factors["panel"] == "mu_mass" else "configured"}


def prepare(study, params, body, rng: np.random.Generator) -> dict[str, Any]:
    """PSO identification for the mu x m bodies (as ``quasi_static``); nothing for the others."""
    if body["contact"] == "configured":
        return {"identified": False}
    return quasi_static.prepare(study, params, body, rng)


def plan_and_evaluate(study, shape: str, nodes: int, mass: float, mu: float, contact,
                      planner: str, rng: np.random.Generator, n_cand: int | None = None,
                      evaluator=None) -> tuple[Any, Any, dict[str, Any]]:
    """Plan one grasp with ``planner`` and judge it under ``contact``; return ctx, plan, record.

    The record holds the ``quasi_static`` outcome columns, both readings of the residual check,
    the contact parameters used and the timings (``plan_time_s``: Algorithm 1 with the candidate
    search and Algorithm 2; ``context_time_s``: the per-body preparation, cached per worker).
    """
    ctx, plan, truth, context_time, plan_time, _ = quasi_static.plan_and_judge(
        study, shape, nodes, mass, mu, contact, planner, rng, n_cand, evaluator)
    out = quasi_static.plan_record(ctx, plan, truth)
    out.update({
        "loop_capped": bool(truth.iterations[0] >= ctx.evaluator.n_max),
        "n_cand": ctx.n_cand,
        "contact_lambda1": contact.lambda1, "contact_lambda2": contact.lambda2,
        "contact_n_exp": contact.n, "k_contact_n_per_mm_n": contact.k_n_per_mm_n,
        "plan_time_s": plan_time, "context_time_s": context_time,
    })
    return ctx, plan, out


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Plan and evaluate one cell's grasp under the panel's contact parameters."""
    f, study, params = inp.trial.factors, inp.study, inp.params
    panel = f["panel"]
    if panel == "mu_mass":
        contact = quasi_static.body_contact(study, inp.prepared)
    elif panel == "lambda":
        contact = common.contact_params(study, lambda1=f["lambda1"], lambda2=f["lambda2"])
    else:
        contact = common.contact_params(study, n=f["n_exp"])
    _, _, out = plan_and_evaluate(study, f["shape"], params.nodes, f["mass_kg"], f["mu"],
                                  contact, f["planner"], rng)
    out["identified"] = bool(inp.prepared and inp.prepared.get("identified"))
    out["pso_at_bound"] = common.at_bound_text(inp.prepared)
    out["nodes"] = params.nodes
    out["runtime_ms"] = 1e3 * out["plan_time_s"]
    return out


SENSITIVITY = TrialKind(
    name="sensitivity",
    run=run,
    params=SensitivityParams,
    seconds_per_trial=0.012,
    body_key=body_key,
    prepare=prepare,
    design=design,
    trial_keys=("panel",),  # the figure panel a design row belongs to
    description="Fig. 19 sweeps: mu x m (identified), lambda1 x lambda2 and n x b (set directly)",
    stages="a PSO identification of each mu x m body before the trials (at paper scale about as "
           "long as the trials; docs/decisions.md)",
)
