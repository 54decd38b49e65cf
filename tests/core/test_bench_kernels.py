"""Tests of graspcampaign.core.bench_kernels: the compiled kernels against their references.

References: ``numpy.exp`` for the vectorised exp; the numpy path of
:func:`graspcampaign.core.bench.trace_rmse_pct` (``contact.normal_force`` on the whole grid and a
matrix product) for the fused RMSE kernel, on virtual-bench traces; closed forms (an exact
Eq. 13 trace has zero error, a constant force offset ``e`` has RMSE ``|e|``).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from graspcampaign.core import bench, bench_kernels
from graspcampaign.core.bench import FAMILIES, EventCommand


def test_exp_kernel_is_within_one_ulp_of_numpy():
    x = np.concatenate([np.linspace(-700.0, 700.0, 400_001),
                        np.arange(-60, 61) * math.log(2.0),  # reduction boundaries
                        (np.arange(-60, 60) + 0.5) * math.log(2.0),
                        [0.0, -0.0, 1e-300, -1e-300, 5e-324]])
    got = bench_kernels.exp_kernel(x)
    want = np.exp(x)
    ulps = np.abs(got - want) / np.spacing(want)
    assert ulps.max() <= 1.0, f"{ulps.max()} ulp at x = {x[np.argmax(ulps)]}"


def _traces(n_traces=6, seed=0):
    """Loading windows of virtual-bench normal presses (depth, rate, force, peak)."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n_traces):
        fam = list(FAMILIES.values())[i % 4]
        spec = bench.draw_specimen(fam, 1, "normal_lab", rng)
        cmd = EventCommand("normal", depth=rng.uniform(0.25e-3, 1.75e-3),
                           speed=rng.choice([0.5e-3, 2e-3, 10e-3]), daq_hz=500.0)
        w = bench.simulate_event(cmd, spec, rng)
        win = bench.loading_window(w.displacement, w.normal_force)
        rate = np.gradient(w.displacement, w.time)
        out.append((w.displacement[win], rate[win], w.normal_force[win],
                    float(w.normal_force.max())))
    return out


@pytest.fixture(scope="module")
def points():
    return bench.TraceSet.from_traces(_traces())


def test_trace_rmse_numba_matches_numpy_reference(points):
    depths, rates = points.depths.copy(), points.rates.copy()
    depths[[0, 5]] = [0.0, -2e-6]  # open contacts carry no force
    rates[[1, 7]] = -0.5  # the max(0, .) clamp fires
    edited = bench.TraceSet(depths, rates, points.forces, points.offsets, points.peaks)
    rng = np.random.default_rng(1)
    # the PSO's box: lambda1 in [0.05, 5] -> K, n in [0.1, 1], lambda2 in [0.05, 1.5] -> C
    k = rng.uniform(0.05, 1.8, 64)
    n = rng.uniform(0.1, 1.0, 64)
    c = rng.uniform(3e-3, 0.1, 64)
    got = edited.rmse_pct(k, n, c)
    want = edited.rmse_pct(k, n, c, backend="numpy")
    assert got.shape == (64, points.peaks.size)
    np.testing.assert_allclose(got, want, rtol=1e-13)


def test_trace_rmse_libm_fallback_for_huge_exponents(points):
    # |n ln delta_mm| > 700: the exponent-field construction would overflow; libm's exp is used
    k, n, c = np.array([0.5, 0.5]), np.array([0.4, 400.0]), np.array([0.05, 0.05])
    np.testing.assert_allclose(points.rmse_pct(k, n, c),
                               points.rmse_pct(k, n, c, backend="numpy"), rtol=1e-13)


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_trace_rmse_closed_forms(backend):
    # a trace that is exactly Eq. 13 has zero error; a constant offset e has RMSE |e|
    depths = np.linspace(0.05e-3, 1.5e-3, 50)
    rates = np.full(50, 2e-3)
    k, n, c = 0.4, 0.47, 0.06
    exact = k * (depths * 1e3) ** n + c * rates
    for offset, want in ((0.0, 0.0), (0.01, 0.01), (-0.02, 0.02)):
        got = bench.TraceSet(depths, rates, exact + offset, [0, 50], [2.0]).rmse_pct(
            [k], [n], [c], backend=backend)
        assert got[0, 0] == pytest.approx(want / 2.0 * 100.0, abs=1e-12)


@pytest.mark.parametrize("offsets, n_peaks", [([0, 5, 5, 10], 3), ([1, 10], 1), ([0, 9], 1),
                                              ([0, 5, 10], 1)])
def test_trace_set_rejects_bad_offsets(offsets, n_peaks):
    x = np.full(10, 1e-3)
    message = (f"offsets must rise strictly from 0 to 10 (one non-empty trace per peak), got "
               f"{offsets}")
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        bench.TraceSet(x, x, x, offsets, [1.0] * n_peaks)


def test_trace_set_rejects_unequal_channels():
    x = np.full(10, 1e-3)
    with pytest.raises(ValueError, match="^depths, rates and forces must have one value per "
                                         "point, got 10, 9 and 10$"):
        bench.TraceSet(x, x[:9], x, [0, 10], [1.0])


def test_trace_rmse_rejects_unknown_backend():
    x = np.full(3, 1e-3)
    with pytest.raises(ValueError, match="^backend must be 'numba' or 'numpy', got 'cuda'$"):
        bench.TraceSet(x, x, x, [0, 3], [1.0]).rmse_pct([1.0], [0.5], [0.0], backend="cuda")


# ------------------------------------------------------------------------ virtual bench


def _axis_by_trapezoid_move(times, start, moves):
    """An axis from bench.trapezoid_move move after move: each move takes over t >= t0."""
    pos, vel = np.full_like(times, start), np.zeros_like(times)
    current = start
    for t0, target, v, a in moves:
        p, dv, dur = bench.trapezoid_move(times - t0, target - current, v, a)
        after = times >= t0
        pos = np.where(after, current + p, pos)
        vel = np.where(after & (times <= t0 + dur), dv, vel)
        current = target
    return pos, vel


@pytest.mark.parametrize("seed", range(6))
def test_axis_profile_is_trapezoid_move_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    times = np.arange(0.0, rng.uniform(1.0, 20.0), 1.0 / rng.choice([50.0, 250.0, 500.0]))
    moves, t0, pos = [], 0.0, -1e-4
    for _ in range(int(rng.integers(1, 4))):
        target = pos + rng.choice([-1.0, 1.0, 0.0]) * rng.uniform(1e-5, 3e-3)
        moves.append((t0, target, rng.uniform(5e-4, 5e-2), rng.uniform(0.05, 0.3)))
        t0 += rng.uniform(0.0, 5.0)
        pos = target
    got = bench_kernels.axis_profile(times, -1e-4, np.array(moves))
    want = _axis_by_trapezoid_move(times, -1e-4, moves)
    np.testing.assert_array_equal(got[0], want[0])
    np.testing.assert_array_equal(got[1], want[1])


def test_first_order_filter_is_lfilter_bit_for_bit():
    from scipy.signal import lfilter

    x = np.diff(np.random.default_rng(2).uniform(0.0, 1.0, 5000), prepend=0.0)
    b0, decay = 0.3 * math.exp(-0.01), math.exp(-0.02)
    np.testing.assert_array_equal(bench_kernels.first_order_filter(x, b0, decay),
                                  lfilter([b0], [1.0, -decay], x))


@pytest.mark.parametrize("times", [
    np.round(np.arange(0.0, 4.0, 1 / 50.0), 9),  # the rig's time column: not exactly uniform
    np.arange(8) * 0.25,  # exactly uniform: numpy's scalar-spacing formula
    np.array([0.0, 0.1]),  # two samples: one-sided differences only
    np.cumsum(np.random.default_rng(3).uniform(0.001, 0.01, 300)),
])
def test_gradient_is_numpy_gradient_bit_for_bit(times):
    values = np.sin(7.0 * times) + np.random.default_rng(1).normal(0.0, 1e-3, times.size)
    np.testing.assert_array_equal(bench_kernels.gradient(values, times), np.gradient(values, times))


def test_gradient_rejects_a_single_sample():
    with pytest.raises(ValueError, match="^gradient needs at least 2 samples and one time per "
                                         "sample$"):
        bench_kernels.gradient(np.ones(1), np.ones(1))


def test_noisy_quantised_is_numpy_round_bit_for_bit():
    rng = np.random.default_rng(8)
    values, noise = rng.uniform(-0.5, 2.0, 10_000), rng.standard_normal(10_000)
    values[:4], noise[:4] = [0.5e-3, 1.5e-3, -2.5e-3, 0.0], 0.0  # halfway: round to even
    np.testing.assert_array_equal(bench_kernels.noisy_quantised(values, noise, 1.5e-3, 1e-3),
                                  np.round((values + 1.5e-3 * noise) / 1e-3) * 1e-3)
