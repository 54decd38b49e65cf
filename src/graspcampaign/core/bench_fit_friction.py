"""Test 1 per-event friction fits: :func:`fit_sliding` (``mu_s``, ``mu_k``, ``k_t``),
:func:`fit_oblique` (peak components and measured slip) and the slip margin.

References
----------
Paper Eq. 15-16 (stick-slip), §7.3.
Baumberger, T. & Caroli, C. (2006). Solid friction from stick-slip down to pinning and
aging. *Adv. Phys.* 55, 279.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from graspcampaign.core.bench_fit_relaxation import MIN_FIT_SAMPLES, peak_hold

__all__ = [
    "KINETIC_WINDOW",
    "SLIP_DETECTION",
    "ObliqueFitResult",
    "SlidingFitResult",
    "fit_oblique",
    "fit_sliding",
    "slip_margin",
]


@dataclass(frozen=True)
class SlidingFitResult:
    """Friction constants of one sliding event (§7.3).

    Attributes
    ----------
    mu_s : float
        Breakaway peak ``max f_t / f_n`` before the first slip.
    mu_k : float
        Mean ``f_t / f_n`` over the kinetic window (40-90 % of the stroke).
    k_t : float
        Initial tangential slope ``d f_t / d x`` at the start of the stroke: linear coefficient
        of a quadratic through the samples below half the breakaway force [N/m].
    normal_force : float
        Mean normal force over the stroke [N].
    stick_slip_amplitude : float
        SD of ``f_t / f_n`` in the kinetic window (sawtooth strength).
    success : bool
    """

    mu_s: float
    mu_k: float
    k_t: float
    normal_force: float
    stick_slip_amplitude: float
    success: bool


KINETIC_WINDOW = (0.4, 0.9)
"""Fraction of the stroke over which mu_k is averaged: after the breakaway transient and
before the deceleration (v^2 / 2a <= 0.17 mm of the 3 mm stroke at 10 mm/s)."""


def fit_sliding(time: np.ndarray, normal_force_: np.ndarray, tangential_force: np.ndarray,
                tangential_displacement: np.ndarray) -> SlidingFitResult:
    """Extract mu_s, mu_k and k_t from a tangential slide under constant normal load.

    Parameters
    ----------
    time : (s,) float
        [s].
    normal_force_, tangential_force : (s,) float
        [N].
    tangential_displacement : (s,) float
        In-plane stage travel [m].

    Returns
    -------
    SlidingFitResult

    References
    ----------
    Paper Eq. 15-16, §7.3.
    """
    del time
    fn = np.asarray(normal_force_, dtype=float)
    ft = np.asarray(tangential_force, dtype=float)
    xs = np.asarray(tangential_displacement, dtype=float)
    nan = SlidingFitResult(math.nan, math.nan, math.nan, math.nan, math.nan, False)
    stroke = xs.max() - xs.min() if xs.size else 0.0
    if xs.size < MIN_FIT_SAMPLES or stroke <= 0:
        return nan
    start = xs.min()
    rel = xs - start
    moving = np.flatnonzero(rel > 2e-6)
    full = np.flatnonzero(rel >= stroke - 2e-6)
    if moving.size < MIN_FIT_SAMPLES or not full.size:
        return nan
    seg = np.arange(max(int(moving[0]) - 1, 0), int(full[0]) + 1)
    fn_seg = fn[seg]
    fnm = float(np.mean(fn_seg))
    if fnm <= 0 or seg.size < MIN_FIT_SAMPLES:
        return nan
    pos = rel[seg] / stroke
    fts = ft[seg]
    # breakaway: the static peak precedes the kinetic window; later re-stick peaks stay below
    # it because the aged re-stick threshold never exceeds mu_s (Eq. 15-16)
    pre = np.flatnonzero(pos < KINETIC_WINDOW[0])
    if pre.size < 3:
        return nan
    ib = int(pre[np.argmax(fts[pre])])
    f_break = float(fts[ib])
    mu_s = f_break / float(np.mean(fn_seg[pre]))
    kin = (pos >= KINETIC_WINDOW[0]) & (pos <= KINETIC_WINDOW[1])
    ratio = fts[kin] / np.maximum(fn_seg[kin], 1e-6)
    mu_k = float(np.mean(ratio))
    amp = float(np.std(ratio))
    # initial slope: quadratic through the pre-sliding samples below half the breakaway force
    # (the curvature term absorbs the softening towards full slip)
    sel = np.arange(ib + 1)
    band = fts[sel] <= 0.5 * f_break
    if np.count_nonzero(band) >= 4:
        k_t = float(np.polyfit(rel[seg][sel][band], fts[sel][band], 2)[1])
    elif np.count_nonzero(band) >= 2:
        k_t = float(np.polyfit(rel[seg][sel][band], fts[sel][band], 1)[0])
    else:
        k_t = math.nan
    return SlidingFitResult(mu_s, mu_k, k_t, fnm, amp, bool(np.isfinite(k_t)))


SLIP_DETECTION = 0.25e-3
"""Tangential slip above which an oblique press counts as measured slip [m] (decision: about
twice the largest elastic stick deflection mu_s f_n / k_t of the oblique block, ~0.13 mm)."""


@dataclass(frozen=True)
class ObliqueFitResult:
    """Peak load components and measured state of one oblique press (§7.3).

    Attributes
    ----------
    normal_force, tangential_force : float
        Mean components over the dwell at peak [N].
    slip : float
        Largest tangential slip during the press [m].
    slipped : bool
        Measured state: ``slip > SLIP_DETECTION`` (0.25 mm).
    success : bool
    """

    normal_force: float
    tangential_force: float
    slip: float
    slipped: bool
    success: bool


def fit_oblique(time: np.ndarray, displacement: np.ndarray, normal_force_: np.ndarray,
                tangential_force: np.ndarray, tangential_displacement: np.ndarray,
                tolerance: float = 3e-6) -> ObliqueFitResult:
    """Read the peak load components and the tangential slip of an oblique press.

    Parameters
    ----------
    time, displacement, normal_force_, tangential_force, tangential_displacement : (s,) float
        [s], [m], [N], [N], [m].
    tolerance : float, optional
        Band defining the dwell at peak travel [m].

    Returns
    -------
    ObliqueFitResult
    """
    del time
    x = np.asarray(displacement, dtype=float)
    if x.size < 5:
        return ObliqueFitResult(math.nan, math.nan, math.nan, False, False)
    dwell = peak_hold(x, tolerance)
    fn = float(np.mean(np.asarray(normal_force_)[dwell]))
    ft = float(np.mean(np.asarray(tangential_force)[dwell]))
    xt = np.asarray(tangential_displacement, dtype=float)
    slip = float(np.max(np.abs(xt - xt[0])))
    return ObliqueFitResult(fn, ft, slip, slip > SLIP_DETECTION, fn > 0)


def slip_margin(mu_s: float | np.ndarray, normal_force_: float | np.ndarray,
                tangential_force: float | np.ndarray) -> float | np.ndarray:
    """Return the friction-cone slip margin ``mu_s f_n - |f_t|`` [N] (§7.3, Eq. 15-16)."""
    return np.asarray(mu_s) * np.asarray(normal_force_) - np.abs(tangential_force)
