"""Benchmark the H(G)-epsilon correlation (report table ``h_epsilon``) near campaign scale.

Run: ``python benchmarks/bench_h_epsilon.py``. Synthetic ferrari_canny trials (20,000 trials x
10 candidates, ties in epsilon) at bench_report's baseline_grid scale. Prints a Markdown table:
the pooled trial-cluster bootstrap per resample, compiled (analysis.rank_kernel) against the numpy
ranks it replaced (commit 39c048a, copied below as the reference; timed on 40 resamples, as
each costs 13-35 ms), the same trial-count draws for both; and the parts of
``h_epsilon_correlation``: the whole call, and one ``scipy.stats.bootstrap`` of the median per
trial (10,000 resamples; the call runs two; best of two, as the first call in a process also
pays for mapping its ~3 GB of resample arrays). No asserts on time.
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd
from _common import best_of
from scipy import stats

from graspcampaign.analysis.quasi_static import h_epsilon_correlation
from graspcampaign.analysis.rank_kernel import sorted_pairs, weighted_rho

N_TRIALS, N_CANDIDATES, N_BOOT, N_BOOT_NUMPY = 20_000, 10, 2000, 40


def _ranker(x):  # the numpy reference (39c048a)
    order = np.argsort(x, kind="stable")
    tie = np.r_[0, np.cumsum(np.diff(x[order]) != 0)]

    def ranks(w):
        group = np.bincount(tie, weights=w[order])
        out = np.empty(len(x))
        out[order] = (np.cumsum(group) - group + (group + 1) / 2)[tie]
        return out
    return ranks


def _rho(rank_x, rank_y, w):  # the numpy reference (39c048a)
    rx, ry = rank_x(w), rank_y(w)
    dx, dy = rx - np.average(rx, weights=w), ry - np.average(ry, weights=w)
    return float(np.sum(w * dx * dy) / np.sqrt(np.sum(w * dx * dx) * np.sum(w * dy * dy)))


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

    rx, ry = _ranker(h), _ranker(eps)
    ranks = sorted_pairs(h, eps, np.ones(n), trial)
    weighted_rho(*ranks, counts[:1])  # compile (or load the cache) outside the timing
    t_numpy = best_of(lambda: [_rho(rx, ry, c[trial]) for c in counts[:N_BOOT_NUMPY]], 1)
    t_kernel = best_of(lambda: [weighted_rho(*ranks, counts[i:i + 64])
                                for i in range(0, N_BOOT, 64)], 2)
    same = max(abs(_rho(rx, ry, c[trial]) - r) for c, r in
               zip(counts[:N_BOOT_NUMPY], weighted_rho(*ranks, counts[:N_BOOT_NUMPY]), strict=True))
    t_median = best_of(lambda: stats.bootstrap((per_trial,), np.median, method="percentile",
                                               n_resamples=10_000,
                                               random_state=np.random.default_rng(1)), 2)
    start = time.perf_counter()
    h_epsilon_correlation(records, candidates)
    t_call = time.perf_counter() - start

    per_numpy, per_kernel = t_numpy / N_BOOT_NUMPY, t_kernel / N_BOOT
    print(f"{N_TRIALS} trials x {N_CANDIDATES} candidates = {n} pairs; "
          f"max |rho kernel - rho numpy| over {N_BOOT_NUMPY} resamples = {same:.1e}")
    print("| call | time [ms] | reference | reference [ms] | ratio |")
    print("|---|---:|---|---:|---:|")
    print(f"| pooled bootstrap, compiled, per resample | {1e3 * per_kernel:.2f} "
          f"| numpy ranks (39c048a), per resample | {1e3 * per_numpy:.2f} "
          f"| {per_kernel / per_numpy:.3f} |")
    print(f"| pooled bootstrap, compiled, {N_BOOT} resamples | {1e3 * t_kernel:.0f} "
          f"| numpy, {N_BOOT} resamples (extrapolated) | {1e3 * per_numpy * N_BOOT:.0f} "
          f"| {per_kernel / per_numpy:.3f} |")
    print(f"| scipy.stats.bootstrap median, {N_TRIALS} values, 10,000 resamples | "
          f"{1e3 * t_median:.0f} | h_epsilon_correlation (whole call) | {1e3 * t_call:.0f} "
          f"| {t_median / t_call:.3f} |")


if __name__ == "__main__":
    main()
