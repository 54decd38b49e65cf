"""Implicit midpoint (theta-method) integration of the MSD body with sparse Newton iterations.

The paper integrates Eq. 5 with explicit RK4 at a fixed step and lists the missing comparison
with the semi-implicit schemes standard for stiff mass-spring systems as a limitation (§12,
Baraff & Witkin 1998). This module supplies it: one step of the theta-method

    v_1 = v_0 + dt a(x_theta, v_theta),   x_1 = x_0 + dt v_theta,
    v_theta = v_0 + theta (v_1 - v_0),    x_theta = x_0 + theta dt v_theta,

with ``theta = 1/2`` the implicit midpoint rule (default) and ``theta = 1`` backward Euler. The
acceleration ``a`` is :func:`core.msd.msd_rhs` itself (springs, dampers, nodal damping, gravity,
the optional volume term, nodal external forces), so the implicit and the explicit integrator
share one force definition; :mod:`core.jacobian` differentiates it.

Unknown: the velocity increment ``dv = v_1 - v_0`` (3n values). Newton's method on
``G(dv) = dv - dt a(x_theta, v_theta) = 0`` with the matrix

    dG/d(dv) = I - theta dt A_v - theta^2 dt^2 A_x,   A_x = M^-1 dF/dx,  A_v = M^-1 dF/dv,

a sparse (3n, 3n) matrix on the edge graph (plus a rank-one update for the volume term, solved
by Sherman-Morrison), factorised with SuperLU (``scipy.sparse.linalg.splu``).

Why the midpoint rule (docs/decisions.md): it is A-stable, second order, symmetric, and preserves
every quadratic invariant; on the linear damped oscillator it closes the energy balance of the
audit (:func:`core.msd.energy_audit`, dissipation accumulated as ``dt P(x_theta, v_theta)``)
exactly, so the audit measures only the nonlinearity of the springs, like RK4's audit measures
its truncation. Backward Euler (theta = 1) is L-stable but removes energy at O(dt) on its own:
the audit would then measure the integrator's artificial damping, which is kept available for
that comparison.

Shape letters: ``n`` nodes.

References
----------
Hairer, E. & Wanner, G. (1996), Solving Ordinary Differential Equations II, §IV.3 (A-stability of
the theta-method), §IV.8 (simplified Newton iterations and their stopping rule); Hairer, Lubich &
Wanner (2006), Geometric Numerical Integration, §IV.2 (midpoint rule preserves quadratic
invariants); Baraff & Witkin (1998); §12 of the paper. Sherman, J. & Morrison, W. J. (1950),
Ann. Math. Stat. 21(1):124-127.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

from graspcampaign.core.jacobian import JacobianPattern, body_jacobian, floor_jacobian
from graspcampaign.core.msd import (
    FloorParams,
    MsdBody,
    MsdParams,
    check_state,
    dissipation_power,
    floor_forces,
    msd_rhs,
    positions_from_state,
    velocities_from_state,
)

__all__ = [
    "ExternalForce",
    "ImplicitConvergenceError",
    "ImplicitIntegrator",
    "ImplicitParams",
    "ImplicitStepResult",
    "floor_force",
    "linearized_force",
]

logger = logging.getLogger(__name__)

_MIN_LINE_STEP = 1.0 / 64.0
"""Smallest Newton step fraction tried by the backtracking line search."""

ExternalForce = Callable[[np.ndarray], tuple]
"""``external(state) -> (forces (n, 3) [N], dF/dx (3n, 3n) sparse or None, dF/dv or None)``:
a state-dependent nodal force evaluated inside the implicit solve (e.g. the floor, or a contact
law with its stiffness), with its Jacobians at ``state``."""


class ImplicitConvergenceError(RuntimeError):
    """The Newton iterations of an implicit step did not converge."""


@dataclass(frozen=True)
class ImplicitParams:
    """Numerical constants of the implicit step.

    Attributes
    ----------
    theta : float
        1/2: implicit midpoint (default, second order, energy-consistent); 1: backward Euler
        (first order, L-stable). Must lie in [1/2, 1] (A-stable range).
    rtol : float
        Newton stops when the last update satisfies ``|delta|_inf <= atol + rtol |dv|_inf`` [-].
        Default 1e-9: eight orders below the O(dt^2) error of the method at the steps used,
        and 1e7 above double precision round-off.
    atol : float
        Absolute velocity tolerance of the same test [m/s]. Default 1e-12 m/s (node velocities
        are >= 1e-6 m/s whenever anything moves).
    max_iter : int
        Newton iterations allowed per step (the factorisation is refreshed at most once more
        when the iteration stalls). Default 25.
    reuse_jacobian : bool
        Keep the LU factors across iterations and steps while they converge fast (simplified
        Newton, Hairer & Wanner §IV.8); refactorise when the contraction rate
        ``|delta_k| / |delta_{k-1}|`` exceeds ``refactor_rate``, when the step size changes, or
        when the iteration has not converged after half of ``max_iter``. False: full Newton
        (refactorise at every iteration). Default True.
    refactor_rate : float
        Contraction rate above which stale factors are refreshed [-]. Default 0.25 (a fresh
        exact Jacobian converges quadratically; a rate of 1/4 costs about one extra cheap
        solve per digit, a refactorisation costs 20 solves).
    """

    theta: float = 0.5
    rtol: float = 1e-9
    atol: float = 1e-12
    max_iter: int = 25
    reuse_jacobian: bool = True
    refactor_rate: float = 0.25

    def __post_init__(self) -> None:
        if not 0.5 <= self.theta <= 1.0:
            raise ValueError(f"ImplicitParams.theta must lie in [0.5, 1], got {self.theta!r}")
        for name in ("rtol", "atol", "refactor_rate"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0.0:
                raise ValueError(f"ImplicitParams.{name} must be finite and > 0, got {value!r}")
        if self.max_iter < 2:
            raise ValueError(f"ImplicitParams.max_iter must be >= 2, got {self.max_iter!r}")


@dataclass(frozen=True)
class ImplicitStepResult:
    """One implicit step.

    Attributes
    ----------
    state : (6 n,) float
        State at ``t + dt``.
    iterations : int
        Newton iterations taken.
    factorizations : int
        LU factorisations computed during the step (0 when reused).
    dissipated : float
        Energy removed by the body's dampers over the step, ``dt P(x_theta, v_theta)`` [J].
    external_work : float
        Work of ``f_ext`` and of the external force model, ``dt f . v_theta`` [J].
    """

    state: np.ndarray
    iterations: int
    factorizations: int
    dissipated: float
    external_work: float


@dataclass(eq=False)
class ImplicitIntegrator:
    """The theta-method for one MSD body, with its Jacobian pattern and cached LU factors.

    Parameters
    ----------
    body, params
        The MSD body and its constants.
    solver : ImplicitParams
        Method and Newton constants.

    Attributes
    ----------
    n_steps, n_iterations, n_factorizations : int
        Running totals over the integrator's life (for benchmarks and records).


    Notes
    -----
    The object caches the LU factors of the last Newton matrix: reuse one integrator along a
    trajectory, and create a new one for an unrelated run (its results do not depend on the
    cache beyond the Newton tolerance).
    """

    body: MsdBody
    params: MsdParams
    solver: ImplicitParams = field(default_factory=ImplicitParams)
    n_steps: int = 0
    n_iterations: int = 0
    n_factorizations: int = 0
    _pattern: JacobianPattern | None = field(default=None, init=False, repr=False)
    _lu: object = field(default=None, init=False, repr=False)
    _lu_dt: float = field(default=float("nan"), init=False, repr=False)
    _rank_one: tuple | None = field(default=None, init=False, repr=False)

    def _factorize(self, state_theta: np.ndarray, dt: float, external_jac) -> None:
        if self._pattern is None:
            self._pattern = JacobianPattern.of(self.body)
        jac = body_jacobian(self.body, self.params, state_theta, self._pattern)
        theta, inv_m = self.solver.theta, 1.0 / self.body.node_mass
        d_x, d_v = jac.d_position, jac.d_velocity
        ext_x, ext_v = external_jac
        if ext_x is not None:
            d_x = d_x + ext_x
        if ext_v is not None:
            d_v = d_v + ext_v
        n3 = 3 * self.body.n_nodes
        matrix = (scipy.sparse.identity(n3, format="csr")
                  - (theta * dt * inv_m) * d_v - (theta * theta * dt * dt * inv_m) * d_x)
        self._lu = scipy.sparse.linalg.splu(matrix.tocsc())
        self._lu_dt = dt
        self.n_factorizations += 1
        if jac.rank_one_vector is None:
            self._rank_one = None
        else:
            # I - theta^2 dt^2 / m (scale g g^T) = S + beta g g^T, beta = -theta^2 dt^2 scale / m.
            g = jac.rank_one_vector
            beta = -theta * theta * dt * dt * inv_m * jac.rank_one_scale
            s_inv_g = self._lu.solve(g)
            self._rank_one = (g, beta, s_inv_g, 1.0 + beta * float(g @ s_inv_g))

    def _solve(self, rhs: np.ndarray) -> np.ndarray:
        y = self._lu.solve(rhs)
        if self._rank_one is None:
            return y
        g, beta, s_inv_g, denominator = self._rank_one
        return y - s_inv_g * (beta * float(g @ y) / denominator)

    def step(self, state, dt: float, f_ext=None, external: ExternalForce | None = None
             ) -> ImplicitStepResult:
        """Advance the body by one implicit step.

        Parameters
        ----------
        state : (6 n,) float
            State at t (``core.msd`` layout).
        dt : float
            Step [s], > 0.
        f_ext : (n, 3) float, optional
            Nodal forces held constant over the step [N] (e.g. contact forces evaluated once per
            step, as the dynamic grasp does with RK4).
        external : ExternalForce, optional
            State-dependent nodal forces solved implicitly with their Jacobians, e.g. a contact
            force linearised at the start of the step (:func:`linearized_force`).

        Returns
        -------
        result : ImplicitStepResult

        Raises
        ------
        ImplicitConvergenceError
            When Newton does not reach the tolerance within ``max_iter`` iterations with fresh
            factors.

        Notes
        -----
        Newton stops when a full step's update satisfies ``|delta|_inf <= atol + rtol |dv|_inf``
        (Hairer & Wanner §IV.8 use the same increment test). Each update is backtracked on
        ``|G|_2`` (Armijo, down to 1/64 of the step); a stale factorisation whose direction
        needs backtracking is refreshed first.
        """
        if not dt > 0.0:
            raise ValueError(f"dt must be > 0, got {dt!r}")
        state = check_state(state, self.body.n_nodes)
        theta = self.solver.theta
        nodes = state.reshape(-1, 6)
        x0, v0 = nodes[:, :3].ravel(), nodes[:, 3:].ravel()
        f_const = None if f_ext is None else np.asarray(f_ext, dtype=np.float64).reshape(-1, 3)

        def theta_state(dv):
            v_theta = v0 + theta * dv
            st = np.empty((self.body.n_nodes, 6))
            st[:, :3] = (x0 + theta * dt * v_theta).reshape(-1, 3)
            st[:, 3:] = v_theta.reshape(-1, 3)
            return st.ravel()

        def evaluate(dv):
            """Return G(dv), the theta-state and the external Jacobians there."""
            st = theta_state(dv)
            forces, ext_jac = f_const, (None, None)
            if external is not None:
                ext_forces, jx, jv = external(st)
                forces = ext_forces if forces is None else forces + ext_forces
                ext_jac = (jx, jv)
            accel = msd_rhs(0.0, st, self.body, self.params, forces).reshape(-1, 6)[:, 3:]
            return dv - dt * accel.ravel(), st, ext_jac

        dv, iterations, factorizations = self._newton(evaluate, np.zeros_like(v0), dt)
        state_theta = theta_state(dv)
        v_theta = state_theta.reshape(-1, 6)[:, 3:].ravel()
        work = 0.0
        if f_const is not None or external is not None:
            total = np.zeros((self.body.n_nodes, 3)) if f_const is None else f_const.copy()
            if external is not None:
                total += external(state_theta)[0]
            work = dt * float(total.ravel() @ v_theta)
        new = np.empty_like(state)
        out = new.reshape(-1, 6)
        out[:, :3] = (x0 + dt * v_theta).reshape(-1, 3)
        out[:, 3:] = (v0 + dv).reshape(-1, 3)
        self.n_steps += 1
        self.n_iterations += iterations
        return ImplicitStepResult(
            state=new, iterations=iterations, factorizations=factorizations,
            dissipated=dt * dissipation_power(self.body, self.params, state_theta),
            external_work=work,
        )

    def _newton(self, evaluate, dv: np.ndarray, dt: float) -> tuple[np.ndarray, int, int]:
        """Solve ``G(dv) = 0`` from ``dv``; return (dv, iterations, factorisations)."""
        solver = self.solver
        dv = dv.copy()
        residual, state_theta, ext_jac = evaluate(dv)
        norm = float(np.linalg.norm(residual))
        refresh = not solver.reuse_jacobian or self._lu is None or self._lu_dt != dt
        age = 0  # updates since the factors were computed (0: they belong to this iterate)
        factorizations = 0
        previous = size = np.inf
        for iteration in range(1, solver.max_iter + 1):
            if refresh:
                self._factorize(state_theta, dt, ext_jac)
                factorizations += 1
                age, refresh, previous = 0, False, np.inf
            delta = -self._solve(residual)
            size = float(np.max(np.abs(delta)))
            if size <= solver.atol + solver.rtol * float(np.max(np.abs(dv + delta))):
                return dv + delta, iteration, factorizations
            # Backtracking on |G| (Armijo): far from the solution, or on a stale Jacobian, a full
            # step can increase the residual of these strongly nonlinear (rotating) springs.
            step = 1.0
            while True:
                trial, trial_state, trial_jac = evaluate(dv + step * delta)
                trial_norm = float(np.linalg.norm(trial))
                if trial_norm <= (1.0 - 1e-4 * step) * norm or step <= _MIN_LINE_STEP:
                    break
                step *= 0.5
            if step < 1.0 and age > 0:
                refresh = True  # a stale direction that is not a descent direction: refactorise
                continue
            dv += step * delta
            residual, state_theta, ext_jac, norm = trial, trial_state, trial_jac, trial_norm
            rate = step * size / previous
            previous = step * size
            age += 1
            refresh = not solver.reuse_jacobian or rate > solver.refactor_rate or step < 1.0
        raise ImplicitConvergenceError(
            f"implicit step (theta = {solver.theta:g}) did not converge in {solver.max_iter} "
            f"Newton iterations at dt = {dt:.3g} s (last update {size:.3g} m/s)"
        )

    def audit_stepper(self, f_ext=None) -> Callable:
        """Return ``step(state, dt) -> (state, dissipated, work)`` for :func:`core.msd.energy_audit`
        and :func:`core.msd.step_convergence`, with ``f_ext`` (n, 3) [N] held constant."""

        def step(state, dt):
            res = self.step(state, dt, f_ext=f_ext)
            return res.state, res.dissipated, res.external_work

        return step

    def floor_stepper(self) -> Callable:
        """Return ``step(state, floor, anchors, dt) -> state`` for
        :func:`core.msd.settle_on_floor`: the floor linearised at the start of each step
        (:func:`floor_force`) and solved implicitly with the body."""

        def step(state, floor, anchors, dt):
            return self.step(state, dt, external=floor_force(state, floor, anchors)).state

        return step


def linearized_force(state0, forces, d_position=None, d_velocity=None) -> ExternalForce:
    """Return the nodal force ``f0 + dF/dx (x - x0) + dF/dv (v - v0)`` as an :data:`ExternalForce`.

    Parameters
    ----------
    state0 : (6 n,) float
        State at which the force and its Jacobians were evaluated (the start of the step).
    forces : (n, 3) float
        Force ``f0`` at ``state0`` [N].
    d_position, d_velocity : (3n, 3n) sparse, optional
        Its Jacobians there [N/m], [N*s/m] (None: that dependence is held constant).

    Returns
    -------
    external : ExternalForce
        Linear in the state, so Newton sees no kink within the step.

    Notes
    -----
    This is how non-smooth external forces enter the implicit step (linearly implicit, as in
    Baraff & Witkin 1998 §5): the floor's contact and slip sets, or a fingertip's contact law,
    are taken at the start of the step, and their stiffness and damping act implicitly over it.
    The sets are re-evaluated at the next step. Solving the switching forces exactly inside
    Newton (tried first: full and simplified Newton with Armijo backtracking, then a primal
    active-set iteration over the floor's contact and slip sets) cycled between contact sets on
    the settling sphere and cost up to 22 Newton iterations per step (docs/decisions.md).
    """
    x0 = positions_from_state(state0).ravel()
    v0 = velocities_from_state(state0).ravel()
    f0 = np.asarray(forces, dtype=np.float64).reshape(-1, 3)

    def model(state):
        out = f0.ravel().copy()
        if d_position is not None:
            out += d_position @ (positions_from_state(state).ravel() - x0)
        if d_velocity is not None:
            out += d_velocity @ (velocities_from_state(state).ravel() - v0)
        return out.reshape(-1, 3), d_position, d_velocity

    return model


def floor_force(state0, floor: FloorParams, anchors=None) -> ExternalForce:
    """Return the rigid floor of :func:`core.msd.floor_forces` linearised at ``state0``.

    Parameters
    ----------
    state0 : (6 n,) float
        State at the start of the step.
    floor : FloorParams
    anchors : (n, 2) float, optional
        Stick anchors, held over the step (updated by ``msd.floor_anchors_update`` after it).

    Returns
    -------
    external : ExternalForce
        :func:`linearized_force` of the floor forces and their Jacobians
        (:func:`core.jacobian.floor_jacobian`) at ``state0``.
    """
    d_pos, d_vel = floor_jacobian(state0, floor, anchors)
    return linearized_force(state0, floor_forces(state0, floor, anchors),
                            _block_diagonal(d_pos), _block_diagonal(d_vel))


def _block_diagonal(blocks: np.ndarray) -> scipy.sparse.csr_matrix | None:
    """Return the (3n, 3n) block-diagonal matrix of (n, 3, 3) blocks (None when all zero)."""
    nonzero = np.flatnonzero(np.any(blocks != 0.0, axis=(1, 2)))
    if nonzero.size == 0:
        return None
    n3 = 3 * blocks.shape[0]
    comp_r, comp_c = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
    rows = (3 * nonzero[:, None, None] + comp_r).ravel()
    cols = (3 * nonzero[:, None, None] + comp_c).ravel()
    return scipy.sparse.csr_matrix((blocks[nonzero].ravel(), (rows, cols)), shape=(n3, n3))
