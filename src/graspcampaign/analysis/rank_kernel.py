"""Compiled weighted Spearman rho: the rank correlation of a sample with integer or real weights.

Spearman's rho of the sample in which the pair (x_i, y_i) occurs ``w_i`` times is Pearson's r of
the average ranks of that repeated sample (ties share the mean of their positions). The ranks are
a function of the tie groups of x and of y alone, so :func:`tie_groups` sorts each variable once
and every weighting -- a cluster-bootstrap resample weights each pair by the number of times its
trial was drawn -- costs two linear passes over the pairs and a few over the tie groups, with no
array of the pairs' size allocated per weighting.

References
----------
Spearman, C. (1904). The proof and measurement of association between two things. Am. J.
Psychol. 15, 72-101 (rho as the correlation of ranks; average ranks for ties: Kendall & Gibbons
(1990), Rank Correlation Methods, 5th ed., ch. 3).
Efron, B. & Tibshirani, R. J. (1993). An Introduction to the Bootstrap, ch. 16 (resampling
clusters: a resample is a vector of counts over the clusters).
"""

from __future__ import annotations

import numpy as np
from numba import njit


def tie_groups(x: np.ndarray) -> tuple[np.ndarray, int]:
    """Return each value's tie group (0 for the smallest value, ties share one) and the count.

    Parameters
    ----------
    x : ndarray, shape (n,)
        The values; NaNs sort last, each its own group (as ``np.argsort`` orders them).

    Returns
    -------
    group : ndarray of int64, shape (n,)
        ``group[i] < group[j]`` iff ``x[i] < x[j]``; equal values share a group.
    n_groups : int
    """
    group = np.zeros(len(x), dtype=np.int64)
    if not len(x):
        return group, 0
    order = np.argsort(x, kind="stable")
    group[order] = np.r_[0, np.cumsum(np.diff(x[order]) != 0)]
    return group, int(group[order[-1]]) + 1


def sorted_pairs(x: np.ndarray, y: np.ndarray, weight: np.ndarray, cluster: np.ndarray) -> tuple:
    """Return the arguments of :func:`weighted_rho` but ``counts``, the pairs in the order of x.

    rho does not depend on the pairs' order; in x's order the kernel's pass over x's tie groups
    reads memory in sequence (only y's groups are visited out of order).

    Parameters
    ----------
    x, y : ndarray, shape (n,)
        The paired values.
    weight : ndarray, shape (n,)
        A weight per pair (ones for a cluster bootstrap).
    cluster : ndarray of int, shape (n,)
        Each pair's cluster (``0 .. k - 1``).
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    order = np.argsort(x, kind="stable")
    return (*tie_groups(x[order]), *tie_groups(y[order]),
            np.asarray(weight, dtype=float)[order], np.asarray(cluster, dtype=np.int64)[order])


@njit(cache=True)
def _average_ranks(w, r):
    """Fill ``r`` with the average rank of each tie group of weight ``w`` (in the order of the
    values); return the weighted mean rank and the number of groups with positive weight."""
    below, total_wr, occupied = 0.0, 0.0, 0
    for g in range(w.size):
        s = w[g]
        r[g] = below + (s + 1.0) / 2.0  # positions below+1 .. below+s, averaged
        below += s
        total_wr += s * r[g]
        if s > 0.0:
            occupied += 1
    return (total_wr / below if below > 0.0 else np.nan), occupied


@njit(cache=True)
def _sum_squares(w, r, mean):
    out = 0.0
    for g in range(w.size):
        d = r[g] - mean
        out += w[g] * d * d
    return out


@njit(cache=True)
def weighted_rho(group_x, n_x, group_y, n_y, weight, cluster, counts):
    """Return Spearman's rho for each row of ``counts`` (NaN where x or y is constant).

    Parameters
    ----------
    group_x, group_y : ndarray of int64, shape (n,)
        The pairs' tie groups (:func:`tie_groups`); ``n_x``, ``n_y`` their counts.
    weight : ndarray of float64, shape (n,)
        A weight per pair, multiplied by its cluster's count.
    cluster : ndarray of int64, shape (n,)
        Each pair's cluster, in ``0 .. k - 1``.
    counts : ndarray of float64, shape (B, k)
        Each weighting's count per cluster (a bootstrap resample: how often each was drawn).

    Returns
    -------
    rho : ndarray of float64, shape (B,)
    """
    wx, rx = np.empty(n_x), np.empty(n_x)
    wy, ry = np.empty(n_y), np.empty(n_y)
    out = np.empty(counts.shape[0])
    for b in range(counts.shape[0]):
        c = counts[b]
        wx[:] = 0.0
        wy[:] = 0.0
        for i in range(group_x.size):  # each tie group's weight
            wi = weight[i] * c[cluster[i]]
            wx[group_x[i]] += wi
            wy[group_y[i]] += wi
        mx, occupied_x = _average_ranks(wx, rx)
        my, occupied_y = _average_ranks(wy, ry)
        if occupied_x < 2 or occupied_y < 2:  # a constant sample: no rank correlation
            out[b] = np.nan
            continue
        sxy = 0.0
        for i in range(group_x.size):
            sxy += weight[i] * c[cluster[i]] * (rx[group_x[i]] - mx) * (ry[group_y[i]] - my)
        out[b] = sxy / np.sqrt(_sum_squares(wx, rx, mx) * _sum_squares(wy, ry, my))
    return out
