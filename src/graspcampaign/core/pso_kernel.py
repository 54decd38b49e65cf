"""Compiled (numba) swarm update of :func:`graspcampaign.core.pso.pso_minimize`.

A PSO iteration is a handful of elementwise operations on (p, d) arrays; in numpy each is a
separate call costing ~1 us whatever its size, ~40-55 us per iteration for 40 particles x 6
parameters -- as much as a fast cost function (the §7.5 trace cost runs 1250 iterations x ~120
restarts). These kernels do the same operations in the same order, so the swarm is the same
bit for bit (tests hold them to the numpy update).

Shape letters: ``p`` particles, ``d`` parameters.

References
----------
Kennedy, J. & Eberhart, R. (1995); Shi, Y. & Eberhart, R. (1998) (inertia weight); Robinson, J.
& Rahmat-Samii, Y. (2004) (absorbing walls) -- as in :mod:`graspcampaign.core.identify`.
"""

from __future__ import annotations

from numba import njit


@njit(cache=True)
def swarm_update(positions, velocities, best_positions, leader, r1, r2, lower, upper, inertia,
                 c1, c2, new_positions):
    """Move the swarm: ``v <- w v + c1 r1 (pbest - x) + c2 r2 (gbest - x)``, ``x <- x + v``.

    Parameters
    ----------
    positions, best_positions : (p, d) float
        Current and personal-best positions.
    velocities : (p, d) float
        Velocities, updated in place; the component that crossed a bound is set to zero.
    leader : int
        Row of the global best in ``best_positions``.
    r1, r2 : (p, d) float
        Uniform draws.
    lower, upper : (d,) float
        Box; moved positions are clamped to it.
    inertia, c1, c2 : float
        w, c1, c2.
    new_positions : (p, d) float
        Output: the clamped new positions.
    """
    n_particles, n_dims = positions.shape
    for i in range(n_particles):
        for j in range(n_dims):
            x = positions[i, j]
            v = (inertia * velocities[i, j] + c1 * r1[i, j] * (best_positions[i, j] - x)
                 + c2 * r2[i, j] * (best_positions[leader, j] - x))
            moved = x + v
            clamped = min(max(moved, lower[j]), upper[j])
            new_positions[i, j] = clamped
            velocities[i, j] = 0.0 if clamped != moved else v


@njit(cache=True)
def swarm_accept(costs, positions, best_positions, best_costs):
    """Keep strict improvements as personal bests (in place); return the global best's row
    (the first of equal costs, as ``numpy.argmin``)."""
    leader = 0
    for i in range(costs.size):
        if costs[i] < best_costs[i]:
            best_costs[i] = costs[i]
            for j in range(positions.shape[1]):
                best_positions[i, j] = positions[i, j]
        if best_costs[i] < best_costs[leader]:
            leader = i
    return leader
