"""Rates: Wilson and cluster-bootstrap intervals, McNemar on matched pairs, sample size.

Fractions in [0, 1]; success denominators are executed trials, pairs are occurrence-matched (Sec. 11).

References
----------
Wilson, E. B. (1927). J. Am. Stat. Assoc. 22(158), 209-212. Newcombe, R. G. (1998). Stat. Med.
17(8), 857-872. Efron, B. & Tibshirani, R. J. (1993). An Introduction to the Bootstrap, ch. 13.
Davison, A. C. & Hinkley, D. V. (1997). Bootstrap Methods and Their Application, sec. 3.8.
McNemar, Q. (1947). Psychometrika 12(2), 153-157. Edwards, A. L. (1948). Psychometrika 13(3),
185-187. Clopper, C. J. & Pearson, E. S. (1934). Biometrika 26(4), 404-413. Breslow, N. E. & Day,
N. E. (1980). Statistical Methods in Cancer Research I, sec. 5.2. Cohen, J. (1988). Statistical
Power Analysis for the Behavioral Sciences, 2nd ed., ch. 6. Connor, R. J. (1987). Biometrics
43(1), 207-211.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
from numpy.typing import ArrayLike
from scipy import stats
from statsmodels.stats.contingency_tables import mcnemar as sm_mcnemar
from statsmodels.stats.power import NormalIndPower
from statsmodels.stats.proportion import proportion_confint, proportion_effectsize

from graspcampaign.analysis.checks import (
    check_cluster_counts,
    check_count,
    check_fraction,
    check_paired,
    check_rng,
    require,
    result,
)

#: Percentile-bootstrap resamples of every report interval (one number, stated in captions).
BOOTSTRAP_RESAMPLES = 10_000
#: Confidence level of every report interval.
CONFIDENCE_LEVEL = 0.95


ProportionInterval = result(
    "ProportionInterval", "A binomial proportion with its confidence interval.", estimate=float,
    low=float, high=float, n=int, successes=int, confidence_level=float, method=str)
BootstrapInterval = result(
    "BootstrapInterval", "Cluster-bootstrap percentile interval of a pooled rate; ``seed``: the int "
    "seed if one was given, ``rng_note``: how the generator was made.",
    estimate=float, low=float, high=float, n_clusters=int, n_trials=int, n_resamples=int,
    confidence_level=float, seed=int | None, rng_note=str)
McNemarResult = result(
    "McNemarResult", "McNemar's test with the discordant-pair odds ratio ``n10 / n01`` (the odds "
    "that a discordant pair favours A); ``statistic`` is nan without discordant pairs.",
    statistic=float, pvalue_chi2=float, pvalue_exact=float, odds_ratio=float, odds_ratio_low=float,
    odds_ratio_high=float, n_discordant=int, n01=int, n10=int, confidence_level=float)
SampleSizeResult = result(
    "SampleSizeResult", "Trials per arm (pairs, when paired) to detect a success-rate difference.",
    n_per_arm=int, n_per_arm_unrounded=float, effect_size=float, effect_size_kind=str, alpha=float,
    power=float, paired=bool, alternative=str)


def wilson_interval(successes: int, n: int, confidence_level: float = CONFIDENCE_LEVEL) -> ProportionInterval:
    """Return the Wilson score interval (statsmodels ``proportion_confint``) of ``successes`` of
    ``n``, clipped to [0, 1]: exactly 0 at no success and exactly 1 at ``successes == n``."""
    require(not (isinstance(n, numbers.Real) and n <= 0),
            f"n must be positive (the number of executed trials), got {n!r}.")
    n, successes = check_count(n, "n"), check_count(successes, "successes")
    require(successes <= n, f"successes must not exceed n, got successes={successes} and n={n}.")
    level = check_fraction(confidence_level, "confidence_level")
    low, high = proportion_confint(successes, n, alpha=1.0 - level, method="wilson")
    return ProportionInterval(successes / n, 0.0 if successes == 0 else float(np.clip(low, 0, 1)),
                              1.0 if successes == n else float(np.clip(high, 0, 1)), n, successes,
                              level, "wilson")


def cluster_bootstrap_interval(successes_per_cluster: ArrayLike, trials_per_cluster: ArrayLike, *,
                               n_resamples: int = BOOTSTRAP_RESAMPLES,
                               confidence_level: float = CONFIDENCE_LEVEL,
                               rng: np.random.Generator | int) -> BootstrapInterval:
    """Return the percentile interval of a pooled rate ``sum(s) / sum(n)``, resampling clusters.

    Each resample draws the ``k`` clusters (objects) with replacement, with all their trials; the
    ``(B, k)`` indices are drawn as ``scipy.stats.bootstrap(..., paired=True)`` draws them (same
    interval for the same generator). ``rng``: a Generator or an int seed."""
    s, t = check_cluster_counts(successes_per_cluster, trials_per_cluster)
    n_resamples = check_count(n_resamples, "n_resamples", positive=True)
    level = check_fraction(confidence_level, "confidence_level")
    generator, seed, note = check_rng(rng)
    idx = generator.integers(0, s.size, size=(n_resamples, s.size))
    tail = (1.0 - level) / 2.0
    low, high = np.clip(np.quantile(s[idx].sum(axis=1) / t[idx].sum(axis=1), [tail, 1 - tail]), 0, 1)
    return BootstrapInterval(float(s.sum() / t.sum()), float(low), float(high), int(s.size),
                             int(t.sum()), n_resamples, level, seed, note)


def discordant_pairs(success_a: ArrayLike, success_b: ArrayLike) -> tuple[int, int]:
    """Return ``(n01, n10)`` of (n,) paired outcomes: pairs where only B succeeded, only A."""
    a, b = check_paired(success_a, success_b, "success_a", "success_b", binary=True)
    return int(np.sum(~a & b)), int(np.sum(a & ~b))


def mcnemar(n01: int, n10: int, confidence_level: float = CONFIDENCE_LEVEL) -> McNemarResult:
    """Return McNemar's test and the discordant-pair odds ratio ``n10 / n01``.

    ``statistic``: statsmodels' continuity-corrected chi-square (0, p = 1 when ``n01 == n10``, as
    R's ``mcnemar.test``); ``pvalue_exact``: ``scipy.stats.binomtest`` of ``n10`` of ``n01 + n10``,
    its Clopper-Pearson interval on ``q`` mapped through ``q / (1 - q)``. The paper's "33 won
    against 3 lost" is ``mcnemar(3, 33)``: chi2 = 23.4, odds ratio 11.0 (Sec. 8.5)."""
    n01, n10 = check_count(n01, "n01"), check_count(n10, "n10")
    level = check_fraction(confidence_level, "confidence_level")
    n = n01 + n10
    if n == 0:
        return McNemarResult(math.nan, 1.0, 1.0, math.nan, math.nan, math.nan, 0, 0, 0, level)
    chi2 = sm_mcnemar([[0, n01], [n10, 0]], exact=False, correction=True) if n01 != n10 else None
    exact = stats.binomtest(n10, n)
    ci = exact.proportion_ci(confidence_level=level, method="exact")
    low, high = (math.inf if q >= 1.0 else q / (1.0 - q) for q in (float(ci.low), float(ci.high)))
    return McNemarResult(float(chi2.statistic) if chi2 else 0.0,
                         min(float(chi2.pvalue), 1.0) if chi2 else 1.0, min(float(exact.pvalue), 1.0),
                         math.inf if n01 == 0 else n10 / n01, low, high, n, n01, n10, level)


def power_two_proportions(p1: float, p2: float, *, alpha: float = 0.05, power: float = 0.8,
                          paired: bool = False, alternative: str = "two-sided",
                          discordant: float | None = None) -> SampleSizeResult:
    """Return the trials per arm (pairs, when ``paired``) to tell success rates p1 and p2 apart.

    Unpaired: statsmodels' ``NormalIndPower`` on Cohen's h. Paired: Connor's ``n = (z_a sqrt(psi) +
    z_b sqrt(psi - d**2))**2 / d**2``, ``d = p1 - p2``, ``psi = discordant`` (default: independent
    outcomes). No continuity correction: slightly optimistic for small n."""
    p1, p2 = check_fraction(p1, "p1", closed=True), check_fraction(p2, "p2", closed=True)
    require(p1 != p2, f"p1 and p2 must differ (no sample size detects a zero difference), got {p1} "
                      f"and {p2}.")
    alpha, power = check_fraction(alpha, "alpha"), check_fraction(power, "power")
    require(alternative in ("two-sided", "one-sided"), "alternative must be 'two-sided' or "
                                                       f"'one-sided', got {alternative!r}.")
    if not paired:
        require(discordant is None, "discordant applies only to paired designs; pass paired=True.")
        effect, kind = float(proportion_effectsize(p1, p2)), "cohen_h"
        n = float(NormalIndPower().solve_power(
            effect_size=abs(effect), alpha=alpha, power=power, ratio=1.0,
            alternative="two-sided" if alternative == "two-sided" else "larger"))
    else:
        effect, kind = p1 - p2, "paired_difference"
        psi = p1 * (1 - p2) + p2 * (1 - p1) if discordant is None \
            else check_fraction(discordant, "discordant", closed=True)
        require(psi >= abs(effect), f"discordant must be at least |p1 - p2| = {abs(effect):.4g} "
                                    f"(the discordant pairs carry the whole difference), got {psi}.")
        z_a = stats.norm.isf(alpha / 2 if alternative == "two-sided" else alpha)
        n = (z_a * math.sqrt(psi) + stats.norm.isf(1 - power) * math.sqrt(psi - effect**2)) ** 2 \
            / effect**2
    return SampleSizeResult(math.ceil(n - 1e-9), float(n), effect, kind, alpha, power, paired,
                            alternative)
