"""Input validation of the statistics, kept apart from the computation (as in scipy.stats).

Each ``check_*`` returns the value in the form the computation needs, or raises ``ValueError``
with one sentence naming the argument, the expected form and what was given.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike


def check_count(value: object, name: str) -> int:
    """Return ``value`` as a non-negative int, or raise naming ``name``."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a non-negative integer count, got {value!r}.")
    if not math.isfinite(value) or value != int(value) or value < 0:
        raise ValueError(f"{name} must be a non-negative integer count, got {value!r}.")
    return int(value)


def check_successes_n(successes: object, n: object) -> tuple[int, int]:
    if isinstance(n, numbers.Real) and not isinstance(n, bool) and n <= 0:
        raise ValueError(f"n must be positive (the number of executed trials), got {n!r}.")
    n = check_count(n, "n")
    successes = check_count(successes, "successes")
    if successes > n:
        raise ValueError(f"successes must not exceed n, got successes={successes} and n={n}.")
    return successes, n


def check_probability_open(value: object, name: str) -> float:
    """Return ``value`` as a float strictly between 0 and 1, or raise naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not 0 < value < 1:
        raise ValueError(f"{name} must be a number strictly between 0 and 1, got {value!r}.")
    return float(value)


def check_probability_closed(value: object, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not 0 <= value <= 1:
        raise ValueError(f"{name} must be a number between 0 and 1, got {value!r}.")
    return float(value)


def check_positive_int(value: object, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}.")
    return int(value)


def check_1d(x: ArrayLike, name: str, min_size: int = 1) -> np.ndarray:
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


def check_paired(a: ArrayLike, b: ArrayLike, name_a: str, name_b: str,
                  min_size: int = 1) -> tuple[np.ndarray, np.ndarray]:
    a = check_1d(a, name_a, min_size)
    b = check_1d(b, name_b, min_size)
    if a.shape != b.shape:
        raise ValueError(f"{name_a} and {name_b} must have the same length, got {a.size} and "
                         f"{b.size}.")
    return a, b


def check_binary(x: ArrayLike, name: str) -> np.ndarray:
    """Return ``x`` as a 1-D bool array; accept bool or 0/1 values."""
    arr = np.asarray(x)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array, got shape {arr.shape}.")
    if arr.dtype == bool:
        return arr
    if arr.dtype.kind not in "iuf" or not np.all(np.isin(arr, (0, 1))):
        raise ValueError(f"{name} must hold only booleans or 0/1 values.")
    return arr.astype(bool)


def check_cluster_counts(successes: ArrayLike, trials: ArrayLike
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


def check_rng(rng: object) -> tuple[np.random.Generator, int | None, str]:
    """Return a Generator, the seed (if an int was given) and a note for the report."""
    if isinstance(rng, np.random.Generator):
        return rng, None, f"caller-supplied numpy Generator({type(rng.bit_generator).__name__})"
    if isinstance(rng, numbers.Integral) and not isinstance(rng, bool) and rng >= 0:
        return np.random.default_rng(int(rng)), int(rng), f"numpy.random.default_rng({int(rng)})"
    raise ValueError("rng must be a numpy.random.Generator or a non-negative integer seed, got "
                     f"{rng!r}.")


def check_table(table: ArrayLike) -> np.ndarray:
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


def check_frame(df: object, outcome: object, predictors: object
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


def check_alternative(alternative: object) -> str:
    if alternative not in ("two-sided", "one-sided"):
        raise ValueError(f"alternative must be 'two-sided' or 'one-sided', got {alternative!r}.")
    return str(alternative)
