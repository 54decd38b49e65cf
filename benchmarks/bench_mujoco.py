"""Peer benchmark: our dynamic grasp step against MuJoCo's flex soft body, same sphere, same squeeze.

The scenario is the dynamic-grasp timing of ``bench_msd.py``: the 356-node sphere (r = 50 mm,
0.4 kg, ``MsdParams`` with gravity off), three 5 mm fingertips on the approach lines of the
paper's reachable optimum (45/45/-90), seeded 0.5 mm deep, mu = 0.3, out-of-contact fingers
re-closing at 0.3 m/s; 100 of our RK4 steps (20.75 ms simulated). Our run is recorded once and
its fingertip paths are replayed in MuJoCo as mocap bodies, so both simulators see the same
fingertip kinematics over the same simulated interval. The MuJoCo model, the map of our
constants onto it and its static check are in ``_mujoco_sphere.py``.

Printed, all measured in this run: wall time per step, cost per simulated second and real-time
factor of each simulator (best of 5; the ratio to ours is the figure to read on a shared
machine); the step used, each simulator's stability criterion and the largest step found stable
by a doubling scan (each run 0.1 s: the window, then the fingertips held; bounded = finite and
no node 25 mm off its rest position relative to the centroid); fingertips touching, contact
points, total normal force and deepest penetration over the window; the squeeze stiffness of the
whole shell in each body model; what differs in the physics.

Run: ``python benchmarks/bench_mujoco.py``. Without MuJoCo (the optional ``bench`` extra,
``pip install -e '.[bench]'``) it prints one line and exits.
"""

from __future__ import annotations

import logging
import os
from dataclasses import dataclass, replace

import numpy as np
from _common import best_of, print_table
from _mujoco_sphere import (
    MJ_TIMESTEP,
    SQUEEZE_FORCE,
    VARIANTS,
    WindowTrace,
    build_mujoco,
    contact_secant,
    edge_rows_at_rest,
    membrane_elasticity,
    mocap_paths,
    mujoco,
    mujoco_squeeze_stiffness,
    our_elastic_frequencies,
    ours_squeeze_stiffness,
    run_mujoco,
    squeeze_pair,
    trace_mujoco,
)

from graspcampaign.core import dynamics, grasp_kernel, msd
from graspcampaign.core.contact import ContactParams
from graspcampaign.core.mesh import SPHERE_RADIUS, make_object

N_NODES = 356
N_STEPS = 100  # our steps in the timed window, as bench_msd.py
MU = 0.3
GRIP_SPEED = 0.3  # [m/s] out-of-contact fingers re-close fast (bench_msd.py)
REPEATS = 5
STABILITY_HORIZON = 0.1  # [s]
DEFORMATION_BOUND = 0.5 * SPHERE_RADIUS  # [m] beyond it the body is no longer a sphere
SCAN_DOUBLINGS = 3


# ------------------------------------------------------------------------------------------------
# Our side
# ------------------------------------------------------------------------------------------------


OURS_STEP = "grasp_kernel.compiled_grasp_step (numba; the numpy grasp_step is its reference)"
"""What :func:`ours_step` calls (printed in the tables)."""


def ours_step(setup: dynamics.GraspSetup, gs: dynamics.GraspState):
    """Take one step of our dynamic grasp (Fig. 3: contacts, forces, one RK4 step).

    The benchmark's only call into our dynamic step: the compiled step of issue 16, held to the
    numpy ``grasp_step`` by tests/core/test_grasp_kernel.py. Returns the advanced state and the
    contact evaluation the step started from.
    """
    return grasp_kernel.compiled_grasp_step(setup, gs), gs.contact


def our_grasp(dt: float | None = None):
    """Return (mesh, setup, initial state) of the bench_msd.py grasp (gravity off, mu = 0.3)."""
    mesh = make_object("sphere", N_NODES)
    setup, opened = dynamics.prepare_grasp(
        mesh, MU, msd.MsdParams(g=0.0), ContactParams.table3(),
        dynamics.GraspParams(grip_speed=GRIP_SPEED, dt=dt),
    )
    # the fingers start at the 0.5 mm seed of Sec. 5.1 (as in bench_msd.py), not opened
    seeded = replace(opened, grip=np.full(3, 5e-4))
    return mesh, setup, replace(seeded, contact=dynamics.grasp_forces(setup, seeded))


def trace_ours(setup, initial, n_steps: int) -> tuple[WindowTrace, np.ndarray]:
    """Run our grasp untimed; return its trace and the (s, 3) finger advances it used [m]."""
    gs = initial  # a GraspState is immutable: grasp steps return a new one
    rows, grips = [], []
    for _ in range(n_steps):
        grips.append(gs.grip.copy())
        start = gs.time
        gs, out = ours_step(setup, gs)
        rows.append((start, out.contacts.active, out.normal_forces, out.contacts.depths))
    times, active, forces, depths = (np.array(col) for col in zip(*rows, strict=True))
    trace = WindowTrace(times=times, touching=active, n_points=active.sum(axis=1),
                        normal_forces=forces, depths=depths)
    return trace, np.array(grips)


def ours_bounded(dt: float, horizon: float = STABILITY_HORIZON) -> bool:
    """Run our grasp at step ``dt`` for ``horizon``; return whether it stayed bounded."""
    _, setup, gs = our_grasp(dt)
    try:
        with np.errstate(all="ignore"):
            for _ in range(int(np.ceil(horizon / dt))):
                gs, _ = ours_step(setup, gs)
    except FloatingPointError:
        return False
    positions = msd.positions_from_state(gs.state)
    return _bounded(positions - setup.body.rest_positions)


def _bounded(displacements: np.ndarray) -> bool:
    """Finite, and every node within DEFORMATION_BOUND of its rest position (centroid removed)."""
    if not np.all(np.isfinite(displacements)):
        return False
    relative = displacements - displacements.mean(axis=0)
    return bool(np.sqrt(np.sum(relative * relative, axis=1)).max() < DEFORMATION_BOUND)


def mujoco_bounded(mesh, params, contact, variant, setup, grips, dt_ours, timestep) -> bool:
    """Replay the window then hold the fingertips, to STABILITY_HORIZON; return bounded."""
    model, data = build_mujoco(mesh, params, contact, MU, variant, timestep)
    times = timestep * np.arange(int(np.ceil(STABILITY_HORIZON / timestep)))
    with np.errstate(all="ignore"):
        run_mujoco(model, data, mocap_paths(setup, grips, dt_ours, times))
    return _bounded(data.qpos.reshape(-1, 3))  # slide joints: qpos is the node displacement


# ------------------------------------------------------------------------------------------------
# Report
# ------------------------------------------------------------------------------------------------

PHYSICS = """What differs in the physics (statics matched, dynamics not):
- Body. Ours: explicit edge springs k and dampers c plus absolute nodal damping b (Eq. 1-4),
  classical RK4 (fourth order, four force evaluations per step) at half its stability limit.
  MuJoCo `edge`: every edge a soft equality constraint, at rest exactly our spring and damper
  (K imp/R = k, B/R = c above), but solved as a_c = A (A+R)^-1 a_ref + R (A+R)^-1 a_u, so a mode
  of our network at frequency w moves at w / sqrt(1 + w^2 / w_c^2), w_c = sqrt(K imp) =
  {w_c:.0f} rad/s: our lowest elastic mode ({w_1:.0f} rad/s) at {w_1_mj:.0f}, the mesh-scale modes (up to
  {w_max:.0f} rad/s) capped near w_c. That cap is what lets a soft constraint take a large step.
  MuJoCo `membrane`: constant-strain SVK triangles (a continuum, not edge springs) with the
  lattice-equivalent E t and nu = 1/3 and Rayleigh damping c/k; `discrete` is implicit in
  position (backward-Euler-like): stable at any step, numerically dissipative. Both MuJoCo
  integrators are first order.
- Contact. Ours: one contact per fingertip (its deepest face), f = K delta^n + C delta_dot with
  n = {n:g} (Eq. 13; its stiffness is unbounded as delta -> 0), held over the RK4 stages, Coulomb
  stick-slip with a tangential spring k_t (Eq. 15-16). MuJoCo: a soft contact constraint per flex
  triangle the fingertip overlaps (several per fingertip), linear in depth at rest (the secant of
  ours at 0.5 mm), solved together with the edge rows; a pyramidal friction cone without a
  tangential spring; mocap fingertips carry no velocity, so contact damping sees only the sphere.
- Step. Ours at 0.5x the RK4 limit of its stiffest mode (contact terms included); MuJoCo at its
  default {mj_ms:g} ms, {ratio:.0f}x ours."""


def physics_text(mesh, setup, w_c: float) -> str:
    """Return :data:`PHYSICS` with this run's numbers."""
    w_1, w_max = our_elastic_frequencies(mesh, setup.msd_params)
    return PHYSICS.format(w_c=w_c, w_1=w_1, w_1_mj=w_1 / np.sqrt(1.0 + (w_1 / w_c) ** 2),
                          w_max=w_max, n=setup.contact.n, mj_ms=MJ_TIMESTEP * 1e3,
                          ratio=MJ_TIMESTEP / setup.dt)


def _us(seconds: float) -> str:
    return f"{seconds * 1e6:,.0f}"


def _scan(bounded, start: float) -> tuple[float, float | None]:
    """Doubling scan from ``start``: (largest bounded step, first unbounded one or None at the
    cap); if ``start`` itself is unbounded, halve instead (nan when nothing is bounded)."""
    if not bounded(start):
        step = start
        for _ in range(SCAN_DOUBLINGS):
            step /= 2.0
            if bounded(step):
                return step, 2.0 * step
        return float("nan"), step
    step = start
    for _ in range(SCAN_DOUBLINGS):
        if not bounded(2.0 * step):
            return step, 2.0 * step
        step *= 2.0
    return step, None


def _scan_text(used: float, ok: float, bad: float | None) -> str:
    if not np.isfinite(ok):
        return f"unbounded down to {_us(bad)}"
    text = f"bounded at {_us(ok)} ({ok / used:g}x the step used)"
    return text + (", scan cap" if bad is None else f", not at {_us(bad)}")


@dataclass(frozen=True)
class SimulatorResult:
    """One row of the report: cost, step, stability and contacts of one simulator."""

    name: str
    integrator: str
    step: float
    wall: float
    simulated: float
    n_steps: int
    trace: WindowTrace
    criterion: str
    scan: str

    def cost_row(self, reference: SimulatorResult) -> tuple[str, ...]:
        per_second = self.wall / self.simulated
        return (self.name, self.integrator, _us(self.step), f"{self.wall / self.n_steps * 1e3:.2f}",
                f"{per_second:.2f}", f"{self.simulated / self.wall:.3f}",
                f"{per_second / (reference.wall / reference.simulated):.2f}x")

    def stability_row(self) -> tuple[str, ...]:
        return (self.name, _us(self.step), self.criterion, self.scan)

    def contact_row(self) -> tuple[str, ...]:
        t = self.trace
        return (self.name, f"{t.touching.sum(axis=1).mean():.2f} / 3", f"{t.n_points.mean():.1f}",
                f"{t.normal_forces.sum(axis=1).mean():.3f}", f"{t.depths.max() * 1e3:.2f}")


def measure_ours(mesh, setup, initial) -> tuple[SimulatorResult, np.ndarray]:
    """Time our window, scan our stable step; return the result and the finger advances used."""
    trace, grips = trace_ours(setup, initial, N_STEPS)  # also warms the caches

    def window():
        gs = initial  # a GraspState is immutable: grasp steps return a new one
        for _ in range(N_STEPS):
            gs, _ = ours_step(setup, gs)

    wall = best_of(window, REPEATS)
    limit = msd.body_step_limit(setup.body, setup.msd_params, setup.grasp.k_t,
                                setup.grasp.c_t + setup.contact.c_n_s_per_m)
    quiet = logging.getLogger(dynamics.__name__)
    level = quiet.level
    quiet.setLevel(logging.ERROR)  # the scan exceeds the RK4 limit on purpose
    try:
        ok, bad = _scan(ours_bounded, setup.dt)
    finally:
        quiet.setLevel(level)
    result = SimulatorResult(
        f"ours: MSD + Hunt-Crossley ({OURS_STEP}), reference", "RK4", setup.dt, wall, N_STEPS * setup.dt,
        N_STEPS, trace, f"RK4 region, linearised modes (msd.body_step_limit): {_us(limit)}",
        _scan_text(setup.dt, ok, bad))
    return result, grips


def measure_mujoco(variant, mesh, setup, grips) -> tuple[SimulatorResult, str, float]:
    """Time one MuJoCo variant over our window; return the result, its mapping check and the
    constraint-space frequency of its edge rows [rad/s] (nan without edge rows)."""
    label, integrator, solver = VARIANTS[variant]
    params, contact = setup.msd_params, setup.contact
    model, data = build_mujoco(mesh, params, contact, MU, variant)
    h = model.opt.timestep
    n_steps = int(round(N_STEPS * setup.dt / h))
    paths = mocap_paths(setup, grips, setup.dt, h * np.arange(n_steps))
    trace = trace_mujoco(model, data, paths)
    wall = best_of(lambda: run_mujoco(model, data, paths), REPEATS)
    ok, bad = _scan(lambda step: mujoco_bounded(mesh, params, contact, variant, setup, grips,
                                                setup.dt, step), h)
    omega = float("nan")
    if variant == "edge":
        spring, damper, omega = edge_rows_at_rest(model, data)
        criterion = f"explicit in position, 2 / sqrt(K imp) of the edge rows: {_us(2.0 / omega)}"
        mapping = f"edge rows at rest: K imp/R = {spring:.0f} N/m, B/R = {damper:.2f} N*s/m"
    else:
        criterion = "implicit in position: any step (Computation chapter)"
        e = membrane_elasticity(params)
        mapping = (f"E t = {e['young'] * e['thickness']:.0f} N/m, nu = 1/3, "
                   f"Rayleigh {e['damping'] * 1e3:.3f} ms")
    result = SimulatorResult(f"MuJoCo {variant}: {label}, {solver}",
                             integrator, h, wall, n_steps * h, n_steps, trace, criterion,
                             _scan_text(h, ok, bad))
    return result, mapping, omega


def main() -> None:
    mesh, setup, initial = our_grasp()
    ours, grips = measure_ours(mesh, setup, initial)
    results, checks = [ours], []
    pair = squeeze_pair(np.asarray(mesh.vertices))
    checks.append(("ours (linearised, exact small-load limit)",
                   ours_squeeze_stiffness(mesh, setup.msd_params, pair),
                   f"edge k = {setup.msd_params.k:.0f} N/m, c = {setup.msd_params.c:.2f} N*s/m"))
    w_c = float("nan")
    for variant in VARIANTS:
        result, mapping, omega = measure_mujoco(variant, mesh, setup, grips)
        w_c = omega if variant == "edge" else w_c
        results.append(result)
        checks.append((f"MuJoCo {variant} (simulated to rest)", mujoco_squeeze_stiffness(
            mesh, setup.msd_params, setup.contact, variant, pair), mapping))

    print(f"356-node sphere, {setup.body.n_edges} edges, 0.4 kg, gravity off, mu = {MU}; "
          f"{N_STEPS * setup.dt * 1e3:.2f} ms simulated ({N_STEPS} of our steps) with our fingertip "
          f"paths replayed in MuJoCo {mujoco.__version__}; best of {REPEATS}; load average "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs (shared machine: read the ratios)")
    print()
    print_table(["simulator: body model, solver", "integrator", "step [us]", "wall per step [ms]",
                 "cost per simulated s [s]", "real-time factor", "cost per simulated s vs ours"],
                [r.cost_row(ours) for r in results], ["---", "---"] + ["---:"] * 5)
    print()
    print(f"Largest stable step: criterion, and a doubling scan from the step used (each run "
          f"{STABILITY_HORIZON:g} s, bounded = no node {DEFORMATION_BOUND * 1e3:.0f} mm off its "
          f"rest position relative to the centroid):")
    print()
    print_table(["simulator", "step used [us]", "criterion [us]", "scan [us]"],
                [r.stability_row() for r in results], ["---", "---:", "---", "---"])
    print()
    print(f"Contacts over the window (MuJoCo contact: secant of ours at 0.5 mm = "
          f"{contact_secant(setup.contact):.0f} N/m, damping "
          f"C = {setup.contact.c_n_s_per_m:.4f} N*s/m):")
    print()
    print_table(["simulator", "fingertips touching", "contact points", "total normal force [N]",
                 "deepest penetration [mm]"],
                [r.contact_row() for r in results], ["---"] + ["---:"] * 4)
    print()
    print(f"Squeeze stiffness of the whole shell: nodes {pair[0]} and {pair[1]} (+x, -x) pushed "
          f"together by {SQUEEZE_FORCE * 1e3:g} mN each:")
    print()
    print_table(["body", "squeeze stiffness [N/m]", "mapping"],
                [(name, f"{value:.2f}", note) for name, value, note in checks],
                ["---", "---:", "---"])
    print()
    print(physics_text(mesh, setup, w_c))


if __name__ == "__main__":
    if mujoco is None:
        print("bench_mujoco: skipped, MuJoCo is not installed (pip install -e '.[bench]')")
    else:
        main()
