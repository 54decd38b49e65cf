"""MSD + RK4 benchmark: 100 steps at 356 nodes with three fingertips in contact.

Figures, all measured in this run (median and best of repeats):
- the dynamic-grasp step (contacts of Fig. 3 + one RK4 step), 100 steps on the 356-node sphere
  with all three fingertips touching, on the numpy reference path (``dynamics.grasp_step``) and on
  the compiled path (``grasp_kernel.compiled_grasp_step``), with their ratio and real-time factors
  (issue 16 targets: compiled real-time factor >= 5, i.e. 100 steps in <= 4 ms at the 207.5 us
  step, and >= 10x the numpy path; the paper reports 1.8 s in MATLAB, Table 2);
- the same 100 compiled steps with their loop in numba (``grasp_kernel.step_kernel`` called from
  a compiled driver with the same grip law; checked to give the same final state bit for bit):
  the cost of the compiled step without the Python between steps;
- the same 100 RK4 steps without contact, and with the optional volume term;
- the reference: ``scipy.integrate.solve_ivp`` RK45 (default tolerances) on the same body without
  contact over the same simulated time;
- the real-time factor, simulated seconds per wall second.

Contacts on a shell of light nodes flicker: each contact force kicks its three face nodes away.
For the timed grasp, the fingers start at the 0.5 mm seed, gravity is off, the body is free
(load fraction 1) and the fingers close fast (0.3 m/s) while out of contact or while
|R_z| >= tau_F (the grip law of §3), so that the fingertips stay on the surface; the mean number
of active contacts per step is printed (the cost of a step hardly depends on it: the narrow
phase runs on the faces near every fingertip). The same steps with the
body held by the support (load fraction 0: the rigid-body part of the accelerations removed at
every RK4 stage, as during closure, ``core.dynamics.rigid_body_part``) are timed too.
The no-contact runs start from the rest shape perturbed by 0.1 mm (fixed seed), so that RK45 sees
elastic dynamics rather than an exactly integrable free fall.

A second table compares the implicit midpoint rule (``core.implicit``, sparse Newton with SuperLU)
with RK4 on the same body without contact: cost per step (with the LU factors reused along the
run, and with a fresh factorisation at every Newton iteration), cost per simulated second, and the
largest stable step (RK4: ``msd.body_step_limit``, checked by running at 0.99x and 2x of it;
the implicit rule is A-stable, so the table lists the multiples of RK4's limit at which it was run
and stayed bounded with its mechanical energy decaying, i.e. the largest step tested).

The first-call cost of the compiled path is measured too: a fresh interpreter with an empty
numba cache directory (what a fresh clone pays once: JIT compilation, then the cache is written)
and again with that cache (every later process).

A last table gathers the issue 16 figures: step cost [us] on CPU time, real-time factor on CPU
time (the machine may be shared) and on the best wall time, and the speed-up over the numpy step,
for the compiled step called from Python, its loop in numba, and the whole grasp's compiled phase
loop.

Run: ``python benchmarks/bench_msd.py``.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from dataclasses import replace

import numpy as np
from numba import njit
from scipy.integrate import solve_ivp

from graspcampaign.core import dynamics, grasp_kernel, implicit, msd, phase_kernel
from graspcampaign.core.contact import ContactParams
from graspcampaign.core.mesh import make_object

N_STEPS = 100
REPEATS = 7
COMPILED_REPEATS = 41  # a compiled run lasts milliseconds: more repeats for a stable median
TARGET_MS = 90.0  # issue 6, numpy path
COMPILED_TARGET_RTF = 5.0  # issue 16: real-time factor of the compiled path
COMPILED_TARGET_SPEEDUP = 10.0  # issue 16: compiled vs numpy, same run
PAPER_MS = 1800.0
CLOSING_SPEED = 0.3  # finger speed of the timed grasp while closing [m/s] (module docstring)


def _median_times(fn, repeats: int = REPEATS, best: bool = False):
    """Return (median wall, median process CPU) seconds, plus the best wall if ``best``; CPU time
    is less sensitive to other jobs on a shared machine, wall time is what a user waits, the best
    wall approaches what an idle machine gives."""
    walls, cpus = [], []
    for _ in range(repeats):
        start, start_cpu = time.perf_counter(), time.process_time()
        fn()
        walls.append(time.perf_counter() - start)
        cpus.append(time.process_time() - start_cpu)
    out = float(np.median(walls)), float(np.median(cpus))
    return (*out, float(np.min(walls))) if best else out


@njit  # not cached: numba's cache would not see a change of the step_kernel it calls
def _compiled_driver(x, nodal, grip, slip, active, v_rel, anchors, residual_z, n_steps, dt,
                     edges, rest_lengths, faces, constants, targets, approach, law, weight_z,
                     load_fraction, tau_f, closing_speed):
    """The timed grasp of ``main`` (same grip law, same steps) with the loop in numba: the cost
    of ``grasp_kernel.step_kernel`` alone, without the Python between steps. Returns the final
    (n, 6) state and the mean number of active contacts."""
    n_active = 0
    rate = np.empty(grip.shape[0])
    for _ in range(n_steps):
        for p in range(grip.shape[0]):
            n_active += active[p]
            closing = (not active[p]) or abs(residual_z) >= tau_f
            rate[p] = closing_speed if closing else 0.0
        finite, x, vec, scal, flags, hosts, sums, nodal = grasp_kernel.step_kernel(
            x, dt, edges, rest_lengths, faces, constants, nodal, 1.0 - load_fraction, grip, rate,
            slip, active, v_rel, anchors, targets, approach, law, weight_z, load_fraction)
        grip, slip, v_rel = scal[grasp_kernel.GRIP], vec[grasp_kernel.SLIP], vec[grasp_kernel.REL_VEL]
        active, anchors = flags[grasp_kernel.ACTIVE], vec[grasp_kernel.ANCHORS]
        residual_z = sums[grasp_kernel.RESIDUAL, 2]
    return x, n_active / n_steps


_JIT_PROBE = """
import time
import numpy as np
from graspcampaign.core import dynamics, grasp_kernel, msd
from graspcampaign.core.contact import ContactParams
from graspcampaign.core.mesh import make_object
mesh = make_object("sphere", 92)
setup, state = dynamics.prepare_grasp(mesh, 0.3, msd.MsdParams(), ContactParams.table3())
start, start_cpu = time.perf_counter(), time.process_time()
grasp_kernel.compiled_grasp_step(setup, state)
print(time.perf_counter() - start, time.process_time() - start_cpu)
"""


def first_call_costs() -> tuple[tuple[float, float], tuple[float, float]]:
    """Return (wall, CPU) seconds of the first compiled step in a fresh process: with an empty
    numba cache (JIT compilation, a fresh clone) and then with the cache that run wrote."""
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        runs = []
        for _ in range(2):
            out = subprocess.run([sys.executable, "-c", _JIT_PROBE], env=env, check=True,
                                 capture_output=True, text=True).stdout.split()
            runs.append((float(out[0]), float(out[1])))
    return runs[0], runs[1]


def main() -> list[tuple]:
    """Time the grasp steps and the integrators; return the issue 16 figures of the compiled step
    (name, CPU per step [s], real-time factor on CPU and on best wall, speed-up over the numpy
    step on CPU and on best wall)."""
    mesh = make_object("sphere", 356)
    contact = ContactParams.table3()
    params = msd.MsdParams(g=0.0)
    setup, opened = dynamics.prepare_grasp(mesh, 0.3, params, contact, dynamics.GraspParams())
    seeded = replace(opened, grip=np.full(3, 5e-4))
    initial = replace(seeded, contact=dynamics.grasp_forces(setup, seeded))
    dt = setup.dt
    active_counts = []

    def grasp_run(load_fraction, step=dynamics.grasp_step):
        def run():
            gs = initial
            active = 0
            for _ in range(N_STEPS):
                out = gs.contact
                active += int(out.contacts.active.sum())
                closing = ~out.contacts.active | (abs(out.residual[2]) >= setup.grasp.tau_f)
                gs = step(setup, gs.commanded(np.where(closing, CLOSING_SPEED, 0.0), load_fraction))
            active_counts.append(active / N_STEPS)
            return gs
        return run

    packed = grasp_kernel.packed_setup(setup)
    start = initial.contact

    def driver_run(load_fraction):
        def run():
            return _compiled_driver(
                initial.state.reshape(-1, 6), start.nodal_forces, initial.grip,
                initial.slip_coords, start.contacts.active, start.relative_velocity,
                start.stick.anchors, float(start.residual[2]), N_STEPS, dt, packed.edges,
                packed.rest_lengths, packed.faces, packed.constants, packed.targets,
                packed.approach, packed.law, packed.weight_z, load_fraction, setup.grasp.tau_f,
                CLOSING_SPEED)
        return run

    body = setup.body
    gravity = msd.MsdParams()
    rng = np.random.default_rng(20240601)
    state0 = msd.state_from_positions(body.rest_positions + 1e-4 * rng.normal(size=(body.n_nodes, 3)))

    def rk4_run(p):
        def run():
            msd.integrate_rk4(
                lambda t, x: msd.msd_rhs(t, x, body, p), 0.0, state0, dt, N_STEPS,
                record_every=N_STEPS,
            )
        return run

    volume = msd.MsdParams(bulk_modulus=0.47e6)
    body_volume = msd.msd_body_from_mesh(mesh, volume)

    def rk4_volume():
        msd.integrate_rk4(
            lambda t, x: msd.msd_rhs(t, x, body_volume, volume), 0.0, state0, dt, N_STEPS,
            record_every=N_STEPS,
        )

    t_end = N_STEPS * dt
    nfev = []

    def ivp_run():
        sol = solve_ivp(lambda t, x: msd.msd_rhs(t, x, body, gravity), (0.0, t_end), state0, method="RK45")
        nfev.append(sol.nfev)

    compiled = grasp_kernel.compiled_grasp_step
    grasp_run(1.0)()  # warm caches (step-limit tables, sparse structures)
    grasp_run(1.0, compiled)()  # load (or compile) the numba kernels
    wall_grasp, cpu_grasp, best_grasp = _median_times(grasp_run(1.0), best=True)
    wall_held, cpu_held, best_held = _median_times(grasp_run(0.0), best=True)
    wall_fast, cpu_fast, best_fast = _median_times(grasp_run(1.0, compiled), COMPILED_REPEATS,
                                                   best=True)
    wall_fast_held, cpu_fast_held, best_fast_held = _median_times(grasp_run(0.0, compiled),
                                                                  COMPILED_REPEATS, best=True)
    # the loop in numba must run the very same steps as the Python loop over compiled steps
    driver_end, driver_active = driver_run(1.0)()
    same_steps = np.array_equal(driver_end.reshape(-1), grasp_run(1.0, compiled)().state)
    wall_loop, cpu_loop, best_loop = _median_times(driver_run(1.0), COMPILED_REPEATS, best=True)
    wall_loop_held, cpu_loop_held, best_loop_held = _median_times(driver_run(0.0),
                                                                  COMPILED_REPEATS, best=True)
    wall_rk4, cpu_rk4 = _median_times(rk4_run(gravity))
    wall_volume, cpu_volume = _median_times(rk4_volume)
    wall_ivp, cpu_ivp = _median_times(ivp_run)
    (cold_wall, cold_cpu), (warm_wall, warm_cpu) = first_call_costs()

    rows = [
        ("RK4 + 3 fingertip contacts (Fig. 3 step), numpy", wall_grasp, cpu_grasp, best_grasp,
         4 * N_STEPS),
        ("the same, body held by the support (closure), numpy", wall_held, cpu_held, best_held,
         4 * N_STEPS),
        ("RK4 + 3 fingertip contacts, compiled", wall_fast, cpu_fast, best_fast, 4 * N_STEPS),
        ("the same, body held by the support, compiled", wall_fast_held, cpu_fast_held,
         best_fast_held, 4 * N_STEPS),
        ("RK4 + 3 fingertip contacts, compiled, loop in numba (no Python between steps)",
         wall_loop, cpu_loop, best_loop, 4 * N_STEPS),
        ("the same, body held by the support, loop in numba", wall_loop_held, cpu_loop_held,
         best_loop_held, 4 * N_STEPS),
        ("RK4, no contact, numpy", wall_rk4, cpu_rk4, float("nan"), 4 * N_STEPS),
        ("RK4, no contact, volume term (K_b = 0.47 MPa), numpy", wall_volume, cpu_volume,
         float("nan"), 4 * N_STEPS),
        ("solve_ivp RK45 (rtol 1e-3), no contact [reference]", wall_ivp, cpu_ivp, float("nan"),
         int(np.median(nfev))),
    ]
    print(f"356 nodes, {body.n_edges} edges, dt = {dt * 1e6:.1f} us, {N_STEPS} steps = "
          f"{t_end * 1e3:.2f} ms simulated; median of {REPEATS} ({COMPILED_REPEATS} compiled); "
          f"mean active contacts {np.mean(active_counts):.2f} / 3; load average "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs")
    print()
    print("| run | wall [ms] | CPU [ms] | best wall [ms] | RHS evals | real-time factor (wall) | "
          "CPU vs solve_ivp RK45 |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, wall, cpu, best, evals in rows:
        print(f"| {name} | {wall * 1e3:.1f} | {cpu * 1e3:.1f} | {best * 1e3:.1f} | {evals} | "
              f"{t_end / wall:.3f} | {cpu / cpu_ivp:.2f}x |")
    print(f"| target (issue 6, numpy) | {TARGET_MS:.0f} | | | | | |")
    print(f"| target (issue 16, compiled) | {t_end / COMPILED_TARGET_RTF * 1e3:.1f} | | | | "
          f"{COMPILED_TARGET_RTF:.0f} | |")
    print(f"| paper, MATLAB (Table 2) | {PAPER_MS:.0f} | | | | | |")
    print()
    verdict = "meets" if cpu_grasp * 1e3 <= TARGET_MS else "misses"
    print(f"numpy grasp step: {cpu_grasp * 1e3:.1f} ms CPU ({wall_grasp * 1e3:.1f} ms wall) per "
          f"100 steps, {verdict} the {TARGET_MS:.0f} ms target; {PAPER_MS / (wall_grasp * 1e3):.0f}x "
          f"the paper's 1.8 s")
    print(f"the loop in numba runs the same steps as the Python loop over compiled steps: "
          f"{'yes' if same_steps else 'NO'} (final states equal bit for bit; mean active "
          f"contacts {driver_active:.2f} / 3)")
    print(f"compiled step, first call in a fresh process: {cold_wall:.1f} s wall ({cold_cpu:.1f} s "
          f"CPU) with an empty numba cache (a fresh clone: JIT compilation), {warm_wall:.2f} s "
          f"({warm_cpu:.2f} s CPU) once the cache is written")
    simulated = t_end
    return [(name, cpu / N_STEPS, simulated / cpu, simulated / best, cpu_grasp / cpu,
             best_grasp / best)
            for name, cpu, best in (("compiled step called from Python (compiled_grasp_step)",
                                     cpu_fast, best_fast),
                                    ("compiled step, loop in numba (step_kernel)", cpu_loop,
                                     best_loop))]


IMPLICIT_STEPS = 40
IMPLICIT_MULTIPLES = (1.0, 4.0, 16.0, 64.0)


def implicit_table() -> None:
    """Implicit midpoint against RK4 on the 356-node sphere (no contact): cost and stable step."""
    mesh = make_object("sphere", 356)
    params = msd.msd_params_from_modulus(mesh)
    body = msd.msd_body_from_mesh(mesh, params)
    limit = msd.body_step_limit(body, params)
    rng = np.random.default_rng(20240601)
    state0 = msd.state_from_positions(body.rest_positions + 1e-4 * rng.normal(size=(body.n_nodes, 3)))

    def rhs(t, x):
        return msd.msd_rhs(t, x, body, params)

    def energy(states):
        return (msd.kinetic_energy(body, states) + msd.elastic_energy(body, params, states)
                + msd.gravitational_energy(body, params, states))

    def rk4_growth(dt, n=2000):
        with np.errstate(all="ignore"):
            run = msd.integrate_rk4(lambda t, x: msd.msd_rhs(t, x, body, msd.MsdParams(
                mass=params.mass, k=params.k, c=params.c, b=params.b, g=0.0)), 0.0, state0, dt, n,
                record_every=n)
        e = msd.kinetic_energy(body, run.states) + msd.elastic_energy(body, params, run.states)
        return float(e[-1] / e[0])

    wall_rk4, _ = _median_times(lambda: msd.integrate_rk4(rhs, 0.0, state0, 0.5 * limit,
                                                         IMPLICIT_STEPS, IMPLICIT_STEPS), 3)
    rows = [("RK4 at 0.5x its limit", 0.5 * limit, wall_rk4 / IMPLICIT_STEPS, 4.0, 0.0, "stable")]
    for reuse in (True, False):
        for multiple in IMPLICIT_MULTIPLES if reuse else (4.0,):
            dt = multiple * limit
            solver = implicit.ImplicitIntegrator(body, params, implicit.ImplicitParams(
                reuse_jacobian=reuse))
            states = [state0]
            start = time.perf_counter()
            try:
                for _ in range(IMPLICIT_STEPS):
                    states.append(solver.step(states[-1], dt).state)
                wall = time.perf_counter() - start
                e = energy(np.asarray(states))
                verdict = ("bounded, energy decays" if np.all(np.isfinite(e)) and e[-1] <= e[0]
                           else "energy grew")
            except implicit.ImplicitConvergenceError as exc:
                wall, verdict = time.perf_counter() - start, f"Newton failed: {exc}"
            n_done = max(1, solver.n_steps)  # a failed first step counts as one
            label = (f"implicit midpoint, {multiple:g}x RK4 limit, "
                     + ("LU reused" if reuse else "full Newton (LU every iteration)"))
            rows.append((label, dt, wall / n_done, solver.n_iterations / n_done,
                         solver.n_factorizations / n_done, verdict))
    print()
    print(f"Implicit midpoint vs RK4, 356 nodes, no contact, gravity on; RK4 limit "
          f"{limit * 1e6:.1f} us (RK4 energy ratio over 2000 steps without gravity at 0.99x: "
          f"{rk4_growth(0.99 * limit):.3g}, at 2x: {rk4_growth(2.0 * limit):.3g}; the limit "
          f"bounds the damped modes conservatively); "
          f"{IMPLICIT_STEPS} steps per run")
    print()
    print("| integrator | dt [us] | wall per step [ms] | Newton its / step | LU / step | "
          "cost per simulated s vs RK4 | outcome |")
    print("|---|---:|---:|---:|---:|---:|---|")
    rk4_per_second = rows[0][2] / rows[0][1]
    for name, dt, per_step, its, lus, verdict in rows:
        print(f"| {name} | {dt * 1e6:.1f} | {per_step * 1e3:.2f} | {its:.1f} | {lus:.2f} | "
              f"{per_step / dt / rk4_per_second:.2f}x | {verdict} |")


def phase_loop_table() -> tuple:
    """A whole grasp (closure, lift-off, hold of Fig. 11) as the campaigns run it, per 100 steps.

    The same 356-node sphere with gravity, the paper's contact constants and the default
    ``GraspParams`` (``friction_mass``'s protocol): the compiled phase loop
    (``phase_kernel.run_grasp_phases_compiled``, no Python per step) against the Python driver on
    the numpy reference step (``GRASP_RUNNERS["numpy"]``), in this run; the result must agree
    (same status and step count) for the ratio to mean anything.
    """
    mesh = make_object("sphere", 356)
    setup, state = dynamics.prepare_grasp(mesh, 0.3, msd.MsdParams(), ContactParams.table3(),
                                          dynamics.GraspParams())
    compiled, numpy_run = phase_kernel.GRASP_RUNNERS["compiled"], phase_kernel.GRASP_RUNNERS["numpy"]
    fast = compiled(setup, state)  # warm (cache load)
    wall_fast, cpu_fast, best_fast = _median_times(lambda: compiled(setup, state), 5, best=True)
    start, start_cpu = time.perf_counter(), time.process_time()
    slow = numpy_run(setup, state)
    wall_slow, cpu_slow = time.perf_counter() - start, time.process_time() - start_cpu
    simulated = fast.times[-1] - fast.times[0]
    n = len(fast.times) - 1
    print(f"Whole grasp (Fig. 11: closure, lift-off, hold), 356 nodes, gravity, Table 3 contact, "
          f"dt = {setup.dt * 1e6:.1f} us: {n} steps = {simulated * 1e3:.1f} ms simulated, status "
          f"{fast.status} (numpy driver: {slow.status}, {len(slow.times) - 1} steps); mean fingertips "
          f"in contact {fast.in_contact.sum(axis=1).mean():.2f} / 3; load average "
          f"{os.getloadavg()[0]:.2f}")
    print()
    print("| runner | CPU [ms] per 100 steps | wall [ms] per 100 steps | real-time factor (CPU) | "
          "CPU vs numpy driver |")
    print("|---|---:|---:|---:|---:|")
    for name, wall, cpu, steps in (("numpy step, Python driver [reference]", wall_slow, cpu_slow,
                                    len(slow.times) - 1),
                                   ("compiled phase loop (campaigns)", wall_fast, cpu_fast, n)):
        print(f"| {name} | {cpu / steps * 1e5:.2f} | {wall / steps * 1e5:.2f} | "
              f"{simulated / cpu:.2f} | {(cpu_slow / (len(slow.times) - 1)) / (cpu / steps):.1f}x |")
    print()
    slow_steps = len(slow.times) - 1
    return ("whole grasp, compiled phase loop (run_grasp_phases_compiled)", cpu_fast / n,
            simulated / cpu_fast, simulated / best_fast, (cpu_slow / slow_steps) / (cpu_fast / n),
            (wall_slow / slow_steps) / (best_fast / n))


def summary(rows) -> None:
    """Print the issue 16 figures of the compiled dynamic step, all measured in this run."""
    print(f"Issue 16, compiled dynamic step (targets: real-time factor >= {COMPILED_TARGET_RTF:.0f}, "
          f">= {COMPILED_TARGET_SPEEDUP:.0f}x the numpy step). The real-time factor is simulated "
          f"time over process CPU time (the machine may be shared; best wall beside it); the "
          f"speed-ups are over the numpy step timed in this run (the whole grasp: over the numpy "
          f"step under the Python driver, per step, its wall time from one run). Load average "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs.")
    print()
    print("| run | step cost [us] (CPU) | real-time factor (CPU) | real-time factor (best wall) | "
          "vs numpy step (CPU) | vs numpy step (best wall) | targets on CPU time (RTF, speed-up) |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for name, per_step, rtf_cpu, rtf_best, speedup_cpu, speedup_best in rows:
        verdicts = ("meets" if rtf_cpu >= COMPILED_TARGET_RTF else "misses",
                    "meets" if speedup_cpu >= COMPILED_TARGET_SPEEDUP else "misses")
        print(f"| {name} | {per_step * 1e6:.1f} | {rtf_cpu:.2f} | {rtf_best:.2f} | "
              f"{speedup_cpu:.1f}x | {speedup_best:.1f}x | {verdicts[0]}, {verdicts[1]} |")
    print()


if __name__ == "__main__":
    step_rows = main()
    phase_row = phase_loop_table()
    summary([*step_rows, phase_row])
    implicit_table()
