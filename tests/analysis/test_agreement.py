"""Tests of the agreement statistics of graspcampaign.stats (classifier metrics,
Bland-Altman, parity, CV, MdAPE, survival) against values computed outside the code.

Pinned numbers carry the command (or publication) that produced them. "Paper" means the
printed statistic of the source paper (/work/shared/paper.txt), reproduced from its own counts.
"""

import math

import numpy as np
import pytest
from scipy import stats as sps

from graspcampaign import stats as S
from graspcampaign.analysis import agreement

# ---------------------------------------------------------------------------------------------
# Classifier metrics
# ---------------------------------------------------------------------------------------------


def _counts_to_arrays(tp, fp, fn, tn):
    predicted = np.r_[np.ones(tp + fp), np.zeros(fn + tn)].astype(bool)
    actual = np.r_[np.ones(tp), np.zeros(fp), np.ones(fn), np.zeros(tn)].astype(bool)
    return predicted, actual


def test_classifier_reproduces_paper_test3_classifier():
    # Paper Sec. 9.5: 680 certified as retained, 51 of them failed; 671 of 830 trials retained
    # (Table 9). Hence tp = 629, fp = 51, fn = 671 - 629 = 42, tn = 830 - 680 - 42 = 108, and the
    # printed "88.8 % accuracy (precision 0.93, recall 0.94, F1 = 0.93)".
    res = S.classifier_metrics(*_counts_to_arrays(629, 51, 42, 108))
    assert round(100 * res.accuracy, 1) == 88.8
    assert (round(res.precision, 2), round(res.recall, 2), round(res.f1, 2)) == (0.93, 0.94, 0.93)
    assert (res.tn, res.fp, res.fn, res.tp, res.n) == (108, 51, 42, 629, 830)


def test_classifier_matches_sklearn():
    skm = pytest.importorskip("sklearn.metrics")  # the `ml` extra

    rng = np.random.default_rng(3)
    actual = rng.random(300) < 0.6
    predicted = np.where(rng.random(300) < 0.8, actual, ~actual)
    res = S.classifier_metrics(predicted, actual)
    assert res.accuracy == pytest.approx(skm.accuracy_score(actual, predicted))
    assert res.precision == pytest.approx(skm.precision_score(actual, predicted))
    assert res.recall == pytest.approx(skm.recall_score(actual, predicted))
    assert res.f1 == pytest.approx(skm.f1_score(actual, predicted))
    np.testing.assert_array_equal(res.confusion, skm.confusion_matrix(actual, predicted))


def test_classifier_undefined_ratios_are_nan():
    no_pred = S.classifier_metrics([0, 0, 0], [1, 0, 1])
    assert math.isnan(no_pred.precision) and no_pred.recall == 0.0 and no_pred.f1 == 0.0
    no_pos = S.classifier_metrics([0, 0], [0, 0])
    assert math.isnan(no_pos.precision) and math.isnan(no_pos.recall) and math.isnan(no_pos.f1)
    assert no_pos.accuracy == 1.0


def test_classifier_validation():
    with pytest.raises(ValueError, match="predicted and actual must have the same length"):
        S.classifier_metrics([1, 0], [1])
    with pytest.raises(ValueError, match="actual must hold only booleans or 0/1"):
        S.classifier_metrics([1, 0], [1, 0.5])
    with pytest.raises(ValueError, match="predicted must be a non-empty 1-D array"):
        S.classifier_metrics([], [])


# ---------------------------------------------------------------------------------------------
# Bland-Altman, parity, CV, MdAPE, survival
# ---------------------------------------------------------------------------------------------

# Bland & Altman (1986) Lancet 327:307, Table 1: first PEFR readings (l/min), Wright peak flow
# meter and mini Wright meter, 17 subjects. Published: mean difference -2.1, SD 38.8.
WRIGHT = [494, 395, 516, 434, 476, 557, 413, 442, 650, 433, 417, 656, 267, 478, 178, 423, 427]
MINI_WRIGHT = [512, 430, 520, 428, 500, 600, 364, 380, 658, 445, 432, 626, 260, 477, 259, 350, 451]


def test_bland_altman_matches_bland_altman_1986():
    res = S.bland_altman(WRIGHT, MINI_WRIGHT)
    assert round(res.bias, 1) == -2.1
    assert round(res.sd, 1) == 38.8
    assert res.lower == pytest.approx(res.bias - 1.96 * res.sd)
    assert res.upper == pytest.approx(res.bias + 1.96 * res.sd)
    assert res.n == 17


def test_bland_altman_sign_is_measured_minus_predicted():
    res = S.bland_altman([2.0, 3.0, 4.0], [1.0, 2.0, 4.0])
    assert res.bias == pytest.approx(2 / 3)
    assert res.sd == pytest.approx(np.std([1.0, 1.0, 0.0], ddof=1))


def test_bland_altman_validation():
    with pytest.raises(ValueError, match="measured must hold at least 2 values"):
        S.bland_altman([1.0], [1.0])
    with pytest.raises(ValueError, match="measured and predicted must have the same length"):
        S.bland_altman([1.0, 2.0], [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="predicted must be finite"):
        S.bland_altman([1.0, 2.0], [1.0, np.inf])


def test_parity_fit_closed_forms():
    rng = np.random.default_rng(11)
    x = rng.uniform(1, 6, 300)
    y = 1.26 * x + rng.normal(0, 1.2, 300)
    res = S.parity_fit(y, x)
    # Closed forms (Eisenhauer 2003): b = sum(xy)/sum(x^2); numpy.linalg.lstsq as a second path.
    b = (x @ y) / (x @ x)
    assert res.slope_through_origin == pytest.approx(b, rel=1e-12)
    assert res.slope_through_origin == pytest.approx(
        np.linalg.lstsq(x[:, None], y, rcond=None)[0][0], rel=1e-12)
    ssr = np.sum((y - b * x) ** 2)
    assert res.r2_uncentred == pytest.approx(1 - ssr / np.sum(y**2), rel=1e-12)
    assert res.r2_centred == pytest.approx(1 - ssr / np.sum((y - y.mean()) ** 2), rel=1e-12)
    assert res.r2_uncentred > res.r2_centred
    assert res.n == 300


def test_parity_centred_r2_can_be_negative():
    # Data far from the origin with a negative trend: the origin line is worse than the mean.
    res = S.parity_fit([10.0, 9.0, 8.0, 7.0], [1.0, 2.0, 3.0, 4.0])
    assert res.r2_centred < 0 < res.r2_uncentred


def test_parity_validation():
    with pytest.raises(ValueError, match="predicted must not be all zero"):
        S.parity_fit([1.0, 2.0], [0.0, 0.0])


def test_coefficient_of_variation():
    x = [1.0, 2.0, 3.0, 4.0]
    # closed form: sample SD sqrt(5/3) over mean 2.5
    assert S.coefficient_of_variation(x) == pytest.approx(math.sqrt(5 / 3) / 2.5, rel=1e-12)
    ratios = np.array([[0.30, 0.33, 0.36], [0.5, 0.5, 0.5]])  # per trial: three fingers
    cv = S.coefficient_of_variation(ratios, axis=1)
    np.testing.assert_allclose(cv, ratios.std(axis=1, ddof=1) / ratios.mean(axis=1))
    assert math.isnan(S.coefficient_of_variation([-1.0, 1.0]))
    with pytest.raises(ValueError, match="x must hold at least 2 values"):
        S.coefficient_of_variation([1.0])


def test_median_abs_pct_error_uses_measured_denominator():
    measured = [4.0, 2.0, 5.0]
    predicted = [3.0, 2.2, 5.0]
    # |errors| / measured = 0.25, 0.1, 0.0 -> median 0.1 -> 10 %
    assert S.median_abs_pct_error(measured, predicted) == pytest.approx(10.0)
    with pytest.raises(ValueError, match="measured must be non-zero"):
        S.median_abs_pct_error([0.0, 1.0], [1.0, 1.0])


def test_survival_curve_counts_thresholds_at_least_level():
    thresholds = [1.0, 2.0, 2.0, 3.5, 5.0]
    curve = S.survival_curve(thresholds)
    np.testing.assert_array_equal(curve.levels, [1.0, 2.0, 3.5, 5.0])
    np.testing.assert_allclose(curve.surviving_fraction, [1.0, 0.8, 0.4, 0.2])
    at = S.survival_curve(thresholds, levels=[0.0, 3.0, 6.0])
    np.testing.assert_allclose(at.surviving_fraction, [1.0, 0.4, 0.0])
    # Same as 1 - ECDF(level-) from scipy.stats.ecdf, evaluated just below each level.
    ecdf = sps.ecdf(thresholds).cdf
    below = np.nextafter(curve.levels, -np.inf)
    np.testing.assert_allclose(curve.surviving_fraction, 1 - ecdf.evaluate(below))
    assert curve.n == 5


def test_cv_interval_is_scipys_bootstrap_of_the_sample_cv():
    # the statistic is the sample CV (ddof 1, as coefficient_of_variation): scipy's bootstrap of
    # scipy.stats.variation(ddof=1) from the same seed draws the same resamples, so the same ends
    x = np.array([2.1, 2.5, 1.7, 3.0, 2.2, 2.8])
    ref = sps.bootstrap((x,), lambda v, axis: sps.variation(v, axis=axis, ddof=1), n_resamples=2000,
                        method="percentile", rng=np.random.default_rng(4), vectorized=True)
    got = agreement.cv_interval(x, seed=4, n_resamples=2000)
    assert got == pytest.approx((ref.confidence_interval.low, ref.confidence_interval.high), rel=1e-12)


def test_a_constant_measurement_has_no_centred_r2():
    # measured = 3 throughout: no variance for the centred R^2 to explain (nan, not -inf); the
    # uncentred one is statsmodels' R^2 of the regression through the origin
    from statsmodels.regression.linear_model import OLS

    measured, predicted = np.array([3.0, 3.0, 3.0]), np.array([1.0, 2.0, 4.0])
    res = S.parity_fit(measured, predicted)
    assert math.isnan(res.r2_centred)
    assert res.r2_uncentred == pytest.approx(OLS(measured, predicted[:, None]).fit().rsquared, rel=1e-12)


def test_median_interval_is_the_percentile_interval_of_the_exact_bootstrap_distribution():
    # The bootstrap median of n = 11 values is the order statistic x_(k) with probability
    # F(k) - F(k-1), F(k) = P(at least 6 of 11 draws <= x_(k)) = binom.sf(5, 11, k/11), each draw
    # being <= x_(k) with probability k/11. Its 2.5 % and 97.5 % points, the smallest x_(k) with
    # F(k) >= q, are x_(3) = 1.3 and x_(9) = 4.4, each 0.018 in probability from the next atom
    # (11 Monte Carlo SDs at 10,000 resamples), so every seed gives those two values exactly
    x = np.array([3.1, 0.4, 2.2, 5.9, 1.3, 4.4, 0.9, 2.8, 3.7, 1.8, 6.5])
    cdf = sps.binom.sf(5, 11, np.arange(1, 12) / 11)
    low, high = np.sort(x)[np.searchsorted(cdf, [0.025, 0.975])]
    assert (low, high) == (1.3, 4.4)
    for seed in range(4):
        assert agreement.median_interval(x, seed=seed) == (low, high)
    # and scipy's percentile bootstrap of np.median from the same seed, at another level
    ref = sps.bootstrap((x,), np.median, n_resamples=999, confidence_level=0.8, method="percentile",
                        rng=np.random.default_rng(7)).confidence_interval
    assert agreement.median_interval(x, seed=7, n_resamples=999, confidence_level=0.8) == (
        ref.low, ref.high)
    with pytest.raises(ValueError, match=r"^x must hold at least 3 values, got 2\.$"):
        agreement.median_interval([1.0, 2.0], seed=0)
