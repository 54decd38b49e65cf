"""``surrogate``: the simulator-generated grasp dataset of Appendix A (one trial = one scenario).

Each trial draws its scenario from its own random stream: a shape (uniform over
``params.shapes``), mass, friction, lambda1, lambda2 and nodal damping b uniform in their ranges
(the PSO bounds of Sec. 11 for lambda1, lambda2, b); the exponent n is the configured model's
(Table 3), since Appendix A does not sample it. The heuristic planner (Algorithm 1) chooses the
grasp on the 390-node mesh and the quasi-static evaluator judges it under the drawn parameters.
Each trial also times a brief PSO pre-screening call (about 25 evaluations, Appendix A) on its own
contact set: the cost the surrogate is meant to replace.

The models themselves (64-32 MLP, 100-tree random forest) are fitted by the report section
(``graspcampaign.report.sections.surrogate``), from these records only. scikit-learn is needed
for that, and the study refuses to run without it (exit 2) so that no dataset is generated
that could not be analysed.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common
from graspcampaign.campaign.kinds.sensitivity import check_range, plan_and_evaluate
from graspcampaign.errors import UserInputError

ML_MISSING = ("the surrogate study needs scikit-learn, which is not installed: install the `ml` "
              "extra (pip install 'graspcampaign[ml]') and run it again.")


def sklearn_available() -> bool:
    """Return whether scikit-learn can be imported."""
    try:
        import sklearn  # noqa: F401
    except ImportError:
        return False
    return True


def _list(default: list) -> Any:
    return field(default_factory=lambda: list(default))


@dataclass
class SurrogateParams:
    """Scenario distribution of Appendix A and the brief PSO call's budget."""

    nodes: int = field(default=common.DEFAULT_NODES, metadata={"ge": 12})
    planner: str = field(default="heuristic", metadata={"choices": "planner"})
    shapes: list[str] = _list(["sphere", "ellipsoid", "rounded_cube", "pear", "handle"])
    mass_range_kg: list[float] = _list([0.1, 0.8])  # Appendix A
    mu_range: list[float] = _list([0.05, 0.6])  # Appendix A
    lambda1_range: list[float] = _list([0.05, 1.5])  # Sec. 11 bounds
    lambda2_range: list[float] = _list([0.05, 1.5])  # Sec. 11 bounds
    b_range: list[float] = _list([0.1, 2.0])  # Sec. 11 bounds (internal units)
    pso_particles: int = field(default=5, metadata={"ge": 1})  # 5 x 5 = 25 evaluations
    pso_iterations: int = field(default=5, metadata={"ge": 1})
    test_fraction: float = field(default=0.2, metadata={"gt": 0.0, "le": 0.5})  # 80/20 split
    hidden_layers: list[int] = _list([64, 32])  # Appendix A
    n_trees: int = field(default=100, metadata={"ge": 1})  # Appendix A

    def __post_init__(self) -> None:
        # Here, not in ``design``: params are validated by `run` before anything is written, but
        # not by `list`/`show`, which must keep working without the extra.
        if not sklearn_available():
            raise UserInputError(ML_MISSING)
        check_range("params.mass_range_kg", self.mass_range_kg, lower=1e-9)
        check_range("params.mu_range", self.mu_range)
        check_range("params.lambda1_range", self.lambda1_range, lower=1e-9)
        check_range("params.lambda2_range", self.lambda2_range, lower=1e-9)
        check_range("params.b_range", self.b_range)


def draw_scenario(params: SurrogateParams, rng: np.random.Generator) -> dict[str, Any]:
    """Draw one scenario of Appendix A from ``rng`` (the trial's stream)."""
    return {
        "shape": str(params.shapes[int(rng.integers(len(params.shapes)))]),
        "mass_kg": float(rng.uniform(*params.mass_range_kg)),
        "mu": float(rng.uniform(*params.mu_range)),
        "lambda1": float(rng.uniform(*params.lambda1_range)),
        "lambda2": float(rng.uniform(*params.lambda2_range)),
        "msd_b": float(rng.uniform(*params.b_range)),
    }


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Draw a scenario, plan and evaluate it, and time a brief PSO call on its contacts."""
    from graspcampaign.core.identify import identify_body

    study, params = inp.study, inp.params
    scenario = draw_scenario(params, rng)
    contact = common.contact_params(study, lambda1=scenario["lambda1"],
                                    lambda2=scenario["lambda2"])
    ctx, plan, out = plan_and_evaluate(study, scenario["shape"], params.nodes,
                                       scenario["mass_kg"], scenario["mu"], contact,
                                       params.planner, rng)
    start = time.perf_counter()
    pso = identify_body(plan.points, plan.normals, ctx.centroid, ctx.mass, ctx.mu, rng,
                        material=common.contact_params(study), evaluator=ctx.evaluator,
                        n_particles=params.pso_particles, n_iterations=params.pso_iterations)
    pso_time = time.perf_counter() - start
    out.update(scenario)
    out.update({
        "n_exp": contact.n, "nodes": params.nodes,
        "abs_residual_z_n": abs(out["residual_z_n"]),
        "pso_time_s": pso_time, "pso_n_evaluations": int(pso.pso.n_evaluations),
        "pso_best_cost": float(pso.best_cost), "pso_at_bound": ",".join(pso.at_bound),
    })
    return out


SURROGATE = TrialKind(
    name="surrogate",
    run=run,
    params=SurrogateParams,
    seconds_per_trial=0.03,
    description="Appendix A dataset: sampled scenarios through the evaluator (+ a brief PSO call)",
)
