"""Solvers of the Test 1 per-event fits: the compiled Levenberg-Marquardt of
:mod:`graspcampaign.core.fit_kernel` (default) or ``scipy.optimize.least_squares`` (the
reference, and the fallback of the compiled path).

References
----------
Moré, J. J. (1978). The Levenberg-Marquardt algorithm: implementation and theory. *Numerical
Analysis*, Lecture Notes in Mathematics 630, 105-116.
"""

from __future__ import annotations

import logging

import numpy as np
from scipy.optimize import least_squares

from graspcampaign.core import fit_kernel

__all__ = [
    "FIT_BACKENDS",
    "TYPICAL_NORMAL",
    "TYPICAL_RELAXATION",
    "TYPICAL_SHIFTED",
    "UNBOUNDED",
    "check_fit_backend",
    "solve_least_squares",
]

log = logging.getLogger(__name__)


FIT_BACKENDS = ("numba", "scipy")
"""Solvers of the per-event fits: the compiled Levenberg-Marquardt run to a stationary point
(:func:`graspcampaign.core.fit_kernel.lm_fit`, default) or ``scipy.optimize.least_squares``
with its default tolerances (the reference, and the fallback of the compiled path)."""


UNBOUNDED = np.full(3, -np.inf), np.full(3, np.inf)
# typical magnitudes of the parameters (the absolute part of the compiled solver's step test):
# (K [N mm^-n], n, C [N s/m]) as the reference's x_scale; (K, m, x0 [mm]); (A [N], B [N], tau [s])
TYPICAL_NORMAL = np.array([0.1, 0.1, 0.05])
TYPICAL_SHIFTED = np.array([0.1, 0.1, 0.01])
TYPICAL_RELAXATION = np.array([1e-3, 1e-3, 1e-2])


def solve_least_squares(resid, jac, x0: np.ndarray, model: int, data: tuple[np.ndarray, ...],
                        bounds: tuple[np.ndarray, np.ndarray], typical: np.ndarray, backend: str,
                        check=None, **scipy_options) -> tuple[np.ndarray, np.ndarray, bool]:
    """Minimise ``|resid(p)|^2`` from ``x0``; return the solution, its residuals, success.

    ``backend="numba"`` runs :func:`graspcampaign.core.fit_kernel.lm_fit` on the model
    ``model`` with ``data = (a, b, y)`` (contiguous float arrays); when it does not reach a
    stationary point strictly inside ``bounds`` ((3,) float arrays, +-inf where free), or
    ``check(p)`` is False (a condition under which the compiled model is not the reference
    residual), the fit falls back to ``backend="scipy"``:
    ``scipy.optimize.least_squares(resid, x0, jac=jac, bounds=bounds, **scipy_options)``.
    """
    if backend == "numba":
        p, _, status, _ = fit_kernel.lm_fit(model, x0, *data, *bounds, typical)
        if (status == fit_kernel.LM_CONVERGED and np.all(np.isfinite(p))
                and (check is None or check(p))):
            return p, resid(p), True
        log.debug("compiled fit (model %d) ended with status %d; using scipy", model, status)
    if bounds is UNBOUNDED:
        sol = least_squares(resid, x0, jac=jac, **scipy_options)
    else:
        sol = least_squares(resid, x0, jac=jac, bounds=bounds, **scipy_options)
    return sol.x, sol.fun, bool(sol.success)


def check_fit_backend(backend: str) -> None:
    """Refuse a fit backend not in ``FIT_BACKENDS``."""
    if backend not in FIT_BACKENDS:
        raise ValueError(f"backend must be 'numba' or 'scipy', got {backend!r}")
