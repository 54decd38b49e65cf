"""Agreement of predictions with measurements: classifier scores, Bland-Altman, parity, coefficient
of variation, median absolute percentage error, survival. Signed errors are measured - predicted
(paper Sec. 9.3).

References
----------
van Rijsbergen, C. J. (1979). Information Retrieval, 2nd ed., ch. 7 (F-measure). Bland, J. M. &
Altman, D. G. (1986). Lancet 327(8476), 307-310. Eisenhauer, J. G. (2003). Teaching Statistics
25(3), 76-80. Kvalseth, T. O. (1985). Am. Stat. 39(4), 279-285. Everitt, B. S. & Skrondal, A.
(2010). The Cambridge Dictionary of Statistics, 4th ed. Efron, B. & Tibshirani, R. J. (1993). An
Introduction to the Bootstrap, ch. 13. Hanley, J. A. & McNeil, B. J. (1982). Radiology 143(1),
29-36. Hyndman, R. J. & Koehler, A. B. (2006). Int. J. Forecast.
22(4), 679-688. Kaplan, E. L. & Meier, P. (1958). J. Am. Stat. Assoc. 53(282), 457-481.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy import stats
from statsmodels.regression.linear_model import OLS

from graspcampaign.analysis.checks import check_1d, check_paired, require, result
from graspcampaign.analysis.rates import BOOTSTRAP_RESAMPLES, CONFIDENCE_LEVEL
from graspcampaign.core.words import counted

#: Fewer held-out positives or negatives than this and the AUC gets no interval: the percentile
#: interval's coverage is below 90 % with 5 positives (docs/decisions.md, surrogate AUC interval).
AUC_INTERVAL_MIN_CLASS = 10

#: Multiplier of the SD for the 95 % limits of agreement (Bland & Altman 1986, p. 308).
LIMITS_OF_AGREEMENT_Z = 1.96


ClassifierMetrics = result(
    "ClassifierMetrics", "Binary classifier scores (nan at a zero denominator); ``confusion`` is "
    "``[[tn, fp], [fn, tp]]`` (rows actual, as scikit-learn's).",
    {k: property(lambda self, i=i: int(self.confusion.flat[i]))
     for i, k in enumerate(("tn", "fp", "fn", "tp"))},
    accuracy=float, precision=float, recall=float, f1=float, confusion=np.ndarray, n=int)
BlandAltmanResult = result(
    "BlandAltmanResult", "Bland-Altman bias and 95 % limits of ``measured - predicted``.",
    bias=float, sd=float, lower=float, upper=float, n=int)
ParityResult = result(
    "ParityResult", "Line ``measured = slope * predicted`` through the origin; ``r2_uncentred = 1 - "
    "SSR / sum(y**2)``, ``r2_centred = 1 - SSR / sum((y - mean)**2)`` (negative if the mean wins).",
    slope_through_origin=float, r2_uncentred=float, r2_centred=float, n=int)
AucInterval = result(
    "AucInterval", "95 % percentile bootstrap interval of a held-out AUC (nan, and ``reason`` why, "
    "when there is none).", low=float, high=float, method=str, n_resamples=int, reason=str)
SurvivalCurve = result(
    "SurvivalCurve", "Share of trials whose threshold is at least each level.",
    levels=np.ndarray, surviving_fraction=np.ndarray, n=int)


def _ratio(numerator: int, denominator: int) -> float:
    return math.nan if denominator == 0 else numerator / denominator


def _frozen(values: ArrayLike, dtype=np.float64) -> np.ndarray:
    arr = np.array(values, dtype=dtype)
    arr.setflags(write=False)
    return arr


def classifier_metrics(predicted: ArrayLike, actual: ArrayLike) -> ClassifierMetrics:
    """Return the scores of ``predicted`` (certified) against ``actual`` (measured) positives;
    ``f1 = 2 tp / (2 tp + fp + fn)`` is 0, not nan, when tp = 0 but fp + fn > 0."""
    p, a = check_paired(predicted, actual, "predicted", "actual", binary=True)
    tp, fp, fn, tn = (int(np.sum(x & y)) for x, y in ((p, a), (p, ~a), (~p, a), (~p, ~a)))
    return ClassifierMetrics((tp + tn) / p.size, _ratio(tp, tp + fp), _ratio(tp, tp + fn),
                             _ratio(2 * tp, 2 * tp + fp + fn),
                             _frozen([[tn, fp], [fn, tp]], np.int64), int(p.size))


def bland_altman(measured: ArrayLike, predicted: ArrayLike) -> BlandAltmanResult:
    """Return the bias (positive: the model under-predicts), SD (ddof 1), ``bias -/+ 1.96 sd``."""
    measured, predicted = check_paired(measured, predicted, "measured", "predicted", 2)
    d = measured - predicted
    bias, sd = float(np.mean(d)), float(np.std(d, ddof=1))
    return BlandAltmanResult(bias, sd, bias - LIMITS_OF_AGREEMENT_Z * sd,
                             bias + LIMITS_OF_AGREEMENT_Z * sd, int(d.size))


def parity_fit(measured: ArrayLike, predicted: ArrayLike) -> ParityResult:
    """Return the slope of measured on predicted through the origin (statsmodels ``OLS``) and R^2;
    the uncentred R^2 grows with the data's distance from the origin, the centred one does not."""
    measured, predicted = check_paired(measured, predicted, "measured", "predicted", 2)
    require(np.any(predicted != 0.0), "predicted must not be all zero (the slope through the "
                                      "origin is then undefined).")
    fit = OLS(measured, predicted[:, None]).fit()
    centred, uncentred = np.sum((measured - measured.mean()) ** 2), np.sum(measured**2)
    return ParityResult(float(fit.params[0]), 1 - fit.ssr / uncentred if uncentred > 0 else math.nan,
                        1 - fit.ssr / centred if centred > 0 else math.nan, int(measured.size))


def coefficient_of_variation(x: ArrayLike, axis: int | None = None) -> float | np.ndarray:
    """Return ``std(x, ddof=1) / mean(x)`` along ``axis`` (``scipy.stats.variation``; nan at a zero
    mean, negative at a negative one)."""
    arr = np.asarray(x)
    require(arr.dtype.kind in "biuf", f"x must hold real numbers, got dtype {arr.dtype}.")
    require(np.isfinite(arr).all(), "x must be finite (no nan or inf).")
    size = arr.size if axis is None else (arr.shape[axis] if arr.ndim else 0)
    require(size >= 2, f"x must hold at least 2 values along the axis, got {size}.")
    arr = arr.astype(np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        cv = np.where(arr.mean(axis=axis) == 0.0, np.nan, stats.variation(arr, axis=axis, ddof=1))
    return float(cv) if cv.ndim == 0 else cv


def cv_interval(x: ArrayLike, *, seed: int, n_resamples: int = BOOTSTRAP_RESAMPLES,
                confidence_level: float = CONFIDENCE_LEVEL) -> tuple[float, float]:
    """Return the percentile interval of the CV of ``x`` by ``scipy.stats.bootstrap`` (n >= 3)."""
    arr = check_1d(x, "x", 3)
    require(np.ptp(arr) > 0, "every value is the same: a zero spread has no interval")
    return _percentile_interval(arr, lambda v, axis=-1: np.std(v, axis=axis, ddof=1) / np.mean(v, axis=axis),
                                seed, n_resamples, confidence_level)


def median_interval(x: ArrayLike, *, seed: int, n_resamples: int = BOOTSTRAP_RESAMPLES,
                    confidence_level: float = CONFIDENCE_LEVEL) -> tuple[float, float]:
    """Return the percentile interval of the median of ``x`` by ``scipy.stats.bootstrap`` (n >= 3)."""
    return _percentile_interval(check_1d(x, "x", 3), np.median, seed, n_resamples, confidence_level)


def _percentile_interval(arr: np.ndarray, statistic, seed: int, n_resamples: int,
                         confidence_level: float) -> tuple[float, float]:
    res = stats.bootstrap((arr,), statistic, n_resamples=n_resamples, confidence_level=confidence_level,
                          method="percentile", rng=np.random.default_rng(seed), vectorized=True)
    return float(res.confidence_interval.low), float(res.confidence_interval.high)


def auc(positive: np.ndarray, negative: np.ndarray, axis: int = -1) -> np.ndarray:
    """ROC AUC along ``axis``: the share of (positive, negative) score pairs ranked right, a tie
    counting one half (Mann-Whitney U / (n_pos n_neg); Hanley & McNeil 1982)."""
    u = stats.mannwhitneyu(positive, negative, axis=axis, method="asymptotic").statistic
    return u / (positive.shape[axis] * negative.shape[axis])


def auc_interval(positive: ArrayLike, negative: ArrayLike, *, seed: int,
                 n_resamples: int = BOOTSTRAP_RESAMPLES,
                 min_class: int = AUC_INTERVAL_MIN_CLASS) -> AucInterval:
    """Return the AUC's 95 % percentile bootstrap interval from the held-out scores of the positives
    and negatives, resampled apart (every resample keeps the stratified split's class counts); none,
    with its reason, below ``min_class`` of either class (lowered only by
    benchmarks/auc_interval_coverage.py, which measures the coverage the default guards)."""
    positive, negative = check_1d(positive, "positive", 0), check_1d(negative, "negative", 0)
    require(positive.size and negative.size, "an AUC needs both classes among the held-out scores, got "
                                             f"{positive.size} positives and {negative.size} negatives.")
    few = [f"only {counted(a.size, f'held-out {word}')}"
           for a, word in ((positive, "positive"), (negative, "negative")) if a.size < min_class]
    if few:
        return AucInterval(math.nan, math.nan, "", 0, " and ".join(few) + ", too few for an interval")
    ci = stats.bootstrap((positive, negative), auc, paired=False, vectorized=True, n_resamples=n_resamples,
                         method="percentile", rng=np.random.default_rng(seed)).confidence_interval
    return AucInterval(float(ci.low), float(ci.high), "percentile", n_resamples, "")


def median_abs_pct_error(measured: ArrayLike, predicted: ArrayLike) -> float:
    """Return ``100 * median(|predicted - measured| / |measured|)`` [%] (paper Sec. 9.3)."""
    measured, predicted = check_paired(measured, predicted, "measured", "predicted")
    zeros = int(np.sum(measured == 0.0))
    require(not zeros, f"measured must be non-zero (it is the denominator), got {zeros} zero values.")
    return float(100.0 * np.median(np.abs(predicted - measured) / np.abs(measured)))


def survival_curve(thresholds: ArrayLike, levels: ArrayLike | None = None) -> SurvivalCurve:
    """Return ``P(T >= level)`` at each level (default: the distinct thresholds); uncensored, so a
    lower bound above the largest load (Kaplan-Meier would be needed there)."""
    values = np.sort(check_1d(thresholds, "thresholds"))
    grid = np.unique(values) if levels is None else check_1d(levels, "levels")
    fraction = (values.size - np.searchsorted(values, grid, side="left")) / values.size
    return SurvivalCurve(_frozen(grid), _frozen(fraction), int(values.size))
