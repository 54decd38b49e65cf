"""Tests of graspcampaign.stats (the analysis layer's statistics) against values computed outside the code.

Every pinned number carries the command (or publication) that produced it. "Paper" means the
printed statistic of the source paper (/work/shared/paper.txt), reproduced from its own counts.
"""

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats as sps

import graspcampaign.stats as public_stats
from graspcampaign import stats as S
from graspcampaign import stats as public_stats_from
from graspcampaign.report import format as fmt

# ---------------------------------------------------------------------------------------------
# Public module
# ---------------------------------------------------------------------------------------------


def test_public_module_reexports_the_analysis_layer():
    from graspcampaign.analysis import agreement, association, rates

    assert public_stats is public_stats_from
    for name in public_stats.__all__:
        obj = getattr(public_stats, name)
        assert any(getattr(m, name, None) is obj for m in (agreement, association, rates)), name
    assert not any(name.startswith("format") for name in public_stats.__all__)


def test_results_are_frozen():
    res = S.wilson_interval(1, 2)
    with pytest.raises(AttributeError):
        res.low = 0.0  # type: ignore[misc]


# ---------------------------------------------------------------------------------------------
# Wilson interval
# ---------------------------------------------------------------------------------------------


def _wilson_closed_form(k, n, z=1.959963984540054):
    """Wilson (1927) score interval written out by hand, independent of statsmodels."""
    p = k / n
    centre = (p + z**2 / (2 * n)) / (1 + z**2 / n)
    half = z / (1 + z**2 / n) * math.sqrt(p * (1 - p) / n + z**2 / (4 * n**2))
    return centre - half, centre + half


# Paper Table 9 (Test 3, all trials) and Sec. 8.5 (Test 2: 637/819), printed to 0.1 %.
PAPER_WILSON = [
    (671, 830, "78.0–83.4"),  # proposed, Table 9 / Sec. 9.5
    (46, 100, "36.6–55.7"),  # no-PSO, Table 9
    (42, 100, "32.8–51.8"),  # centroid, Table 9
    (27, 100, "19.3–36.4"),  # force-balance, Table 9
    (17, 100, "10.9–25.5"),  # random, Table 9
    (637, 819, "74.8–80.5"),  # proposed, Test 2, Sec. 8.5
]


@pytest.mark.parametrize(("k", "n", "printed"), PAPER_WILSON)
def test_wilson_reproduces_paper_intervals(k, n, printed):
    res = S.wilson_interval(k, n)
    assert fmt.interval(100 * res.low, 100 * res.high, 1) == printed
    low, high = _wilson_closed_form(k, n)
    assert res.low == pytest.approx(low, abs=1e-12)
    assert res.high == pytest.approx(high, abs=1e-12)
    assert (res.estimate, res.n, res.successes, res.method) == (k / n, n, k, "wilson")
    assert res.confidence_level == 0.95


def test_wilson_table9_row_format():
    # Paper Table 9, proposed row: "80.8 (78.0–83.4)".
    res = S.wilson_interval(671, 830)
    assert fmt.estimate(100 * res.estimate, 100 * res.low, 100 * res.high, 1) == "80.8 (78.0–83.4)"


@pytest.mark.parametrize(
    ("k", "n", "low", "high"),
    [
        # Newcombe (1998) Stat. Med. 17:857, Table II, method 3 (score, no continuity correction).
        (81, 263, 0.2553, 0.3662),
        (15, 148, 0.0624, 0.1605),
        (0, 20, 0.0000, 0.1611),
        (1, 29, 0.0061, 0.1718),
    ],
)
def test_wilson_matches_newcombe_1998(k, n, low, high):
    res = S.wilson_interval(k, n)
    assert res.low == pytest.approx(low, abs=5e-5)
    assert res.high == pytest.approx(high, abs=5e-5)


def test_wilson_extremes_are_exact():
    zero = S.wilson_interval(0, 20)
    assert zero.low == 0.0 and zero.estimate == 0.0
    full = S.wilson_interval(29, 29)
    assert full.high == 1.0 and full.estimate == 1.0
    # python -c "from statsmodels.stats.proportion import proportion_confint as c;
    #            print(c(29, 29, method='wilson'))"  -> (0.8830..., 1.0)
    assert full.low == pytest.approx(0.88302, abs=5e-5)


def test_wilson_paper_ablation_half_width_is_about_12_points():
    # Paper Sec. 6.3: "With 50 trials per variant the 95% CI on each rate is roughly ±12
    # percentage points" (72 % = 36/50).
    res = S.wilson_interval(36, 50)
    assert (res.high - res.low) / 2 == pytest.approx(0.12, abs=0.005)


def test_wilson_other_confidence_level():
    res = S.wilson_interval(17, 100, confidence_level=0.90)
    low, high = _wilson_closed_form(17, 100, z=sps.norm.isf(0.05))
    assert (res.low, res.high) == pytest.approx((low, high), abs=1e-12)


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 10**6).flatmap(lambda n: st.tuples(st.integers(0, n), st.just(n))),
       st.floats(0.5, 0.999))
def test_wilson_properties(kn, level):
    k, n = kn
    res = S.wilson_interval(k, n, confidence_level=level)
    assert 0.0 <= res.low <= res.estimate <= res.high <= 1.0


def test_wilson_validation():
    with pytest.raises(ValueError, match="n must be positive"):
        S.wilson_interval(0, 0)
    with pytest.raises(ValueError, match="n must be positive"):
        S.wilson_interval(0, -3)
    with pytest.raises(ValueError, match="successes must not exceed n"):
        S.wilson_interval(5, 4)
    with pytest.raises(ValueError, match="successes must be a non-negative integer"):
        S.wilson_interval(2.5, 4)
    with pytest.raises(ValueError, match="successes must be a non-negative integer"):
        S.wilson_interval(True, 4)
    with pytest.raises(ValueError, match="confidence_level must be a number strictly between"):
        S.wilson_interval(1, 4, confidence_level=95)


def test_wilson_accepts_numpy_and_integral_float_counts():
    res = S.wilson_interval(np.int64(17), 100.0)
    assert (res.successes, res.n) == (17, 100)


# ---------------------------------------------------------------------------------------------
# Cluster bootstrap
# ---------------------------------------------------------------------------------------------


def _pooled(s, n, axis=-1):
    return s.sum(axis=axis) / n.sum(axis=axis)


def test_cluster_bootstrap_matches_scipy_paired_percentile_bootstrap():
    # Reference: scipy.stats.bootstrap((s, n), pooled, paired=True, method="percentile") draws
    # the same (B, k) cluster indices from the same generator state, so the intervals agree.
    rng = np.random.default_rng(7)
    trials = rng.integers(5, 40, size=40)
    successes = rng.binomial(trials, rng.uniform(0.4, 0.95, size=40))
    ours = S.cluster_bootstrap_interval(successes, trials, n_resamples=4000,
                                        confidence_level=0.95, rng=123)
    ref = sps.bootstrap((successes, trials), _pooled, paired=True, vectorized=True,
                        n_resamples=4000, method="percentile", confidence_level=0.95,
                        rng=np.random.default_rng(123))
    assert ours.low == pytest.approx(ref.confidence_interval.low, abs=1e-12)
    assert ours.high == pytest.approx(ref.confidence_interval.high, abs=1e-12)
    assert ours.estimate == pytest.approx(successes.sum() / trials.sum())
    assert (ours.n_clusters, ours.n_trials, ours.n_resamples) == (40, trials.sum(), 4000)
    assert ours.seed == 123 and "default_rng(123)" in ours.rng_note


def test_cluster_bootstrap_with_generator_and_reproducibility():
    s, n = [3, 9, 10, 1, 7], [10, 10, 12, 4, 9]
    a = S.cluster_bootstrap_interval(s, n, n_resamples=500, rng=np.random.default_rng(5))
    b = S.cluster_bootstrap_interval(s, n, n_resamples=500, rng=np.random.default_rng(5))
    assert (a.low, a.high) == (b.low, b.high)
    assert a.seed is None and "caller-supplied" in a.rng_note


def test_cluster_bootstrap_is_wider_than_trial_level_when_objects_differ():
    # 40 objects, 20 trials each: half always succeed, half succeed 50 %: strong clustering.
    s = np.r_[np.full(20, 20), np.full(20, 10)]
    n = np.full(40, 20)
    boot = S.cluster_bootstrap_interval(s, n, n_resamples=2000, rng=0)
    wilson = S.wilson_interval(int(s.sum()), int(n.sum()))
    assert boot.high - boot.low > wilson.high - wilson.low


def test_cluster_bootstrap_degenerate_clusters_give_point_interval():
    boot = S.cluster_bootstrap_interval([5, 5, 5], [10, 10, 10], n_resamples=100, rng=1)
    assert boot.low == boot.high == boot.estimate == 0.5


@settings(max_examples=50, deadline=None)
@given(st.lists(st.tuples(st.integers(1, 30), st.floats(0, 1)), min_size=2, max_size=25),
       st.integers(0, 2**32 - 1))
def test_cluster_bootstrap_properties(clusters, seed):
    trials = np.array([t for t, _ in clusters])
    successes = np.array([int(round(t * f)) for t, f in clusters])
    res = S.cluster_bootstrap_interval(successes, trials, n_resamples=200, rng=seed)
    assert 0.0 <= res.low <= res.high <= 1.0
    assert min(successes / trials) <= res.low and res.high <= max(successes / trials)


def test_cluster_bootstrap_validation():
    with pytest.raises(ValueError, match="at least 2 clusters"):
        S.cluster_bootstrap_interval([1], [2], rng=0)
    with pytest.raises(ValueError, match="trials_per_cluster must be positive"):
        S.cluster_bootstrap_interval([0, 1], [0, 2], rng=0)
    with pytest.raises(ValueError, match="must not exceed trials_per_cluster"):
        S.cluster_bootstrap_interval([3, 1], [2, 2], rng=0)
    with pytest.raises(ValueError, match="same length"):
        S.cluster_bootstrap_interval([1, 1], [2, 2, 2], rng=0)
    with pytest.raises(ValueError, match="successes_per_cluster must hold non-negative integer"):
        S.cluster_bootstrap_interval([1.5, 1], [2, 2], rng=0)
    with pytest.raises(ValueError, match="rng must be a numpy.random.Generator"):
        S.cluster_bootstrap_interval([1, 1], [2, 2], rng=None)
    with pytest.raises(ValueError, match="n_resamples must be a positive integer"):
        S.cluster_bootstrap_interval([1, 1], [2, 2], n_resamples=0, rng=0)


# ---------------------------------------------------------------------------------------------
# McNemar
# ---------------------------------------------------------------------------------------------


def test_mcnemar_reproduces_paper_test3():
    # Paper Sec. 9.5: "McNemar chi2 = 49.2, p ≈ 2e-12; 54 trials won against 1 lost".
    res = S.mcnemar(n01=1, n10=54)
    assert round(res.statistic, 1) == 49.2
    # closed form (|54 - 1| - 1)^2 / 55 and scipy.stats.chi2.sf of it
    assert res.statistic == pytest.approx(52**2 / 55, rel=1e-12)
    assert res.pvalue_chi2 == pytest.approx(sps.chi2.sf(52**2 / 55, 1), rel=1e-9)
    assert f"{res.pvalue_chi2:.0e}" == "2e-12"
    # python -c "from statsmodels.stats.contingency_tables import mcnemar;
    #            print(mcnemar([[0,1],[54,0]], exact=True).pvalue)"  -> 3.1086244689504383e-15
    assert res.pvalue_exact == pytest.approx(3.1086244689504383e-15, rel=1e-6)
    assert res.odds_ratio == 54.0
    assert res.n_discordant == 55


def test_mcnemar_reproduces_paper_test2_with_odds_ratio():
    # Paper Sec. 8.5: "chi2 = 23.4, p ≈ 1e-6; 33 trials won ... against 3 lost, a
    # discordant-pair odds ratio of 11.0".
    res = S.mcnemar(n01=3, n10=33)
    assert round(res.statistic, 1) == 23.4
    assert res.statistic == pytest.approx(29**2 / 36, rel=1e-12)
    assert f"{res.pvalue_chi2:.0e}" == "1e-06"
    assert round(res.odds_ratio, 1) == 11.0
    # python -c "from statsmodels.stats.contingency_tables import mcnemar;
    #            print(mcnemar([[0,3],[33,0]], exact=True).pvalue)"  -> 2.2721360437572002e-07
    assert res.pvalue_exact == pytest.approx(2.2721360437572002e-07, rel=1e-6)
    # Clopper-Pearson by beta quantiles, mapped through q / (1 - q):
    # python -c "from scipy.stats import beta; lo=beta.ppf(.025,33,4); hi=beta.ppf(.975,34,3);
    #            print(lo/(1-lo), hi/(1-hi))"  -> 3.450581092441178 56.056470633948834
    assert res.odds_ratio_low == pytest.approx(3.450581092441178, rel=1e-8)
    assert res.odds_ratio_high == pytest.approx(56.056470633948834, rel=1e-8)


def test_mcnemar_statistic_is_symmetric_and_odds_ratio_inverts():
    a, b = S.mcnemar(3, 33), S.mcnemar(33, 3)
    assert a.statistic == b.statistic and a.pvalue_exact == b.pvalue_exact
    assert a.odds_ratio == pytest.approx(1 / b.odds_ratio)
    assert a.odds_ratio_low == pytest.approx(1 / b.odds_ratio_high)


def test_mcnemar_no_discordant_pairs_is_undefined_not_infinite():
    res = S.mcnemar(0, 0)
    assert math.isnan(res.statistic) and math.isnan(res.odds_ratio)
    assert res.pvalue_chi2 == 1.0 and res.pvalue_exact == 1.0
    assert res.n_discordant == 0


def test_mcnemar_ties_and_one_sided_discordance():
    tie = S.mcnemar(4, 4)  # R: mcnemar.test applies no correction when n01 == n10 -> 0, p = 1
    assert (tie.statistic, tie.pvalue_chi2, tie.pvalue_exact, tie.odds_ratio) == (0, 1, 1, 1)
    one = S.mcnemar(0, 5)
    assert one.odds_ratio == math.inf and one.odds_ratio_high == math.inf
    # statsmodels mcnemar([[0,0],[5,0]], exact=True).pvalue -> 0.0625 (= 2 / 2**5)
    assert one.pvalue_exact == pytest.approx(0.0625)
    assert one.statistic == pytest.approx(16 / 5)


def test_discordant_pairs_orientation():
    proposed = np.array([1, 1, 1, 0, 0, 1], dtype=bool)
    baseline = np.array([0, 0, 1, 1, 0, 1], dtype=bool)
    n01, n10 = S.discordant_pairs(proposed, baseline)
    assert (n01, n10) == (1, 2)  # A failed & B succeeded once; A won twice
    assert S.mcnemar(n01, n10).odds_ratio == 2.0


def test_mcnemar_validation():
    with pytest.raises(ValueError, match="n01 must be a non-negative integer count"):
        S.mcnemar(-1, 3)
    with pytest.raises(ValueError, match="n10 must be a non-negative integer count"):
        S.mcnemar(1, 3.5)
    with pytest.raises(ValueError, match="same length"):
        S.discordant_pairs([1, 0], [1, 0, 1])
    with pytest.raises(ValueError, match="success_a must hold only booleans or 0/1"):
        S.discordant_pairs([2, 0], [1, 0])


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
    res, reference = S.chi2_contingency_test(small, n_resamples=999), sps.chi2_contingency(small)
    assert (res.method, res.statistic, res.dof) == ("Monte Carlo χ²", reference.statistic, reference.dof)
    with pytest.raises(ValueError, match="must be an integer"):  # scipy's: resampling needs whole counts
        S.chi2_contingency_test([[0.5, 4], [1, 3]], n_resamples=999)


def test_equal_rates_without_a_success_or_failure_needs_no_test():
    assert S.equal_rates_test([0, 0], [3, 5]) == S.RatesTest(0.0, 1.0, "", 2, 8)
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


# ---------------------------------------------------------------------------------------------
# Power analysis
# ---------------------------------------------------------------------------------------------


def test_power_unpaired_matches_closed_form():
    # Cohen (1988) two-sample arcsine test: n = 2 ((z_{1-a/2} + z_{1-b}) / h)^2 per arm when the
    # far tail is negligible (R: pwr::pwr.2p.test(h = ES.h(0.72, 0.62), power = 0.8)).
    p1, p2 = 0.72, 0.62
    h = 2 * math.asin(math.sqrt(p1)) - 2 * math.asin(math.sqrt(p2))
    closed = 2 * ((sps.norm.isf(0.025) + sps.norm.isf(0.2)) / h) ** 2
    res = S.power_two_proportions(p1, p2)
    assert res.effect_size == pytest.approx(h, rel=1e-12)
    assert res.n_per_arm_unrounded == pytest.approx(closed, rel=1e-5)  # far tail ~1e-6
    assert res.n_per_arm == math.ceil(closed) == 346
    assert res.effect_size_kind == "cohen_h" and not res.paired


def test_power_paper_ablation_50_trials_underpowered_for_10_points():
    # Paper Sec. 6.3: 50 trials per variant "has limited power to resolve small effects".
    assert S.power_two_proportions(0.72, 0.62).n_per_arm > 50
    assert S.power_two_proportions(0.72, 0.06).n_per_arm <= 50  # random-baseline gap: ample


def test_power_paired_matches_connor_formula_and_simulation():
    # Connor (1987) Biometrics 43:207, as coded in R by B. Greenwell (pwr.mcnemar):
    #   n = ((qnorm(1 - a/2) sqrt(psi) + qnorm(power) sqrt(psi - d^2)) / d)^2
    p10, p01 = 0.15, 0.10
    psi, d = p10 + p01, p10 - p01
    closed = ((sps.norm.isf(0.025) * math.sqrt(psi) + sps.norm.isf(0.2)
               * math.sqrt(psi - d**2)) / d) ** 2
    res = S.power_two_proportions(0.65, 0.60, paired=True, discordant=psi)
    assert res.n_per_arm_unrounded == pytest.approx(closed, rel=1e-12)
    assert res.n_per_arm == 783
    # Monte Carlo check of the achieved power of the (uncorrected) McNemar test at that n (the
    # normal approximation is good at this n; at n ~ 50 it under-states power by a few points).
    rng = np.random.default_rng(2024)
    counts = rng.multinomial(res.n_per_arm, [p10, p01, 1 - psi], size=20_000)
    b, c = counts[:, 0], counts[:, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        z2 = np.where(b + c > 0, (b - c) ** 2 / (b + c), 0.0)
    power = np.mean(z2 > sps.chi2.isf(0.05, 1))
    assert power == pytest.approx(0.8, abs=0.02)


def test_power_paired_default_discordance_is_independence():
    res = S.power_two_proportions(0.8, 0.6, paired=True)
    psi = 0.8 * 0.4 + 0.6 * 0.2
    explicit = S.power_two_proportions(0.8, 0.6, paired=True, discordant=psi)
    assert res.n_per_arm == explicit.n_per_arm


def test_power_validation():
    with pytest.raises(ValueError, match="p1 and p2 must differ"):
        S.power_two_proportions(0.5, 0.5)
    with pytest.raises(ValueError, match="p1 must be a number between 0 and 1"):
        S.power_two_proportions(1.5, 0.5)
    with pytest.raises(ValueError, match="discordant must be at least"):
        S.power_two_proportions(0.8, 0.4, paired=True, discordant=0.2)
    with pytest.raises(ValueError, match="discordant applies only to paired designs"):
        S.power_two_proportions(0.8, 0.4, discordant=0.5)
    with pytest.raises(ValueError, match="alternative must be"):
        S.power_two_proportions(0.8, 0.4, alternative="less")
