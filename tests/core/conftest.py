"""Fixtures shared by the core tests."""

from __future__ import annotations

import math

import numpy as np
import pytest

from graspcampaign.core import dynamics, grasp_phases, msd
from graspcampaign.core.contact import ContactParams
from graspcampaign.core.mesh import make_object

# The firm preset of conf/model/firm.yaml (docs/decisions.md): Shore 30A fingertip, Shore 50A
# object (Gent 1958), Hertz contact (lambda1 = 2/3, n = 3/2).
FIRM = ContactParams(lambda1=2.0 / 3.0, lambda2=0.88, n=1.5, e_finger=1.1424e6,
                     e_object=2.4558e6, nu_finger=0.5, nu_object=0.5)


@pytest.fixture(scope="session")
def firm_setup():
    """A small firm-preset grasp that holds (144 nodes, 0.2 kg, mu = 0.3, default phases), not
    yet run: ``(setup, initial_state)`` (for tests that need no numpy reference run: that run
    takes about 5 s)."""
    mesh = make_object("sphere", 144)
    params = msd.msd_params_from_modulus(mesh, youngs_modulus=FIRM.e_object, mass=0.2)
    return dynamics.prepare_grasp(mesh, 0.3, params, FIRM)


@pytest.fixture(scope="session")
def firm_grasp(firm_setup):
    """:func:`firm_setup` run once per session on the numpy reference step:
    ``(setup, initial_state, result)``."""
    setup, state = firm_setup
    return setup, state, grasp_phases.run_grasp_phases(setup, state)


def _numpy_rounds_as_libm() -> bool:
    """Whether numpy's float64 ``power`` and ``exp`` give the C library's results on this machine.

    The numba kernels call the C library (libm). numpy 2.x on an AVX-512 CPU uses its own SIMD
    routines instead, about 1 ulp apart from libm on ~5 % of arguments (seen on an AMD EPYC with
    numpy 2.4.6), so a compiled kernel can equal its numpy reference bit for bit only where numpy
    rounds as libm does.
    """
    x = np.random.default_rng(0).uniform(1e-6, 2.0, 4096)
    return bool(np.array_equal(np.power(x, 1.37), [math.pow(v, 1.37) for v in x])
                and np.array_equal(np.exp(-x), [math.exp(-v) for v in x]))


NUMPY_IS_LIBM = _numpy_rounds_as_libm()


@pytest.fixture(scope="session")
def same_floats():
    """``check(got, want, rtol=1e-12)``: a compiled kernel's floats against its numpy reference,
    bit for bit where numpy rounds as libm does (:data:`NUMPY_IS_LIBM`), else to ``rtol`` (the
    elementary functions' ulp differences grown through the kernel's arithmetic), the non-finite
    entries matching exactly. It returns whether the comparison was exact, so a test of a
    rounding-sensitive quantity (the last iteration that changed a value) checks it only then."""
    def check(got, want, rtol: float = 1e-12) -> bool:
        got, want = np.asarray(got), np.asarray(want)
        if NUMPY_IS_LIBM:
            assert np.array_equal(got, want, equal_nan=True)
        else:
            np.testing.assert_array_equal(np.isfinite(got), np.isfinite(want))
            np.testing.assert_allclose(got, want, rtol=rtol, atol=0.0, equal_nan=True)
        return NUMPY_IS_LIBM
    return check
