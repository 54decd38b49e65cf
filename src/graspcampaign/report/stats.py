"""Statistics for campaign reports: rate intervals, paired and unpaired tests, agreement.

Public as ``graspcampaign.stats``. Every function validates its inputs first (``_check_*``
helpers, raising ``ValueError`` with one sentence naming the argument) and then hands the
computation to the well-kept libraries (scipy.stats, statsmodels); the few closed forms kept here
(percentile bootstrap of a pooled rate, classifier counts, Bland-Altman limits, Connor's paired
sample size) are one line each and cite their source. Results are small frozen dataclasses.

Conventions, as in the paper (Sec. 11, "Software and data"): success denominators are executed
trials; paired comparisons use occurrence-matched pairs; signed errors are measured - predicted.

Shape letters used in this module: ``n`` observations (trials or pairs), ``k`` clusters
(objects), ``B`` bootstrap resamples, ``m`` survival levels, ``p`` regression coefficients,
``r x c`` contingency tables.
"""

from __future__ import annotations

import math
import numbers
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from decimal import ROUND_HALF_EVEN, Decimal

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike
from scipy import optimize, stats
from statsmodels.discrete.discrete_model import Logit
from statsmodels.regression.linear_model import OLS
from statsmodels.stats.contingency_tables import mcnemar as _sm_mcnemar
from statsmodels.stats.power import NormalIndPower
from statsmodels.stats.proportion import proportion_confint, proportion_effectsize
from statsmodels.tools.sm_exceptions import PerfectSeparationError

__all__ = [
    "LIMITS_OF_AGREEMENT_Z",
    "BlandAltmanResult",
    "BootstrapInterval",
    "Chi2Result",
    "ClassifierMetrics",
    "KruskalResult",
    "LogisticResult",
    "McNemarResult",
    "ParityResult",
    "ProportionInterval",
    "SampleSizeResult",
    "SurvivalCurve",
    "bland_altman",
    "chi2_contingency_test",
    "classifier_metrics",
    "cluster_bootstrap_interval",
    "coefficient_of_variation",
    "discordant_pairs",
    "format_estimate_interval",
    "format_interval",
    "kruskal_wallis",
    "logistic_regression",
    "mcnemar",
    "median_abs_pct_error",
    "parity_fit",
    "power_two_proportions",
    "survival_curve",
    "wilson_interval",
]

#: Multiplier of the SD for the 95 % limits of agreement (Bland & Altman 1986, p. 308).
LIMITS_OF_AGREEMENT_Z = 1.96


# --------------------------------------------------------------------------------------------
# Result types
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class ProportionInterval:
    """Binomial proportion with its confidence interval (fractions in [0, 1])."""

    estimate: float
    low: float
    high: float
    n: int
    successes: int
    confidence_level: float
    method: str


@dataclass(frozen=True, slots=True)
class BootstrapInterval:
    """Cluster-bootstrap percentile interval of a pooled rate (fractions in [0, 1]).

    ``seed`` is the integer seed when one was given; ``rng_note`` says how the generator was
    made, so a report can state it next to ``n_resamples``.
    """

    estimate: float
    low: float
    high: float
    n_clusters: int
    n_trials: int
    n_resamples: int
    confidence_level: float
    seed: int | None
    rng_note: str


@dataclass(frozen=True, slots=True)
class McNemarResult:
    """McNemar test on discordant pairs, with the discordant-pair odds ratio.

    ``statistic`` is nan when there are no discordant pairs (the test is undefined there).
    ``odds_ratio = n10 / n01``: the odds that a discordant pair favours method A.
    """

    statistic: float
    pvalue_chi2: float
    pvalue_exact: float
    odds_ratio: float
    odds_ratio_low: float
    odds_ratio_high: float
    n_discordant: int
    n01: int
    n10: int
    confidence_level: float


@dataclass(frozen=True, slots=True)
class Chi2Result:
    """Pearson chi-square test of independence on an r x c table."""

    statistic: float
    pvalue: float
    dof: int
    expected: np.ndarray
    yates_correction: bool


@dataclass(frozen=True, slots=True)
class KruskalResult:
    """Kruskal-Wallis H test; ``statistic`` is nan (and ``pvalue`` 1) when all values tie."""

    statistic: float
    pvalue: float
    n_groups: int
    n: int


@dataclass(frozen=True, slots=True)
class LogisticResult:
    """Unpenalised logistic regression.

    ``coefficients`` has one row per term (``"intercept"`` first, then the predictors in the
    order given) and the columns ``coef, se, z, p, ci_low, ci_high`` on the log-odds scale
    (``numpy.exp`` of a coefficient is its odds ratio). When ``separation`` is True or
    ``converged`` is False the maximum-likelihood estimate does not exist or was not reached, and
    the numbers are the optimiser's last iterate, not estimates to interpret.
    """

    coefficients: pd.DataFrame
    converged: bool
    separation: bool
    separation_kind: str
    n: int
    messages: tuple[str, ...]


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


@dataclass(frozen=True, slots=True)
class SampleSizeResult:
    """Trials per arm (pairs, when paired) needed to detect a success-rate difference."""

    n_per_arm: int
    n_per_arm_unrounded: float
    effect_size: float
    effect_size_kind: str
    alpha: float
    power: float
    paired: bool
    alternative: str


# --------------------------------------------------------------------------------------------
# Input validation (kept apart from the computation)
# --------------------------------------------------------------------------------------------


def _check_count(value: object, name: str) -> int:
    """Return ``value`` as a non-negative int, or raise naming ``name``."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a non-negative integer count, got {value!r}.")
    if not math.isfinite(value) or value != int(value) or value < 0:
        raise ValueError(f"{name} must be a non-negative integer count, got {value!r}.")
    return int(value)


def _check_successes_n(successes: object, n: object) -> tuple[int, int]:
    if isinstance(n, numbers.Real) and not isinstance(n, bool) and n <= 0:
        raise ValueError(f"n must be positive (the number of executed trials), got {n!r}.")
    n = _check_count(n, "n")
    successes = _check_count(successes, "successes")
    if successes > n:
        raise ValueError(f"successes must not exceed n, got successes={successes} and n={n}.")
    return successes, n


def _check_probability_open(value: object, name: str) -> float:
    """Return ``value`` as a float strictly between 0 and 1, or raise naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not 0 < value < 1:
        raise ValueError(f"{name} must be a number strictly between 0 and 1, got {value!r}.")
    return float(value)


def _check_probability_closed(value: object, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not 0 <= value <= 1:
        raise ValueError(f"{name} must be a number between 0 and 1, got {value!r}.")
    return float(value)


def _check_positive_int(value: object, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}.")
    return int(value)


def _check_1d(x: ArrayLike, name: str, min_size: int = 1) -> np.ndarray:
    """Return ``x`` as a finite 1-D float64 array of at least ``min_size`` values."""
    arr = np.asarray(x)
    if arr.dtype.kind not in "biuf":
        raise ValueError(f"{name} must hold real numbers, got dtype {arr.dtype}.")
    arr = arr.astype(np.float64)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be 1-D, got shape {arr.shape}.")
    if arr.size < min_size:
        raise ValueError(f"{name} must hold at least {min_size} values, got {arr.size}.")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no nan or inf), got {np.sum(~np.isfinite(arr))} "
                         "non-finite values.")
    return arr


def _check_paired(a: ArrayLike, b: ArrayLike, name_a: str, name_b: str,
                  min_size: int = 1) -> tuple[np.ndarray, np.ndarray]:
    a = _check_1d(a, name_a, min_size)
    b = _check_1d(b, name_b, min_size)
    if a.shape != b.shape:
        raise ValueError(f"{name_a} and {name_b} must have the same length, got {a.size} and "
                         f"{b.size}.")
    return a, b


def _check_binary(x: ArrayLike, name: str) -> np.ndarray:
    """Return ``x`` as a 1-D bool array; accept bool or 0/1 values."""
    arr = np.asarray(x)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array, got shape {arr.shape}.")
    if arr.dtype == bool:
        return arr
    if arr.dtype.kind not in "iuf" or not np.all(np.isin(arr, (0, 1))):
        raise ValueError(f"{name} must hold only booleans or 0/1 values.")
    return arr.astype(bool)


def _check_cluster_counts(successes: ArrayLike, trials: ArrayLike
                          ) -> tuple[np.ndarray, np.ndarray]:
    s = np.asarray(successes)
    t = np.asarray(trials)
    for arr, name in ((s, "successes_per_cluster"), (t, "trials_per_cluster")):
        if arr.ndim != 1:
            raise ValueError(f"{name} must be 1-D (one count per cluster), got shape {arr.shape}.")
        if arr.dtype.kind not in "iuf" or not np.all(np.isfinite(arr)) \
                or np.any(arr < 0) or np.any(arr != np.round(arr)):
            raise ValueError(f"{name} must hold non-negative integer counts.")
    if s.shape != t.shape:
        raise ValueError("successes_per_cluster and trials_per_cluster must have the same "
                         f"length, got {s.size} and {t.size}.")
    if s.size < 2:
        raise ValueError(f"at least 2 clusters are needed to resample clusters, got {s.size}.")
    if np.any(t == 0):
        raise ValueError("trials_per_cluster must be positive for every cluster (drop clusters "
                         "with no executed trials).")
    if np.any(s > t):
        raise ValueError("successes_per_cluster must not exceed trials_per_cluster in any "
                         "cluster.")
    return s.astype(np.int64), t.astype(np.int64)


def _check_rng(rng: object) -> tuple[np.random.Generator, int | None, str]:
    """Return a Generator, the seed (if an int was given) and a note for the report."""
    if isinstance(rng, np.random.Generator):
        return rng, None, f"caller-supplied numpy Generator({type(rng.bit_generator).__name__})"
    if isinstance(rng, numbers.Integral) and not isinstance(rng, bool) and rng >= 0:
        return np.random.default_rng(int(rng)), int(rng), f"numpy.random.default_rng({int(rng)})"
    raise ValueError("rng must be a numpy.random.Generator or a non-negative integer seed, got "
                     f"{rng!r}.")


def _check_table(table: ArrayLike) -> np.ndarray:
    arr = np.asarray(table)
    if arr.ndim != 2 or arr.shape[0] < 2 or arr.shape[1] < 2:
        raise ValueError(f"table must be a 2-D array of at least 2 x 2 counts, got shape "
                         f"{arr.shape}.")
    if arr.dtype.kind not in "iuf" or not np.all(np.isfinite(arr)) or np.any(arr < 0):
        raise ValueError("table must hold finite non-negative counts.")
    if np.any(arr.sum(axis=1) == 0) or np.any(arr.sum(axis=0) == 0):
        raise ValueError("table must have no all-zero row or column (its expected counts would "
                         "be zero); drop the empty category first.")
    return arr.astype(np.float64)


def _check_frame(df: object, outcome: object, predictors: object
                 ) -> tuple[np.ndarray, np.ndarray, list[str]]:
    if not isinstance(df, pd.DataFrame):
        raise ValueError(f"df must be a pandas DataFrame, got {type(df).__name__}.")
    if not isinstance(outcome, str) or outcome not in df.columns:
        raise ValueError(f"outcome must name a column of df, got {outcome!r}.")
    if isinstance(predictors, str) or not isinstance(predictors, Sequence) or not predictors:
        raise ValueError("predictors must be a non-empty list of column names.")
    predictors = list(predictors)
    missing = [p for p in predictors if p not in df.columns]
    if missing:
        raise ValueError(f"predictors must name columns of df; not found: {missing}.")
    if outcome in predictors or len(set(predictors)) != len(predictors):
        raise ValueError("predictors must be distinct and must not include the outcome.")
    columns = [outcome, *predictors]
    bad = [c for c in columns if not (pd.api.types.is_numeric_dtype(df[c])
                                      or pd.api.types.is_bool_dtype(df[c]))]
    if bad:
        raise ValueError(f"outcome and predictors must be numeric or boolean columns; not: {bad}.")
    if df[columns].isna().to_numpy().any():
        raise ValueError("outcome and predictors must have no missing values; drop or impute "
                         "them first.")
    y = df[outcome].to_numpy(dtype=np.float64)
    if not np.all(np.isin(y, (0.0, 1.0))):
        raise ValueError(f"outcome column {outcome!r} must hold only 0/1 or booleans.")
    x = df[predictors].to_numpy(dtype=np.float64)
    if not np.all(np.isfinite(x)):
        raise ValueError("predictors must be finite (no inf).")
    if len(df) <= len(predictors) + 1:
        raise ValueError(f"df must have more rows than coefficients ({len(predictors) + 1}), got "
                         f"{len(df)}.")
    design = np.column_stack([np.ones(len(df)), x])
    if np.linalg.matrix_rank(design) < design.shape[1]:
        raise ValueError("predictors must not be linearly dependent on each other or on the "
                         "intercept (the design matrix is rank-deficient).")
    return y, design, predictors


def _check_alternative(alternative: object) -> str:
    if alternative not in ("two-sided", "one-sided"):
        raise ValueError(f"alternative must be 'two-sided' or 'one-sided', got {alternative!r}.")
    return str(alternative)


# --------------------------------------------------------------------------------------------
# Rates and their intervals
# --------------------------------------------------------------------------------------------


def wilson_interval(successes: int, n: int, confidence_level: float = 0.95
                    ) -> ProportionInterval:
    """Return the Wilson score interval of a binomial success rate.

    Parameters
    ----------
    successes : int
        Number of successes, ``0 <= successes <= n``.
    n : int
        Number of executed trials (the paper's denominator), positive.
    confidence_level : float
        Two-sided confidence level, strictly between 0 and 1.

    Returns
    -------
    ProportionInterval
        Fractions in [0, 1]; ``low`` is exactly 0 when ``successes == 0`` and ``high`` exactly 1
        when ``successes == n``.

    Notes
    -----
    Computed by ``statsmodels.stats.proportion.proportion_confint(method="wilson")``; the bounds
    are then clipped to [0, 1] so floating-point round-off can never leave the unit interval.

    References
    ----------
    Wilson, E. B. (1927). Probable inference, the law of succession, and statistical inference.
    J. Am. Stat. Assoc. 22(158), 209-212.
    Newcombe, R. G. (1998). Two-sided confidence intervals for the single proportion: comparison
    of seven methods. Stat. Med. 17(8), 857-872 (method 3).
    """
    successes, n = _check_successes_n(successes, n)
    confidence_level = _check_probability_open(confidence_level, "confidence_level")
    low, high = proportion_confint(successes, n, alpha=1.0 - confidence_level, method="wilson")
    low = 0.0 if successes == 0 else min(max(float(low), 0.0), 1.0)
    high = 1.0 if successes == n else min(max(float(high), 0.0), 1.0)
    return ProportionInterval(estimate=successes / n, low=low, high=high, n=n,
                              successes=successes, confidence_level=confidence_level,
                              method="wilson")


def cluster_bootstrap_interval(successes_per_cluster: ArrayLike, trials_per_cluster: ArrayLike,
                               *, n_resamples: int = 10_000, confidence_level: float = 0.95,
                               rng: np.random.Generator | int) -> BootstrapInterval:
    """Return the percentile interval of a pooled rate, resampling clusters (objects).

    Parameters
    ----------
    successes_per_cluster : (k,) int
        Successes in each cluster (e.g. each physical object).
    trials_per_cluster : (k,) int
        Executed trials in each cluster, each positive.
    n_resamples : int
        Bootstrap resamples ``B``.
    confidence_level : float
        Two-sided confidence level.
    rng : numpy.random.Generator or int
        Source of randomness; an int is a seed for ``numpy.random.default_rng`` and is reported
        back in ``seed`` (prefer it for reports, so the interval can be reproduced).

    Returns
    -------
    BootstrapInterval
        ``estimate`` is the pooled rate ``sum(s) / sum(n)`` of the data.

    Notes
    -----
    Each resample draws ``k`` clusters with replacement and keeps every trial of each drawn
    cluster (Davison & Hinkley's strategy of resampling at the top stage only), so the
    within-object correlation that a trial-level interval ignores is carried into the
    interval. The statistic of a resample is the pooled rate ``sum(s[i]) / sum(n[i])``. All
    resample indices are drawn at once as a ``(B, k)`` array (memory ``8 B k`` bytes), in the
    same order as ``scipy.stats.bootstrap(..., paired=True, method="percentile")``, which
    gives the same interval for the same generator state. Percentiles use linear interpolation
    (``numpy.quantile`` default).

    References
    ----------
    Efron, B. & Tibshirani, R. J. (1993). An Introduction to the Bootstrap. Chapman & Hall,
    ch. 13 (percentile interval).
    Davison, A. C. & Hinkley, D. V. (1997). Bootstrap Methods and Their Application. Cambridge
    University Press, sec. 3.8 (hierarchical data).
    """
    s, t = _check_cluster_counts(successes_per_cluster, trials_per_cluster)
    n_resamples = _check_positive_int(n_resamples, "n_resamples")
    confidence_level = _check_probability_open(confidence_level, "confidence_level")
    generator, seed, note = _check_rng(rng)

    n_clusters = s.size
    indices = generator.integers(0, n_clusters, size=(n_resamples, n_clusters))
    rates = s[indices].sum(axis=1) / t[indices].sum(axis=1)
    tail = (1.0 - confidence_level) / 2.0
    low, high = np.quantile(rates, [tail, 1.0 - tail])
    return BootstrapInterval(
        estimate=float(s.sum() / t.sum()),
        low=min(max(float(low), 0.0), 1.0),
        high=min(max(float(high), 0.0), 1.0),
        n_clusters=int(n_clusters),
        n_trials=int(t.sum()),
        n_resamples=n_resamples,
        confidence_level=confidence_level,
        seed=seed,
        rng_note=note,
    )


# --------------------------------------------------------------------------------------------
# Tests
# --------------------------------------------------------------------------------------------


def discordant_pairs(success_a: ArrayLike, success_b: ArrayLike) -> tuple[int, int]:
    """Return ``(n01, n10)`` from occurrence-matched outcomes of methods A and B.

    Parameters
    ----------
    success_a, success_b : (n,) bool
        Outcome of A and of B on the same matched occurrences (same object, condition and
        repeat index), element ``i`` of each forming one pair.

    Returns
    -------
    n01 : int
        Pairs where A failed and B succeeded.
    n10 : int
        Pairs where A succeeded and B failed.
    """
    a = _check_binary(success_a, "success_a")
    b = _check_binary(success_b, "success_b")
    if a.shape != b.shape:
        raise ValueError(f"success_a and success_b must have the same length, got {a.size} and "
                         f"{b.size}.")
    return int(np.sum(~a & b)), int(np.sum(a & ~b))


def mcnemar(n01: int, n10: int, confidence_level: float = 0.95) -> McNemarResult:
    """Return McNemar's test and the discordant-pair odds ratio for paired binary outcomes.

    Parameters
    ----------
    n01 : int
        Discordant pairs in which method A failed and method B succeeded.
    n10 : int
        Discordant pairs in which method A succeeded and method B failed.
    confidence_level : float
        Level of the exact interval on the odds ratio.

    Returns
    -------
    McNemarResult
        ``statistic`` is the continuity-corrected chi-square
        ``(|n10 - n01| - 1)**2 / (n01 + n10)`` on 1 degree of freedom and ``pvalue_chi2`` its
        upper tail; ``pvalue_exact`` is the two-sided binomial p of ``n10`` out of ``n01 + n10``
        at 1/2. ``odds_ratio = n10 / n01`` (inf when ``n01 == 0``), with the exact interval
        obtained by mapping the Clopper-Pearson interval on ``q = n10 / (n01 + n10)`` through
        ``q / (1 - q)``.

    Notes
    -----
    Orientation: with A the proposed planner and B a baseline, ``n10`` counts the pairs "won"
    by the proposed planner, so the paper's "33 won against 3 lost" is ``mcnemar(3, 33)`` and
    gives chi2 = 23.4 and odds ratio 11.0 (paper Sec. 8.5); its "54 won against 1 lost" gives
    chi2 = 49.2 (Sec. 9.5). The statistic is symmetric in ``n01`` and ``n10``.

    With no discordant pairs the test is undefined: ``statistic`` and the odds ratio are nan and
    both p-values are 1.0 (not inf or a division warning). When ``n01 == n10 > 0`` the
    correction is not applied (it would overshoot zero), so the statistic is 0 and p = 1, as in
    R's ``mcnemar.test``. Otherwise the chi-square comes from
    ``statsmodels.stats.contingency_tables.mcnemar(exact=False, correction=True)`` and the exact
    p and interval from ``scipy.stats.binomtest``.

    References
    ----------
    McNemar, Q. (1947). Note on the sampling error of the difference between correlated
    proportions or percentages. Psychometrika 12(2), 153-157.
    Edwards, A. L. (1948). Note on the "correction for continuity" in testing the significance
    of the difference between correlated proportions. Psychometrika 13(3), 185-187.
    Clopper, C. J. & Pearson, E. S. (1934). The use of confidence or fiducial limits
    illustrated in the case of the binomial. Biometrika 26(4), 404-413.
    Breslow, N. E. & Day, N. E. (1980). Statistical Methods in Cancer Research I, sec. 5.2
    (conditional odds ratio of matched pairs and its exact limits).
    """
    n01 = _check_count(n01, "n01")
    n10 = _check_count(n10, "n10")
    confidence_level = _check_probability_open(confidence_level, "confidence_level")
    n_discordant = n01 + n10
    if n_discordant == 0:
        return McNemarResult(statistic=math.nan, pvalue_chi2=1.0, pvalue_exact=1.0,
                             odds_ratio=math.nan, odds_ratio_low=math.nan,
                             odds_ratio_high=math.nan, n_discordant=0, n01=0, n10=0,
                             confidence_level=confidence_level)
    if n01 == n10:
        statistic, pvalue_chi2 = 0.0, 1.0
    else:
        chi2 = _sm_mcnemar(np.array([[0, n01], [n10, 0]]), exact=False, correction=True)
        statistic, pvalue_chi2 = float(chi2.statistic), float(chi2.pvalue)
    exact = stats.binomtest(n10, n_discordant, 0.5, alternative="two-sided")
    ci = exact.proportion_ci(confidence_level=confidence_level, method="exact")
    return McNemarResult(
        statistic=statistic,
        pvalue_chi2=min(pvalue_chi2, 1.0),
        pvalue_exact=min(float(exact.pvalue), 1.0),
        odds_ratio=_odds(n10, n01),
        odds_ratio_low=_odds_from_fraction(float(ci.low)),
        odds_ratio_high=_odds_from_fraction(float(ci.high)),
        n_discordant=n_discordant,
        n01=n01,
        n10=n10,
        confidence_level=confidence_level,
    )


def _odds(numerator: int, denominator: int) -> float:
    return math.inf if denominator == 0 else numerator / denominator


def _odds_from_fraction(q: float) -> float:
    return math.inf if q >= 1.0 else q / (1.0 - q)


def chi2_contingency_test(table: ArrayLike, *, yates: bool = False) -> Chi2Result:
    """Return Pearson's chi-square test of independence on an r x c table of counts.

    Parameters
    ----------
    table : (r, c) int
        Counts, e.g. rows = planners and columns = (success, failure). Every row and column
        must have a positive total.
    yates : bool
        Apply Yates' continuity correction. Only ever used for 2 x 2 tables (scipy ignores it
        for larger ones); the default is False so that a 2 x 2 table gets the same plain
        Pearson statistic as every other table.

    Returns
    -------
    Chi2Result
        ``expected`` (r, c) holds the expected counts under independence; check them before
        trusting the asymptotic p (Cochran's rule: most cells at least 5).

    Notes
    -----
    Computed by ``scipy.stats.chi2_contingency(table, correction=yates)``. From the paper's own
    counts, Test 2's planner comparison (637/819, 213/474, 79/282) gives chi2 = 270.0 and Test
    3's (671/830, 42/100, 17/100) gives chi2 = 221 (paper Secs. 8.5, 9.5), both uncorrected.

    References
    ----------
    Pearson, K. (1900). On the criterion that a given system of deviations ... Phil. Mag.
    Ser. 5, 50(302), 157-175.
    Yates, F. (1934). Contingency tables involving small numbers and the chi2 test. Suppl. J. R.
    Stat. Soc. 1(2), 217-235.
    """
    counts = _check_table(table)
    res = stats.chi2_contingency(counts, correction=bool(yates))
    expected = np.array(res.expected_freq, dtype=np.float64)
    expected.setflags(write=False)
    return Chi2Result(statistic=float(res.statistic), pvalue=float(res.pvalue), dof=int(res.dof),
                      expected=expected, yates_correction=bool(yates) and counts.shape == (2, 2))


def kruskal_wallis(*groups: ArrayLike) -> KruskalResult:
    """Return the Kruskal-Wallis H test that several samples come from one distribution.

    Parameters
    ----------
    *groups : (n_g,) float
        Two or more samples, each non-empty and finite.

    Returns
    -------
    KruskalResult
        H corrected for ties and its chi-square p on ``n_groups - 1`` degrees of freedom. When
        every value ties, H is 0/0: ``statistic`` is nan (undefined) and ``pvalue`` 1.0, since
        every permutation of the labels then gives the same H.

    Notes
    -----
    Computed by ``scipy.stats.kruskal``.

    References
    ----------
    Kruskal, W. H. & Wallis, W. A. (1952). Use of ranks in one-criterion variance analysis.
    J. Am. Stat. Assoc. 47(260), 583-621.
    """
    if len(groups) < 2:
        raise ValueError(f"groups must be at least 2 samples, got {len(groups)}.")
    arrays = [_check_1d(g, f"groups[{i}]") for i, g in enumerate(groups)]
    pooled = np.concatenate(arrays)
    if np.all(pooled == pooled[0]):
        return KruskalResult(statistic=math.nan, pvalue=1.0, n_groups=len(arrays),
                             n=int(pooled.size))
    res = stats.kruskal(*arrays)
    return KruskalResult(statistic=float(res.statistic), pvalue=float(res.pvalue),
                         n_groups=len(arrays), n=int(pooled.size))


# --------------------------------------------------------------------------------------------
# Logistic regression
# --------------------------------------------------------------------------------------------


def logistic_regression(df: pd.DataFrame, outcome: str, predictors: Sequence[str], *,
                        confidence_level: float = 0.95, maxiter: int = 100) -> LogisticResult:
    """Fit an unpenalised logistic regression and report convergence and separation.

    Parameters
    ----------
    df : pandas.DataFrame
        One row per trial; no missing values in the columns used.
    outcome : str
        Column of 0/1 or booleans (e.g. ``failed``).
    predictors : sequence of str
        Numeric or boolean columns; an intercept is added and named ``"intercept"``. Build
        indicator columns for categories before calling.
    confidence_level : float
        Level of the Wald intervals ``ci_low, ci_high``.
    maxiter : int
        Newton-Raphson iteration limit.

    Returns
    -------
    LogisticResult
        Never raises on separation or non-convergence: they are reported in ``separation``,
        ``separation_kind`` ("none", "quasi-complete", "complete", or "undetermined" if the
        linear programme fails numerically) and ``converged``, with the optimiser's warnings in
        ``messages``.

    Notes
    -----
    Fitted by maximum likelihood with ``statsmodels.discrete.discrete_model.Logit`` (Newton),
    standard errors from the observed information, Wald z, p and intervals. Separation is
    decided independently of the optimiser by linear programming (Konis 2007): the data are
    separated when some direction ``b != 0`` has ``(2 y_i - 1) x_i . b >= 0`` for every trial
    with at least one strict inequality ("quasi-complete"); "complete" when all can be strict.
    The maximum-likelihood estimate then does not exist (Albert & Anderson 1984). A penalised
    fit (Firth 1993) is the usual remedy; it is not applied here because the paper reports an
    unpenalised fit.

    References
    ----------
    Albert, A. & Anderson, J. A. (1984). On the existence of maximum likelihood estimates in
    logistic regression models. Biometrika 71(1), 1-10.
    Konis, K. (2007). Linear programming algorithms for detecting separated data in binary
    logistic regression models. DPhil thesis, University of Oxford, ch. 4.
    Firth, D. (1993). Bias reduction of maximum likelihood estimates. Biometrika 80(1), 27-38.
    """
    y, design, names = _check_frame(df, outcome, predictors)
    confidence_level = _check_probability_open(confidence_level, "confidence_level")
    maxiter = _check_positive_int(maxiter, "maxiter")

    separation_kind = _separation_kind(design, y)
    terms = ["intercept", *names]
    messages: list[str] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            fit = Logit(y, design).fit(method="newton", maxiter=maxiter, disp=0)
        except (np.linalg.LinAlgError, PerfectSeparationError) as exc:
            # Newton can hit a singular Hessian on separated data; report, do not raise.
            fit = None
            messages.append(f"{type(exc).__name__}: {exc}")
    for w in caught:
        text = f"{w.category.__name__}: {w.message}"
        if text not in messages:
            messages.append(text)

    if fit is None:
        nan = np.full(len(terms), np.nan)
        table = pd.DataFrame({"coef": nan, "se": nan, "z": nan, "p": nan, "ci_low": nan,
                              "ci_high": nan}, index=terms)
        converged = False
    else:
        ci = np.asarray(fit.conf_int(alpha=1.0 - confidence_level))
        table = pd.DataFrame({"coef": fit.params, "se": fit.bse, "z": fit.tvalues,
                              "p": fit.pvalues, "ci_low": ci[:, 0], "ci_high": ci[:, 1]},
                             index=terms)
        converged = bool(fit.mle_retvals.get("converged", False)) \
            and bool(np.all(np.isfinite(fit.bse)))
    return LogisticResult(coefficients=table, converged=converged,
                          separation=separation_kind in ("quasi-complete", "complete"),
                          separation_kind=separation_kind, n=int(y.size),
                          messages=tuple(messages))


def _separation_kind(design: np.ndarray, y: np.ndarray) -> str:
    """Classify the separation of ``(design, y)`` by two linear programmes (Konis 2007)."""
    signed = np.where(y[:, None] == 1.0, design, -design)
    scale = np.abs(signed).max(axis=0)
    signed = signed / np.where(scale > 0, scale, 1.0)  # separation is invariant to column scale
    n, p = signed.shape
    tol = 1e-7 * n
    box = [(-1.0, 1.0)] * p
    # Quasi-complete or complete: maximise sum_i a_i.b subject to a_i.b >= 0 for all i.
    quasi = optimize.linprog(-signed.sum(axis=0), A_ub=-signed, b_ub=np.zeros(n), bounds=box,
                             method="highs")
    if quasi.status != 0:  # feasible (b = 0) and bounded, so only numerical trouble lands here
        return "undetermined"
    if -quasi.fun <= tol:
        return "none"
    # Complete: maximise t subject to a_i.b >= t for all i (t <= 1 keeps it bounded).
    complete = optimize.linprog(np.r_[np.zeros(p), -1.0],
                                A_ub=np.column_stack([-signed, np.ones(n)]), b_ub=np.zeros(n),
                                bounds=[*box, (None, 1.0)], method="highs")
    if complete.status == 0 and -complete.fun > 1e-7:
        return "complete"
    return "quasi-complete"


# --------------------------------------------------------------------------------------------
# Classifier scores, agreement and error summaries
# --------------------------------------------------------------------------------------------


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
    p = _check_binary(predicted, "predicted")
    a = _check_binary(actual, "actual")
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
    measured, predicted = _check_paired(measured, predicted, "measured", "predicted", 2)
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
    measured, predicted = _check_paired(measured, predicted, "measured", "predicted", 2)
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
    measured, predicted = _check_paired(measured, predicted, "measured", "predicted")
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
    values = np.sort(_check_1d(thresholds, "thresholds"))
    grid = np.unique(values) if levels is None else _check_1d(levels, "levels")
    at_least = values.size - np.searchsorted(values, grid, side="left")
    fraction = at_least / values.size
    grid = np.array(grid, dtype=np.float64)
    grid.setflags(write=False)
    fraction.setflags(write=False)
    return SurvivalCurve(levels=grid, surviving_fraction=fraction, n=int(values.size))


# --------------------------------------------------------------------------------------------
# Power analysis
# --------------------------------------------------------------------------------------------


def power_two_proportions(p1: float, p2: float, *, alpha: float = 0.05, power: float = 0.8,
                          paired: bool = False, alternative: str = "two-sided",
                          discordant: float | None = None) -> SampleSizeResult:
    """Return the trials per arm needed to detect the success-rate difference p1 vs p2.

    Parameters
    ----------
    p1, p2 : float
        Success rates to tell apart, in [0, 1] and different.
    alpha : float
        Type-I error rate.
    power : float
        Desired power, 1 - type-II error rate.
    paired : bool
        False: two independent arms (e.g. ablation variants on different seeds). True: matched
        pairs analysed with McNemar's test; the result is the number of pairs.
    alternative : {"two-sided", "one-sided"}
        Sidedness of the test.
    discordant : float or None
        Paired only: expected fraction of discordant pairs ``psi = p01 + p10``. Default: the
        value under independence of the two outcomes, ``p1 (1 - p2) + p2 (1 - p1)``; positively
        correlated outcomes have fewer discordant pairs and need fewer pairs.

    Returns
    -------
    SampleSizeResult
        ``n_per_arm`` rounded up; ``effect_size`` is Cohen's h
        (``2 asin sqrt(p1) - 2 asin sqrt(p2)``) unpaired, or ``p1 - p2`` paired.

    Notes
    -----
    Unpaired: ``statsmodels.stats.power.NormalIndPower().solve_power`` with Cohen's h from
    ``statsmodels.stats.proportion.proportion_effectsize`` (normal approximation on the
    arcsine scale, equal arms). Paired: Connor's normal approximation for McNemar's test,
    ``n = (z_a sqrt(psi) + z_b sqrt(psi - d**2))**2 / d**2`` with ``d = p1 - p2`` (statsmodels
    has no paired routine). Both ignore the continuity correction, so they are slightly
    optimistic for small n.

    References
    ----------
    Cohen, J. (1988). Statistical Power Analysis for the Behavioral Sciences, 2nd ed.,
    Erlbaum, ch. 6 (effect size h).
    Connor, R. J. (1987). Sample size for testing differences in proportions for the
    paired-sample design. Biometrics 43(1), 207-211.
    """
    p1 = _check_probability_closed(p1, "p1")
    p2 = _check_probability_closed(p2, "p2")
    if p1 == p2:
        raise ValueError(f"p1 and p2 must differ (no sample size detects a zero difference), got "
                         f"{p1} and {p2}.")
    alpha = _check_probability_open(alpha, "alpha")
    power = _check_probability_open(power, "power")
    alternative = _check_alternative(alternative)
    if not paired:
        if discordant is not None:
            raise ValueError("discordant applies only to paired designs; pass paired=True.")
        h = float(proportion_effectsize(p1, p2))
        n = float(NormalIndPower().solve_power(
            effect_size=abs(h), nobs1=None, alpha=alpha, power=power, ratio=1.0,
            alternative="two-sided" if alternative == "two-sided" else "larger"))
        return SampleSizeResult(n_per_arm=math.ceil(n - 1e-9), n_per_arm_unrounded=n,
                                effect_size=h, effect_size_kind="cohen_h", alpha=alpha,
                                power=power, paired=False, alternative=alternative)
    delta = p1 - p2
    psi = p1 * (1.0 - p2) + p2 * (1.0 - p1) if discordant is None \
        else _check_probability_closed(discordant, "discordant")
    if psi < abs(delta):
        raise ValueError(f"discordant must be at least |p1 - p2| = {abs(delta):.4g} (the "
                         f"discordant pairs carry the whole difference), got {psi}.")
    z_alpha = stats.norm.isf(alpha / 2.0 if alternative == "two-sided" else alpha)
    z_beta = stats.norm.isf(1.0 - power)
    n = (z_alpha * math.sqrt(psi) + z_beta * math.sqrt(psi - delta**2)) ** 2 / delta**2
    return SampleSizeResult(n_per_arm=math.ceil(n - 1e-9), n_per_arm_unrounded=float(n),
                            effect_size=delta, effect_size_kind="paired_difference", alpha=alpha,
                            power=power, paired=True, alternative=alternative)


# --------------------------------------------------------------------------------------------
# Formatting for reports
# --------------------------------------------------------------------------------------------


def _round_once(value: float, digits: int, percent: bool) -> str:
    """Round the exact binary value of ``value`` (times 100 if percent) once, half to even."""
    if math.isnan(value):
        return "nan"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    exact = Decimal(value) * (100 if percent else 1)  # exact: no intermediate float rounding
    text = f"{exact.quantize(Decimal(1).scaleb(-digits), rounding=ROUND_HALF_EVEN):f}"
    return text[1:] if text.startswith("-") and not any(c in "123456789" for c in text) else text


def _check_digits(digits: object) -> int:
    if isinstance(digits, bool) or not isinstance(digits, numbers.Integral) or digits < 0:
        raise ValueError(f"digits must be a non-negative integer, got {digits!r}.")
    return int(digits)


def format_interval(low: float, high: float, digits: int = 1, percent: bool = True) -> str:
    """Return ``"low–high"`` with each bound rounded once from full precision.

    Parameters
    ----------
    low, high : float
        Interval bounds (fractions when ``percent``).
    digits : int
        Decimal places kept.
    percent : bool
        Multiply by 100 before rounding (no % sign is added).

    Returns
    -------
    str
        E.g. the Wilson interval of 17/100 (0.108936..., 0.255480...) gives ``"10.9–25.5"``.
        Rounding first to 2 places and then to 1 would give the wrong ``25.6``; here each
        bound is rounded a single time from its exact value (``decimal``, ties to even), and
        a negative zero is printed as ``0.0``.
    """
    digits = _check_digits(digits)
    return f"{_round_once(float(low), digits, percent)}–{_round_once(float(high), digits, percent)}"


def format_estimate_interval(estimate: float, low: float, high: float, digits: int = 1,
                             percent: bool = True) -> str:
    """Return ``"estimate (low–high)"`` in the style of the paper's tables.

    E.g. ``80.8 (78.0–83.4)`` for the Wilson interval of 671/830. Each number is rounded once
    from full precision, as in :func:`format_interval`.
    """
    digits = _check_digits(digits)
    return (f"{_round_once(float(estimate), digits, percent)} "
            f"({format_interval(low, high, digits, percent)})")
