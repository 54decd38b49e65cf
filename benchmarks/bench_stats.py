"""Benchmark the report statistics at campaign scale.

Run: ``python benchmarks/bench_stats.py``. Prints a Markdown table of wall times with ratios
against a reference measured in the same run: the object-clustered bootstrap against
``scipy.stats.bootstrap(paired=True, method="percentile")`` (same resamples, same interval),
and the other calls against one Wilson interval. No asserts on time.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from _common import best_of
from scipy import stats as sps

from graspcampaign import stats

N_TRIALS = 100_000
N_OBJECTS = 40
N_RESAMPLES = 10_000


def _pooled(s, n, axis=-1):
    return s.sum(axis=axis) / n.sum(axis=axis)


def main() -> None:
    rng = np.random.default_rng(0)
    objects = rng.integers(0, N_OBJECTS, N_TRIALS)
    success = rng.random(N_TRIALS) < rng.uniform(0.5, 0.95, N_OBJECTS)[objects]
    s = np.bincount(objects, weights=success, minlength=N_OBJECTS).astype(np.int64)
    n = np.bincount(objects, minlength=N_OBJECTS)
    df = pd.DataFrame({"failed": ~success, "load_n": rng.uniform(0, 4, N_TRIALS),
                       "mass_kg": rng.uniform(0.1, 0.6, N_TRIALS),
                       "proposed": rng.integers(0, 2, N_TRIALS)})
    measured = rng.uniform(1, 6, N_TRIALS)
    predicted = measured / 1.26 + rng.normal(0, 0.5, N_TRIALS)

    rows: list[tuple[str, float, str, float]] = []
    t_scipy = best_of(lambda: sps.bootstrap(
        (s, n), _pooled, paired=True, vectorized=True, n_resamples=N_RESAMPLES,
        method="percentile", rng=np.random.default_rng(1)))
    t_ours = best_of(lambda: stats.cluster_bootstrap_interval(
        s, n, n_resamples=N_RESAMPLES, rng=1))
    rows.append((f"cluster_bootstrap_interval (k={N_OBJECTS}, B={N_RESAMPLES})", t_ours,
                 "scipy.stats.bootstrap paired percentile", t_scipy))

    t_wilson = best_of(lambda: stats.wilson_interval(int(success.sum()), N_TRIALS), repeat=20)
    for label, fn in [
        ("mcnemar(33, 3)", lambda: stats.mcnemar(3, 33)),
        ("chi2_contingency_test 3x2", lambda: stats.chi2_contingency_test(
            [[637, 182], [213, 261], [79, 203]])),
        (f"kruskal_wallis, 3 groups, n={N_TRIALS}", lambda: stats.kruskal_wallis(
            measured[objects % 3 == 0], measured[objects % 3 == 1], measured[objects % 3 == 2])),
        (f"logistic_regression, 3 predictors, n={N_TRIALS}", lambda: stats.logistic_regression(
            df, "failed", ["load_n", "mass_kg", "proposed"])),
        (f"classifier_metrics, n={N_TRIALS}", lambda: stats.classifier_metrics(
            predicted > 3, measured > 3)),
        (f"bland_altman, n={N_TRIALS}", lambda: stats.bland_altman(measured, predicted)),
        (f"parity_fit, n={N_TRIALS}", lambda: stats.parity_fit(measured, predicted)),
        (f"median_abs_pct_error, n={N_TRIALS}", lambda: stats.median_abs_pct_error(
            measured, predicted)),
        (f"survival_curve, n={N_TRIALS}", lambda: stats.survival_curve(measured)),
    ]:
        rows.append((label, best_of(fn), "wilson_interval", t_wilson))

    print("| call | time [ms] | reference | reference [ms] | ratio |")
    print("|---|---:|---|---:|---:|")
    for label, t, ref_label, t_ref in rows:
        print(f"| {label} | {1e3 * t:.2f} | {ref_label} | {1e3 * t_ref:.3f} | {t / t_ref:.2f} |")


if __name__ == "__main__":
    main()
