"""Benchmark the H(G)-epsilon correlation (report table ``h_epsilon``) near campaign scale.

Run: ``python benchmarks/bench_h_epsilon.py``. Synthetic ferrari_canny trials (20,000 trials x
10 candidates, ties in epsilon) at bench_report's baseline_grid scale. Prints a Markdown table:
the pooled trial-cluster bootstrap per resample, compiled (analysis.rank_kernel) against
``scipy.stats.spearmanr`` on the explicitly repeated sample (timed on 40 resamples), the same
trial-count draws for both; one ``scipy.stats.bootstrap`` of the median per trial (10,000
resamples; the call runs two) in batches of ~4·10^6 values as ``h_epsilon_correlation`` runs it,
against one call (~3 GB of resample arrays); and the whole ``h_epsilon_correlation`` call. No
asserts on time.
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd
from _common import best_of
from scipy import stats

from graspcampaign.analysis.quasi_static import h_epsilon_correlation
from graspcampaign.analysis.rank_kernel import sorted_pairs, weighted_rho

N_TRIALS, N_CANDIDATES, N_BOOT, N_BOOT_SCIPY = 20_000, 10, 2000, 40


def _scipy_rho(x, y, w):
    """The reference: scipy's Spearman rho of the sample in which (x_i, y_i) occurs w_i times."""
    return stats.spearmanr(np.repeat(x, w.astype(int)), np.repeat(y, w.astype(int))).statistic


def main() -> None:
    rng = np.random.default_rng(0)
    n = N_TRIALS * N_CANDIDATES
    trial = np.repeat(np.arange(N_TRIALS), N_CANDIDATES)
    h = rng.uniform(0, 1, n)
    eps = np.round(np.maximum(0.0, 0.5 - h + 0.2 * rng.normal(size=n)), 4)
    per_trial = rng.uniform(-1, 0.2, N_TRIALS)
    records = pd.DataFrame({"trial_id": np.arange(N_TRIALS), "status": "ok",
                            "planner": "ferrari_canny", "grip_law": "paper",
                            "spearman_h_epsilon": per_trial, "spearman_h_epsilon_fc": per_trial})
    candidates = pd.DataFrame({"trial_id": trial, "h_total": h, "epsilon_fc": eps})
    counts = np.array([np.bincount(rng.integers(0, N_TRIALS, N_TRIALS), minlength=N_TRIALS)
                       for _ in range(N_BOOT)], dtype=float)

    ranks = sorted_pairs(h, eps, np.ones(n), trial)
    weighted_rho(*ranks, counts[:1])  # compile (or load the cache) outside the timing
    t_scipy = best_of(lambda: [_scipy_rho(h, eps, c[trial]) for c in counts[:N_BOOT_SCIPY]], 1)
    t_kernel = best_of(lambda: [weighted_rho(*ranks, counts[i:i + 64])
                                for i in range(0, N_BOOT, 64)], 2)
    same = max(abs(_scipy_rho(h, eps, c[trial]) - r) for c, r in
               zip(counts[:N_BOOT_SCIPY], weighted_rho(*ranks, counts[:N_BOOT_SCIPY]), strict=True))
    t_median, t_median_one = (best_of(lambda b=b: stats.bootstrap(
        (per_trial,), np.median, method="percentile", n_resamples=10_000, batch=b,
        random_state=np.random.default_rng(1)), 2) for b in (2**22 // N_TRIALS, None))
    start = time.perf_counter()
    h_epsilon_correlation(records, candidates)
    t_call = time.perf_counter() - start

    per_scipy, per_kernel = t_scipy / N_BOOT_SCIPY, t_kernel / N_BOOT
    print(f"{N_TRIALS} trials x {N_CANDIDATES} candidates = {n} pairs; "
          f"max |rho kernel - rho scipy| over {N_BOOT_SCIPY} resamples = {same:.1e}")
    print("| call | time [ms] | reference | reference [ms] | ratio |")
    print("|---|---:|---|---:|---:|")
    print(f"| pooled bootstrap, compiled, per resample | {1e3 * per_kernel:.2f} "
          f"| scipy spearmanr of the repeated sample, per resample | {1e3 * per_scipy:.2f} "
          f"| {per_kernel / per_scipy:.3f} |")
    print(f"| pooled bootstrap, compiled, {N_BOOT} resamples | {1e3 * t_kernel:.0f} "
          f"| scipy, {N_BOOT} resamples (extrapolated) | {1e3 * per_scipy * N_BOOT:.0f} "
          f"| {per_kernel / per_scipy:.3f} |")
    print(f"| median bootstrap, {N_TRIALS} values, 10,000 resamples, in batches | "
          f"{1e3 * t_median:.0f} | the same in one call | {1e3 * t_median_one:.0f} "
          f"| {t_median / t_median_one:.3f} |")
    print(f"| h_epsilon_correlation (whole call) | {1e3 * t_call:.0f} | | | |")


if __name__ == "__main__":
    main()
