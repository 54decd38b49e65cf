"""Test 1 per-event fit of stress relaxation: ``F(t) = F_0 (rho + (1 - rho) exp(-t / tau))``.

References
----------
Paper §7.2 (hold phase). Fung, Y. C. (1981). *Biomechanics*, ch. 7 -- quasi-linear
viscoelasticity (QLV).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from graspcampaign.core.bench_fit_backend import TYPICAL_RELAXATION, check_fit_backend, solve_least_squares
from graspcampaign.core.fit_kernel import MODEL_RELAXATION

__all__ = [
    "MIN_FIT_SAMPLES",
    "RELAXATION_FIT_POINTS",
    "RelaxationFitResult",
    "fit_relaxation",
    "peak_hold",
]

log = logging.getLogger(__name__)


RELAXATION_FIT_POINTS = 600
"""Largest number of (block-averaged) hold samples passed to the relaxation solver."""


MIN_FIT_SAMPLES = 10
"""The fewest samples a relaxation or sliding fit (:func:`fit_relaxation`,
:func:`graspcampaign.core.bench_fit_friction.fit_sliding`) reads, of the event's waveform and of the
stretch it fits (the hold, the slide): fewer, and the fit fails (an oblique press reads 5). Test 1
ingest refuses an event shorter than this (:mod:`graspcampaign.rig.test1_ingest`)."""


@dataclass(frozen=True)
class RelaxationFitResult:
    """Hold-relaxation fit ``F(t) = F_0 (rho + (1 - rho) exp(-t / tau))`` (§7.4).

    Attributes
    ----------
    f0 : float
        Force at the start of the hold [N].
    rho, tau : float
        Steady ratio and time constant [s].
    rmse_pct : float
        RMSE in % of ``f0``.
    hold : float
        Duration of the detected hold [s].
    success : bool
    """

    f0: float
    rho: float
    tau: float
    rmse_pct: float
    hold: float
    success: bool


def peak_hold(x: np.ndarray, tolerance: float) -> np.ndarray:
    """Indices of the hold at peak travel: the span from the first to the last sample within
    ``tolerance`` of the plateau level (median of the samples within 5 um of the maximum, so
    one quantisation outlier neither sets the level nor splits the hold)."""
    top = x[x >= x.max() - 5e-6]
    level = float(np.median(top))
    idx = np.flatnonzero(x >= level - tolerance)
    return np.arange(idx[0], idx[-1] + 1) if idx.size else idx


def fit_relaxation(time: np.ndarray, displacement: np.ndarray, normal_force_: np.ndarray,
                   tolerance: float = 3e-6, backend: str = "numba") -> RelaxationFitResult:
    """Fit the §7.4 relaxation law to the hold at peak indentation.

    The hold is the span of samples whose displacement lies within ``tolerance`` of the
    peak plateau. ``F = A + B exp(-(t - t_0)/tau)`` is fitted by least squares within
    ``A, B >= 0``, ``0.01 s <= tau <= 10 x hold`` from a start read off the trace;
    ``F_0 = A + B`` and ``rho = A / F_0``.

    Parameters
    ----------
    time, displacement, normal_force_ : (s,) float
        [s], [m], [N].
    tolerance : float, optional
        Hold detection band [m].
    backend : {"numba", "scipy"}, optional
        Solver (:data:`FIT_BACKENDS`): the compiled Levenberg-Marquardt run to a stationary
        point strictly inside the bounds (default), or the reference
        ``scipy.optimize.least_squares`` (trust-region reflective), which is also the
        fallback when the compiled path meets a bound.

    Returns
    -------
    RelaxationFitResult
    """
    check_fit_backend(backend)
    t = np.asarray(time, dtype=float)
    x = np.asarray(displacement, dtype=float)
    f = np.asarray(normal_force_, dtype=float)
    nan = RelaxationFitResult(math.nan, math.nan, math.nan, math.nan, math.nan, False)
    if x.size < MIN_FIT_SAMPLES:
        return nan
    run = peak_hold(x, tolerance)
    if run.size < MIN_FIT_SAMPLES:
        return nan
    th = t[run] - t[run[0]]
    y = f[run]
    hold = float(th[-1])
    # block means of at most RELAXATION_FIT_POINTS: the law is smooth on the scale of tau
    # (>= 5 s) and averaging keeps the information while bounding the solver's cost
    m = -(-th.size // RELAXATION_FIT_POINTS)
    if m > 1:
        nb = th.size // m
        th = th[: nb * m].reshape(nb, m).mean(axis=1)
        y = y[: nb * m].reshape(nb, m).mean(axis=1)
    tail = y[-max(3, y.size // 20):].mean()
    head = y[: 3].mean()
    if head <= 0 or th.size < 5:
        return nan
    target = tail + (head - tail) / math.e
    below = np.flatnonzero(y <= target)
    tau0 = float(th[below[0]]) if below.size and th[below[0]] > 0 else hold / 4.0
    p0 = np.array([max(tail, 1e-6), max(head - tail, 1e-6),
                   float(np.clip(tau0, 2e-2, 5.0 * max(hold, 1.0)))])

    def resid(p: np.ndarray) -> np.ndarray:
        return p[0] + p[1] * np.exp(-th / p[2]) - y

    def jac(p: np.ndarray) -> np.ndarray:
        e = np.exp(-th / p[2])
        return np.column_stack([np.ones_like(th), e, p[1] * e * th / p[2] ** 2])

    try:
        # bounded: a drifting baseline must not send tau to infinity with a negative amplitude
        p_fit, fun, success = solve_least_squares(
            resid, jac, p0, MODEL_RELAXATION, (th, th, y),
            (np.array([0.0, 0.0, 1e-2]), np.array([np.inf, np.inf, 10.0 * max(hold, 1.0)])),
            TYPICAL_RELAXATION, backend, method="trf", max_nfev=200)
    except (ValueError, np.linalg.LinAlgError) as exc:  # pragma: no cover - defensive
        log.debug("relaxation fit failed: %s", exc)
        return nan
    a, b, tau = (float(v) for v in p_fit)
    f0 = a + b
    ok = success and f0 > 0 and tau > 0
    rmse = float(np.sqrt(np.mean(fun**2)) / f0 * 100.0) if f0 > 0 else math.nan
    return RelaxationFitResult(f0, a / f0 if f0 > 0 else math.nan, tau, rmse, hold, ok)
