"""Statistics at the edges their rules name: Cochran's expected count of 5, a constant sample.

Outside references: ``scipy.stats.chi2_contingency`` (the chi-square distribution's p-value) and
``scipy.stats.spearmanr`` (no rank correlation, nan, for a constant sample).
"""

from __future__ import annotations

import warnings

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy import stats

from graspcampaign.analysis.association import MIN_EXPECTED, chi2_contingency_test, equal_rates_test
from graspcampaign.analysis.rank_kernel import sorted_pairs, weighted_rho


def test_an_expected_count_of_exactly_five_reads_the_chi_square_distribution():
    # Cochran (1954): the distribution is trusted unless an expected count is *below* 5
    table = np.array([[3, 7], [7, 3]])  # every expected count is 5
    assert stats.contingency.expected_freq(table).min() == MIN_EXPECTED
    res = chi2_contingency_test(table, n_resamples=999)
    assert res.method == "χ²"
    assert res.pvalue == stats.chi2_contingency(table, correction=False).pvalue
    rates = equal_rates_test([3, 7], [10, 10], n_resamples=999)
    assert (rates.method, rates.pvalue) == (res.method, res.pvalue)
    # one count below 5 takes the Monte Carlo p-value
    assert chi2_contingency_test([[2, 8], [7, 3]], n_resamples=999).method == "Monte Carlo χ²"


@settings(deadline=None)  # the first call compiles the kernel
@given(arrays(np.float64, st.integers(2, 12), elements=st.floats(0.1, 5.0)), st.floats(-10.0, 10.0),
       st.integers(0, 2**32 - 1))
def test_a_constant_sample_has_no_rank_correlation(weights, value, seed):
    # real weights (a pair's weight times its cluster's count): a constant x must give nan, as
    # spearmanr does, not a rounding residue of the centred ranks (~1e-16)
    n = weights.size
    y = np.random.default_rng(seed).normal(size=n)
    x = np.full(n, value)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert np.isnan(stats.spearmanr(x, y).statistic)
    for a, b in ((x, y), (y, x)):
        rho = weighted_rho(*sorted_pairs(a, b, weights, np.arange(n)), np.ones((1, n)))
        assert np.isnan(rho[0])
