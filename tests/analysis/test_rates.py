"""Tests of the rates statistics of graspcampaign.stats (the public module; Wilson and
cluster-bootstrap intervals, McNemar, power) against values computed outside the code.

Pinned numbers carry the command (or publication) that produced them. "Paper" means the
printed statistic of the source paper (/work/shared/paper.txt), reproduced from its own counts.
"""

import math

import numpy as np
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


def test_power_one_sided_unpaired_matches_closed_form():
    # One-sided arcsine test (Cohen 1988): n = 2 ((z_{1-a} + z_{1-b}) / h)^2 per arm exactly (no
    # far tail to neglect)
    p1, p2 = 0.72, 0.62
    h = 2 * math.asin(math.sqrt(p1)) - 2 * math.asin(math.sqrt(p2))
    closed = 2 * ((sps.norm.isf(0.05) + sps.norm.isf(0.2)) / h) ** 2
    res = S.power_two_proportions(p1, p2, alternative="one-sided")
    assert res.n_per_arm_unrounded == pytest.approx(closed, rel=1e-9)
    assert res.n_per_arm == math.ceil(closed) == 272


def test_power_accepts_a_rate_of_zero_or_one():
    # a random baseline that never succeeds (p = 0) is a rate the power question asks about;
    # one-sided, so the closed form is exact: h = 2 asin(sqrt(0.3)) - 0
    h = 2 * math.asin(math.sqrt(0.3))
    closed = 2 * ((sps.norm.isf(0.05) + sps.norm.isf(0.2)) / h) ** 2
    for p1, p2 in ((0.3, 0.0), (1.0, 0.7)):
        res = S.power_two_proportions(p1, p2, alternative="one-sided")
        assert res.n_per_arm_unrounded == pytest.approx(closed, rel=1e-9)


def test_power_paired_whole_number_is_not_rounded_up_a_pair():
    # z_{1-a/2} = 2 (alpha = 2 sf(2)), power 0.5 (z_b = 0), psi = 0.5, d = 0.5:
    # n = (2 sqrt(0.5))^2 / 0.25 = 8 by hand; the float path gives 8 + 9e-15
    res = S.power_two_proportions(0.75, 0.25, alpha=2 * sps.norm.sf(2.0), power=0.5, paired=True,
                                  discordant=0.5)
    assert res.n_per_arm_unrounded == pytest.approx(8.0, rel=1e-12)
    assert res.n_per_arm == 8
