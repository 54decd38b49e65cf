"""Compiled (numba) Levenberg-Marquardt for the Test 1 per-event fits (paper §7.2, §7.4).

:func:`lm_fit` solves the three-parameter least-squares problems of
:func:`graspcampaign.core.bench.fit_normal` (Eq. 13), :func:`~graspcampaign.core.bench.
fit_shifted` (shifted law) and :func:`~graspcampaign.core.bench.fit_relaxation` (§7.4 law) to a
stationary point. ``scipy.optimize.least_squares`` is the reference (the fits'
``backend="scipy"``) and the fallback when this solver stops elsewhere; tests hold both to the
same minima. Compiled with ``cache=True`` and no threads.

Shape letters: ``m`` data points.

References
----------
Moré, J. J. (1978). The Levenberg-Marquardt algorithm: implementation and theory.
*Numerical Analysis*, Lecture Notes in Mathematics 630, 105-116.
Nocedal, J. & Wright, S. J. (2006). *Numerical Optimization*, 2nd ed., §10.3.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

MODEL_NORMAL = 0
"""Eq. 13 on a loading window: ``K a^n + C b - y``, ``a`` depth [mm], ``b`` rate [m/s]."""
MODEL_SHIFTED = 1
"""Shifted law: ``K max(a - x0, 1e-9)^m - y``, ``a`` displacement [mm] (``b`` unused)."""
MODEL_RELAXATION = 2
"""Relaxation law: ``A + B exp(-a / tau) - y``, ``a`` time into the hold [s] (``b`` unused)."""

LM_CONVERGED = 1
"""A stationary point: the Gauss-Newton step is below ``xtol`` of every parameter, or no step
lowers the cost any more and every Jacobian column is orthogonal to the residual."""
LM_MAX_ITERATIONS = 0
"""The iteration budget ran out, or the cost stalled away from a stationary point."""
LM_AT_BOUND = -1
"""The cost stalled away from a stationary point after steps were refused at the box (the
minimum may lie on a bound)."""


@njit(cache=True, error_model="numpy")
def _residuals(model, p, a, b, y, out):
    """Fill ``out`` (m,) with the model's residuals at ``p``; return their sum of squares."""
    cost = 0.0
    for i in range(a.size):
        if model == MODEL_NORMAL:
            r = p[0] * a[i] ** p[1] + p[2] * b[i] - y[i]
        elif model == MODEL_SHIFTED:
            r = p[0] * max(a[i] - p[2], 1e-9) ** p[1] - y[i]
        else:
            r = p[0] + p[1] * math.exp(-a[i] / p[2]) - y[i]
        out[i] = r
        cost += r * r
    return cost


@njit(cache=True, error_model="numpy")
def _normal_equations(model, p, a, b, y, h, g):
    """Fill ``h = J^T J`` (3, 3) and ``g = J^T r`` (3,) at ``p`` (analytic Jacobian)."""
    for u in range(3):
        g[u] = 0.0
        for v in range(3):
            h[u, v] = 0.0
    jr = np.empty(3)
    for i in range(a.size):
        if model == MODEL_NORMAL:
            pw = a[i] ** p[1]
            r = p[0] * pw + p[2] * b[i] - y[i]
            jr[0], jr[1], jr[2] = pw, p[0] * pw * math.log(a[i]), b[i]
        elif model == MODEL_SHIFTED:
            d = max(a[i] - p[2], 1e-9)
            pw = d ** p[1]
            r = p[0] * pw - y[i]
            jr[0], jr[1], jr[2] = pw, p[0] * pw * math.log(d), -p[0] * p[1] * pw / d
        else:
            e = math.exp(-a[i] / p[2])
            r = p[0] + p[1] * e - y[i]
            jr[0], jr[1], jr[2] = 1.0, e, p[1] * e * a[i] / p[2] ** 2
        for u in range(3):
            g[u] += jr[u] * r
            for v in range(u + 1):
                h[u, v] += jr[u] * jr[v]
    for u in range(3):
        for v in range(u + 1, 3):
            h[u, v] = h[v, u]


@njit(cache=True, error_model="numpy")
def _solve_damped(h, g, scale, lam, step):
    """Solve ``(H + lam diag(scale^2)) step = -g`` by Cholesky in scaled variables; return
    False when the matrix is not positive definite."""
    m = np.empty((3, 3))
    for u in range(3):
        for v in range(3):
            m[u, v] = h[u, v] / (scale[u] * scale[v])
        m[u, u] += lam
    low = np.zeros((3, 3))
    for u in range(3):
        for v in range(u + 1):
            s = m[u, v]
            for w in range(v):
                s -= low[u, w] * low[v, w]
            if u == v:
                if not s > 0.0:
                    return False
                low[u, u] = math.sqrt(s)
            else:
                low[u, v] = s / low[v, v]
    z = np.empty(3)
    for u in range(3):  # L z = -g / scale
        s = -g[u] / scale[u]
        for w in range(u):
            s -= low[u, w] * z[w]
        z[u] = s / low[u, u]
    for u in range(2, -1, -1):  # L^T x = z
        s = z[u]
        for w in range(u + 1, 3):
            s -= low[w, u] * step[w]
        step[u] = s / low[u, u]
    for u in range(3):
        step[u] /= scale[u]
    return True


@njit(cache=True, error_model="numpy")
def lm_fit(model, p0, a, b, y, lower, upper, typical, xtol=1e-12, max_iter=200):
    """Minimise the sum of squared residuals of a three-parameter bench model.

    Levenberg-Marquardt with Marquardt's scaling (the columns of ``J`` scaled by their running
    largest norms, Moré 1978) and a trust-ratio update of the damping, run to a stationary
    point rather than to a cost-reduction tolerance: it stops when the undamped Gauss-Newton
    step is below ``xtol (|p| + typical)`` in every parameter, or when no damped step lowers
    the cost although the model predicts a decrease below rounding (``1e-15`` of the cost) and
    every Jacobian column is orthogonal to the residual (cosine < 1e-7). Iterates stay
    strictly inside ``[lower, upper]``: a step that would leave the box is refused and the
    damping raised; a run stalled against the box reports ``LM_AT_BOUND`` so that the caller
    can use a bounded solver instead.

    Parameters
    ----------
    model : int
        ``MODEL_NORMAL``, ``MODEL_SHIFTED`` or ``MODEL_RELAXATION``.
    p0 : (3,) float
        Start.
    a, b, y : (m,) float
        Model data (see the model constants) and observations.
    lower, upper : (3,) float
        Box; use +-inf for a free parameter.
    typical : (3,) float
        Typical magnitude of each parameter (the absolute part of the step test).
    xtol : float, optional
        Relative step below which the iteration has converged.
    max_iter : int, optional
        Largest number of Jacobian evaluations.

    Returns
    -------
    p : (3,) float
        Solution.
    cost : float
        Sum of squared residuals at ``p``.
    status : int
        ``LM_CONVERGED``, ``LM_MAX_ITERATIONS`` or ``LM_AT_BOUND``.
    n_iter : int
        Jacobian evaluations.

    References
    ----------
    Moré, J. J. (1978). The Levenberg-Marquardt algorithm: implementation and theory.
    *Numerical Analysis*, Lecture Notes in Mathematics 630, 105-116.
    Nocedal, J. & Wright, S. J. (2006). *Numerical Optimization*, 2nd ed., §10.3.
    """
    p = p0.copy()
    res = np.empty(a.size)
    cost = _residuals(model, p, a, b, y, res)
    h = np.empty((3, 3))
    g = np.empty(3)
    scale = np.zeros(3)
    step = np.empty(3)
    trial = np.empty(3)
    lam = 1e-3
    hits = 0
    for it in range(max_iter):
        _normal_equations(model, p, a, b, y, h, g)
        for u in range(3):
            scale[u] = max(scale[u], math.sqrt(h[u, u]), 1e-150)
        if _solve_damped(h, g, scale, 0.0, step):
            small = True
            for u in range(3):
                if abs(step[u]) > xtol * (abs(p[u]) + typical[u]):
                    small = False
            if small:
                return p, cost, LM_CONVERGED, it + 1
        accepted = False
        while lam < 1e16:
            if not _solve_damped(h, g, scale, lam, step):
                lam *= 10.0
                continue
            predicted = 0.0  # -(2 g.step + step.H.step) >= 0
            for u in range(3):
                hs = 0.0
                for v in range(3):
                    hs += h[u, v] * step[v]
                predicted -= 2.0 * g[u] * step[u] + step[u] * hs
            inside = True
            for u in range(3):
                trial[u] = p[u] + step[u]
                if not (lower[u] < trial[u] < upper[u]):
                    inside = False
            if not inside:
                hits += 1
                lam *= 10.0
                continue
            new_cost = _residuals(model, trial, a, b, y, res)
            if new_cost < cost:
                ratio = (cost - new_cost) / predicted if predicted > 0.0 else 0.0
                if ratio > 0.75:
                    lam = max(lam / 3.0, 1e-12)
                elif ratio < 0.25:
                    lam *= 2.0
                for u in range(3):
                    p[u] = trial[u]
                cost = new_cost
                accepted = True
                break
            if predicted <= 1e-15 * cost:
                break  # no step lowers the cost any more: judge stationarity below
            lam *= 10.0
        if not accepted:
            # the cost cannot be lowered within rounding: a stationary point when every
            # Jacobian column is orthogonal to the residual (cosine < 1e-7); otherwise the
            # iterates were stopped by the box (or by rounding far from a minimum)
            for u in range(3):
                if abs(g[u]) > 1e-7 * math.sqrt(h[u, u] * cost):
                    return p, cost, (LM_AT_BOUND if hits else LM_MAX_ITERATIONS), it + 1
            return p, cost, LM_CONVERGED, it + 1
    return p, cost, LM_MAX_ITERATIONS, max_iter
