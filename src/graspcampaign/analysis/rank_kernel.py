"""Compiled weighted Spearman rho (the rank correlation of a sample with integer or real weights)
and the medians of resampled tie groups: the H(G)-epsilon bootstraps at campaign scale.

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
def _centred_ranks(w, r):
    """Fill ``r[g, b]`` with the average rank of tie group ``g`` (in the order of the values) of
    weight ``w[g, b]`` in weighting ``b``, less the weighting's weighted mean rank (NaN if it
    weighs nothing); return per weighting the number of groups with positive weight."""
    n_b = w.shape[1]
    below, total_wr, occupied = np.zeros(n_b), np.zeros(n_b), np.zeros(n_b, dtype=np.int64)
    for g in range(w.shape[0]):
        for b in range(n_b):
            s = w[g, b]
            r[g, b] = below[b] + (s + 1.0) / 2.0  # positions below+1 .. below+s, averaged
            below[b] += s
            total_wr[b] += s * r[g, b]
            if s > 0.0:
                occupied[b] += 1
    mean = total_wr / below  # NaN (0 / 0) where the weighting weighs nothing
    for g in range(w.shape[0]):
        for b in range(n_b):
            r[g, b] -= mean[b]
    return occupied


@njit(cache=True)
def _sum_squares(w, d):
    out = np.zeros(w.shape[1])
    for g in range(w.shape[0]):
        for b in range(w.shape[1]):
            out[b] += w[g, b] * d[g, b] * d[g, b]
    return out


@njit(cache=True)
def weighted_rho(group_x, n_x, group_y, n_y, weight, cluster, counts):
    """Return Spearman's rho for each row of ``counts`` (NaN where x or y is constant).

    Each pass over the pairs carries every weighting (side by side in memory, so the loop over
    them runs in vector lanes) and each tie group's rank is centred once, not once per pair;
    each weighting's sums still add the pairs in their order.

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
    n_b = counts.shape[0]
    c = np.ascontiguousarray(counts.T)  # c[k]: cluster k's count in every weighting
    wx, dx = np.zeros((n_x, n_b)), np.empty((n_x, n_b))
    wy, dy = np.zeros((n_y, n_b)), np.empty((n_y, n_b))
    for i in range(group_x.size):  # each tie group's weight
        ci, wxi, wyi = c[cluster[i]], wx[group_x[i]], wy[group_y[i]]
        for b in range(n_b):
            wi = weight[i] * ci[b]
            wxi[b] += wi
            wyi[b] += wi
    occupied_x, occupied_y = _centred_ranks(wx, dx), _centred_ranks(wy, dy)
    sxy = np.zeros(n_b)
    for i in range(group_x.size):
        ci, dxi, dyi = c[cluster[i]], dx[group_x[i]], dy[group_y[i]]
        for b in range(n_b):
            sxy[b] += weight[i] * ci[b] * dxi[b] * dyi[b]
    out = sxy / np.sqrt(_sum_squares(wx, dx) * _sum_squares(wy, dy))
    for b in range(n_b):
        if occupied_x[b] < 2 or occupied_y[b] < 2:  # a constant sample: no rank correlation
            out[b] = np.nan
    return out


@njit(cache=True)
def row_medians(groups, distinct):
    """Return ``np.median`` of each row of ``distinct[groups]`` (``groups``: int32 (B, n), a
    resample of tie groups per row; ``distinct``: the sorted distinct values): one pass over a
    row tallies its groups, one over the tallies finds the order statistics ``(n - 1) // 2`` and
    ``n // 2`` (one for odd n), whose mean is the median."""
    n_rows, n = groups.shape
    out, tally = np.empty(n_rows), np.empty(distinct.size, dtype=np.int64)
    for row in range(n_rows):
        tally[:] = 0
        for i in range(n):
            tally[groups[row, i]] += 1
        low, seen = -1, 0
        for g in range(distinct.size):
            seen += tally[g]
            if low < 0 and seen > (n - 1) // 2:
                low = g
            if seen > n // 2:
                out[row] = (distinct[low] + distinct[g]) / 2
                break
    return out
