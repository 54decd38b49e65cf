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


def _stack(traces):
    return (np.concatenate([t[0] for t in traces]), np.concatenate([t[1] for t in traces]),
            np.concatenate([t[2] for t in traces]),
            np.concatenate([[0], np.cumsum([t[0].size for t in traces])]),
            np.array([t[3] for t in traces]))


@pytest.fixture(scope="module")
def stacked():
    return _stack(_traces())


def test_trace_rmse_numba_matches_numpy_reference(stacked):
    depths, rates, forces, offsets, peaks = stacked
    depths = depths.copy()
    rates = rates.copy()
    depths[[0, 5]] = [0.0, -2e-6]  # open contacts carry no force
    rates[[1, 7]] = -0.5  # the max(0, .) clamp fires
    rng = np.random.default_rng(1)
    # the PSO's box: lambda1 in [0.05, 5] -> K, n in [0.1, 1], lambda2 in [0.05, 1.5] -> C
    k = rng.uniform(0.05, 1.8, 64)
    n = rng.uniform(0.1, 1.0, 64)
    c = rng.uniform(3e-3, 0.1, 64)
    got = bench.trace_rmse_pct(k, n, c, depths, rates, forces, offsets, peaks)
    want = bench.trace_rmse_pct(k, n, c, depths, rates, forces, offsets, peaks,
                                backend="numpy")
    assert got.shape == (64, peaks.size)
    np.testing.assert_allclose(got, want, rtol=1e-13)


def test_trace_rmse_libm_fallback_for_huge_exponents(stacked):
    # |n ln delta_mm| > 700: the exponent-field construction would overflow; libm's exp is used
    depths, rates, forces, offsets, peaks = stacked
    k, n, c = np.array([0.5, 0.5]), np.array([0.4, 400.0]), np.array([0.05, 0.05])
    got = bench.trace_rmse_pct(k, n, c, depths, rates, forces, offsets, peaks)
    want = bench.trace_rmse_pct(k, n, c, depths, rates, forces, offsets, peaks,
                                backend="numpy")
    np.testing.assert_allclose(got, want, rtol=1e-13)


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_trace_rmse_closed_forms(backend):
    # a trace that is exactly Eq. 13 has zero error; a constant offset e has RMSE |e|
    depths = np.linspace(0.05e-3, 1.5e-3, 50)
    rates = np.full(50, 2e-3)
    k, n, c = 0.4, 0.47, 0.06
    exact = k * (depths * 1e3) ** n + c * rates
    for offset, want in ((0.0, 0.0), (0.01, 0.01), (-0.02, 0.02)):
        got = bench.trace_rmse_pct([k], [n], [c], depths, rates, exact + offset, [0, 50],
                                   [2.0], backend=backend)
        assert got[0, 0] == pytest.approx(want / 2.0 * 100.0, abs=1e-12)


@pytest.mark.parametrize("offsets, message", [
    ([0, 5, 5, 10], "offsets must rise strictly from 0 to 10 (one non-empty trace each), got "
                    "[0, 5, 5, 10]"),
    ([1, 10], "offsets must rise strictly from 0 to 10 (one non-empty trace each), got [1, 10]"),
    ([0, 9], "offsets must rise strictly from 0 to 10 (one non-empty trace each), got [0, 9]"),
])
def test_trace_rmse_rejects_bad_offsets(offsets, message):
    x = np.full(10, 1e-3)
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        bench.trace_rmse_pct([1.0], [0.5], [0.0], x, x, x, offsets, [1.0] * (len(offsets) - 1))


def test_trace_rmse_rejects_unknown_backend():
    x = np.full(3, 1e-3)
    with pytest.raises(ValueError, match="^backend must be 'numba' or 'numpy', got 'cuda'$"):
        bench.trace_rmse_pct([1.0], [0.5], [0.0], x, x, x, [0, 3], [1.0], backend="cuda")
