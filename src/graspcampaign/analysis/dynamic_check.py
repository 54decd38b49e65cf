"""Agreement of the quasi-static and the dynamic labels of the ``dynamic_check`` study.

Pure functions of the records (one row per source trial and material preset, docs/records.md):
the 2 x 2 confusion matrix of two boolean label columns, Cohen's kappa with its asymptotic
interval (statsmodels), and the agreement per group (planner, shape, preset). They return arrays,
small frozen results and DataFrames; the report formats them.

Which label pairs to compare (:data:`LABEL_PAIRS`): the dynamic ``success`` (Eq. 19 held, every
penetration within the fingertip radius) against

- ``qs_success``: the source study's recorded quasi-static label (its own contact law: the
  PSO-identified gel constants for ``baseline_grid``), i.e. the label the paper reports;
- ``qs_preset_success``: Algorithms 1-2 re-run on the same contacts under the trial's preset (the
  like-for-like comparison: same contacts, same contact law, only the evaluator differs);

and the same pairs without the validity gate (``*_unbounded``).

Orientation of every table: rows are the quasi-static label (success, failure), columns the
dynamic label (success, failure)::

    [[both succeed,          quasi-static only],
     [dynamic only,          both fail        ]]

References
----------
Cohen, J. (1960), "A coefficient of agreement for nominal scales", Educational and Psychological
Measurement 20(1):37-46; Fleiss, J. L., Cohen, J. & Everitt, B. S. (1969), "Large sample
standard errors of kappa and weighted kappa", Psychological Bulletin 72(5):323-327 (the ASE of
``statsmodels.stats.inter_rater.cohens_kappa``); Wilson, E. B. (1927), JASA 22:209-212.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

__all__ = [
    "LABEL_PAIRS",
    "KappaResult",
    "agreement_table",
    "cohens_kappa",
    "confusion_matrix",
    "ok_records",
]

LABEL_PAIRS: dict[str, tuple[str, str]] = {
    "source": ("qs_success", "success"),
    "preset": ("qs_preset_success", "success"),
    "source_unbounded": ("qs_success_unbounded", "success_unbounded"),
    "preset_unbounded": ("qs_preset_success_unbounded", "success_unbounded"),
}
"""Comparison name -> (quasi-static column, dynamic column) of the dynamic_check records."""


@dataclass(frozen=True)
class KappaResult:
    """Cohen's kappa of a 2 x 2 table.

    Attributes
    ----------
    table : (2, 2) int
        The confusion matrix (module orientation).
    n : int
        Trials.
    observed_agreement : float
        ``(both succeed + both fail) / n`` [-].
    expected_agreement : float
        Agreement expected from the marginals alone [-].
    kappa : float
        ``(p_o - p_e) / (1 - p_e)``; nan when ``p_e = 1`` (one label constant in both columns:
        kappa is undefined, the agreement is then the observed proportion alone).
    std_error : float
        Asymptotic standard error (Fleiss, Cohen & Everitt 1969) [-].
    ci_low, ci_high : float
        ``kappa -/+ z std_error`` at the requested confidence (statsmodels' interval).
    confidence_level : float
        [-].
    """

    table: np.ndarray
    n: int
    observed_agreement: float
    expected_agreement: float
    kappa: float
    std_error: float
    ci_low: float
    ci_high: float
    confidence_level: float


def ok_records(records: pd.DataFrame) -> pd.DataFrame:
    """Return the executed trials (``status == "ok"``): error records carry no label."""
    if "status" not in records.columns:
        return records
    return records[records["status"] == "ok"]


def confusion_matrix(records: pd.DataFrame, qs_column: str = "qs_success",
                     dynamic_column: str = "success") -> np.ndarray:
    """Return the 2 x 2 counts of two boolean label columns (rows quasi-static, columns dynamic).

    Parameters
    ----------
    records : DataFrame
        dynamic_check records (only ``status == "ok"`` rows are counted).
    qs_column, dynamic_column : str
        Label columns (e.g. a pair of :data:`LABEL_PAIRS`).

    Returns
    -------
    table : (2, 2) int
        ``[[both, quasi-static only], [dynamic only, neither]]``.

    Raises
    ------
    KeyError
        If a column is missing (the message names it).
    """
    rows = ok_records(records)
    for column in (qs_column, dynamic_column):
        if column not in rows.columns:
            raise KeyError(f"dynamic_check records have no column {column!r}")
    qs = rows[qs_column].astype(bool).to_numpy()
    dyn = rows[dynamic_column].astype(bool).to_numpy()
    return np.array([[np.sum(qs & dyn), np.sum(qs & ~dyn)],
                     [np.sum(~qs & dyn), np.sum(~qs & ~dyn)]], dtype=np.int64)


def cohens_kappa(table, confidence_level: float = 0.95) -> KappaResult:
    """Return Cohen's kappa of a 2 x 2 agreement table with its asymptotic interval.

    Parameters
    ----------
    table : (2, 2) int
        Counts (any consistent orientation: kappa is symmetric).
    confidence_level : float
        Of the interval.

    Returns
    -------
    result : KappaResult
        Computed by ``statsmodels.stats.inter_rater.cohens_kappa``; kappa, its standard error
        and interval are nan when the marginals make kappa undefined (``p_e = 1``) or the table
        is empty.

    References
    ----------
    Cohen (1960); Fleiss, Cohen & Everitt (1969).
    """
    from statsmodels.stats.inter_rater import cohens_kappa as sm_kappa

    table = np.asarray(table, dtype=np.int64)
    if table.shape != (2, 2) or np.any(table < 0):
        raise ValueError(f"table must be a (2, 2) array of counts, got {table.tolist()}")
    n = int(table.sum())
    nan = float("nan")
    if n == 0:
        return KappaResult(table, 0, nan, nan, nan, nan, nan, nan, confidence_level)
    observed = float(np.trace(table)) / n
    expected = float(table.sum(axis=1) @ table.sum(axis=0)) / n**2
    if expected >= 1.0:  # both raters constant and equal: kappa = 0/0
        return KappaResult(table, n, observed, expected, nan, nan, nan, nan, confidence_level)
    res = sm_kappa(table, return_results=True)
    alpha = 1.0 - confidence_level
    if np.isclose(alpha, res.alpha):
        low, high = float(res.kappa_low), float(res.kappa_upp)
    else:
        from scipy.stats import norm

        half = norm.ppf(1.0 - alpha / 2.0) * float(res.std_kappa)
        low, high = float(res.kappa) - half, float(res.kappa) + half
    return KappaResult(table, n, observed, expected, float(res.kappa), float(res.std_kappa), low,
                       high, confidence_level)


def agreement_table(records: pd.DataFrame, qs_column: str = "qs_success",
                    dynamic_column: str = "success", by=None,
                    confidence_level: float = 0.95) -> pd.DataFrame:
    """Return the agreement of two label columns, overall or per group.

    Parameters
    ----------
    records : DataFrame
        dynamic_check records.
    qs_column, dynamic_column : str
        Label columns.
    by : str or list of str, optional
        Grouping columns (e.g. ``"model_preset"``, ``["model_preset", "planner"]``); None: one
        row for all trials.
    confidence_level : float
        Of the Wilson and kappa intervals.

    Returns
    -------
    table : DataFrame
        One row per group: the group columns, ``n``, ``both_success``, ``qs_only``,
        ``dynamic_only``, ``both_failure`` (counts), ``qs_success_rate``,
        ``dynamic_success_rate``, ``agreement`` (observed proportion) with its Wilson interval
        ``agreement_low`` / ``agreement_high``, ``kappa``, ``kappa_std_error``, ``kappa_low``,
        ``kappa_high`` (nan where kappa is undefined), ``expected_agreement``.

    References
    ----------
    Cohen (1960); Wilson (1927).
    """
    from statsmodels.stats.proportion import proportion_confint

    rows = ok_records(records)
    keys = [] if by is None else ([by] if isinstance(by, str) else list(by))
    groups = [((), rows)] if not keys else rows.groupby(keys, sort=True, observed=True)
    out = []
    for key, group in groups:
        table = confusion_matrix(group, qs_column, dynamic_column)
        kappa = cohens_kappa(table, confidence_level)
        n = kappa.n
        agree = int(np.trace(table))
        low, high = proportion_confint(agree, n, alpha=1.0 - confidence_level, method="wilson")
        key = key if isinstance(key, tuple) else (key,)
        out.append({
            **dict(zip(keys, key, strict=True)),
            "n": n,
            "both_success": int(table[0, 0]), "qs_only": int(table[0, 1]),
            "dynamic_only": int(table[1, 0]), "both_failure": int(table[1, 1]),
            "qs_success_rate": float(table[0].sum()) / n,
            "dynamic_success_rate": float(table[:, 0].sum()) / n,
            "agreement": agree / n, "agreement_low": float(low), "agreement_high": float(high),
            "kappa": kappa.kappa, "kappa_std_error": kappa.std_error,
            "kappa_low": kappa.ci_low, "kappa_high": kappa.ci_high,
            "expected_agreement": kappa.expected_agreement,
        })
    return pd.DataFrame(out)
