"""Coverage of the held-out AUC's 95 % percentile bootstrap interval (the shipped
analysis.agreement.auc_interval, positives and negatives resampled apart, its cutoff lifted) with few
positives: binormal scores (negatives N(0, 1), positives N(d, 1), true AUC = Phi(d / sqrt 2)),
n_neg = 147 (a 20 % split of 750 trials).
Prints, per true AUC and n_pos, the share of intervals holding the true AUC (docs/decisions.md).

    PYTHONPATH=src python benchmarks/auc_interval_coverage.py [replicates] [resamples]
"""

import sys

import numpy as np
from scipy import stats

from graspcampaign.analysis.agreement import auc_interval

replicates, resamples = (int(a) for a in (sys.argv[1:] or ["400", "2000"]))
rng = np.random.default_rng(0)
print("true AUC  n_pos  coverage  mean width")
for true in (0.75, 0.90):
    d = np.sqrt(2) * stats.norm.ppf(true)
    for n_pos in (3, 5, 10, 20):
        hits, widths = 0, []
        for _ in range(replicates):
            positive, negative = rng.normal(d, 1, n_pos), rng.normal(0, 1, 147)
            # the shipped statistic, its cutoff lifted to measure the sizes it refuses
            ci = auc_interval(positive, negative, seed=int(rng.integers(2**63)), n_resamples=resamples,
                              min_class=1)
            hits += ci.low <= true <= ci.high
            widths.append(ci.high - ci.low)
        print(f"{true:8.2f}  {n_pos:5d}  {hits / replicates:8.3f}  {np.mean(widths):10.3f}")
