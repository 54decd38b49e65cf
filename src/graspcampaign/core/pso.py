"""Global-best, inertia-weight particle swarm optimisation over a box (§4, §11), the search of
:func:`graspcampaign.core.identify.identify_body` and of the Test 1 bench fits.

Shape letters: ``p`` particles, ``d`` parameters, ``t`` swarm evaluations (iterations).

References
----------
§4 and §11 of the paper (budgets, coefficients). Kennedy, J. & Eberhart, R. (1995), "Particle
swarm optimization", Proc. ICNN'95, 1942-1948. Shi, Y. & Eberhart, R. (1998), "A modified particle
swarm optimizer", Proc. IEEE ICEC, 69-73 (inertia weight). Robinson, J. & Rahmat-Samii, Y. (2004),
"Particle swarm optimization in electromagnetics", IEEE Trans. Antennas Propag. 52(2):397-407
(absorbing walls). Engelbrecht, A. (2012), "Particle swarm optimization: Velocity
initialization", Proc. IEEE CEC (zero initial velocities).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from graspcampaign.core.pso_kernel import swarm_accept, swarm_update

__all__ = ["PsoResult", "pso_minimize"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class PsoResult:
    """Outcome of :func:`pso_minimize`.

    Attributes
    ----------
    best_x : (d,) float
        Global-best position.
    best_cost : float
        Its cost.
    history_best_cost : (t,) float
        Global-best cost after each swarm evaluation (entry 0: the initial swarm); non-increasing.
    history_n_evaluations : (t,) int
        Cumulative cost evaluations at each entry (the NFE axis of Fig. 9).
    history_best_x : (t, d) float
        Global-best position after each swarm evaluation.
    n_evaluations : int
        Total cost evaluations, ``n_particles * n_iterations``.
    final_positions : (p, d) float
        Swarm positions at the last evaluation.
    final_costs : (p,) float
        Their costs.
    """

    best_x: np.ndarray
    best_cost: float
    history_best_cost: np.ndarray
    history_n_evaluations: np.ndarray
    history_best_x: np.ndarray
    n_evaluations: int
    final_positions: np.ndarray
    final_costs: np.ndarray


def _check_bounds(lower, upper) -> tuple[np.ndarray, np.ndarray]:
    lower = np.asarray(lower, dtype=float)
    upper = np.asarray(upper, dtype=float)
    if lower.ndim != 1 or lower.shape != upper.shape:
        raise ValueError(
            f"lower and upper must have the same shape (d,), got {lower.shape} and {upper.shape}"
        )
    if not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper)) and np.all(upper > lower)):
        raise ValueError("bounds must be finite with upper > lower in every dimension")
    return lower, upper


def _evaluate(cost, positions: np.ndarray) -> np.ndarray:
    values = np.asarray(cost(positions), dtype=float)
    if values.shape != (positions.shape[0],):
        raise ValueError(
            f"cost must map (p, d) positions to (p,) values, got {values.shape} for {positions.shape}"
        )
    return np.where(np.isnan(values), np.inf, values)


def pso_minimize(
    cost,
    lower,
    upper,
    *,
    n_particles: int,
    n_iterations: int,
    rng: np.random.Generator,
    inertia: float = 0.7,
    c1: float = 1.5,
    c2: float = 1.5,
) -> PsoResult:
    """Minimise a batched cost over a box with global-best, inertia-weight PSO.

    Parameters
    ----------
    cost : callable
        ``cost(positions (p, d)) -> (p,)``: the whole swarm is evaluated in one call. NaN costs
        count as ``+inf``.
    lower, upper : (d,) float
        Box bounds.
    n_particles : int
        Swarm size p.
    n_iterations : int
        Swarm evaluations t, the initial one included, so the budget is ``p * t`` cost
        evaluations (§11 counts 8 particles x 15 iterations as 120 evaluations).
    rng : numpy.random.Generator
        Source of the initial positions and of r1, r2.
    inertia, c1, c2 : float
        Inertia weight w, cognitive and social coefficients (§11: 0.7, 1.5, 1.5).

    Returns
    -------
    result : PsoResult

    Notes
    -----
    Positions start uniform in the box with zero velocity (Engelbrecht 2012). Each iteration:
    ``v <- w v + c1 r1 (pbest - x) + c2 r2 (gbest - x)``, ``x <- x + v`` with ``r1, r2 ~ U(0, 1)``
    drawn per particle and dimension (Kennedy & Eberhart 1995; Shi & Eberhart 1998). Positions
    leaving the box are clamped to it, not wrapped, and the velocity component that crossed the
    bound is set to zero (an absorbing wall, Robinson & Rahmat-Samii 2004) so the particle does
    not keep pushing against the wall. No velocity clamp: w = 0.7, c1 + c2 = 3 lie inside the
    order-2 stability region ``c1 + c2 < 24 (1 - w^2)/(7 - 5 w)`` = 3.50 (Poli 2009).
    A personal best is replaced only on strict improvement; ties keep the earlier one.

    References
    ----------
    §4, §11; Kennedy & Eberhart (1995); Shi & Eberhart (1998); Robinson & Rahmat-Samii (2004);
    Poli, R. (2009), "Mean and variance of the sampling distribution of particle swarm
    optimizers during stagnation", IEEE Trans. Evol. Comput. 13(4):712-721.
    """
    lower, upper = _check_bounds(lower, upper)
    if int(n_particles) != n_particles or n_particles < 1:
        raise ValueError(f"n_particles must be a positive int, got {n_particles!r}")
    if int(n_iterations) != n_iterations or n_iterations < 1:
        raise ValueError(f"n_iterations must be a positive int, got {n_iterations!r}")
    n_particles, n_iterations = int(n_particles), int(n_iterations)
    n_dims = lower.shape[0]

    positions = lower + rng.random((n_particles, n_dims)) * (upper - lower)
    velocities = np.zeros_like(positions)
    costs = _evaluate(cost, positions)
    best_positions, best_costs = positions.copy(), costs.copy()
    leader = int(np.argmin(best_costs))

    history_cost = np.empty(n_iterations)
    history_x = np.empty((n_iterations, n_dims))
    history_cost[0], history_x[0] = best_costs[leader], best_positions[leader]
    for iteration in range(1, n_iterations):
        r1 = rng.random((n_particles, n_dims))
        r2 = rng.random((n_particles, n_dims))
        # the update and the personal/global bests in two compiled calls (the numpy version's
        # operations in the same order, bit for bit; ~20 numpy calls per iteration otherwise)
        positions_new = np.empty_like(positions)
        swarm_update(positions, velocities, best_positions, leader, r1, r2, lower, upper,
                     float(inertia), float(c1), float(c2), positions_new)
        positions = positions_new
        costs = _evaluate(cost, positions)
        leader = swarm_accept(costs, positions, best_positions, best_costs)
        history_cost[iteration], history_x[iteration] = best_costs[leader], best_positions[leader]

    logger.debug(
        "PSO %d particles x %d iterations: best cost %.6g",
        n_particles,
        n_iterations,
        best_costs[leader],
    )
    return PsoResult(
        best_x=best_positions[leader].copy(),
        best_cost=float(best_costs[leader]),
        history_best_cost=history_cost,
        history_n_evaluations=n_particles * np.arange(1, n_iterations + 1),
        history_best_x=history_x,
        n_evaluations=n_particles * n_iterations,
        final_positions=positions,
        final_costs=costs,
    )
