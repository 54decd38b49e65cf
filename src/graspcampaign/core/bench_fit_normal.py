"""Test 1 per-event fits of the normal law: :func:`fit_normal` (Eq. 13: ``K``, ``n``, ``C``, RMSE
in % of peak), :func:`fit_shifted` (``K (delta - delta_0)^m``) and :class:`TraceSet` (Eq. 13
error over many traces and parameter sets, the §7.5 PSO cost).

Units are SI; the power term of Eq. 13 takes the indentation in millimetres and ``K`` in
N mm^-n (§3.5, §7.2): that conversion happens only inside
:func:`graspcampaign.core.contact.normal_force`, in the analytic Jacobian of
:func:`fit_normal` and in the compiled kernels that mirror them (tests hold them together).

References
----------
Paper Eq. 13 (normal law), §7.2, §7.5.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from graspcampaign.core import bench_kernels
from graspcampaign.core.bench_fit_backend import (
    TYPICAL_NORMAL,
    TYPICAL_SHIFTED,
    UNBOUNDED,
    check_fit_backend,
    solve_least_squares,
)
from graspcampaign.core.bench_specimen import force_at_reference_depth
from graspcampaign.core.contact import normal_force
from graspcampaign.core.fit_kernel import MODEL_NORMAL, MODEL_SHIFTED
from graspcampaign.core.plausible import PLAUSIBLE

__all__ = [
    "MIN_FIT_FORCE",
    "RMSE_REVIEW_THRESHOLD_PCT",
    "NormalFitResult",
    "ShiftedFitResult",
    "TraceSet",
    "fit_normal",
    "fit_shifted",
    "loading_window",
]

log = logging.getLogger(__name__)


# ------------------------------------------------------------------------------ fits

RMSE_REVIEW_THRESHOLD_PCT = 5.0
"""Normal-fit RMSE (% of peak) above which a fit is flagged for review (§7.2; decision)."""
MIN_FIT_FORCE = 2e-3
"""Smallest force entering the normal fit window [N] (two load-cell LSBs)."""
EXPONENT_RANGE = (0.05, PLAUSIBLE["n_exp"].high)
"""Contact exponents n [-] a normal fit may end at and still be a fit. Below 0.05 the force grows
by less than 12 % over a tenfold indentation (10^0.05), i.e. it does not depend on the indentation
and is no contact law (a constant force trace fits n ~ 1e-17 with zero RMSE); the upper end is the
plausible range of soft-contact exponents (:data:`graspcampaign.core.plausible.PLAUSIBLE`, Hertz
1.5, §7.2's n = 0.46 ± 0.07). The lower end is also the floor of the start value."""


@dataclass(frozen=True)
class NormalFitResult:
    """Eq. 13 fit of one loading branch.

    Attributes
    ----------
    k_n_per_mm_n, n, c : float
        Fitted K [N mm^-n], exponent, damping C [N s/m].
    c_se : float
        Asymptotic standard error of C [N s/m]: at bench speeds ``|C delta_dot|`` is below
        the 1 mN resolution and C is rarely identified within one event (see Notes of
        :func:`fit_normal`).
    f05 : float
        K 0.5^n [N].
    rmse_pct : float
        Force RMSE over the fit window in % of the event's peak force.
    peak_force : float
        Peak measured normal force [N].
    max_depth : float
        Peak indentation [m].
    loading_work, unloading_work : float
        Work on the loading and unloading branches, compressive part [J].
    n_points : int
        Samples in the fit window.
    success : bool
        False when the window was too short or the solver failed (fields are NaN).
    """

    k_n_per_mm_n: float
    n: float
    c: float
    c_se: float
    f05: float
    rmse_pct: float
    peak_force: float
    max_depth: float
    loading_work: float
    unloading_work: float
    n_points: int
    success: bool


def _nan_normal(peak: float = math.nan, npts: int = 0) -> NormalFitResult:
    nan = math.nan
    return NormalFitResult(nan, nan, nan, nan, nan, nan, peak, nan, nan, nan, npts, False)


def loading_window(displacement: np.ndarray, normal_force_: np.ndarray, onset: float = 0.0
                   ) -> np.ndarray:
    """Return the mask of the samples Eq. 13 is fitted to (and judged on).

    Parameters
    ----------
    displacement, normal_force_ : (s,) float
        Probe travel [m] and measured normal force [N].
    onset : float, optional
        Displacement of the contact surface [m]; ``delta = displacement - onset``.

    Returns
    -------
    window : (s,) bool
        Loading branch (up to the first sample of peak travel) with ``delta > 0`` and
        ``f > MIN_FIT_FORCE`` (see :func:`fit_normal`).
    """
    x = np.asarray(displacement, dtype=float)
    window = np.zeros(x.size, dtype=bool)
    window[: int(np.argmax(x)) + 1] = True
    return window & (x - onset > 0.0) & (np.asarray(normal_force_, dtype=float) > MIN_FIT_FORCE)


@dataclass(frozen=True)
class TraceSet:
    """Points of several normal-indentation traces, concatenated, checked once (§7.5).

    Attributes
    ----------
    depths, rates, forces : (m,) float
        Penetration [m], penetration rate [m/s] and measured force [N] of every point, trace
        after trace (e.g. each trace's :func:`loading_window`).
    offsets : (t + 1,) int
        Trace ``j`` holds points ``offsets[j]:offsets[j + 1]``; every trace is non-empty.
    peaks : (t,) float
        Peak force of each trace [N].
    """

    depths: np.ndarray
    rates: np.ndarray
    forces: np.ndarray
    offsets: np.ndarray
    peaks: np.ndarray

    def __post_init__(self) -> None:
        for name in ("depths", "rates", "forces", "peaks"):
            object.__setattr__(self, name, np.ascontiguousarray(getattr(self, name),
                                                                dtype=np.float64))
        offsets = np.ascontiguousarray(self.offsets, dtype=np.int64)
        object.__setattr__(self, "offsets", offsets)
        m = self.depths.size
        if (offsets.size != self.peaks.size + 1 or offsets[0] != 0 or offsets[-1] != m
                or np.any(np.diff(offsets) <= 0)):
            raise ValueError(f"offsets must rise strictly from 0 to {m} (one non-empty trace "
                             f"per peak), got {offsets.tolist()!r}")
        if self.rates.size != m or self.forces.size != m:
            raise ValueError(f"depths, rates and forces must have one value per point, got "
                             f"{m}, {self.rates.size} and {self.forces.size}")

    @classmethod
    def from_traces(cls, traces: list[tuple[np.ndarray, np.ndarray, np.ndarray, float]]
                    ) -> TraceSet:
        """Concatenate ``(depths, rates, forces, peak)`` tuples, one per trace."""
        return cls(np.concatenate([t[0] for t in traces]),
                   np.concatenate([t[1] for t in traces]),
                   np.concatenate([t[2] for t in traces]),
                   np.concatenate([[0], np.cumsum([t[0].size for t in traces])]),
                   np.array([t[3] for t in traces], dtype=float))

    def rmse_pct(self, k: np.ndarray, n: np.ndarray, c: np.ndarray, backend: str = "numba"
                 ) -> np.ndarray:
        """Return the Eq. 13 force RMSE of every trace for every parameter set [% of peak].

        Parameters
        ----------
        k, n, c : (p,) float
            Stiffness K [N mm^-n], exponent n [-] and damping C [N s/m] of each set.
        backend : {"numba", "numpy"}
            ``"numba"`` (default): the fused kernel
            :func:`graspcampaign.core.bench_kernels.trace_rmse_pct`; ``"numpy"``: the
            reference, :func:`graspcampaign.core.contact.normal_force` on the ``(p, m)`` grid
            and a matrix product over trace membership. Both agree to rounding (tests).

        Returns
        -------
        rmse_pct : (p, t) float
            ``100 sqrt(mean_j (f_pred - f)^2) / peak_j``, ``f_pred`` from Eq. 13.

        References
        ----------
        Paper Eq. 13, §7.5.
        """
        k, n, c = (np.ascontiguousarray(v, dtype=np.float64).reshape(-1) for v in (k, n, c))
        if backend == "numba":
            return bench_kernels.trace_rmse_pct(k, n, c, self.depths, self.rates, self.forces,
                                                self.offsets, self.peaks)
        if backend != "numpy":
            raise ValueError(f"backend must be 'numba' or 'numpy', got {backend!r}")
        sizes = np.diff(self.offsets)
        member = np.zeros((self.depths.size, sizes.size))
        member[np.arange(self.depths.size), np.repeat(np.arange(sizes.size), sizes)] = (
            1.0 / np.repeat(sizes, sizes))
        pred = normal_force(self.depths[None, :], self.rates[None, :], k[:, None], n[:, None],
                            c[:, None])
        return np.sqrt(((pred - self.forces[None, :]) ** 2) @ member) / self.peaks * 100.0

    def mean_rmse_pct(self, k: np.ndarray, n: np.ndarray, c: np.ndarray,
                      backend: str = "numba") -> np.ndarray:
        """Return :meth:`rmse_pct` averaged over the traces, shape (p,) [% of peak].

        The numba path averages inside the kernel
        (:func:`graspcampaign.core.bench_kernels.trace_rmse_mean_pct`): this is the §7.5 PSO
        cost, called ~10^5 times per material, where numpy's per-call overhead would cost as
        much as the kernel.
        """
        if backend == "numba":
            k, n, c = (np.ascontiguousarray(v, dtype=np.float64).reshape(-1)
                       for v in (k, n, c))
            return bench_kernels.trace_rmse_mean_pct(k, n, c, self.depths, self.rates,
                                                     self.forces, self.offsets, self.peaks)
        return self.rmse_pct(k, n, c, backend=backend).mean(axis=1)


def _branch_work(x: np.ndarray, f: np.ndarray) -> float:
    fc = np.maximum(f, 0.0)
    return float(abs(np.sum(0.5 * (fc[1:] + fc[:-1]) * np.diff(x))))


def fit_normal(time: np.ndarray, displacement: np.ndarray, normal_force_: np.ndarray,
               onset: float = 0.0, backend: str = "numba") -> NormalFitResult:
    """Fit Eq. 13, ``f = K delta_mm^n + C delta_dot``, to the compressive loading branch.

    The window runs from contact to the peak indentation and keeps samples with
    ``delta > 0`` and ``f > 2 mN``: the tensile pull-off at separation lies outside the
    ``max(0, .)`` law (§7.2 (ii)) and the unloading branch carries the slow viscoelastic
    loop, which §7.2 attributes to relaxation rather than to ``C``. The start comes from a
    log-log regression; Levenberg-Marquardt with the analytic Jacobian refines ``(K, n, C)``.

    Parameters
    ----------
    time : (s,) float
        Sample times [s].
    displacement : (s,) float
        Probe travel from the touched-off surface [m].
    normal_force_ : (s,) float
        Measured normal force [N].
    onset : float, optional
        Displacement of the contact surface [m]; ``delta = displacement - onset``.
    backend : {"numba", "scipy"}, optional
        Solver (:data:`FIT_BACKENDS`): the compiled Levenberg-Marquardt run to a stationary
        point (default), or the reference ``scipy.optimize.least_squares`` (MINPACK's
        Levenberg-Marquardt), which is also the fallback when the compiled path does not
        converge or Eq. 13's ``max(0, .)`` clamp is active at its solution.

    Returns
    -------
    NormalFitResult

    Notes
    -----
    At constant approach speed ``C delta_dot`` is a constant offset, so within one event C is
    told apart from ``K delta^n`` only by the acceleration ramps; with ``|C delta_dot| <=
    0.6 mN`` at 10 mm/s against a 1 mN load cell, per-event C mostly absorbs offset-like model
    error (onset toe, touch-off) and is reported with its standard error ``c_se``.

    References
    ----------
    Paper Eq. 13, §7.2; More (1978) Levenberg-Marquardt, via scipy.optimize.least_squares.
    """
    check_fit_backend(backend)
    x = np.asarray(displacement, dtype=float)
    f = np.asarray(normal_force_, dtype=float)
    t = np.asarray(time, dtype=float)
    if x.size < 8:
        return _nan_normal(float(np.max(f)) if f.size else math.nan, 0)
    ipk = int(np.argmax(x))
    peak = float(np.max(f))
    depth = x - onset
    rate = bench_kernels.gradient(x, t)  # numpy.gradient, bit for bit
    win = loading_window(x, f, onset)
    w_load = _branch_work(x[: ipk + 1], f[: ipk + 1])
    w_unload = _branch_work(x[ipk:], f[ipk:])
    if np.count_nonzero(win) < 6 or peak <= 0.0:
        return _nan_normal(peak, int(np.count_nonzero(win)))
    d_mm = depth[win] * 1e3
    r = rate[win]
    y = f[win]
    # start: log-log regression on the upper part (away from the onset toe)
    upper = y > 0.2 * y.max()
    if np.count_nonzero(upper) < 3:
        upper = np.ones_like(y, dtype=bool)
    slope, icpt = np.polyfit(np.log(d_mm[upper]), np.log(y[upper]), 1)
    x0 = np.array([math.exp(icpt), float(np.clip(slope, *EXPONENT_RANGE)), 0.0])
    log_d = np.log(d_mm)

    def resid(p: np.ndarray) -> np.ndarray:
        return normal_force(depth[win], r, p[0], p[1], p[2]) - y

    def jac(p: np.ndarray) -> np.ndarray:
        pw = np.exp(p[1] * log_d)
        return np.column_stack([pw, p[0] * pw * log_d, r])

    d_win = depth[win]

    def unclamped(p: np.ndarray) -> bool:  # the compiled model omits Eq. 13's max(0, .)
        return bool(np.all(p[0] * np.power(d_win * 1e3, p[1]) + p[2] * r > 0.0))

    try:
        p_fit, fun, success = solve_least_squares(
            resid, jac, x0, MODEL_NORMAL, (d_mm, r, y), UNBOUNDED, TYPICAL_NORMAL, backend,
            check=unclamped, method="lm", x_scale=[0.1, 0.1, 0.05], max_nfev=200)
    except (ValueError, np.linalg.LinAlgError) as exc:  # pragma: no cover - defensive
        log.debug("normal fit failed: %s", exc)
        return _nan_normal(peak, int(d_mm.size))
    k, n, c = (float(v) for v in p_fit)
    ok = success and k > 0 and EXPONENT_RANGE[0] <= n <= EXPONENT_RANGE[1]
    rmse = float(np.sqrt(np.mean(fun**2)) / peak * 100.0)
    dof = max(d_mm.size - 3, 1)
    try:
        j = jac(p_fit)
        cov = np.linalg.inv(j.T @ j) * (float(fun @ fun) / dof)
        c_se = float(np.sqrt(max(cov[2, 2], 0.0)))
    except np.linalg.LinAlgError:
        c_se = math.inf
    return NormalFitResult(k, n, c, c_se, force_at_reference_depth(k, n), rmse, peak,
                           float(depth[ipk]), w_load, w_unload, int(d_mm.size), ok)


@dataclass(frozen=True)
class ShiftedFitResult:
    """Shifted-law fit ``f = K (delta_mm - delta_0,mm)^m`` (the §7.2 refinement).

    Attributes
    ----------
    k_n_per_mm_m, m : float
        Stiffness [N mm^-m] and exponent.
    delta0 : float
        Onset offset [m] (in displacement coordinates: the apparent contact surface).
    rmse_pct : float
        RMSE in % of peak force.
    success : bool
    """

    k_n_per_mm_m: float
    m: float
    delta0: float
    rmse_pct: float
    success: bool


def fit_shifted(time: np.ndarray, displacement: np.ndarray, normal_force_: np.ndarray,
                backend: str = "numba") -> ShiftedFitResult:
    """Fit ``K (x - x_0)^m`` to the loading branch, with the onset ``x_0`` free.

    Samples below 10 % of the peak force are left out so the onset toe does not drive the
    fit; ``x_0`` then extrapolates the contact surface of the power-law part, which is
    also how :func:`fit_normal` is given its ``onset`` for fatigue cycles.

    Parameters
    ----------
    time : (s,) float
    displacement : (s,) float
        [m].
    normal_force_ : (s,) float
        [N].
    backend : {"numba", "scipy"}, optional
        Solver (:data:`FIT_BACKENDS`): the compiled Levenberg-Marquardt run to a stationary
        point (default), or the reference ``scipy.optimize.least_squares`` (trust-region
        reflective within the bounds below), which is also the fallback when the compiled
        path meets a bound.

    Returns
    -------
    ShiftedFitResult

    References
    ----------
    Paper §7.2 ("a shifted law K(delta - delta_0)^m ... a candidate refinement").
    """
    del time
    check_fit_backend(backend)
    x = np.asarray(displacement, dtype=float)
    f = np.asarray(normal_force_, dtype=float)
    nan = ShiftedFitResult(math.nan, math.nan, math.nan, math.nan, False)
    if x.size < 8:
        return nan
    ipk = int(np.argmax(x))
    peak = float(np.max(f))
    xs, fs = x[: ipk + 1], f[: ipk + 1]
    win = fs > 0.1 * peak
    if np.count_nonzero(win) < 6 or peak <= 0:
        return nan
    xm, y = xs[win] * 1e3, fs[win]
    first = xm.min()
    x0 = np.array([y.max() / max(xm.max() - first + 0.05, 0.05) ** 0.5, 0.5, first - 0.05])

    def resid(p: np.ndarray) -> np.ndarray:
        d = np.maximum(xm - p[2], 1e-9)
        return p[0] * d ** p[1] - y

    def jac(p: np.ndarray) -> np.ndarray:
        d = np.maximum(xm - p[2], 1e-9)
        pw = d ** p[1]
        return np.column_stack([pw, p[0] * pw * np.log(d), -p[0] * p[1] * pw / d])

    try:
        p_fit, fun, success = solve_least_squares(
            resid, jac, x0, MODEL_SHIFTED, (xm, xm, y),
            (np.array([1e-6, 0.05, -1.0]), np.array([100.0, 3.0, first - 1e-6])),
            TYPICAL_SHIFTED, backend, method="trf", max_nfev=200)
    except (ValueError, np.linalg.LinAlgError) as exc:  # pragma: no cover - defensive
        log.debug("shifted fit failed: %s", exc)
        return nan
    k, m, d0 = (float(v) for v in p_fit)
    rmse = float(np.sqrt(np.mean(fun**2)) / peak * 100.0)
    return ShiftedFitResult(k, m, d0 * 1e-3, rmse, success)
