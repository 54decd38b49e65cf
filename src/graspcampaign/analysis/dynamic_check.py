"""Agreement of the quasi-static and dynamic labels of ``dynamic_check`` (docs/records.md).

Every 2 x 2 table has the quasi-static label in its rows and the dynamic label in its columns,
success first: ``[[both succeed, quasi-static only], [dynamic only, both fail]]``. :data:`LABEL_PAIRS`
pairs the dynamic ``success`` with the source study's label (``qs_success``, the paper's) and with
Algorithms 1-2 re-run on the same contacts under the trial's preset (``qs_preset_success``), each
also without the validity gate (``*_unbounded``). Only executed trials carry a label, and only a
*determined* dynamic grasp enters a table: one stopped by the time budget (``dynamic_status ==
"not_settled"``) neither held nor failed, so it is counted apart (``not_settled``), never as a failure.

References
----------
Cohen, J. (1960), Educ. Psychol. Meas. 20(1):37-46; Fleiss, J. L., Cohen, J. & Everitt, B. S.
(1969), Psychol. Bull. 72(5):323-327 (the asymptotic standard error of
``statsmodels.stats.inter_rater.cohens_kappa``); Wilson, E. B. (1927), JASA 22:209-212.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.stats import norm
from statsmodels.stats.inter_rater import cohens_kappa as sm_kappa

from graspcampaign.analysis.checks import result
from graspcampaign.analysis.rates import CONFIDENCE_LEVEL, wilson_interval
from graspcampaign.analysis.records import executed, known

LABEL_PAIRS = {"source": ("qs_success", "success"), "preset": ("qs_preset_success", "success"),
               "source_unbounded": ("qs_success_unbounded", "success_unbounded"),
               "preset_unbounded": ("qs_preset_success_unbounded", "success_unbounded")}
#: The dynamic status of a grasp the simulation did not finish (t_max reached): undetermined.
UNDETERMINED = "not_settled"

KappaResult = result(
    "KappaResult", "Cohen's kappa ``(p_o - p_e) / (1 - p_e)`` of a 2 x 2 table with its asymptotic "
    "standard error and interval; nan with ``why`` when undefined (no trial, or ``p_e = 1``), and "
    "``why`` says when one label alone is constant (kappa = 0 by construction, no interval).",
    table=np.ndarray, n=int, observed_agreement=float, expected_agreement=float, kappa=float,
    std_error=float, ci_low=float, ci_high=float, confidence_level=float, why=str)


def confusion_matrix(records: pd.DataFrame, qs_column: str = "qs_success",
                     dynamic_column: str = "success") -> np.ndarray:
    """Return the (2, 2) counts of two boolean label columns over the executed, determined trials
    that carry both labels (:func:`~.records.known`)."""
    return _executed(records, qs_column, dynamic_column)[1]


def _executed(records: pd.DataFrame, qs_column: str, dynamic_column: str) -> tuple[pd.DataFrame, np.ndarray]:
    """The executed trials of ``records`` and :func:`confusion_matrix`: a label is told missing on the
    stored rows, as ``executed()`` fills a missing success with False (its one call per group)."""
    labels = [qs_column, dynamic_column]
    for column in (*labels, "dynamic_status"):
        if column not in records.columns:
            raise KeyError(f"dynamic_check records have no column {column!r}")
    ok = executed(records.assign(_labelled=records[labels].notna().all(axis=1)))
    rows = known(ok[ok["_labelled"] & (ok["dynamic_status"] != UNDETERMINED)], labels)
    qs, dyn = (rows[c].to_numpy() for c in labels)
    return ok, np.array([[np.sum(qs & dyn), np.sum(qs & ~dyn)],
                         [np.sum(~qs & dyn), np.sum(~qs & ~dyn)]], dtype=np.int64)


def cohens_kappa(table, confidence_level: float = CONFIDENCE_LEVEL) -> KappaResult:
    """Return Cohen's kappa of a (2, 2) table of counts (statsmodels' ``cohens_kappa``)."""
    table = np.asarray(table, dtype=np.int64)
    if table.shape != (2, 2) or np.any(table < 0):
        raise ValueError(f"table must be a (2, 2) array of counts, got {table.tolist()}")
    n, nan = int(table.sum()), float("nan")
    observed = float(np.trace(table)) / n if n else nan
    expected = float(table.sum(axis=1) @ table.sum(axis=0)) / n**2 if n else nan
    constant = [w for w, m in (("quasi-static", table.sum(axis=1)), ("dynamic", table.sum(axis=0)))
                if m.min() == 0]
    why = ("no trial to compare" if not n else "undefined: every trial has one label in both "
           "columns" if expected >= 1.0 else f"0 by construction: the {constant[0]} label is "
           "constant" if constant else "")
    if not n or expected >= 1.0:  # kappa = 0/0
        return KappaResult(table, n, observed, expected, nan, nan, nan, nan, confidence_level, why)
    with np.errstate(invalid="ignore", divide="ignore"):  # z test of kappa = 0 at std 0
        res = sm_kappa(table, return_results=True)
    std = nan if constant else float(res.std_kappa)  # one label constant: std 0, no interval
    half = norm.ppf(0.5 + confidence_level / 2.0) * std
    return KappaResult(table, n, observed, expected, float(res.kappa), std,
                       float(res.kappa) - half, float(res.kappa) + half, confidence_level, why)


def agreement_table(records: pd.DataFrame, qs_column: str = "qs_success",
                    dynamic_column: str = "success", by=None,
                    confidence_level: float = CONFIDENCE_LEVEL) -> pd.DataFrame:
    """Return the :func:`confusion_matrix` counts, both success rates, the agreement (Wilson
    interval) and :func:`cohens_kappa` of two label columns over the determined trials, and the
    executed trials left out as undetermined (``not_settled``) or, determined, missing a label
    (``unlabelled``), overall or per group of ``by``; the rates are nan in a group with no trial."""
    keys = [] if by is None else ([by] if isinstance(by, str) else list(by))
    out = []
    groups = records.groupby(keys, sort=True, observed=True) if keys else [((), records)]
    for key, group in groups:
        ok, table = _executed(group, qs_column, dynamic_column)
        if keys and not len(ok):  # a group of ``by`` with no executed trial is no row
            continue
        k, agree = cohens_kappa(table, confidence_level), int(np.trace(table))
        settled = int((ok["dynamic_status"] != UNDETERMINED).sum())
        w = wilson_interval(agree, k.n, confidence_level) if k.n else None
        n = k.n or np.nan  # no determined trial: no rate
        out.append({
            **dict(zip(keys, key if isinstance(key, tuple) else (key,), strict=True)),
            "n": k.n, "not_settled": len(ok) - settled, "unlabelled": settled - k.n,
            "both_success": int(table[0, 0]), "qs_only": int(table[0, 1]), "dynamic_only": int(table[1, 0]),
            "both_failure": int(table[1, 1]), "qs_success_rate": table[0].sum() / n,
            "dynamic_success_rate": table[:, 0].sum() / n, "agreement": agree / n,
            "agreement_low": w.low if w else np.nan, "agreement_high": w.high if w else np.nan,
            "kappa": k.kappa, "kappa_std_error": k.std_error, "kappa_low": k.ci_low,
            "kappa_high": k.ci_high, "kappa_why": k.why,
            "expected_agreement": k.expected_agreement})
    return pd.DataFrame(out)
