"""Input validation and result types of the statistics: each ``check_*`` returns the value as the
computation needs it or raises ``ValueError`` naming the argument, the expected form and the value."""

from __future__ import annotations

import numbers
import sys
from collections.abc import Sequence
from dataclasses import make_dataclass

import numpy as np
import pandas as pd


def result(name: str, doc: str, namespace: dict | None = None, **fields: type) -> type:
    """Return a frozen, slotted result dataclass with ``fields`` (name=type) in this order."""
    namespace = {"__doc__": doc, "__module__": sys._getframe(1).f_globals["__name__"], **(namespace or {})}
    return make_dataclass(name, list(fields.items()), frozen=True, slots=True, namespace=namespace)


def require(ok: object, message: str) -> None:
    """Raise ``ValueError(message)`` unless ``ok``."""
    if not ok:
        raise ValueError(message)


def _real(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)


def check_count(value: object, name: str, positive: bool = False) -> int:
    """Return ``value`` as a non-negative (``positive``: positive) int; integral floats pass."""
    require(_real(value) and np.isfinite(value) and value == int(value) and value >= positive,
            f"{name} must be a {'positive integer' if positive else 'non-negative integer count'}, "
            f"got {value!r}.")
    return int(value)


def check_fraction(value: object, name: str, closed: bool = False) -> float:
    """Return ``value`` as a float in (0, 1), or in [0, 1] when ``closed``."""
    inside = _real(value) and (0 <= value <= 1 if closed else 0 < value < 1)
    require(inside, f"{name} must be a number {'' if closed else 'strictly '}between 0 and 1, got "
                    f"{value!r}.")
    return float(value)


def check_1d(x: object, name: str, min_size: int = 1) -> np.ndarray:
    """Return ``x`` as a finite 1-D float64 array of at least ``min_size`` values."""
    arr = np.asarray(x)
    require(arr.dtype.kind in "biuf", f"{name} must hold real numbers, got dtype {arr.dtype}.")
    require(arr.ndim == 1, f"{name} must be 1-D, got shape {arr.shape}.")
    require(arr.size >= min_size, f"{name} must hold at least {min_size} values, got {arr.size}.")
    bad = int(np.sum(~np.isfinite(arr)))
    require(not bad, f"{name} must be finite (no nan or inf), got {bad} non-finite values.")
    return arr.astype(np.float64)


def check_paired(a: object, b: object, name_a: str, name_b: str, min_size: int = 1,
                 binary: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Return two 1-D arrays of the same length (``binary``: as bool arrays)."""
    a, b = ((check_binary(a, name_a), check_binary(b, name_b)) if binary
            else (check_1d(a, name_a, min_size), check_1d(b, name_b, min_size)))
    require(a.shape == b.shape, f"{name_a} and {name_b} must have the same length, got {a.size} "
                                f"and {b.size}.")
    return a, b


def check_binary(x: object, name: str) -> np.ndarray:
    """Return ``x`` as a non-empty 1-D bool array; accept bool or 0/1 values."""
    arr = np.asarray(x)
    require(arr.ndim == 1 and arr.size, f"{name} must be a non-empty 1-D array, got shape "
                                        f"{arr.shape}.")
    require(arr.dtype == bool or (arr.dtype.kind in "iuf" and np.isin(arr, (0, 1)).all()),
            f"{name} must hold only booleans or 0/1 values.")
    return arr.astype(bool)


def check_cluster_counts(successes: object, trials: object, group: str = "cluster"
                         ) -> tuple[np.ndarray, np.ndarray]:
    """Return per-``group`` successes and trials as int64 arrays (at least two groups)."""
    s, t = np.asarray(successes), np.asarray(trials)
    for arr, name in ((s, f"successes_per_{group}"), (t, f"trials_per_{group}")):
        require(arr.ndim == 1, f"{name} must be 1-D (one count per {group}), got shape {arr.shape}.")
        require(arr.dtype.kind in "iuf" and np.isfinite(arr).all() and (arr >= 0).all()
                and (arr == np.round(arr)).all(), f"{name} must hold non-negative integer counts.")
    require(s.shape == t.shape, f"successes_per_{group} and trials_per_{group} must have the same "
                                f"length, got {s.size} and {t.size}.")
    require(s.size >= 2, f"at least 2 {group}s are needed, got {s.size}.")
    require((t > 0).all(), f"trials_per_{group} must be positive for every {group} (drop {group}s "
                           "with no executed trials).")
    require((s <= t).all(), f"successes_per_{group} must not exceed trials_per_{group} in any "
                            f"{group}.")
    return s.astype(np.int64), t.astype(np.int64)


def check_rng(rng: object) -> tuple[np.random.Generator, int | None, str]:
    """Return a Generator, the seed (if an int was given) and a note for the report."""
    if isinstance(rng, np.random.Generator):
        return rng, None, f"caller-supplied numpy Generator({type(rng.bit_generator).__name__})"
    require(isinstance(rng, numbers.Integral) and not isinstance(rng, bool) and rng >= 0,
            f"rng must be a numpy.random.Generator or a non-negative integer seed, got {rng!r}.")
    return np.random.default_rng(int(rng)), int(rng), f"numpy.random.default_rng({int(rng)})"


def check_table(table: object) -> np.ndarray:
    """Return an r x c table of counts (r, c >= 2) with no all-zero row or column."""
    arr = np.asarray(table)
    require(arr.ndim == 2 and min(arr.shape) >= 2, "table must be a 2-D array of at least 2 x 2 "
                                                   f"counts, got shape {arr.shape}.")
    require(arr.dtype.kind in "iuf" and np.isfinite(arr).all() and (arr >= 0).all(),
            "table must hold finite non-negative counts.")
    require(arr.sum(axis=1).all() and arr.sum(axis=0).all(), "table must have no all-zero row or "
            "column (its expected counts would be zero); drop the empty category first.")
    return arr.astype(np.float64)


def check_frame(df: object, outcome: object, predictors: object
                ) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Return the 0/1 outcome, the design matrix (intercept first) and the predictor names."""
    require(isinstance(df, pd.DataFrame), f"df must be a pandas DataFrame, got {type(df).__name__}.")
    require(isinstance(outcome, str) and outcome in df, f"outcome must name a column of df, got "
                                                        f"{outcome!r}.")
    require(isinstance(predictors, Sequence) and not isinstance(predictors, str) and predictors,
            "predictors must be a non-empty list of column names.")
    predictors = list(predictors)
    missing = [p for p in predictors if p not in df]
    require(not missing, f"predictors must name columns of df; not found: {missing}.")
    require(outcome not in predictors and len(set(predictors)) == len(predictors),
            "predictors must be distinct and must not include the outcome.")
    columns = [outcome, *predictors]
    bad = [c for c in columns if not pd.api.types.is_numeric_dtype(df[c])]  # bool is numeric
    require(not bad, f"outcome and predictors must be numeric or boolean columns; not: {bad}.")
    require(not df[columns].isna().to_numpy().any(), "outcome and predictors must have no "
            "missing values; drop or impute them first.")
    y, x = df[outcome].to_numpy(np.float64), df[predictors].to_numpy(np.float64)
    require(np.isin(y, (0.0, 1.0)).all(), f"outcome column {outcome!r} must hold only 0/1 or "
                                          "booleans.")
    require(np.isfinite(x).all(), "predictors must be finite (no inf).")
    require(len(df) > len(predictors) + 1, "df must have more rows than coefficients "
                                           f"({len(predictors) + 1}), got {len(df)}.")
    design = np.column_stack([np.ones(len(df)), x])
    require(np.linalg.matrix_rank(design) == design.shape[1], "predictors must not be linearly "
            "dependent on each other or on the intercept (the design matrix is rank-deficient).")
    return y, design, predictors
