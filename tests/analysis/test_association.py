"""Tests of the association statistics of graspcampaign.stats (chi-square, Kruskal-Wallis,
logistic regression) against values computed outside the code.

Pinned numbers carry the command (or publication) that produced them. "Paper" means the
printed statistic of the source paper (/work/shared/paper.txt), reproduced from its own counts.
"""

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats as sps

from graspcampaign import stats as S

# ---------------------------------------------------------------------------------------------
# Chi-square contingency and Kruskal-Wallis
# ---------------------------------------------------------------------------------------------


def test_chi2_reproduces_paper_test2_three_way():
    # Paper Sec. 8.5: "three-way success-versus-method association (chi2 = 270.0, p < 0.001)":
    # proposed 637/819 (77.8 %), centroid 213/474 (44.9 %), random 79/282 (28.0 %).
    res = S.chi2_contingency_test([[637, 182], [213, 261], [79, 203]])
    assert round(res.statistic, 1) == 270.0
    assert res.dof == 2 and res.pvalue < 1e-3 and not res.yates_correction
    assert res.expected.sum() == pytest.approx(819 + 474 + 282)


def test_chi2_reproduces_paper_test3_three_way():
    # Paper Sec. 9.5: "chi2 contingency test of retention against planner across the proposed,
    # centroid, and random arms ... chi2 = 221": 671/830, 42/100, 17/100 (Table 9).
    res = S.chi2_contingency_test([[671, 159], [42, 58], [17, 83]])
    assert round(res.statistic) == 221


def test_chi2_2x2_is_plain_pearson_unless_yates_requested():
    table = np.array([[12, 5], [3, 10]])
    # Pearson closed form: sum (O - E)^2 / E with E = row * col / total
    expected = table.sum(1, keepdims=True) * table.sum(0, keepdims=True) / table.sum()
    pearson = ((table - expected) ** 2 / expected).sum()
    res = S.chi2_contingency_test(table)
    assert res.statistic == pytest.approx(pearson, rel=1e-12)
    assert res.pvalue == pytest.approx(sps.chi2.sf(pearson, 1), rel=1e-12)
    yates = ((np.abs(table - expected) - 0.5) ** 2 / expected).sum()
    res_y = S.chi2_contingency_test(table, yates=True)
    assert res_y.statistic == pytest.approx(yates, rel=1e-12) and res_y.yates_correction


def test_yates_is_not_said_to_correct_a_table_larger_than_2x2():
    # Yates' correction is defined for one degree of freedom: on a 2 x 3 table the statistic is
    # Pearson's closed form, uncorrected, so the result must not claim a correction
    table = np.array([[12, 5, 7], [3, 10, 6]])
    expected = table.sum(1, keepdims=True) * table.sum(0, keepdims=True) / table.sum()
    res = S.chi2_contingency_test(table, yates=True)
    assert res.statistic == pytest.approx(((table - expected) ** 2 / expected).sum(), rel=1e-12)
    assert not res.yates_correction


def test_chi2_refuses_yates_with_monte_carlo_up_front():
    # scipy refuses correction=True with MonteCarloMethod, but only once a small table resampled, in
    # its own words; the combination is refused on its arguments, whatever the table
    for table in ([[12, 5], [3, 10]], [[1, 2], [3, 1]]):
        with pytest.raises(ValueError) as err:
            S.chi2_contingency_test(table, yates=True, n_resamples=99)
        assert str(err.value) == ("yates=True cannot be combined with n_resamples: the Monte Carlo "
                                  "p-value has no Yates correction (scipy refuses it); pass one of them.")


def test_chi2_validation():
    with pytest.raises(ValueError, match="table must be a 2-D array of at least 2 x 2"):
        S.chi2_contingency_test([1, 2, 3])
    with pytest.raises(ValueError, match="no all-zero row or column"):
        S.chi2_contingency_test([[0, 0], [3, 4]])
    with pytest.raises(ValueError, match="finite non-negative counts"):
        S.chi2_contingency_test([[1, -2], [3, 4]])


def test_chi2_refuses_a_single_row_and_an_empty_column():
    # one row compares nothing (scipy: 0 degrees of freedom); an empty column expects 0 counts
    with pytest.raises(ValueError) as err:
        S.chi2_contingency_test([[3, 4, 5]])
    assert str(err.value) == "table must be a 2-D array of at least 2 x 2 counts, got shape (1, 3)."
    assert sps.chi2_contingency([[3, 4, 5]]).dof == 0
    with pytest.raises(ValueError, match="no all-zero row or column"):
        S.chi2_contingency_test([[0, 3], [0, 4]])


@pytest.mark.parametrize("successes, trials", [([40, 10], [100, 100]), ([26, 24, 30], [100, 100, 90])])
def test_equal_rates_with_large_counts_is_scipys_pearson_chi_square(successes, trials):
    table = pd.DataFrame({"won": successes, "lost": np.subtract(trials, successes)})
    reference = sps.chi2_contingency(table, correction=False)
    res = S.equal_rates_test(successes, trials)
    assert (res.statistic, res.pvalue) == pytest.approx((reference.statistic, reference.pvalue), rel=1e-12)
    assert (res.method, res.groups, res.n) == ("χ²", len(trials), sum(trials))


def test_equal_rates_with_small_counts_is_the_exact_conditional_p_value_within_monte_carlo_error():
    """Expected counts below 5: the p-value over tables with the observed margins, against the exact
    one enumerated from the multivariate hypergeometric distribution of the success counts."""
    successes, trials = [0, 1, 4], [4, 4, 4]
    total, observed = sum(successes), sps.chi2_contingency(
        np.column_stack([successes, np.subtract(trials, successes)]), correction=False).statistic
    exact = 0.0
    for s in np.ndindex(*(n + 1 for n in trials)):
        if sum(s) == total:
            table = np.column_stack([s, np.subtract(trials, s)])
            stat = sps.chi2_contingency(table, correction=False).statistic
            ways = math.prod(math.comb(n, k) for n, k in zip(trials, s, strict=True))
            exact += (stat >= observed - 1e-9) * ways
    exact /= math.comb(sum(trials), total)
    res = S.equal_rates_test(successes, trials)
    assert res.method == "Monte Carlo χ²" and res.pvalue == pytest.approx(exact, abs=0.02)
    assert S.equal_rates_test(successes, trials).pvalue == res.pvalue  # seeded: one report, one p


def test_chi2_monte_carlo_p_only_for_small_expected_counts_and_keeps_the_tables_dof():
    """Given n_resamples, a table with every expected count >= 5 keeps scipy's asymptotic test; a
    smaller one is resampled, its statistic and degrees of freedom still scipy's."""
    large, small = [[40, 60], [10, 90]], [[0, 4], [1, 3], [4, 0]]
    res = S.chi2_contingency_test(large, n_resamples=999)
    assert (res.method, res.pvalue) == ("χ²", sps.chi2_contingency(large, correction=False).pvalue)
    assert res.n_resamples == 0  # the distribution's p: no table drawn
    res, reference = S.chi2_contingency_test(small, n_resamples=999), sps.chi2_contingency(small)
    assert (res.method, res.statistic, res.dof) == ("Monte Carlo χ²", reference.statistic, reference.dof)
    assert res.n_resamples == 999
    with pytest.raises(ValueError, match="must be an integer"):  # scipy's: resampling needs whole counts
        S.chi2_contingency_test([[0.5, 4], [1, 3]], n_resamples=999)


def test_equal_rates_without_a_success_or_failure_needs_no_test():
    assert S.equal_rates_test([0, 0], [3, 5]) == S.RatesTest(0.0, 1.0, "", 2, 8, 0)
    assert S.equal_rates_test([3, 5], [3, 5]).pvalue == 1.0


def test_equal_rates_validation():
    with pytest.raises(ValueError, match="at least 2 groups are needed, got 1"):
        S.equal_rates_test([1], [4])
    with pytest.raises(ValueError, match="successes_per_group must not exceed trials_per_group"):
        S.equal_rates_test([5, 1], [4, 4])


def test_kruskal_matches_r_example():
    # R: example(kruskal.test) (Hollander & Wolfe 1973, p. 116):
    #   kruskal.test(list(c(2.9, 3.0, 2.5, 2.6, 3.2), c(3.8, 2.7, 4.0, 2.4),
    #                     c(2.8, 3.4, 3.7, 2.2, 2.0)))
    #   -> Kruskal-Wallis chi-squared = 0.77143, df = 2, p-value = 0.68
    res = S.kruskal_wallis([2.9, 3.0, 2.5, 2.6, 3.2], [3.8, 2.7, 4.0, 2.4],
                           [2.8, 3.4, 3.7, 2.2, 2.0])
    assert res.statistic == pytest.approx(0.77143, abs=5e-6)
    assert res.pvalue == pytest.approx(0.68, abs=5e-3)
    assert (res.n_groups, res.n) == (3, 14)


def test_kruskal_all_ties_is_undefined_with_p_one():
    res = S.kruskal_wallis([1.0, 1.0], [1.0, 1.0, 1.0])
    assert math.isnan(res.statistic) and res.pvalue == 1.0


def test_kruskal_validation():
    with pytest.raises(ValueError, match="groups must be at least 2 samples"):
        S.kruskal_wallis([1.0, 2.0])
    with pytest.raises(ValueError, match=r"groups\[1\] must hold at least 1 values"):
        S.kruskal_wallis([1.0, 2.0], [])
    with pytest.raises(ValueError, match=r"groups\[0\] must be finite"):
        S.kruskal_wallis([1.0, np.nan], [2.0])


# ---------------------------------------------------------------------------------------------
# Logistic regression
# ---------------------------------------------------------------------------------------------


def _two_by_two_frame(a, b, c, d):
    """Trials of two planners: a successes / b failures (proposed), c / d (centroid)."""
    success = np.r_[np.ones(a), np.zeros(b), np.ones(c), np.zeros(d)]
    proposed = np.r_[np.ones(a + b), np.zeros(c + d)]
    return pd.DataFrame({"success": success.astype(bool), "proposed": proposed.astype(bool)})


def test_logistic_reproduces_paper_odds_ratio_4_3():
    # Paper Sec. 8.5: "the proposed planner's odds of success exceed the centroid planner's by a
    # factor of 4.3" (637/819 vs 213/474). A saturated one-indicator logit has the closed form
    # coef = log(a d / (b c)), se = sqrt(1/a + 1/b + 1/c + 1/d) (Woolf 1955).
    a, b, c, d = 637, 182, 213, 261
    res = S.logistic_regression(_two_by_two_frame(a, b, c, d), "success", ["proposed"])
    row = res.coefficients.loc["proposed"]
    assert round(math.exp(row["coef"]), 1) == 4.3
    assert row["coef"] == pytest.approx(math.log(a * d / (b * c)), rel=1e-9)
    assert row["se"] == pytest.approx(math.sqrt(1 / a + 1 / b + 1 / c + 1 / d), rel=1e-7)
    assert res.coefficients.loc["intercept", "coef"] == pytest.approx(math.log(c / d), rel=1e-9)
    assert row["ci_low"] == pytest.approx(row["coef"] - 1.959963984540054 * row["se"], rel=1e-9)
    assert list(res.coefficients.columns) == ["coef", "se", "z", "p", "ci_low", "ci_high"]
    assert list(res.coefficients.index) == ["intercept", "proposed"]
    assert res.converged and not res.separation and res.separation_kind == "none"
    assert res.n == a + b + c + d


def test_logistic_matches_statsmodels_glm_irls():
    # Reference: statsmodels GLM(family=Binomial()) fitted by IRLS, a different code path from
    # the Newton fit of Logit used by the implementation.
    import statsmodels.api as sm

    rng = np.random.default_rng(42)
    n = 400
    df = pd.DataFrame({"load_n": rng.uniform(0, 4, n), "mass_kg": rng.uniform(0.1, 0.6, n),
                       "mu": rng.choice([0.3, 0.5, 0.8], n), "proposed": rng.integers(0, 2, n)})
    eta = -2 + 0.55 * df.load_n + 2.5 * df.mass_kg + 0.4 * df.mu - 3.0 * df.proposed
    df["failed"] = rng.random(n) < 1 / (1 + np.exp(-eta))
    predictors = ["load_n", "mass_kg", "mu", "proposed"]
    res = S.logistic_regression(df, "failed", predictors)
    glm = sm.GLM(df.failed.astype(float), sm.add_constant(df[predictors].astype(float)),
                 family=sm.families.Binomial()).fit()
    np.testing.assert_allclose(res.coefficients["coef"].to_numpy(), glm.params.to_numpy(),
                               rtol=1e-6)
    np.testing.assert_allclose(res.coefficients["se"].to_numpy(), glm.bse.to_numpy(), rtol=1e-5)
    np.testing.assert_allclose(res.coefficients["p"].to_numpy(), glm.pvalues.to_numpy(),
                               rtol=1e-4)
    assert res.converged and res.separation_kind == "none"


def test_logistic_reports_complete_separation_without_raising():
    x = np.arange(8.0)
    df = pd.DataFrame({"y": x > 3.5, "x": x})
    res = S.logistic_regression(df, "y", ["x"])
    assert res.separation and res.separation_kind == "complete"
    assert not res.converged
    assert any("PerfectSeparation" in m or "converge" in m for m in res.messages)


def test_logistic_reports_quasi_complete_separation():
    # Ties at x = 3.5 with both outcomes: separable with equality on the boundary only.
    x = np.r_[np.arange(8.0), 3.5, 3.5]
    y = np.r_[np.arange(8.0) > 3.5, False, True]
    res = S.logistic_regression(pd.DataFrame({"y": y, "x": x}), "y", ["x"])
    assert res.separation and res.separation_kind == "quasi-complete"
    assert not res.converged


def test_logistic_zero_cell_indicator_is_quasi_complete():
    # A planner that never fails: the indicator's MLE is infinite (quasi-complete separation).
    df = _two_by_two_frame(50, 0, 20, 30)
    res = S.logistic_regression(df, "success", ["proposed"])
    assert res.separation_kind == "quasi-complete"


def test_logistic_constant_outcome_is_reported_not_raised():
    df = pd.DataFrame({"y": np.zeros(10), "x": np.arange(10.0)})
    res = S.logistic_regression(df, "y", ["x"])
    assert res.separation_kind == "complete" and not res.converged


def test_logistic_validation():
    df = pd.DataFrame({"y": [0, 1, 0, 1, 1], "x": [1.0, 2, 3, 4, 5], "s": list("abcde")})
    with pytest.raises(ValueError, match="outcome must name a column of df"):
        S.logistic_regression(df, "z", ["x"])
    with pytest.raises(ValueError, match="predictors must name columns of df"):
        S.logistic_regression(df, "y", ["w"])
    with pytest.raises(ValueError, match="predictors must be a non-empty list"):
        S.logistic_regression(df, "y", "x")
    with pytest.raises(ValueError, match="numeric or boolean columns"):
        S.logistic_regression(df, "y", ["s"])
    with pytest.raises(ValueError, match="must hold only 0/1"):
        S.logistic_regression(df.assign(y=[0, 1, 2, 1, 0]), "y", ["x"])
    with pytest.raises(ValueError, match="no missing values"):
        S.logistic_regression(df.assign(x=[1.0, np.nan, 3, 4, 5]), "y", ["x"])
    with pytest.raises(ValueError, match="rank-deficient"):
        S.logistic_regression(df.assign(x2=df.x * 2), "y", ["x", "x2"])
    with pytest.raises(ValueError, match="df must be a pandas DataFrame"):
        S.logistic_regression({"y": [0, 1]}, "y", ["x"])
    # as many rows as coefficients leaves no residual degree of freedom: refused, one row more is not
    with pytest.raises(ValueError) as err:
        S.logistic_regression(df.iloc[:2], "y", ["x"])
    assert str(err.value) == "df must have more rows than coefficients (2), got 2."


def test_a_fit_without_finite_standard_errors_is_not_converged(monkeypatch):
    # statsmodels' Newton fit says "converged" from the size of its last step alone; its standard
    # errors are the square roots of the diagonal of inv(-Hessian) / n, nan where a numerically
    # indefinite Hessian leaves a negative entry. The paper's 2 x 2 fit converges with finite Woolf
    # SEs; the same fit with its SEs made nan (no real data set was found that does it: 3,000
    # random small designs, 1-2 predictors at scales 1e-8 to 1e8) is no estimate to report
    from statsmodels.discrete.discrete_model import Logit

    from graspcampaign.analysis import association

    class NanSE:
        def __init__(self, fit):
            self.fit, self.bse = fit, np.full(len(fit.params), np.nan)

        def __getattr__(self, name):
            return getattr(self.fit, name)

    class Model(Logit):
        def fit(self, *args, **kwargs):
            return NanSE(super().fit(*args, **kwargs))

    df = _two_by_two_frame(637, 182, 213, 261)
    assert S.logistic_regression(df, "success", ["proposed"]).converged
    monkeypatch.setattr(association, "Logit", Model)
    res = S.logistic_regression(df, "success", ["proposed"])
    assert res.coefficients["se"].isna().all() and res.separation_kind == "none"
    assert not res.converged
