"""Tests for analysis.rank_kernel (the compiled weighted Spearman rho of the pooled bootstrap).

Reference: ``scipy.stats.spearmanr`` on the explicitly repeated sample (the pair of a cluster
drawn c times occurs c times) for the kernel's rho. ``h_epsilon_correlation`` is held to the plain
form of its bootstraps: one resample at a time (it passes the kernel 64 at once) and scipy's
median bootstrap in one call (it runs it in batches), the same generator draws in the same order.
"""

import warnings

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from graspcampaign.analysis.quasi_static import h_epsilon_correlation, paper_law, weighted_spearman
from graspcampaign.analysis.rank_kernel import row_medians, sorted_pairs, tie_groups, weighted_rho


def _h_epsilon_reference(records, candidates, confidence=0.95, n_resamples=10_000, seed=0):
    """h_epsilon_correlation in its plain form: one resample's rho at a time, one median call."""
    rng, alpha = np.random.default_rng(seed), (1 - confidence) / 2
    rows = paper_law(records).query("planner == 'ferrari_canny'")
    out = []
    for reading, column in (("median per trial", "spearman_h_epsilon"),
                            ("median per trial, force closure", "spearman_h_epsilon_fc")):
        v = rows[column].dropna().to_numpy(float)
        if len(v) >= 2:
            ci = stats.bootstrap((v,), np.median, confidence_level=confidence, method="percentile",
                                 n_resamples=n_resamples, random_state=rng).confidence_interval
            out.append((reading, float(np.median(v)), ci.low, ci.high, len(v), np.nan))
    pooled = candidates[candidates["trial_id"].isin(rows["trial_id"])]
    trial = pooled["trial_id"].astype("category").cat.codes.to_numpy()
    if (k := len(np.unique(trial))) >= 2:
        x, y = (pooled[c].to_numpy(float) for c in ("h_total", "epsilon_fc"))
        draws = [weighted_spearman(x, y, np.bincount(rng.integers(0, k, k), minlength=k)[trial])
                 for _ in range(min(n_resamples, 2000))]
        low, high = np.nanquantile(draws, [alpha, 1 - alpha])
        out.append(("pooled", weighted_spearman(x, y, np.ones(len(trial))), low, high, k, len(trial)))
    return pd.DataFrame(out, columns=["reading", "rho", "low", "high", "n_trials", "n_pairs"])


def _kernel(x, y, cluster, counts):
    return weighted_rho(*sorted_pairs(x, y, np.ones(len(x)), cluster),
                        np.atleast_2d(counts).astype(float))


@settings(max_examples=80, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 4), st.integers(0, 6), st.integers(0, 4)), min_size=3,
                max_size=40),
       st.lists(st.lists(st.integers(0, 3), min_size=5, max_size=5), min_size=1, max_size=4))
def test_kernel_rho_is_spearman_of_the_repeated_sample(rows, counts):
    """Pairs (x, y) in five clusters; each row of ``counts`` says how often each cluster occurs."""
    x, y, cluster = (np.array(c) for c in zip(*rows, strict=True))
    x, y = x.astype(float), y.astype(float)
    counts = np.array(counts, dtype=float)
    got = _kernel(x, y, cluster, counts)
    assert got.shape == (len(counts),)
    for rho, c in zip(got, counts, strict=True):
        w = c[cluster]
        xs, ys = np.repeat(x, w.astype(int)), np.repeat(y, w.astype(int))
        if len(xs) < 2 or np.ptp(xs) == 0 or np.ptp(ys) == 0:
            assert np.isnan(rho)  # a constant (or empty) sample has no rank correlation
            continue
        assert rho == pytest.approx(stats.spearmanr(xs, ys).statistic, abs=1e-12)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-1e3, 1e3, allow_nan=False), min_size=0, max_size=30))
def test_tie_groups_order_the_values_and_share_a_group_exactly_when_equal(values):
    x = np.array(values, dtype=float)
    group, n = tie_groups(x)
    assert n == len(np.unique(x))
    # the dense rank of x: the index of each value among the sorted distinct values
    assert group.tolist() == np.searchsorted(np.unique(x), x).tolist()


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(-3, 3), min_size=1, max_size=9), st.integers(1, 4), st.integers(0, 99))
def test_row_medians_are_numpys_medians_of_the_resampled_values(values, n_rows, seed):
    """Each row resamples the values (ties among them) with replacement; even and odd lengths."""
    v = np.array(values, dtype=float) / 4
    group, _ = tie_groups(v)
    rows = np.random.default_rng(seed).integers(0, len(v), (n_rows, len(v)))
    medians = row_medians(group.astype(np.int32)[rows], np.unique(v))
    assert medians.tolist() == np.median(v[rows], axis=1).tolist()


def test_kernel_without_ties_at_scale_matches_scipy():
    rng = np.random.default_rng(4)
    x, y = rng.normal(size=5000), rng.normal(size=5000)
    y += 0.3 * x
    cluster = rng.integers(0, 50, 5000)
    counts = np.bincount(rng.integers(0, 50, 50), minlength=50)
    w = counts[cluster]
    expected = stats.spearmanr(np.repeat(x, w), np.repeat(y, w)).statistic
    assert _kernel(x, y, cluster, counts)[0] == pytest.approx(expected, abs=1e-12)


def _synthetic(n_trials=60, n_candidates=40, seed=2):
    """Ferrari-Canny trials with candidates; epsilon has ties (0 outside force closure, rounded)."""
    rng = np.random.default_rng(seed)
    rows, tables = [], []
    for t in range(n_trials):
        h = np.round(rng.uniform(0, 1, n_candidates), 2)
        eps = np.round(np.maximum(0.0, 0.5 - h + 0.2 * rng.normal(size=n_candidates)), 2)
        fc = eps > 0
        rows.append({"trial_id": f"fc{t}", "status": "ok", "planner": "ferrari_canny",
                     "grip_law": "paper", "spearman_h_epsilon": stats.spearmanr(h, eps).statistic,
                     "spearman_h_epsilon_fc": stats.spearmanr(h[fc], eps[fc]).statistic})
        tables.append(pd.DataFrame({"trial_id": f"fc{t}", "h_total": h, "epsilon_fc": eps}))
    rows.append({"trial_id": "r0", "status": "ok", "planner": "random", "grip_law": "paper",
                 "spearman_h_epsilon": np.nan, "spearman_h_epsilon_fc": np.nan})
    tables.append(pd.DataFrame({"trial_id": "r0", "h_total": [0.1, 0.2], "epsilon_fc": [0.3, 0.0]}))
    return pd.DataFrame(rows), pd.concat(tables, ignore_index=True)


def _many(n_trials: int, seed: int = 3):
    """Many two-candidate trials whose per-trial rho is drawn directly (only its median is
    bootstrapped), enough of them that scipy's median bootstrap runs in batches; the force-closure
    rho in tenths (ties) and missing in one trial (an odd count where n_trials is even)."""
    rng = np.random.default_rng(seed)
    ids = [f"fc{t}" for t in range(n_trials)]
    rho_fc = np.round(rng.uniform(-1, 1, n_trials), 1)
    rho_fc[0] = np.nan
    records = pd.DataFrame({"trial_id": ids, "status": "ok", "planner": "ferrari_canny",
                            "grip_law": "paper", "spearman_h_epsilon": rng.uniform(-1, 1, n_trials),
                            "spearman_h_epsilon_fc": rho_fc})
    candidates = pd.DataFrame({"trial_id": np.repeat(ids, 2),
                               "h_total": np.round(rng.uniform(0, 1, 2 * n_trials), 2),
                               "epsilon_fc": np.round(rng.uniform(0, 1, 2 * n_trials), 2)})
    return records, candidates


@pytest.mark.parametrize(("n_resamples", "n_trials"), [(300, 60), (2500, 60), (2500, 2000)])
def test_h_epsilon_correlation_is_its_plain_bootstrap(n_resamples, n_trials):
    """Same draws, same values: the interval ends to 1e-12 (2500 > the 2000-resample cap; at 2000
    trials scipy's median bootstrap runs in batches, the reference in one call)."""
    records, candidates = _synthetic(n_trials=n_trials) if n_trials < 100 else _many(n_trials)
    got = h_epsilon_correlation(records, candidates, n_resamples=n_resamples, seed=7)
    expected = _h_epsilon_reference(records, candidates, n_resamples=n_resamples, seed=7)
    assert got["reading"].tolist() == expected["reading"].tolist()
    assert got[["n_trials", "n_pairs"]].equals(expected[["n_trials", "n_pairs"]])
    np.testing.assert_allclose(got[["rho", "low", "high"]].to_numpy(float),
                               expected[["rho", "low", "high"]].to_numpy(float), rtol=0, atol=1e-12)


def test_kernel_weighs_each_row_of_counts_as_if_alone():
    """The rows of ``counts`` share the passes over the pairs, never a sum: each rho is the one
    its row gives alone, to the bit (real weights, an empty and a one-cluster row among them)."""
    rng = np.random.default_rng(5)
    x, y = np.round(rng.normal(size=3000), 1), np.round(rng.normal(size=3000), 1)
    pairs = sorted_pairs(x, y, rng.uniform(0.1, 3.0, 3000), rng.integers(0, 40, 3000))
    counts = rng.integers(0, 4, (70, 40)).astype(float)
    counts[3], counts[4] = 0.0, np.eye(40)[0]
    together = weighted_rho(*pairs, counts)
    alone = np.concatenate([weighted_rho(*pairs, row[None]) for row in counts])
    assert np.array_equal(together, alone, equal_nan=True)
    assert np.isnan(together[3]) and not np.isnan(np.delete(together, 3)).any()  # row 3 is empty


def test_nans_sort_last_each_in_a_group_of_its_own():
    """As the docstring says (np.argsort puts NaN last, in input order; nan != nan): [nan, 1, nan,
    1] has the 1s in group 0 and the NaNs, the first one first, in groups 1 and 2."""
    group, n = tie_groups(np.array([np.nan, 1.0, np.nan, 1.0]))
    assert (group.tolist(), n) == ([1, 0, 2, 0], 3)


def test_a_sample_constant_where_it_has_weight_has_no_rank_correlation():
    """x takes three values but only the pairs at x = 2 weigh anything (0.1 and 0.3, a tenth of
    the integer weights 1 and 3): the repeated sample (2, 1), 3 x (2, 2) has a constant x, so no
    rank correlation (nan, as spearmanr of it), not the ~1e-15 left by centring ranks of
    weightless groups."""
    x, y = np.array([1.0, 2.0, 2.0, 4.0]), np.array([3.0, 1.0, 2.0, 4.0])
    weights = np.array([0.0, 0.1, 0.3, 0.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert np.isnan(stats.spearmanr(np.repeat(x, [0, 1, 3, 0]), np.repeat(y, [0, 1, 3, 0])).statistic)
    for a, b in ((x, y), (y, x)):
        assert np.isnan(weighted_rho(*sorted_pairs(a, b, weights, np.zeros(4, dtype=np.int64)),
                                     np.ones((1, 1)))[0])
