"""Tests of graspcampaign.core.pso_kernel: the compiled swarm update against numpy's.

Reference: the numpy loop that :func:`graspcampaign.core.pso.pso_minimize` ran before the
update was compiled (kept here verbatim); the swarm must be the same bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest

from graspcampaign.core.identify import paper_bounds
from graspcampaign.core.pso import pso_minimize


def _pso_numpy(cost, lower, upper, n_particles, n_iterations, rng, inertia=0.7, c1=1.5,
               c2=1.5):
    """pso_minimize's loop as numpy operations (the implementation before the kernel)."""
    n_dims = lower.shape[0]
    positions = lower + rng.random((n_particles, n_dims)) * (upper - lower)
    velocities = np.zeros_like(positions)
    costs = np.where(np.isnan(c := np.asarray(cost(positions), float)), np.inf, c)
    best_positions, best_costs = positions.copy(), costs.copy()
    leader = int(np.argmin(best_costs))
    history = [best_costs[leader]]
    for _ in range(1, n_iterations):
        r1 = rng.random((n_particles, n_dims))
        r2 = rng.random((n_particles, n_dims))
        velocities = (inertia * velocities + c1 * r1 * (best_positions - positions)
                      + c2 * r2 * (best_positions[leader] - positions))
        moved = positions + velocities
        positions = np.clip(moved, lower, upper)
        velocities = np.where(positions != moved, 0.0, velocities)
        costs = np.where(np.isnan(c := np.asarray(cost(positions), float)), np.inf, c)
        improved = costs < best_costs
        best_positions[improved] = positions[improved]
        best_costs[improved] = costs[improved]
        leader = int(np.argmin(best_costs))
        history.append(best_costs[leader])
    return best_positions[leader], np.array(history), positions, costs


LOWER, UPPER = paper_bounds()
TARGET = UPPER + 0.3 * (UPPER - LOWER) * np.array([1, -1, 0, 1, -2, 0])  # some corners hit


def _rastrigin(x):
    z = 4.0 * (x - LOWER) / (UPPER - LOWER) - 2.0
    return 10 * z.shape[1] + np.sum(z**2 - 10 * np.cos(2 * np.pi * z), axis=1)


def _plateau_with_nan(x):
    # ties (a flat region) and NaN costs (counted as +inf) exercise the acceptance rules
    out = np.round(np.sum((x - TARGET) ** 2, axis=1), 2)
    out[x[:, 0] > 1.4] = np.nan
    return out


@pytest.mark.parametrize("cost", [_rastrigin, _plateau_with_nan,
                                  lambda x: np.sum((x - TARGET) ** 2, axis=1)])
@pytest.mark.parametrize("n_particles, n_iterations", [(8, 15), (40, 300)])
def test_pso_minimize_is_the_numpy_swarm_bit_for_bit(cost, n_particles, n_iterations):
    res = pso_minimize(cost, LOWER, UPPER, n_particles=n_particles, n_iterations=n_iterations,
                       rng=np.random.default_rng(11))
    best_x, history, positions, costs = _pso_numpy(cost, LOWER, UPPER, n_particles,
                                                   n_iterations, np.random.default_rng(11))
    np.testing.assert_array_equal(res.best_x, best_x)
    np.testing.assert_array_equal(res.history_best_cost, history)
    np.testing.assert_array_equal(res.final_positions, positions)
    np.testing.assert_array_equal(res.final_costs, costs)
