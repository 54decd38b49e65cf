"""Agreement of predictions with measurements: classifier scores, Bland-Altman, parity,
coefficient of variation, median absolute percentage error, empirical survival.

Signed errors are measured - predicted (paper Sec. 9.3). Shape letters: ``n`` observations,
``m`` survival levels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import stats
from statsmodels.regression.linear_model import OLS

from graspcampaign.analysis.checks import check_1d, check_binary, check_paired

#: Multiplier of the SD for the 95 % limits of agreement (Bland & Altman 1986, p. 308).
LIMITS_OF_AGREEMENT_Z = 1.96


@dataclass(frozen=True, slots=True)
class ClassifierMetrics:
    """Binary classifier scores; nan where a ratio has a zero denominator.

    ``confusion`` is ``[[tn, fp], [fn, tp]]``: rows are the actual class (0, 1), columns the
    predicted class (0, 1), as in scikit-learn's ``confusion_matrix``.
    """

    accuracy: float
    precision: float
    recall: float
    f1: float
    confusion: np.ndarray
    n: int

    @property
    def tn(self) -> int:
        return int(self.confusion[0, 0])

    @property
    def fp(self) -> int:
        return int(self.confusion[0, 1])

    @property
    def fn(self) -> int:
        return int(self.confusion[1, 0])

    @property
    def tp(self) -> int:
        return int(self.confusion[1, 1])


@dataclass(frozen=True, slots=True)
class BlandAltmanResult:
    """Bland-Altman bias and 95 % limits of agreement of ``measured - predicted``."""

    bias: float
    sd: float
    lower: float
    upper: float
    n: int


@dataclass(frozen=True, slots=True)
class ParityResult:
    """Least-squares line through the origin, ``measured = slope * predicted``.

    ``r2_uncentred = 1 - SSR / sum(measured**2)`` (what regression-through-origin software
    reports); ``r2_centred = 1 - SSR / sum((measured - mean)**2)`` (same residuals, judged
    against the mean; negative when the origin line does worse than the mean).
    """

    slope_through_origin: float
    r2_uncentred: float
    r2_centred: float
    n: int


@dataclass(frozen=True, slots=True)
class SurvivalCurve:
    """Empirical fraction of trials whose threshold is at least each level."""

    levels: np.ndarray
    surviving_fraction: np.ndarray
    n: int


def classifier_metrics(predicted: ArrayLike, actual: ArrayLike) -> ClassifierMetrics:
    """Return accuracy, precision, recall, F1 and the confusion matrix of a binary classifier.

    Parameters
    ----------
    predicted : (n,) bool
        Predicted positive (e.g. the planner certified the grasp as stable/retained).
    actual : (n,) bool
        Measured positive (e.g. the trial succeeded).

    Returns
    -------
    ClassifierMetrics
        ``precision = tp / (tp + fp)`` (nan with no predicted positives),
        ``recall = tp / (tp + fn)`` (nan with no actual positives),
        ``f1 = 2 tp / (2 tp + fp + fn)`` (nan only when there are no positives at all; it is
        0, not nan, when tp = 0 but fp + fn > 0, which equals the harmonic mean wherever both
        precision and recall are defined).

    References
    ----------
    van Rijsbergen, C. J. (1979). Information Retrieval, 2nd ed., Butterworths, ch. 7 (F-measure).
    """
    p = check_binary(predicted, "predicted")
    a = check_binary(actual, "actual")
    if p.shape != a.shape:
        raise ValueError(f"predicted and actual must have the same length, got {p.size} and "
                         f"{a.size}.")
    tp = int(np.sum(p & a))
    fp = int(np.sum(p & ~a))
    fn = int(np.sum(~p & a))
    tn = int(np.sum(~p & ~a))
    confusion = np.array([[tn, fp], [fn, tp]], dtype=np.int64)
    confusion.setflags(write=False)
    return ClassifierMetrics(accuracy=(tp + tn) / p.size, precision=_ratio(tp, tp + fp),
                             recall=_ratio(tp, tp + fn), f1=_ratio(2 * tp, 2 * tp + fp + fn),
                             confusion=confusion, n=int(p.size))


def _ratio(numerator: int, denominator: int) -> float:
    return math.nan if denominator == 0 else numerator / denominator


def bland_altman(measured: ArrayLike, predicted: ArrayLike) -> BlandAltmanResult:
    """Return the Bland-Altman bias and 95 % limits of agreement of measured - predicted.

    Parameters
    ----------
    measured : (n,) float
        Measured values (e.g. lateral slip threshold [N]); n >= 2.
    predicted : (n,) float
        Predictions of the same quantity, in the same unit.

    Returns
    -------
    BlandAltmanResult
        ``bias`` = mean of ``d = measured - predicted`` (positive: the model under-predicts,
        the paper's convention), ``sd`` the sample SD of ``d`` (ddof = 1), and
        ``lower, upper = bias -/+ 1.96 sd``.

    References
    ----------
    Bland, J. M. & Altman, D. G. (1986). Statistical methods for assessing agreement between two
    methods of clinical measurement. Lancet 327(8476), 307-310.
    """
    measured, predicted = check_paired(measured, predicted, "measured", "predicted", 2)
    d = measured - predicted
    bias = float(np.mean(d))
    sd = float(np.std(d, ddof=1))
    half_width = LIMITS_OF_AGREEMENT_Z * sd
    return BlandAltmanResult(bias=bias, sd=sd, lower=bias - half_width, upper=bias + half_width,
                             n=int(d.size))


def parity_fit(measured: ArrayLike, predicted: ArrayLike) -> ParityResult:
    """Return the least-squares slope of measured on predicted through the origin, and R^2.

    Parameters
    ----------
    measured : (n,) float
        Ordinate of the parity plot (e.g. trial-mean measured fingertip normal force [N]).
    predicted : (n,) float
        Abscissa, same unit; not all zero.

    Returns
    -------
    ParityResult
        ``slope_through_origin = sum(x y) / sum(x**2)`` with x = predicted, y = measured.
        ``r2_uncentred = 1 - SSR / sum(y**2)``: the uncentred R^2 that through-origin
        regression reports (statsmodels OLS without a constant, R ``lm(y ~ 0 + x)``); it is
        inflated by the distance of the data from the origin.
        ``r2_centred = 1 - SSR / sum((y - mean(y))**2)``: the same residuals judged against the
        mean (Kvalseth's R^2_1); it can be negative. nan when measured is constant.

    Notes
    -----
    Computed with ``statsmodels.regression.linear_model.OLS`` (no constant).

    References
    ----------
    Eisenhauer, J. G. (2003). Regression through the origin. Teaching Statistics 25(3), 76-80.
    Kvalseth, T. O. (1985). Cautionary note about R^2. Am. Stat. 39(4), 279-285.
    """
    measured, predicted = check_paired(measured, predicted, "measured", "predicted", 2)
    if not np.any(predicted != 0.0):
        raise ValueError("predicted must not be all zero (the slope through the origin is then "
                         "undefined).")
    fit = OLS(measured, predicted[:, None]).fit()
    ssr = float(fit.ssr)
    centred_tss = float(np.sum((measured - measured.mean()) ** 2))
    uncentred_tss = float(np.sum(measured**2))
    return ParityResult(
        slope_through_origin=float(fit.params[0]),
        r2_uncentred=1.0 - ssr / uncentred_tss if uncentred_tss > 0 else math.nan,
        r2_centred=1.0 - ssr / centred_tss if centred_tss > 0 else math.nan,
        n=int(measured.size),
    )


def coefficient_of_variation(x: ArrayLike, axis: int | None = None) -> float | np.ndarray:
    """Return the coefficient of variation, sample SD over mean.

    Parameters
    ----------
    x : (..., n) float
        Values; at least 2 along ``axis`` (e.g. a trial's three per-finger f_t/f_n ratios).
    axis : int or None
        Axis along which to compute, or None (default) for all values.

    Returns
    -------
    float or numpy.ndarray
        ``std(x, ddof=1) / mean(x)``, a fraction (multiply by 100 for %). Signed: a negative
        mean gives a negative CV; a zero mean gives nan.

    Notes
    -----
    Computed by ``scipy.stats.variation(x, ddof=1)``.

    References
    ----------
    Everitt, B. S. & Skrondal, A. (2010). The Cambridge Dictionary of Statistics, 4th ed.,
    "coefficient of variation".
    """
    arr = np.asarray(x)
    if arr.dtype.kind not in "biuf":
        raise ValueError(f"x must hold real numbers, got dtype {arr.dtype}.")
    arr = arr.astype(np.float64)
    if not np.all(np.isfinite(arr)):
        raise ValueError("x must be finite (no nan or inf).")
    size = arr.size if axis is None else (arr.shape[axis] if arr.ndim else 0)
    if size < 2:
        raise ValueError(f"x must hold at least 2 values along the axis, got {size}.")
    mean = arr.mean(axis=axis)
    with np.errstate(divide="ignore", invalid="ignore"):
        cv = stats.variation(arr, axis=axis, ddof=1)
    cv = np.where(mean == 0.0, np.nan, cv)
    return float(cv) if cv.ndim == 0 else cv


def median_abs_pct_error(measured: ArrayLike, predicted: ArrayLike) -> float:
    """Return the median absolute percentage error of predictions, relative to the measurement.

    Parameters
    ----------
    measured : (n,) float
        Measured values; none may be zero (they are the denominators).
    predicted : (n,) float
        Predictions of the same quantity.

    Returns
    -------
    float
        ``100 * median(|predicted - measured| / |measured|)`` [%]. The denominator is the
        *measured* value, as in the paper's threshold-prediction errors (Sec. 9.3).

    References
    ----------
    Hyndman, R. J. & Koehler, A. B. (2006). Another look at measures of forecast accuracy.
    Int. J. Forecast. 22(4), 679-688 (median absolute percentage error).
    """
    measured, predicted = check_paired(measured, predicted, "measured", "predicted")
    zeros = int(np.sum(measured == 0.0))
    if zeros:
        raise ValueError(f"measured must be non-zero (it is the denominator), got {zeros} zero "
                         "values.")
    return float(100.0 * np.median(np.abs(predicted - measured) / np.abs(measured)))


def survival_curve(thresholds: ArrayLike, levels: ArrayLike | None = None) -> SurvivalCurve:
    """Return the empirical fraction of trials whose threshold is at least each level.

    Parameters
    ----------
    thresholds : (n,) float
        Per-trial sustained disturbance threshold (e.g. lateral pull at slip [N]).
    levels : (m,) float or None
        Levels at which to evaluate; default the sorted distinct thresholds.

    Returns
    -------
    SurvivalCurve
        ``surviving_fraction[j] = #{i : thresholds[i] >= levels[j]} / n``, the empirical
        survival function ``P(T >= level)`` (left-continuous).

    Notes
    -----
    No censoring is modelled: every threshold is taken as observed. A trial that survived the
    largest load applied has a threshold that is only a lower bound; counted at that load, it
    makes the curve a lower bound of the true survival at higher levels. Filter or mark such
    trials before calling if they occur (a Kaplan-Meier estimate would be needed instead).

    References
    ----------
    Kaplan, E. L. & Meier, P. (1958). Nonparametric estimation from incomplete observations.
    J. Am. Stat. Assoc. 53(282), 457-481 (the uncensored case reduces to this curve).
    """
    values = np.sort(check_1d(thresholds, "thresholds"))
    grid = np.unique(values) if levels is None else check_1d(levels, "levels")
    at_least = values.size - np.searchsorted(values, grid, side="left")
    fraction = at_least / values.size
    grid = np.array(grid, dtype=np.float64)
    grid.setflags(write=False)
    fraction.setflags(write=False)
    return SurvivalCurve(levels=grid, surviving_fraction=fraction, n=int(values.size))


def cv_interval(x: ArrayLike, *, seed: int, n_resamples: int = 10_000,
                confidence_level: float = 0.95) -> tuple[float, float]:
    """Return the percentile-bootstrap interval of the coefficient of variation of ``x``.

    Parameters
    ----------
    x : (n,) float
        Values (e.g. one identified parameter over PSO restarts); n >= 3 and not all equal.
    seed : int
        Generator seed (the study seed), so the interval is reproducible.

    Returns
    -------
    tuple of float
        ``(low, high)`` of ``std(x, ddof=1) / mean(x)`` (fractions).

    Raises
    ------
    ValueError
        Fewer than 3 values, or every value equal (a zero spread has no interval).

    References
    ----------
    Efron, B. & Tibshirani, R. J. (1993), ch. 13 (percentile interval);
    ``scipy.stats.bootstrap``.
    """
    arr = check_1d(x, "x", 3)
    if np.ptp(arr) == 0:
        raise ValueError("every value is the same: a zero spread has no interval")
    res = stats.bootstrap((arr,), lambda v, axis=-1: np.std(v, axis=axis, ddof=1)
                          / np.mean(v, axis=axis), n_resamples=n_resamples,
                          confidence_level=confidence_level, method="percentile",
                          rng=np.random.default_rng(seed), vectorized=True)
    return float(res.confidence_interval.low), float(res.confidence_interval.high)
