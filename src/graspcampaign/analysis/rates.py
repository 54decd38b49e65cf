"""Rates: Wilson and cluster-bootstrap intervals, McNemar on matched pairs, sample size.

Fractions in [0, 1]. Conventions as in the paper (Sec. 11): success denominators are executed
trials; paired comparisons use occurrence-matched pairs. Shape letters: ``n`` trials or pairs,
``k`` clusters (objects), ``B`` bootstrap resamples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import stats
from statsmodels.stats.contingency_tables import mcnemar as _sm_mcnemar
from statsmodels.stats.power import NormalIndPower
from statsmodels.stats.proportion import proportion_confint, proportion_effectsize

from graspcampaign.analysis.checks import (
    check_alternative,
    check_binary,
    check_cluster_counts,
    check_count,
    check_positive_int,
    check_probability_closed,
    check_probability_open,
    check_rng,
    check_successes_n,
)

#: Percentile-bootstrap resamples of every report interval (one number, stated in captions).
BOOTSTRAP_RESAMPLES = 10_000
#: Confidence level of every report interval.
CONFIDENCE_LEVEL = 0.95


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
    successes, n = check_successes_n(successes, n)
    confidence_level = check_probability_open(confidence_level, "confidence_level")
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
    s, t = check_cluster_counts(successes_per_cluster, trials_per_cluster)
    n_resamples = check_positive_int(n_resamples, "n_resamples")
    confidence_level = check_probability_open(confidence_level, "confidence_level")
    generator, seed, note = check_rng(rng)

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
    a = check_binary(success_a, "success_a")
    b = check_binary(success_b, "success_b")
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
    n01 = check_count(n01, "n01")
    n10 = check_count(n10, "n10")
    confidence_level = check_probability_open(confidence_level, "confidence_level")
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
    p1 = check_probability_closed(p1, "p1")
    p2 = check_probability_closed(p2, "p2")
    if p1 == p2:
        raise ValueError(f"p1 and p2 must differ (no sample size detects a zero difference), got "
                         f"{p1} and {p2}.")
    alpha = check_probability_open(alpha, "alpha")
    power = check_probability_open(power, "power")
    alternative = check_alternative(alternative)
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
        else check_probability_closed(discordant, "discordant")
    if psi < abs(delta):
        raise ValueError(f"discordant must be at least |p1 - p2| = {abs(delta):.4g} (the "
                         f"discordant pairs carry the whole difference), got {psi}.")
    z_alpha = stats.norm.isf(alpha / 2.0 if alternative == "two-sided" else alpha)
    z_beta = stats.norm.isf(1.0 - power)
    n = (z_alpha * math.sqrt(psi) + z_beta * math.sqrt(psi - delta**2)) ** 2 / delta**2
    return SampleSizeResult(n_per_arm=math.ceil(n - 1e-9), n_per_arm_unrounded=float(n),
                            effect_size=delta, effect_size_kind="paired_difference", alpha=alpha,
                            power=power, paired=True, alternative=alternative)
