"""Compiled (numba) kernels of the Test 1 bench fits (paper §7.2, §7.5).

Each kernel has a numpy reference in :mod:`graspcampaign.core.bench` that tests hold it to:

* :func:`trace_rmse_pct` -- the Eq. 13 force RMSE (% of peak) of every trace of a set for a
  batch of parameter sets, one fused pass per parameter set (the §7.5 PSO cost; reference:
  :func:`graspcampaign.core.contact.normal_force` over the ``(p, m)`` grid and a matrix
  product);
* :func:`axis_profile` -- an axis driven by sequential trapezoidal moves (reference:
  :func:`graspcampaign.core.bench.trapezoid_move` move after move);
* :func:`first_order_filter` -- ``y_i = b0 x_i + decay y_(i-1)``, the QLV recursion (reference:
  ``scipy.signal.lfilter([b0], [1, -decay], x)``).

The per-event least-squares solver is :mod:`graspcampaign.core.fit_kernel`. Speed-ups against
the references are measured in ``benchmarks/bench_test1.py``.

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


@njit(cache=True, error_model="numpy", fastmath={"contract"})
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


@njit(cache=True, error_model="numpy")
def exp_kernel(x):
    """Return ``exp(x)`` of a (m,) array by :func:`_scaled_exp_into` (tests; ``|x| <= 700``)."""
    poly = np.empty(x.size)
    bits = np.empty(x.size)
    _scaled_exp_into(1.0, x, poly, bits)
    return poly * bits


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
def trace_rmse_mean_pct(k, n, c, depths, rates, forces, offsets, peaks):
    """Return the mean over traces of :func:`trace_rmse_pct`, shape (p,) [% of peak]: the
    §7.5 PSO cost without a round trip through numpy per call."""
    rmse = trace_rmse_pct(k, n, c, depths, rates, forces, offsets, peaks)
    n_sets, n_traces = rmse.shape
    out = np.empty(n_sets)
    for p in range(n_sets):
        total = 0.0
        for j in range(n_traces):
            total += rmse[p, j]
        out[p] = total / n_traces
    return out


# ------------------------------------------------------------------------- virtual bench


@njit(cache=True, error_model="numpy")
def axis_profile(times, start, moves):
    """Position and velocity of one axis driven by sequential trapezoidal moves.

    Parameters
    ----------
    times : (s,) float
        Sample times [s].
    start : float
        Position before the first move [m].
    moves : (k, 4) float
        One row per move, in order: start time t0 [s], target position [m], speed limit
        [m/s], acceleration limit [m/s^2]; a move takes over the samples with ``t >= t0``.

    Returns
    -------
    positions, velocities : (s,) float
        [m], [m/s].

    Notes
    -----
    Each move is :func:`graspcampaign.core.bench.trapezoid_move` (trapezoidal, triangular when
    too short) evaluated with the same operations in the same order, so both paths agree bit
    for bit (tests), in one pass per move instead of ~15 array temporaries.
    """
    n = times.size
    pos = np.full(n, start)
    vel = np.zeros(n)
    current = start
    for k in range(moves.shape[0]):
        t0, target, v_max, a_max = moves[k, 0], moves[k, 1], moves[k, 2], moves[k, 3]
        distance = target - current
        d = abs(distance)
        sign = 1.0 if distance >= 0 else -1.0
        if d == 0.0:
            v = ta = duration = 0.0
        elif d * a_max >= v_max * v_max:
            v, ta = v_max, v_max / a_max
            duration = 2 * ta + (d - v_max * v_max / a_max) / v_max
        else:
            v = math.sqrt(a_max * d)
            ta = v / a_max
            duration = 2 * ta
        half_a = 0.5 * a_max
        cruise0 = half_a * (ta * ta)
        end = t0 + duration
        for i in range(n):
            if not times[i] >= t0:
                continue
            if d == 0.0:
                p = dv = 0.0
            else:
                tt = times[i] - t0
                t = min(max(tt, 0.0), duration)
                if t < ta:
                    p, dv = half_a * (t * t), a_max * t
                elif t <= duration - ta:
                    p, dv = cruise0 + v * (t - ta), v
                else:
                    rest = duration - t
                    p, dv = d - half_a * (rest * rest), a_max * rest
                if tt < 0 or tt > duration:
                    dv = 0.0
                p, dv = sign * p, sign * dv
            pos[i] = current + p
            if times[i] <= end:
                vel[i] = dv
        current = target
    return pos, vel


@njit(cache=True, error_model="numpy")
def first_order_filter(x, b0, decay):
    """Return ``y`` (s,) with ``y_i = b0 x_i + decay y_(i-1)``, ``y_(-1) = 0``.

    The operations of ``scipy.signal.lfilter([b0], [1, -decay], x)`` (direct form II
    transposed), in the same order (tests: bit for bit).
    """
    y = np.empty(x.size)
    prev = 0.0
    for i in range(x.size):
        prev = x[i] * b0 + prev * decay
        y[i] = prev
    return y


@njit(cache=True, error_model="numpy")
def press_force(depths, rates, k, n, c, toe, rho, b0, decay, adhesion, neck):
    """Normal force of the virtual fingertip-specimen pair over a depth history [N].

    The numpy path of :func:`graspcampaign.core.bench_contact.contact_force` (the reference, and the
    readable statement of the model) with the same operations in the same order, one pass
    instead of ~40 array temporaries; tests hold both to the same bits.

    Parameters
    ----------
    depths, rates : (s,) float
        Indentation [m] and its rate [m/s].
    k, n, c : float
        Eq. 13's K [N mm^-n] (stiffness scale applied), exponent and C [N s/m].
    toe : float
        Onset-toe length [m] (``<= 0``: none).
    rho, b0, decay : float
        QLV: relaxed fraction, the recursion's input gain ``(1 - rho) exp(-dt / (2 tau))``
        and its decay ``exp(-dt / tau)``.
    adhesion : float
        Pull-off force on the unloading branch [N] (0: none).
    neck : float
        Travel past the surface at which the adhesive neck snaps [m].
    """
    s = depths.size
    force = np.empty(s)
    previous = 0.0
    h = 0.0
    for i in range(s):
        d = max(depths[i], 0.0)
        if toe > 0.0:
            d = d - toe * -math.expm1(-d / toe)
        elastic = max(0.0, k * (d * 1e3) ** n + 0.0) if d > 0.0 else 0.0
        h = (elastic - previous) * b0 + h * decay
        previous = elastic
        relaxed = rho * elastic + h
        in_contact = depths[i] > 0.0
        f = max(relaxed + (c * rates[i] if in_contact else 0.0), 0.0)
        force[i] = f if in_contact or relaxed > 0 else 0.0
    if adhesion > 0.0 and s:
        snapped = False
        for i in range(np.argmax(depths) + 1, s):
            t = depths[i]
            snapped = snapped or t <= -neck
            if not snapped:
                weight = (math.exp(-max(t, 0.0) / neck) if t >= 0.0
                          else min(max(1.0 + t / neck, 0.0), 1.0))
                force[i] = force[i] - adhesion * weight
    return force


@njit(cache=True, error_model="numpy")
def gradient(f, t):
    """Return ``numpy.gradient(f, t)`` (s,) for s >= 2 samples at times ``t`` (s,).

    Second-order central differences inside, first-order one-sided at the ends; numpy's
    operations in numpy's order, including its switch to the uniform-spacing formula when
    every ``diff(t)`` is equal, so both agree bit for bit (tests). One pass instead of
    numpy's ~15 temporaries (the rate of every Eq. 13 fit).
    """
    s = f.size
    if s < 2 or t.size != s:
        raise ValueError("gradient needs at least 2 samples and one time per sample")
    out = np.empty(s)
    uniform = True
    for i in range(1, s - 1):
        if t[i + 1] - t[i] != t[1] - t[0]:
            uniform = False
            break
    if uniform:
        dx = t[1] - t[0]
        for i in range(1, s - 1):
            out[i] = (f[i + 1] - f[i - 1]) / (2.0 * dx)
        out[0] = (f[1] - f[0]) / dx
        out[s - 1] = (f[s - 1] - f[s - 2]) / dx
        return out
    for i in range(1, s - 1):
        dx1 = t[i] - t[i - 1]
        dx2 = t[i + 1] - t[i]
        a = -dx2 / (dx1 * (dx1 + dx2))
        b = (dx2 - dx1) / (dx1 * dx2)
        c = dx1 / (dx2 * (dx1 + dx2))
        out[i] = a * f[i - 1] + b * f[i] + c * f[i + 1]
    out[0] = (f[1] - f[0]) / (t[1] - t[0])
    out[s - 1] = (f[s - 1] - f[s - 2]) / (t[s - 1] - t[s - 2])
    return out


@njit(cache=True, error_model="numpy")
def noisy_quantised(values, noise, sd, step):
    """Return ``round((values + sd noise) / step) * step`` (s,): a sensor channel with its
    noise, quantised to its resolution (round half to even, as ``numpy.round``)."""
    out = np.empty(values.size)
    for i in range(values.size):
        out[i] = np.rint((values[i] + sd * noise[i]) / step) * step
    return out
