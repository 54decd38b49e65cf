"""Compiled (numba) kernels of the Test 1 bench fits (paper §7.2, §7.5).

Each kernel has a numpy reference in :mod:`graspcampaign.core.bench` that tests hold it to:

* :func:`trace_rmse_pct` -- the Eq. 13 force RMSE (% of peak) of every trace of a set for a
  batch of parameter sets, one fused pass per parameter set (the §7.5 PSO cost; reference:
  :func:`graspcampaign.core.contact.normal_force` over the ``(p, m)`` grid and a matrix
  product). Measured ~6x faster than the reference in the same run (benchmarks/bench_test1.py).

Everything is compiled with ``cache=True`` and no threads (the campaign owns the cores).

Shape letters: ``p`` parameter sets (particles), ``m`` trace points of all traces
concatenated, ``t`` traces.

References
----------
Paper Eq. 13 (normal law), §7.5 (re-identification cost).
Cody, W. J. & Waite, W. (1980). *Software Manual for the Elementary Functions*, Prentice-Hall
-- the two-constant reduction ``x = k ln 2 + r`` (constants of fdlibm's ``e_exp.c``).
Muller, J.-M. (2016). *Elementary Functions*, 3rd ed., Birkhauser, §11.3 -- exp by range
reduction, polynomial on ``|r| <= ln 2 / 2`` and a power of two built in the exponent field.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_LOG2E = 1.4426950408889634
_LN2_HI = 6.93147180369123816490e-01  # fdlibm's split of ln 2: k * _LN2_HI is exact, |k| < 2**11
_LN2_LO = 1.90821492927058770002e-10
_SHIFT = 6755399441055744.0  # 1.5 * 2**52: x + _SHIFT rounds x to an integer in the low bits
_SHIFT_BITS = 0x4338000000000000  # the bit pattern of _SHIFT
_EXP_ARG_MAX = 700.0  # |x| beyond which the exponent-field construction would overflow


@njit(cache=True, fastmath={"contract"})
def _scaled_exp_into(a, x, poly, bits):
    """Split ``exp(a x)`` of (m,) ``x`` into ``poly * 2^k``: ``poly`` (m,) and the float64 bit
    pattern of ``2^k`` in ``bits`` (m,), for ``|a x| <= 700``.

    Written without calls so that LLVM vectorises it (libm's ``exp`` is one scalar call per
    element): ``k = round(a x / ln 2)`` by the 1.5 * 2^52 shift, ``r = a x - k ln 2`` in two
    parts (exact for |k| < 2^11), ``exp(r)`` by its Taylor polynomial of degree 13 (truncation
    error < 1e-17 relative on |r| <= ln 2 / 2, below half an ulp) and ``2^k`` assembled in the
    exponent field. ``poly * bits.view(float64)`` is within 1 ulp of ``numpy.exp`` (tests).
    """
    m = x.size
    for i in range(m):
        ax = a * x[i]
        y = ax * _LOG2E + _SHIFT
        kf = y - _SHIFT
        r = (ax - kf * _LN2_HI) - kf * _LN2_LO
        q = 1.0 / 6227020800.0
        q = q * r + 1.0 / 479001600.0
        q = q * r + 1.0 / 39916800.0
        q = q * r + 1.0 / 3628800.0
        q = q * r + 1.0 / 362880.0
        q = q * r + 1.0 / 40320.0
        q = q * r + 1.0 / 5040.0
        q = q * r + 1.0 / 720.0
        q = q * r + 1.0 / 120.0
        q = q * r + 1.0 / 24.0
        q = q * r + 1.0 / 6.0
        q = q * r + 0.5
        q = q * r + 1.0
        poly[i] = q * r + 1.0
        bits[i] = y
    ibits = bits.view(np.int64)
    for i in range(m):
        ibits[i] = (ibits[i] - _SHIFT_BITS + 1023) << 52


@njit(cache=True)
def exp_kernel(x):
    """Return ``exp(x)`` of a (m,) array by :func:`_scaled_exp_into` (tests; ``|x| <= 700``)."""
    poly = np.empty(x.size)
    bits = np.empty(x.size)
    _scaled_exp_into(1.0, x, poly, bits)
    return poly * bits


@njit(cache=True)
def _sum(values, start, stop):
    """Sum ``values[start:stop]`` with four running sums (a single one is latency-bound)."""
    a0 = a1 = a2 = a3 = 0.0
    i = start
    while i + 4 <= stop:
        a0 += values[i]
        a1 += values[i + 1]
        a2 += values[i + 2]
        a3 += values[i + 3]
        i += 4
    while i < stop:
        a0 += values[i]
        i += 1
    return (a0 + a1) + (a2 + a3)


@njit(cache=True)
def trace_rmse_pct(k, n, c, depths, rates, forces, offsets, peaks):
    """Return the Eq. 13 force RMSE of every trace for every parameter set [% of peak].

    Parameters
    ----------
    k, n, c : (p,) float
        Stiffness K [N mm^-n], exponent n [-] and damping C [N s/m] of each parameter set.
    depths, rates, forces : (m,) float
        Penetration [m], penetration rate [m/s] and measured force [N] of every trace point,
        trace after trace.
    offsets : (t + 1,) int
        Trace ``j`` holds points ``offsets[j]:offsets[j + 1]`` (each non-empty).
    peaks : (t,) float
        Peak force of each trace [N].

    Returns
    -------
    rmse_pct : (p, t) float
        ``100 sqrt(mean_j (f_pred - f)^2) / peak_j`` with
        ``f_pred = max(0, K delta_mm^n + C delta_dot)`` (0 where ``delta <= 0``).

    Notes
    -----
    ``delta_mm^n`` is ``exp(n ln delta_mm)`` with ``ln delta_mm`` computed once per call and the
    vectorised exp of :func:`_scaled_exp_into` (libm's ``pow`` costs ~5x more per element); a
    parameter set whose ``|n ln delta_mm|`` exceeds 700 uses libm's ``exp`` instead.
    """
    n_sets = k.size
    n_pts = depths.size
    n_traces = offsets.size - 1
    log_d = np.empty(n_pts)
    active = np.empty(n_pts)
    largest = 0.0
    for i in range(n_pts):
        if depths[i] > 0.0:
            log_d[i] = math.log(depths[i] * 1e3)
            active[i] = 1.0
            largest = max(largest, abs(log_d[i]))
        else:
            log_d[i] = 0.0
            active[i] = 0.0
    poly = np.empty(n_pts)
    bits = np.empty(n_pts)
    sq = np.empty(n_pts)
    out = np.empty((n_sets, n_traces))
    for p in range(n_sets):
        kp, np_, cp = k[p], n[p], c[p]
        if abs(np_) * largest <= _EXP_ARG_MAX:
            _scaled_exp_into(np_, log_d, poly, bits)
        else:
            for i in range(n_pts):
                poly[i] = math.exp(np_ * log_d[i])
                bits[i] = 1.0
        for i in range(n_pts):
            f = kp * (poly[i] * bits[i]) + cp * rates[i]
            d = max(f, 0.0) * active[i] - forces[i]
            sq[i] = d * d
        for j in range(n_traces):
            mean_sq = _sum(sq, offsets[j], offsets[j + 1]) / (offsets[j + 1] - offsets[j])
            out[p, j] = math.sqrt(mean_sq) / peaks[j] * 100.0
    return out
