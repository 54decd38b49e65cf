"""Benchmark planning + quasi-static evaluation and the PSO identification.

Run: ``python benchmarks/bench_evaluator.py``. Prints a Markdown table with ratios against
references measured in the same run (no asserts on time):

- plan + evaluation latency of the ``heuristic`` planner on the 390-node sphere with
  N_cand = 1000 (median over seeds; target < 10 ms; the paper's MATLAB figure is 43 ms per
  evaluation, §6.7), against Algorithm 2 alone on the same triples;
- the cost ratio 1750 vs 144 nodes (target <= 1.5; the paper's is 72/37 = 1.95);
- PSO at 5e4 evaluations (50 particles x 1000 iterations, target < 30 s), against the same
  evaluations done one particle at a time (timed on 2000 and scaled).
"""

from __future__ import annotations

import statistics
import time

import numpy as np
from _common import print_table

from graspcampaign.core.contact import ContactParams
from graspcampaign.core.feature import sharp_features
from graspcampaign.core.identify import identification_cost, identify_body, paper_bounds
from graspcampaign.core.mesh import make_object
from graspcampaign.core.planner import PLANNERS, evaluate_triple, plan_context

N_CAND = 1000
N_SEEDS = 100
MASS_KG = 0.4
MU = 0.3
CONTACT = ContactParams(lambda1=1.5, lambda2=0.5, n=1.0)  # bench placeholder, not an identification


def _context(n_nodes: int):
    mesh = make_object("sphere", n_nodes)
    return plan_context(mesh, sharp_features(mesh), mass=MASS_KG, mu=MU, contact=CONTACT, n_cand=N_CAND)


def _plan_latencies(ctx) -> tuple[list[float], list[float]]:
    plan, evaluate = PLANNERS["heuristic"], []
    plan_times = []
    for seed in range(N_SEEDS):
        rng = np.random.default_rng(seed)
        start = time.perf_counter()
        result = plan(ctx, rng)
        plan_times.append(time.perf_counter() - start)
        start = time.perf_counter()
        evaluate_triple(ctx, result.points, result.normals)
        evaluate.append(time.perf_counter() - start)
    return plan_times, evaluate


def main() -> None:
    rows: list[tuple[str, str, str, str, str]] = []

    contexts = {n: _context(n) for n in (144, 390, 1750)}
    for ctx in contexts.values():  # warm caches and imports
        PLANNERS["heuristic"](ctx, np.random.default_rng(0))
    medians = {}
    for n_nodes, ctx in contexts.items():
        plan_times, eval_times = _plan_latencies(ctx)
        medians[n_nodes] = statistics.median(plan_times)
        if n_nodes == 390:
            eval_median = statistics.median(eval_times)
            rows.append(
                (
                    f"heuristic plan + evaluation, sphere {ctx.n_vertices} nodes, N_cand={N_CAND} "
                    f"(median of {N_SEEDS})",
                    f"{medians[n_nodes] * 1e3:.2f} ms",
                    "Algorithm 2 alone on the chosen triple",
                    f"{eval_median * 1e3:.2f} ms",
                    f"{medians[n_nodes] / eval_median:.2f}x (target < 10 ms; paper 43 ms)",
                )
            )
    rows.append(
        (
            "plan + evaluation, 1750 nodes",
            f"{medians[1750] * 1e3:.2f} ms",
            "same at 144 nodes",
            f"{medians[144] * 1e3:.2f} ms",
            f"{medians[1750] / medians[144]:.2f}x (target <= 1.5; paper 1.95)",
        )
    )

    ctx = contexts[390]
    triple = PLANNERS["heuristic"](ctx, np.random.default_rng(0))
    start = time.perf_counter()
    identification = identify_body(
        triple.points,
        triple.normals,
        ctx.centroid,
        MASS_KG,
        MU,
        np.random.default_rng(1),
        n_particles=50,
        n_iterations=1000,
    )
    pso_time = time.perf_counter() - start

    lower, upper = paper_bounds()
    particles = lower + np.random.default_rng(2).random((2000, 6)) * (upper - lower)
    start = time.perf_counter()
    for x in particles:  # the unbatched reference: one evaluator call per particle
        identification_cost(x[None], triple.points, triple.normals, ctx.centroid, MASS_KG, MU)
    per_particle = (time.perf_counter() - start) / len(particles)
    unbatched = per_particle * identification.pso.n_evaluations
    rows.append(
        (
            f"PSO identification, {identification.pso.n_evaluations} evaluations (50 x 1000)",
            f"{pso_time:.2f} s",
            "same evaluations one particle per call (2000 timed, scaled)",
            f"{unbatched:.1f} s",
            f"{unbatched / pso_time:.1f}x faster batched (target < 30 s)",
        )
    )

    print_table(["benchmark", "ours", "reference (same run)", "reference", "ratio"], rows,
                align=["---", "---:", "---", "---:", "---"])
    print()
    print(
        f"PSO result on the 390-node sphere, m = {MASS_KG} kg, mu = {MU}: "
        f"lambda1 = {identification.contact.lambda1:.3f}, n = {identification.contact.n:.3f}, "
        f"J = {identification.best_cost:.3f}, "
        f"delta_max = {identification.equilibrium.delta_max_mm[0]:.2f} mm"
    )


if __name__ == "__main__":
    main()
