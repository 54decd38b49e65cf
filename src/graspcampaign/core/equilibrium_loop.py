"""Compiled (numba) Algorithm 2 loop of :func:`graspcampaign.core.equilibrium.evaluate_grasps`.

In numpy every one of Algorithm 2's N_max = 100 iterations is ~15 array calls on (b, 3) arrays,
~1 us each whatever b: about 4 ms per evaluation of a 50-particle PSO swarm, paid 1000 times per
converged identification (§11) and once per plan in every quasi-static study. The loop is the
same for every candidate and candidates never interact, so this kernel runs each candidate's
loop on its own, with the numpy version's operations in the same order (sums over the three
contacts left to right, as ``numpy.sum`` does): depths and iteration counts are the same bit for
bit wherever numpy's ``power`` rounds as libm's (tests hold it to the numpy loop, which stays the
reference and the traced path; docs/decisions.md says what holds on AVX-512 machines).

Shape letters: ``b`` candidates, ``c = 3`` contacts.

References
----------
Algorithm 2 and §11 of the paper (seed, N_max, update rule), as in
:mod:`graspcampaign.core.equilibrium`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from graspcampaign.core.contact import MM_PER_M


@njit(cache=True, error_model="numpy")
def algorithm2_depths(k, n, force_z, gradient_z, weight, seed_depth, n_max, alpha, eps):
    """Run Algorithm 2 lines 3-7 on every candidate; return its depths and last change.

    Parameters
    ----------
    k : (b,) float
        Contact stiffness K [N*mm^-n].
    n : (b,) float
        Contact exponent [-].
    force_z : (b, 3) float
        z-components of the push directions ``n_hat = -n_out`` [-].
    gradient_z : (b, 3) float
        The same with near-horizontal directions set to 0 (``CandidateBatch.direction_z``) [-].
    weight : (b,) float
        m g [N].
    seed_depth : float
        Initial penetration [m].
    n_max : int
        Iterations N_max.
    alpha, eps : float
        Step gain [-] and regulariser [N/m].

    Returns
    -------
    depths : (b, 3) float
        Penetrations after the loop [m].
    last_change : (b,) int
        Last iteration that changed the candidate's depths (0: none did).

    Notes
    -----
    A candidate whose depths did not change is at a floating-point fixed point, so its later
    iterations are no-ops; its loop stops there (the numpy loop stops when every candidate has).
    """
    n_batch = k.shape[0]
    depths = np.empty((n_batch, 3))
    last_change = np.zeros(n_batch, dtype=np.int64)
    forces = np.empty(3)
    updated = np.empty(3)
    for b in range(n_batch):
        d = depths[b]
        d[:] = seed_depth
        # one-sided stiffness at delta = 0 (see equilibrium._Loop)
        at_zero = MM_PER_M * k[b] if n[b] == 1.0 else 0.0
        for iteration in range(1, n_max + 1):
            for c in range(3):
                forces[c] = k[b] * (d[c] * MM_PER_M) ** n[b]
            residual_z = (forces[0] * force_z[b, 0] + forces[1] * force_z[b, 1]
                          + forces[2] * force_z[b, 2]) - weight[b]
            g0 = gradient_z[b, 0] * _stiffness(d[0], forces[0], n[b], at_zero)
            g1 = gradient_z[b, 1] * _stiffness(d[1], forces[1], n[b], at_zero)
            g2 = gradient_z[b, 2] * _stiffness(d[2], forces[2], n[b], at_zero)
            denominator = 2.0 * (abs(g0) + abs(g1) + abs(g2)) + eps
            scale = alpha * (-residual_z) / denominator
            updated[0] = _clamp(d[0] + scale * _sign(g0))
            updated[1] = _clamp(d[1] + scale * _sign(g1))
            updated[2] = _clamp(d[2] + scale * _sign(g2))
            # != is True for NaN, as numpy's: a NaN candidate runs all N_max iterations
            changed = updated[0] != d[0] or updated[1] != d[1] or updated[2] != d[2]
            d[:] = updated
            if not changed:
                break
            last_change[b] = iteration
    return depths, last_change


@njit(cache=True, error_model="numpy")
def _stiffness(depth, force, n, at_zero):
    """``n f / delta`` per metre of penetration, ``at_zero`` at a released contact."""
    return at_zero if depth <= 0.0 else n * force / depth


@njit(cache=True, error_model="numpy")
def _sign(x):
    """``numpy.sign``: -1, 0 or 1, NaN for NaN."""
    if x > 0.0:
        return 1.0
    if x < 0.0:
        return -1.0
    return x  # 0.0 (signed zero: multiplies to zero either way) or NaN


@njit(cache=True, error_model="numpy")
def _clamp(x):
    """``numpy.maximum(0.0, x)``: NaN stays NaN."""
    return x if (x > 0.0 or x != x) else 0.0
