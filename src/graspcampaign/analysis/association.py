"""Association: Pearson chi-square, Kruskal-Wallis and logistic regression.

Shape letters: ``r x c`` contingency tables, ``n`` observations, ``p`` coefficients.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike
from scipy import optimize, stats
from statsmodels.discrete.discrete_model import Logit
from statsmodels.tools.sm_exceptions import PerfectSeparationError

from graspcampaign.analysis.checks import (
    check_1d,
    check_frame,
    check_positive_int,
    check_probability_open,
    check_table,
)


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
    counts = check_table(table)
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
    arrays = [check_1d(g, f"groups[{i}]") for i, g in enumerate(groups)]
    pooled = np.concatenate(arrays)
    if np.all(pooled == pooled[0]):
        return KruskalResult(statistic=math.nan, pvalue=1.0, n_groups=len(arrays),
                             n=int(pooled.size))
    res = stats.kruskal(*arrays)
    return KruskalResult(statistic=float(res.statistic), pvalue=float(res.pvalue),
                         n_groups=len(arrays), n=int(pooled.size))


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
    y, design, names = check_frame(df, outcome, predictors)
    confidence_level = check_probability_open(confidence_level, "confidence_level")
    maxiter = check_positive_int(maxiter, "maxiter")

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
