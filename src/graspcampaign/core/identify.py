"""Parameter identification: the parameter vector and bounds, and the composite cost J of §11
minimised by the global-best PSO of :mod:`graspcampaign.core.pso`.

Shape letters: ``p`` particles, ``d`` parameters.

References
----------
§4, §6.8 and §11 of the paper (parameter vector, bounds, budgets, cost J).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from graspcampaign.core.contact import (
    NOMINAL_CONTACT,
    ContactParams,
    contact_stiffness_k,
)
from graspcampaign.core.equilibrium import EquilibriumResult, EvaluatorParams, evaluate_grasps
from graspcampaign.core.pso import PsoResult, pso_minimize

__all__ = [
    "F0_N",
    "DELTA0_MM",
    "PAPER_BOUNDS",
    "PARAMETER_COLUMNS",
    "PARAMETER_NAMES",
    "FLAT_PARAMETERS",
    "IdentificationResult",
    "IdentificationTerms",
    "at_bound",
    "identification_cost",
    "identification_terms",
    "identify_body",
    "paper_bounds",
]

logger = logging.getLogger(__name__)

PARAMETER_NAMES = ("lambda1", "lambda2", "n", "b", "k", "c")
"""Order of the identified parameter vector (§4)."""

PARAMETER_COLUMNS = ("lambda1", "lambda2", "n_exp", "b", "k", "c")
"""The record column of each parameter of :data:`PARAMETER_NAMES` (docs/records.md: n is ``n_exp``)."""

PAPER_BOUNDS = {
    "lambda1": (0.05, 1.5),
    "lambda2": (0.05, 1.5),
    "n": (0.1, 1.0),
    "b": (0.1, 2.0),
    "k": (0.05, 0.5),
    "c": (5.0e-4, 0.02),
}
"""Search bounds of §11 (b, k, c in the simulator's internal units, Table 3 caption)."""

FLAT_PARAMETERS = ("lambda2", "b", "k", "c")
"""Parameters the quasi-static cost does not depend on (see :func:`identification_cost`)."""

F0_N = 1.0
"""Force scale of J [N] (§11)."""

DELTA0_MM = 1.0
"""Penetration scale of J [mm] (§4, §11: the 1 mm design limit)."""


def paper_bounds() -> tuple[np.ndarray, np.ndarray]:
    """Return fresh ``(lower, upper)`` arrays, shape (6,), in :data:`PARAMETER_NAMES` order."""
    lower = np.array([PAPER_BOUNDS[name][0] for name in PARAMETER_NAMES])
    upper = np.array([PAPER_BOUNDS[name][1] for name in PARAMETER_NAMES])
    return lower, upper


def at_bound(x, lower, upper, names=PARAMETER_NAMES, rtol: float = 1e-9) -> tuple[str, ...]:
    """Return the names of the parameters of ``x`` (d,) within ``rtol`` box widths of a bound.

    PSO clamps positions onto the bounds, so a saturated parameter sits on its bound exactly; an
    identified value there is a limit of the search, not an estimate (issue 13).
    """
    x, lower, upper = (np.asarray(v, dtype=float) for v in (x, lower, upper))
    tol = rtol * (upper - lower)
    hit = (np.abs(x - lower) <= tol) | (np.abs(upper - x) <= tol)
    return tuple(name for name, h in zip(names, hit, strict=True) if h)


@dataclass(frozen=True)
class IdentificationTerms:
    """The three dimensionless terms of J and their sum, shape (p,) each.

    Attributes
    ----------
    force : (p,) float
        ``|F_z| / F0`` with F_z the normal-only vertical residual of Algorithm 2 [-].
    depth : (p,) float
        ``(delta_max / delta0 - 1)_+`` [-].
    slip : (p,) float
        ``10 (-sigma_slip / F0)_+`` with sigma_slip the evaluator's slip margin [-].
    total : (p,) float
        J.
    equilibrium : EquilibriumResult
        The batched evaluation behind the terms.
    """

    force: np.ndarray
    depth: np.ndarray
    slip: np.ndarray
    total: np.ndarray
    equilibrium: EquilibriumResult


def _check_parameters(parameters) -> np.ndarray:
    parameters = np.asarray(parameters, dtype=float)
    if parameters.ndim == 1:
        parameters = parameters[None]
    if parameters.ndim != 2 or parameters.shape[1] != len(PARAMETER_NAMES):
        raise ValueError(
            f"parameters must have shape (p, {len(PARAMETER_NAMES)}) in order {PARAMETER_NAMES}, "
            f"got {parameters.shape}"
        )
    return parameters


def identification_terms(
    parameters,
    points,
    normals,
    centroid,
    mass: float,
    mu: float,
    *,
    material: ContactParams = NOMINAL_CONTACT,
    evaluator: EvaluatorParams | None = None,
) -> IdentificationTerms:
    """Evaluate the three terms of J for a swarm of parameter vectors on one contact set.

    Parameters
    ----------
    parameters : (p, 6) float
        ``(lambda1, lambda2, n, b, k, c)`` per particle.
    points : (3, 3) float
        The body's fixed contact set in W [m].
    normals : (3, 3) float
        Outward unit normals there.
    centroid : (3,) float
        Object centroid [m].
    mass : float
        Object mass [kg].
    mu : float
        Friction coefficient [-].
    material : ContactParams
        Source of the fingertip radius, moduli and Poisson ratios (its lambda1, lambda2, n are
        ignored).
    evaluator : EvaluatorParams, optional
        Algorithm 2 settings.

    Returns
    -------
    terms : IdentificationTerms

    Notes
    -----
    The whole swarm is one batch of the evaluator: particle i becomes candidate i with its own
    ``K = 2 lambda1 Psi sqrt(R)`` and ``n`` (Eq. 14). In the quasi-static evaluator the rate term
    ``C delta_dot`` vanishes (Algorithm 2 line 3) and the body is rigid, so lambda2 and the MSD
    constants b, k, c do not enter J at all: the cost is flat along them and PSO returns
    wherever the swarm happened to stop (:data:`FLAT_PARAMETERS`). They are kept in the vector
    so the search space and budget are the paper's, not given an invented influence.

    References
    ----------
    §4, §11 (J, F0 = 1 N, delta0 = 1 mm); Algorithms 1-2.
    """
    parameters = _check_parameters(parameters)
    points = np.asarray(points, dtype=float).reshape(3, 3)
    normals = np.asarray(normals, dtype=float).reshape(3, 3)
    n_particles = parameters.shape[0]
    k = contact_stiffness_k(parameters[:, 0], material.psi, material.fingertip_radius)
    result = evaluate_grasps(
        np.broadcast_to(points, (n_particles, 3, 3)),
        np.broadcast_to(normals, (n_particles, 3, 3)),
        centroid,
        mass,
        mu,
        k,
        parameters[:, 2],
        evaluator,
    )
    force = np.abs(result.residual_z) / F0_N
    depth = np.maximum(result.delta_max_mm / DELTA0_MM - 1.0, 0.0)
    slip = 10.0 * np.maximum(-result.slip_margin / F0_N, 0.0)
    return IdentificationTerms(force, depth, slip, force + depth + slip, result)


def identification_cost(
    parameters,
    points,
    normals,
    centroid,
    mass: float,
    mu: float,
    *,
    material: ContactParams = NOMINAL_CONTACT,
    evaluator: EvaluatorParams | None = None,
) -> np.ndarray:
    """Return ``J = |F_z|/F0 + (delta_max/delta0 - 1)_+ + 10 (-sigma_slip/F0)_+``, shape (p,).

    See :func:`identification_terms` for the parameters and for which parameters enter.

    References
    ----------
    §11.
    """
    return identification_terms(
        parameters, points, normals, centroid, mass, mu, material=material, evaluator=evaluator
    ).total


@dataclass(frozen=True)
class IdentificationResult:
    """One soft body's identification (object x mass x friction).

    Attributes
    ----------
    contact : ContactParams
        Identified lambda1, lambda2, n on the material template.
    msd_b, msd_k, msd_c : float
        Identified MSD constants (internal units; flat in the quasi-static cost).
    best_x : (6,) float
        Best parameter vector in :data:`PARAMETER_NAMES` order.
    best_cost : float
        J at best_x.
    j_force, j_depth, j_slip : float
        The terms of J at best_x.
    equilibrium : EquilibriumResult
        Evaluator outcome at best_x (batch of one).
    pso : PsoResult
        The search itself (convergence history for Fig. 9 / Fig. 21).
    flat_parameters : tuple of str
        Parameters J does not depend on.
    at_bound : tuple of str
        Parameters whose identified value sits on a search bound (:func:`at_bound`).
    """

    contact: ContactParams
    msd_b: float
    msd_k: float
    msd_c: float
    best_x: np.ndarray
    best_cost: float
    j_force: float
    j_depth: float
    j_slip: float
    equilibrium: EquilibriumResult
    pso: PsoResult
    flat_parameters: tuple[str, ...] = FLAT_PARAMETERS
    at_bound: tuple[str, ...] = ()

    def to_record(self) -> dict[str, float | int | str | bool]:
        """Return the identification as flat, unit-suffixed scalars for a record."""
        return {
            "lambda1": float(self.contact.lambda1),
            "lambda2": float(self.contact.lambda2),
            "n_exponent": float(self.contact.n),
            "msd_b": self.msd_b,
            "msd_k": self.msd_k,
            "msd_c": self.msd_c,
            "k_contact_n_per_mm_n": self.contact.k_n_per_mm_n,
            "c_contact_n_s_per_m": self.contact.c_n_s_per_m,
            "pso_best_cost": self.best_cost,
            "j_force": self.j_force,
            "j_depth": self.j_depth,
            "j_slip": self.j_slip,
            "delta_max_mm": float(self.equilibrium.delta_max_mm[0]),
            "residual_z_n": float(self.equilibrium.residual_z[0]),
            "slip_margin_n": float(self.equilibrium.slip_margin[0]),
            "pso_n_evaluations": int(self.pso.n_evaluations),
            "flat_parameters": ",".join(self.flat_parameters),
            "at_bound": ",".join(self.at_bound),
            **{f"at_bound_{name}": name in self.at_bound for name in PARAMETER_NAMES},
        }


def identify_body(
    points,
    normals,
    centroid,
    mass: float,
    mu: float,
    rng: np.random.Generator,
    *,
    material: ContactParams = NOMINAL_CONTACT,
    evaluator: EvaluatorParams | None = None,
    n_particles: int = 50,
    n_iterations: int = 1000,
    bounds: tuple[np.ndarray, np.ndarray] | None = None,
) -> IdentificationResult:
    """Identify ``(lambda1, lambda2, n, b, k, c)`` for one soft body with PSO on J.

    Parameters
    ----------
    points : (3, 3) float
        The body's identification contact set in W [m] (the campaign passes the heuristic
        argmin triple of the body, :func:`graspcampaign.core.planner.identification_contacts`).
    normals : (3, 3) float
        Outward unit normals there.
    centroid : (3,) float
        Object centroid [m].
    mass : float
        Object mass [kg].
    mu : float
        Friction coefficient [-].
    rng : numpy.random.Generator
        Seeds the swarm.
    material : ContactParams
        Fingertip radius, moduli and Poisson ratios (Table 2 by default).
    evaluator : EvaluatorParams, optional
        Algorithm 2 settings.
    n_particles, n_iterations : int
        Budget: the default 50 x 1000 = 5e4 evaluations is the converged budget of §11; the
        repeatability study uses 8 x 15 (§6.8).
    bounds : (lower, upper), optional
        Defaults to :func:`paper_bounds`.

    Returns
    -------
    result : IdentificationResult
    """
    lower, upper = paper_bounds() if bounds is None else bounds

    def cost(positions: np.ndarray) -> np.ndarray:
        return identification_cost(
            positions, points, normals, centroid, mass, mu, material=material, evaluator=evaluator
        )

    search = pso_minimize(cost, lower, upper, n_particles=n_particles, n_iterations=n_iterations, rng=rng)
    best = search.best_x
    terms = identification_terms(
        best, points, normals, centroid, mass, mu, material=material, evaluator=evaluator
    )
    contact = replace(material, lambda1=float(best[0]), lambda2=float(best[1]), n=float(best[2]))
    return IdentificationResult(
        contact=contact,
        msd_b=float(best[3]),
        msd_k=float(best[4]),
        msd_c=float(best[5]),
        best_x=best,
        best_cost=float(terms.total[0]),
        j_force=float(terms.force[0]),
        j_depth=float(terms.depth[0]),
        j_slip=float(terms.slip[0]),
        equilibrium=terms.equilibrium,
        pso=search,
        at_bound=at_bound(best, lower, upper),
    )
