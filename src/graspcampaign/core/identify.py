"""Parameter identification: global-best PSO and the composite cost J of §11.

Shape letters: ``p`` particles, ``d`` parameters, ``t`` swarm evaluations (iterations).

References
----------
§4, §6.8 and §11 of the paper (parameter vector, bounds, budgets, cost J). Kennedy, J. &
Eberhart, R. (1995), "Particle swarm optimization", Proc. ICNN'95, 1942-1948. Shi, Y. &
Eberhart, R. (1998), "A modified particle swarm optimizer", Proc. IEEE ICEC, 69-73 (inertia
weight). Robinson, J. & Rahmat-Samii, Y. (2004), "Particle swarm optimization in
electromagnetics", IEEE Trans. Antennas Propag. 52(2):397-407 (absorbing walls). Engelbrecht, A.
(2012), "Particle swarm optimization: Velocity initialization", Proc. IEEE CEC (zero initial
velocities).
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
from graspcampaign.core.pso_kernel import swarm_accept, swarm_update

__all__ = [
    "F0_N",
    "DELTA0_MM",
    "PAPER_BOUNDS",
    "PARAMETER_NAMES",
    "FLAT_PARAMETERS",
    "IdentificationResult",
    "IdentificationTerms",
    "PsoResult",
    "at_bound",
    "identification_cost",
    "identification_terms",
    "identify_body",
    "paper_bounds",
    "pso_minimize",
]

logger = logging.getLogger(__name__)

PARAMETER_NAMES = ("lambda1", "lambda2", "n", "b", "k", "c")
"""Order of the identified parameter vector (§4)."""

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
class PsoResult:
    """Outcome of :func:`pso_minimize`.

    Attributes
    ----------
    best_x : (d,) float
        Global-best position.
    best_cost : float
        Its cost.
    history_best_cost : (t,) float
        Global-best cost after each swarm evaluation (entry 0: the initial swarm); non-increasing.
    history_n_evaluations : (t,) int
        Cumulative cost evaluations at each entry (the NFE axis of Fig. 9).
    history_best_x : (t, d) float
        Global-best position after each swarm evaluation.
    n_evaluations : int
        Total cost evaluations, ``n_particles * n_iterations``.
    final_positions : (p, d) float
        Swarm positions at the last evaluation.
    final_costs : (p,) float
        Their costs.
    """

    best_x: np.ndarray
    best_cost: float
    history_best_cost: np.ndarray
    history_n_evaluations: np.ndarray
    history_best_x: np.ndarray
    n_evaluations: int
    final_positions: np.ndarray
    final_costs: np.ndarray


def _check_bounds(lower, upper) -> tuple[np.ndarray, np.ndarray]:
    lower = np.asarray(lower, dtype=float)
    upper = np.asarray(upper, dtype=float)
    if lower.ndim != 1 or lower.shape != upper.shape:
        raise ValueError(
            f"lower and upper must have the same shape (d,), got {lower.shape} and {upper.shape}"
        )
    if not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper)) and np.all(upper > lower)):
        raise ValueError("bounds must be finite with upper > lower in every dimension")
    return lower, upper


def _evaluate(cost, positions: np.ndarray) -> np.ndarray:
    values = np.asarray(cost(positions), dtype=float)
    if values.shape != (positions.shape[0],):
        raise ValueError(
            f"cost must map (p, d) positions to (p,) values, got {values.shape} for {positions.shape}"
        )
    return np.where(np.isnan(values), np.inf, values)


def pso_minimize(
    cost,
    lower,
    upper,
    *,
    n_particles: int,
    n_iterations: int,
    rng: np.random.Generator,
    inertia: float = 0.7,
    c1: float = 1.5,
    c2: float = 1.5,
) -> PsoResult:
    """Minimise a batched cost over a box with global-best, inertia-weight PSO.

    Parameters
    ----------
    cost : callable
        ``cost(positions (p, d)) -> (p,)``: the whole swarm is evaluated in one call. NaN costs
        count as ``+inf``.
    lower, upper : (d,) float
        Box bounds.
    n_particles : int
        Swarm size p.
    n_iterations : int
        Swarm evaluations t, the initial one included, so the budget is ``p * t`` cost
        evaluations (§11 counts 8 particles x 15 iterations as 120 evaluations).
    rng : numpy.random.Generator
        Source of the initial positions and of r1, r2.
    inertia, c1, c2 : float
        Inertia weight w, cognitive and social coefficients (§11: 0.7, 1.5, 1.5).

    Returns
    -------
    result : PsoResult

    Notes
    -----
    Positions start uniform in the box with zero velocity (Engelbrecht 2012). Each iteration:
    ``v <- w v + c1 r1 (pbest - x) + c2 r2 (gbest - x)``, ``x <- x + v`` with ``r1, r2 ~ U(0, 1)``
    drawn per particle and dimension (Kennedy & Eberhart 1995; Shi & Eberhart 1998). Positions
    leaving the box are clamped to it, not wrapped, and the velocity component that crossed the
    bound is set to zero (an absorbing wall, Robinson & Rahmat-Samii 2004) so the particle does
    not keep pushing against the wall. No velocity clamp: w = 0.7, c1 + c2 = 3 lie inside the
    order-2 stability region ``c1 + c2 < 24 (1 - w^2)/(7 - 5 w)`` = 3.50 (Poli 2009).
    A personal best is replaced only on strict improvement; ties keep the earlier one.

    References
    ----------
    §4, §11; Kennedy & Eberhart (1995); Shi & Eberhart (1998); Robinson & Rahmat-Samii (2004);
    Poli, R. (2009), "Mean and variance of the sampling distribution of particle swarm
    optimizers during stagnation", IEEE Trans. Evol. Comput. 13(4):712-721.
    """
    lower, upper = _check_bounds(lower, upper)
    if int(n_particles) != n_particles or n_particles < 1:
        raise ValueError(f"n_particles must be a positive int, got {n_particles!r}")
    if int(n_iterations) != n_iterations or n_iterations < 1:
        raise ValueError(f"n_iterations must be a positive int, got {n_iterations!r}")
    n_particles, n_iterations = int(n_particles), int(n_iterations)
    n_dims = lower.shape[0]

    positions = lower + rng.random((n_particles, n_dims)) * (upper - lower)
    velocities = np.zeros_like(positions)
    costs = _evaluate(cost, positions)
    best_positions, best_costs = positions.copy(), costs.copy()
    leader = int(np.argmin(best_costs))

    history_cost = np.empty(n_iterations)
    history_x = np.empty((n_iterations, n_dims))
    history_cost[0], history_x[0] = best_costs[leader], best_positions[leader]
    for iteration in range(1, n_iterations):
        r1 = rng.random((n_particles, n_dims))
        r2 = rng.random((n_particles, n_dims))
        # the update and the personal/global bests in two compiled calls (the numpy version's
        # operations in the same order, bit for bit; ~20 numpy calls per iteration otherwise)
        positions_new = np.empty_like(positions)
        swarm_update(positions, velocities, best_positions, leader, r1, r2, lower, upper,
                     float(inertia), float(c1), float(c2), positions_new)
        positions = positions_new
        costs = _evaluate(cost, positions)
        leader = swarm_accept(costs, positions, best_positions, best_costs)
        history_cost[iteration], history_x[iteration] = best_costs[leader], best_positions[leader]

    logger.debug(
        "PSO %d particles x %d iterations: best cost %.6g",
        n_particles,
        n_iterations,
        best_costs[leader],
    )
    return PsoResult(
        best_x=best_positions[leader].copy(),
        best_cost=float(best_costs[leader]),
        history_best_cost=history_cost,
        history_n_evaluations=n_particles * np.arange(1, n_iterations + 1),
        history_best_x=history_x,
        n_evaluations=n_particles * n_iterations,
        final_positions=positions,
        final_costs=costs,
    )


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
