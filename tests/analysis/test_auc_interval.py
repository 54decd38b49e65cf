"""The held-out AUC and its percentile bootstrap interval (analysis.agreement), checked against
scikit-learn's ``roc_auc_score`` and a resample-at-a-time loop over the same index draws."""

import math

import numpy as np
import pytest
from sklearn.metrics import roc_auc_score

from graspcampaign.analysis.agreement import AUC_INTERVAL_MIN_CLASS, auc, auc_interval


def test_the_auc_statistic_is_sklearn_roc_auc_score_ties_included():
    rng = np.random.default_rng(4)
    actual = np.r_[np.ones(6, bool), np.zeros(70, bool)]  # a run's few held-out positives
    scores = np.round(rng.random((3, 76)) + 0.4 * actual, 1)  # rounded: ties between the classes
    assert auc(scores[:, actual], scores[:, ~actual]) == pytest.approx(
        [roc_auc_score(actual, s) for s in scores], abs=1e-12)  # one row per resample, vectorised


def test_the_interval_is_the_percentiles_of_a_resample_at_a_time_loop():
    """Each resample draws the positives' indices, then the negatives' (one Generator seeded with the
    seed, as scipy draws them); its AUC is sklearn's; the interval is the 2.5th and 97.5th
    percentiles (linear interpolation) of those AUCs."""
    rng = np.random.default_rng(8)
    positive, negative = np.round(rng.random(12) + 0.3, 1), np.round(rng.random(30), 1)  # with ties
    ci = auc_interval(positive, negative, seed=11, n_resamples=500)
    draws = np.random.default_rng(11)
    at_p, at_n = draws.integers(0, 12, (500, 12)), draws.integers(0, 30, (500, 30))
    labels = np.r_[np.ones(12), np.zeros(30)]
    aucs = [roc_auc_score(labels, np.r_[positive[i], negative[j]]) for i, j in zip(at_p, at_n, strict=True)]
    assert (ci.low, ci.high) == pytest.approx(tuple(np.percentile(aucs, [2.5, 97.5])), abs=1e-12)
    assert (ci.method, ci.n_resamples, ci.reason) == ("percentile", 500, "")
    assert ci.low < roc_auc_score(labels, np.r_[positive, negative]) < ci.high


@pytest.mark.parametrize("n_pos, n_neg, reason", [
    (1, 20, "only 1 held-out positive, too few for an interval"),
    (3, 147, "only 3 held-out positives, too few for an interval"),
    (12, 9, "only 9 held-out negatives, too few for an interval"),
    (2, 5, "only 2 held-out positives and only 5 held-out negatives, too few for an interval")])
def test_too_few_of_a_class_gives_no_interval_and_says_why(n_pos, n_neg, reason):
    ci = auc_interval(np.linspace(0.5, 1, n_pos), np.linspace(0, 0.6, n_neg), seed=0)
    assert math.isnan(ci.low) and math.isnan(ci.high)
    assert (ci.method, ci.n_resamples, ci.reason) == ("", 0, reason)


@pytest.mark.parametrize("short", ["positive", "negative"])
def test_the_interval_is_refused_one_below_the_minimum_class_size_and_given_at_it(short):
    """The cutoff the surrogate report's caption names (AUC_INTERVAL_MIN_CLASS) is the one applied."""
    n = AUC_INTERVAL_MIN_CLASS
    below = {"positive": n, "negative": n, short: n - 1}
    scores = np.linspace(0.5, 1, below["positive"]), np.linspace(0, 0.6, below["negative"])
    refused = auc_interval(*scores, seed=0, n_resamples=99)
    assert math.isnan(refused.low)
    assert refused.reason == f"only {n - 1} held-out {short}s, too few for an interval"
    # the coverage benchmark lifts the cutoff to measure the sizes it refuses
    assert auc_interval(*scores, seed=0, n_resamples=99, min_class=n - 1).reason == ""
    given = auc_interval(np.linspace(0.5, 1, n), np.linspace(0, 0.6, n), seed=0, n_resamples=99)
    assert (given.method, given.n_resamples, given.reason) == ("percentile", 99, "")
    assert given.low <= given.high


def test_an_auc_needs_both_classes():
    with pytest.raises(ValueError, match=r"^an AUC needs both classes among the held-out scores, got 0 "
                                         r"positives and 20 negatives\.$"):
        auc_interval([], np.linspace(0, 1, 20), seed=0)
    with pytest.raises(ValueError, match="positive must be finite"):
        auc_interval([0.5, np.nan], np.linspace(0, 1, 20), seed=0)
