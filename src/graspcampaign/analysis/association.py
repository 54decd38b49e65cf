"""Association: Pearson chi-square, Kruskal-Wallis and logistic regression.

References
----------
Pearson, K. (1900). Phil. Mag. Ser. 5, 50(302), 157-175. Yates, F. (1934). Suppl. J. R. Stat. Soc.
1(2), 217-235. Kruskal, W. H. & Wallis, W. A. (1952). J. Am. Stat. Assoc. 47(260), 583-621.
Albert, A. & Anderson, J. A. (1984). Biometrika 71(1), 1-10. Konis, K. (2007). Linear programming
algorithms for detecting separated data in binary logistic regression models, DPhil thesis,
Oxford, ch. 4. Firth, D. (1993). Biometrika 80(1), 27-38. Cochran, W. G. (1954). Biometrics 10(4),
417-451. Hope, A. C. A. (1968). J. R. Stat. Soc. B 30(3), 582-598.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike
from scipy import optimize, stats
from statsmodels.discrete.discrete_model import Logit
from statsmodels.tools.sm_exceptions import PerfectSeparationError

from graspcampaign.analysis.checks import (
    check_1d,
    check_cluster_counts,
    check_count,
    check_fraction,
    check_frame,
    check_table,
    require,
    result,
)
from graspcampaign.analysis.rates import CONFIDENCE_LEVEL

Chi2Result = result(
    "Chi2Result", "Pearson chi-square test of independence; ``expected`` (r, c) under independence; "
    "``method`` names how ``pvalue`` was found, ``n_resamples`` how many random tables a Monte Carlo "
    "``pvalue`` drew (0: none), whose smallest is 1/(n_resamples + 1).", statistic=float, pvalue=float,
    dof=int, expected=np.ndarray, yates_correction=bool, method=str, n_resamples=int)
RatesTest = result(
    "RatesTest", "Test that ``groups`` groups of ``n`` trials share one success rate (their k x 2 table "
    "of successes and failures); ``method`` names how ``pvalue`` was found, \"\" when every trial or "
    "none succeeded (equal rates: no test, ``pvalue`` 1); ``n_resamples`` as :class:`Chi2Result`'s.",
    statistic=float, pvalue=float, method=str, groups=int, n=int, n_resamples=int)
#: Smallest expected count of a table whose chi-square p-value is read from the distribution (Cochran 1954).
MIN_EXPECTED = 5.0
KruskalResult = result(
    "KruskalResult", "Kruskal-Wallis H test; ``statistic`` is nan (and ``pvalue`` 1) when all "
    "values tie.", statistic=float, pvalue=float, n_groups=int, n=int)
LogisticResult = result(
    "LogisticResult", "Unpenalised logistic regression: ``coefficients`` has one row per term "
    "(``intercept`` first), columns ``coef, se, z, p, ci_low, ci_high`` (log-odds). Under separation "
    "or without convergence they are the optimiser's last iterate, not estimates.",
    coefficients=pd.DataFrame, converged=bool, separation=bool, separation_kind=str, n=int,
    messages=tuple)


def chi2_contingency_test(table: ArrayLike, *, yates: bool = False, n_resamples: int | None = None,
                          seed: int = 0) -> Chi2Result:
    """Return Pearson's chi-square test of independence (``scipy.stats.chi2_contingency``) of an
    r x c table of counts; ``yates``: Yates' correction of a 2 x 2 table (off by default). Given
    ``n_resamples``, a table with an expected count below :data:`MIN_EXPECTED` gets the Monte Carlo
    p-value of the same statistic over ``n_resamples`` random tables with the observed margins
    (Hope 1968; R's ``chisq.test(simulate.p.value = TRUE)``), drawn from ``seed``; else the chi-square
    distribution's."""
    require(not (yates and n_resamples is not None), "yates=True cannot be combined with n_resamples: "
            "the Monte Carlo p-value has no Yates correction (scipy refuses it); pass one of them.")
    counts = check_table(table)
    n_resamples = None if n_resamples is None else check_count(n_resamples, "n_resamples", positive=True)
    resampled = n_resamples is not None and stats.contingency.expected_freq(counts).min() < MIN_EXPECTED
    method = stats.MonteCarloMethod(n_resamples=n_resamples, rng=np.random.default_rng(seed))
    res = stats.chi2_contingency(counts, correction=bool(yates), method=method if resampled else None)
    expected = np.array(res.expected_freq, dtype=np.float64)
    expected.setflags(write=False)
    dof = (counts.shape[0] - 1) * (counts.shape[1] - 1)  # scipy's is nan for a Monte Carlo p
    return Chi2Result(float(res.statistic), float(res.pvalue), dof, expected,
                      bool(yates) and counts.shape == (2, 2), "Monte Carlo χ²" if resampled else "χ²",
                      n_resamples if resampled else 0)


RESAMPLES = 9999
"""Random tables a Monte Carlo p of :func:`equal_rates_test` draws by default: its smallest p is
1/(RESAMPLES + 1) = 1e-4, below the report's 0.05 by far (scipy's ``MonteCarloMethod`` default)."""


def equal_rates_test(successes: ArrayLike, trials: ArrayLike, *, n_resamples: int = RESAMPLES,
                     seed: int = 0) -> RatesTest:
    """Return the chi-square test (:func:`chi2_contingency_test`, no correction, its Monte Carlo
    p-value for small expected counts) that groups with ``successes`` of ``trials`` share one success
    rate, on their k x 2 table of successes and failures."""
    s, t = check_cluster_counts(successes, trials, group="group")
    check_count(n_resamples, "n_resamples", positive=True)
    if s.sum() in (0, t.sum()):
        return RatesTest(0.0, 1.0, "", int(s.size), int(t.sum()), 0)
    res = chi2_contingency_test(np.column_stack([s, t - s]), n_resamples=n_resamples, seed=seed)
    return RatesTest(res.statistic, res.pvalue, res.method, int(s.size), int(t.sum()), res.n_resamples)


def kruskal_wallis(*groups: ArrayLike) -> KruskalResult:
    """Return the Kruskal-Wallis H test (``scipy.stats.kruskal``) of 2+ samples; all tied: nan, p 1."""
    require(len(groups) >= 2, f"groups must be at least 2 samples, got {len(groups)}.")
    arrays = [check_1d(g, f"groups[{i}]") for i, g in enumerate(groups)]
    pooled = np.concatenate(arrays)
    if np.all(pooled == pooled[0]):
        return KruskalResult(math.nan, 1.0, len(arrays), int(pooled.size))
    res = stats.kruskal(*arrays)
    return KruskalResult(float(res.statistic), float(res.pvalue), len(arrays), int(pooled.size))


def logistic_regression(df: pd.DataFrame, outcome: str, predictors: Sequence[str], *,
                        confidence_level: float = CONFIDENCE_LEVEL, maxiter: int = 100) -> LogisticResult:
    """Fit statsmodels' ``Logit`` (Newton, Wald intervals, intercept added) and report convergence
    and separation (Konis 2007: none, quasi-complete, complete, undetermined) instead of raising.

    ``outcome``: a 0/1 or boolean column; ``predictors``: numeric or boolean columns. No Firth
    penalty: the paper reports an unpenalised fit."""
    y, design, names = check_frame(df, outcome, predictors)
    level = check_fraction(confidence_level, "confidence_level")
    maxiter = check_count(maxiter, "maxiter", positive=True)
    terms, messages, fit = ["intercept", *names], [], None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            fit = Logit(y, design).fit(method="newton", maxiter=maxiter, disp=0)
        except (np.linalg.LinAlgError, PerfectSeparationError) as exc:  # singular Hessian
            messages.append(f"{type(exc).__name__}: {exc}")
    messages += [t for t in dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught)
                 if t not in messages]
    if fit is None:
        table = pd.DataFrame(np.nan, index=terms, columns=["coef", "se", "z", "p", "ci_low", "ci_high"])
    else:
        ci = np.asarray(fit.conf_int(alpha=1.0 - level))
        table = pd.DataFrame({"coef": fit.params, "se": fit.bse, "z": fit.tvalues, "p": fit.pvalues,
                              "ci_low": ci[:, 0], "ci_high": ci[:, 1]}, index=terms)
    converged = fit is not None and bool(fit.mle_retvals.get("converged", False)) \
        and bool(np.isfinite(fit.bse).all())
    kind = _separation_kind(design, y)
    return LogisticResult(table, converged, kind in ("quasi-complete", "complete"), kind,
                          int(y.size), tuple(messages))


def _separation_kind(design: np.ndarray, y: np.ndarray) -> str:
    """Classify the separation of ``(design, y)`` by two linear programmes (Konis 2007)."""
    signed = np.where(y[:, None] == 1.0, design, -design)
    scale = np.abs(signed).max(axis=0)
    signed = signed / np.where(scale > 0, scale, 1.0)  # separation is invariant to column scale
    n, p = signed.shape
    box = [(-1.0, 1.0)] * p
    # quasi-complete or complete: maximise sum_i a_i.b subject to a_i.b >= 0 for all i
    quasi = optimize.linprog(-signed.sum(axis=0), A_ub=-signed, b_ub=np.zeros(n), bounds=box,
                             method="highs")
    if quasi.status != 0:  # feasible (b = 0) and bounded: only numerical trouble lands here
        return "undetermined"
    if -quasi.fun <= 1e-7 * n:
        return "none"
    # complete: maximise t subject to a_i.b >= t for all i (t <= 1 keeps it bounded)
    complete = optimize.linprog(np.r_[np.zeros(p), -1.0], A_ub=np.column_stack([-signed, np.ones(n)]),
                                b_ub=np.zeros(n), bounds=[*box, (None, 1.0)], method="highs")
    return "complete" if complete.status == 0 and -complete.fun > 1e-7 else "quasi-complete"
