"""Dynamic MSD/RK4 studies: ``gravity_settle`` (Sec. 5.4, Fig. 10) and ``dynamic_grasp``
(``friction_mass``, Sec. 5.5, Figs. 12-13) with the like-for-like checks of Sec. 6.1 / Sec. 12.

The body constants are SI values derived from the object modulus (``core.msd.
msd_params_from_modulus``); Table 3's b, k, c are in the paper's unpublished internal units and are
not reused. The contact law is the configured model (Table 3 lambdas, Table 2 materials), or per
trial the preset named by the ``model_preset`` factor (``friction_mass`` sweeps ``table2`` and the
documented ``firm`` preset). At the paper's constants the bottom finger must carry the whole weight
of a 45/45/-90 grasp, which needs penetrations far beyond the fingertip radius: the records say so
(``dynamic_status``, ``delta_max_mm``, the closed form ``delta_required_mm``); nothing is rescaled.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common
from graspcampaign.campaign.schema import NODES, SIM_TIME_S, config_field

MAX_TRACE_ROWS = 2000  # per trial; longer runs are decimated evenly (the last step is kept)


@dataclass
class DynamicParams:
    nodes: int = config_field(356, **NODES)  # Sec. 5.1: the 356-node sphere
    # 0: the paper's pure spring shell (Sec. 2.1); see msd.MsdParams
    bulk_modulus_pa: float = config_field(0.0, ge=0.0)
    t_max_s: float = config_field(1.0, **SIM_TIME_S)  # simulated time budget of one grasp
    # finger advance rate while |R_z| >= tau_F
    grip_speed_m_per_s: float = config_field(0.02, gt=0.0)
    settle_t_max_s: float = config_field(2.0, **SIM_TIME_S)  # gravity_settle time budget
    # gravity_settle, Sec. 12 energy audit: RK4 steps at the settle step (twice as many at half);
    # 2000 is the former fixed AUDIT_STEPS (docs/decisions.md, audit length as a param)
    audit_steps: int = config_field(2000, ge=1)
    # gravity_settle, factor integrator=implicit: step of the implicit midpoint rule [s]; the
    # largest tested step whose settled shape matches RK4's (docs/decisions.md, implicit settle)
    implicit_dt_s: float = config_field(2.5e-4, gt=0.0)
    # dynamic grasp phases (Fig. 11); sources in core.dynamics.GraspParams
    lift_time_s: float = config_field(0.1, gt=0.0)  # lift-off ramp of the load
    open_gap_m: float = config_field(1e-3, ge=0.0)  # fingers start this far out
    # how a grasp runs (core.phase_kernel.GRASP_RUNNERS): the compiled loop and step, or the
    # Python driver on the numpy reference step (docs/decisions.md, compiled dynamic step)
    step: str = config_field("compiled", choices=("compiled", "numpy"))


@lru_cache(maxsize=64)
def msd_model(shape: str, nodes: int, youngs_modulus: float, mass: float, bulk_modulus: float):
    """Return ``(mesh, MsdParams, MsdBody)`` of one object (cached per worker).

    The constants come from the object modulus (``msd.msd_params_from_modulus``: a dense
    eigen-decomposition, ~1 s at 390 nodes), so a campaign that grasps one body many times builds
    it, and its RK4 step limit, once per worker.
    """
    from dataclasses import replace

    from graspcampaign.core.mesh import make_object
    from graspcampaign.core.msd import msd_body_from_mesh, msd_params_from_modulus

    mesh = make_object(shape, int(nodes))
    msd = replace(msd_params_from_modulus(mesh, youngs_modulus=youngs_modulus, mass=mass),
                  bulk_modulus=bulk_modulus)
    return mesh, msd, msd_body_from_mesh(mesh, msd)


def _decimate(n: int) -> np.ndarray:
    if n <= MAX_TRACE_ROWS:
        return np.arange(n)
    return np.unique(np.r_[np.linspace(0, n - 1, MAX_TRACE_ROWS).round().astype(int), n - 1])


AUDIT_PERTURBATION = 1.0e-3  # [m] node jitter that starts the free elastic motion of the audit
CONVERGENCE_STEPS = 40  # settle steps spanned by the step-size study
CONVERGENCE_REFINEMENTS = (1, 2, 4, 8)  # the settle step divided by these


def numerical_audit(body, msd, dt: float, rng: np.random.Generator, audit_steps: int,
                    stepper=None) -> tuple[dict, dict]:
    """The step-size study and the energy audit that Sec. 12 lists as missing, on the settle body.

    Both run without contact or floor from the rest shape jittered by ``AUDIT_PERTURBATION``
    (seeded by the trial), under gravity: the step-size study compares the integrator (RK4, or
    ``stepper``, see ``core.msd.step_convergence``) at ``dt / r`` for ``r`` in
    ``CONVERGENCE_REFINEMENTS`` with DOP853 at tight tolerances after ``CONVERGENCE_STEPS``
    settle steps; the energy audit closes kinetic + elastic + gravitational energy against the
    integrated damper dissipation over ``audit_steps`` steps at ``dt`` and again at ``dt / 2``
    (the balance error is the method's own error, so it must shrink).

    Returns
    -------
    scalars, tables
        Record columns and the trace tables ``step_convergence`` and ``energy_audit``.
    """
    from graspcampaign.core.msd import energy_audit, state_from_positions, step_convergence

    jitter = AUDIT_PERTURBATION * rng.normal(size=body.rest_positions.shape)
    state0 = state_from_positions(body.rest_positions + jitter)
    conv = step_convergence(body, msd, state0, CONVERGENCE_STEPS * dt,
                            dt / np.asarray(CONVERGENCE_REFINEMENTS, dtype=float), stepper=stepper)
    audits = {"dt": energy_audit(body, msd, state0, dt, audit_steps, record_every=10,
                                 stepper=stepper),
              "dt/2": energy_audit(body, msd, state0, dt / 2, 2 * audit_steps, record_every=20,
                                   stepper=stepper)}
    scalars = {
        "observed_order": float(conv.orders[-1]),
        "error_at_settle_dt_m": float(conv.errors[0]),
        "rk4_observed_order": float(conv.orders[-1]) if stepper is None else float("nan"),
        "rk4_error_at_settle_dt_m": float(conv.errors[0]) if stepper is None else float("nan"),
        "energy_balance_rel_error": float(audits["dt"].max_relative_error),
        "energy_balance_rel_error_half_dt": float(audits["dt/2"].max_relative_error),
        "energy_increases": int(audits["dt"].n_increases + audits["dt/2"].n_increases),
        "energy_audit_steps": int(audit_steps),  # at dt; twice as many at dt / 2
        "energy_audit_span_s": float(audit_steps * dt),
    }
    energy: dict[str, list] = {k: [] for k in (
        "step", "time_s", "kinetic_energy_j", "elastic_energy_j", "gravitational_energy_j",
        "dissipated_energy_j", "balance_error_j")}
    for label, a in audits.items():
        energy["step"] += [label] * len(a.times)
        for key, values in (("time_s", a.times), ("kinetic_energy_j", a.kinetic),
                            ("elastic_energy_j", a.elastic),
                            ("gravitational_energy_j", a.gravitational),
                            ("dissipated_energy_j", a.dissipated),
                            ("balance_error_j", a.balance_error)):
            energy[key] += values.tolist()
    tables = {
        "step_convergence": {"dt_s": conv.dts.tolist(), "max_position_error_m": conv.errors.tolist(),
                             "observed_order": [float("nan"), *conv.orders.tolist()]},
        "energy_audit": energy,
    }
    return scalars, tables


def run_settle(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Drop the body on a rigid floor and let it settle (Fig. 10); audit the integrator.

    Factor ``integrator``: ``rk4`` (the paper's, at half its stable step with the floor) or
    ``implicit`` (the implicit midpoint rule of ``core.implicit`` at ``params.implicit_dt_s``,
    the floor linearised per step). Both audits span the same simulated time.
    """
    from graspcampaign.core.msd import (
        FloorParams,
        body_step_limit,
        settle_on_floor,
    )

    f = inp.trial.factors
    mesh, msd, body = msd_model(f["shape"], common.nodes_of(f, inp.params.nodes),
                                inp.study.model.e_object_pa, f["mass_kg"],
                                inp.params.bulk_modulus_pa)
    integrator = inp.trial.factors.get("integrator", "rk4")
    floor = FloorParams()
    rk4_limit = body_step_limit(body, msd, max(floor.stiffness, floor.tangential_stiffness),
                                max(floor.damping, floor.tangential_damping))
    implicit_stats: dict[str, Any] = {}
    if integrator == "implicit":
        from graspcampaign.core.implicit import ImplicitIntegrator

        solver = ImplicitIntegrator(body, msd)
        dt = float(inp.params.implicit_dt_s)
        res = settle_on_floor(body, msd, floor, dt=dt, t_max=inp.params.settle_t_max_s,
                              stepper=solver.floor_stepper())
        implicit_stats = {"newton_iterations_per_step": solver.n_iterations / solver.n_steps,
                          "lu_factorizations": int(solver.n_factorizations)}
        audit_solver = ImplicitIntegrator(body, msd)
        audit_steps = max(1, int(round(inp.params.audit_steps * 0.5 * rk4_limit / dt)))
        audit, audit_tables = numerical_audit(body, msd, dt, rng, audit_steps,
                                              audit_solver.audit_stepper())
    else:
        res = settle_on_floor(body, msd, floor, t_max=inp.params.settle_t_max_s)
        audit, audit_tables = numerical_audit(body, msd, float(res.dt), rng,
                                              inp.params.audit_steps)
        implicit_stats = {"newton_iterations_per_step": float("nan"), "lu_factorizations": 0}
    keep = _decimate(len(res.times))
    return {
        "dt_over_rk4_limit": float(res.dt / rk4_limit),
        **implicit_stats,
        "settled": bool(res.settled),
        "squash_ratio": float(res.squash_ratio),
        "final_kinetic_energy_j": float(res.kinetic_energy[-1]),
        "max_kinetic_energy_j": float(res.kinetic_energy.max()),
        "max_floor_penetration_mm": float(res.max_floor_penetration * 1e3),
        "simulated_time_s": float(res.times[-1]),
        "dt_s": float(res.dt), "n_steps": int(res.n_steps),
        "spring_k_n_per_m": float(msd.k), "edge_damping_n_s_per_m": float(msd.c),
        "nodal_damping_n_s_per_m": float(msd.b),
        **audit,
        "__tables__": {
            **audit_tables,
            "settle": {"time_s": res.times[keep].tolist(),
                       "kinetic_energy_j": res.kinetic_energy[keep].tolist(),
                       "height_ratio": res.height_ratio[keep].tolist()},
            "shape": {"node": list(range(len(res.positions))),
                      "x0_m": res.initial_positions[:, 0].tolist(),
                      "z0_m": res.initial_positions[:, 2].tolist(),
                      "x_m": res.positions[:, 0].tolist(), "y_m": res.positions[:, 1].tolist(),
                      "z_m": res.positions[:, 2].tolist()},
        },
    }


def trial_study(study, factors: dict):
    """Return the study with the trial's ``model_preset`` (a conf/model option) as its model group.

    Without the factor the study's own ``model`` group is used.
    """
    from dataclasses import replace

    from graspcampaign.campaign.compose import group_config

    name = factors.get("model_preset")
    return study if name is None else replace(study, model=group_config("model", name))


def like_for_like(study, mesh, mass: float, mu: float, contact) -> dict[str, Any]:
    """The quasi-static evaluator and the friction-cone LP on the dynamic pipeline's contact set.

    Sec. 6.1 and Sec. 12 list this run as an open comparison item: Algorithms 1-2 on the identical
    45/45/-90 contacts, plus the closed-form static feasibility of that set at mu and as mu -> 0,
    with the reason of a mu = 0 failure (force or torque balance) and the ideal-sphere reference.
    """
    from graspcampaign.core.equilibrium import evaluate_grasps
    from graspcampaign.core.hand import hand_contact_directions, planned_contacts
    from graspcampaign.core.statics import friction_cone_feasibility, sphere_contacts_from_directions
    from graspcampaign.core.statics_audit import frictionless_diagnosis

    directions = hand_contact_directions()
    points, _, normals = planned_contacts(mesh, directions)
    centroid = np.asarray(mesh.center_mass, dtype=float)
    qs = evaluate_grasps(points[None], normals[None], centroid, mass, mu, contact.k_n_per_mm_n,
                         contact.n, common.evaluator_params(study))
    lp = friction_cone_feasibility(points, normals, mu, mass, centroid)
    mu0 = frictionless_diagnosis(points, normals, mass, centroid)
    radius = float(np.mean(np.linalg.norm(points - centroid, axis=1)))
    ideal = friction_cone_feasibility(*sphere_contacts_from_directions(directions, radius, centroid),
                                      0.0, mass, centroid)
    return {  # the evaluator's one verdict rule: success is gated by valid_geometry (issue 13)
        "qs_success": bool(qs.success[0]),
        "qs_success_unbounded": bool(qs.success_unbounded[0]),
        "qs_valid_geometry": bool(qs.valid_geometry[0]),
        "qs_failure_check": str(qs.failure_labels()[0]),
        "qs_residual_norm_n": float(qs.residual_norm[0]),
        "qs_residual_z_n": float(qs.residual_z[0]),
        "qs_slip_margin_n": float(qs.slip_margin[0]),
        "qs_delta_max_mm": float(qs.delta_max_mm[0]),
        "lp_status": lp.status,
        "lp_status_mu0": mu0.status,
        "lp_mu0_reason": mu0.reason,
        "lp_mu0_force_only_status": mu0.force_only_status,
        "lp_mu0_torque_residual_nm": float("nan") if mu0.torque_residual is None
        else mu0.torque_residual,
        "normal_off_radial_max_deg": float(mu0.off_radial_deg.max()),
        "lp_status_mu0_ideal": ideal.status,
    }


def grasp_params(study, params):
    """Return the GraspParams of a dynamic trial: tau_F from the evaluator config (Sec. 3.7), the
    phase constants from the kind's params (sources in ``core.dynamics.GraspParams``)."""
    from graspcampaign.core.dynamics import GraspParams

    return GraspParams(tau_f=study.evaluator.tau_f_n, t_max=params.t_max_s,
                       grip_speed=params.grip_speed_m_per_s, lift_time=params.lift_time_s,
                       open_gap=params.open_gap_m)


def grasp_record(res, contact, msd, t_max_s: float) -> dict[str, Any]:
    """Flatten a ``DynamicGraspResult`` of a ``t_max_s`` budget into record columns
    (docs/records.md, friction_mass)."""
    force, torque = res.wrench[:3], res.wrench[3:]
    times = res.phase_times
    lifted = res.phase != "closure"
    z_lift = res.centroid[lifted, 2][0] if lifted.any() else float("nan")
    return {
        "dynamic_status": res.status,
        "final_phase": res.final_phase,
        "success": bool(res.success),
        "success_unbounded": bool(res.success_unbounded),
        "valid_geometry": bool(res.valid_geometry),
        "settled_at_s": float(res.settled_at),
        "closure_start_s": times.closure_start, "closure_end_s": times.closure_end,
        **{f"touch_{j + 1}_s": float(t) for j, t in enumerate(times.touch)},
        "lift_start_s": times.lift_start, "lift_end_s": times.lift_end,
        "hold_start_s": times.hold_start, "hold_end_s": times.hold_end,
        "simulated_time_s": float(res.times[-1]),
        "t_max_s": t_max_s,
        "dt_s": float(res.dt), "n_steps": int(res.n_steps),
        "final_residual_z_n": float(res.residual_z[-1]),
        "delta_max_mm": float(res.delta_max * 1e3),
        "delta_required_mm": float(res.delta_required * 1e3),
        "fingertip_radius_mm": float(contact.fingertip_radius * 1e3),
        **{f"delta_{j + 1}_mm": float(res.depths[-1, j] * 1e3) for j in range(3)},
        "centroid_drop_mm": float((z_lift - res.centroid[-1, 2]) * 1e3),
        "slip_margin_ratio": float(res.slip_margin),
        "wrench_force_norm_n": float(np.linalg.norm(force)),
        "wrench_torque_norm_nm": float(np.linalg.norm(torque)),
        **{f"wrench_{a}": float(v) for a, v in zip(("fx_n", "fy_n", "fz_n", "tx_nm", "ty_nm",
                                                     "tz_nm"), res.wrench, strict=True)},
        **{f"normal_force_{j + 1}_n": float(res.normal_forces[-1, j]) for j in range(3)},
        "lambda1": contact.lambda1, "n_exp": contact.n,
        "k_contact_n_per_mm_n": float(contact.k_n_per_mm_n),
        "e_finger_pa": float(contact.e_finger), "e_object_pa": float(contact.e_object),
        "spring_k_n_per_m": float(msd.k),
    }


def run_grasp(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """The dynamic grasp in the order of Fig. 11 on the 45/45/-90 set, then the like-for-like checks.

    The model preset (factor ``model_preset``, else the study's ``model`` group) sets the contact
    law and the object modulus of the MSD body.
    """
    from graspcampaign.core.dynamics import prepare_grasp
    from graspcampaign.core.phase_kernel import GRASP_RUNNERS

    f, params = inp.trial.factors, inp.params
    study = trial_study(inp.study, f)
    mesh, msd, body = msd_model(f["shape"], common.nodes_of(f, params.nodes),
                                study.model.e_object_pa, f["mass_kg"], params.bulk_modulus_pa)
    contact = common.contact_params(study, damping_law=f.get("damping_law", study.model.damping_law))
    setup, state = prepare_grasp(mesh, f["mu"], msd, contact, grasp_params(study, params),
                                 body=body)
    res = GRASP_RUNNERS[params.step](setup, state)
    keep = _decimate(len(res.times))
    out = grasp_record(res, contact, msd, params.t_max_s)
    out.update(like_for_like(study, mesh, f["mass_kg"], f["mu"], contact))
    out["__tables__"] = {"steps": {
        "step": keep.tolist(),
        "time_s": res.times[keep].tolist(),
        "phase": res.phase[keep].tolist(),
        "load_fraction": res.load_fraction[keep].tolist(),
        "residual_z_n": res.residual_z[keep].tolist(),
        "support_force_z_n": res.support_force[keep, 2].tolist(),
        "total_penetration_m": res.total_penetration[keep].tolist(),
        **{f"normal_force_{j + 1}_n": res.normal_forces[keep, j].tolist() for j in range(3)},
        **{f"depth_{j + 1}_m": res.depths[keep, j].tolist() for j in range(3)},
        **{f"grip_{j + 1}_m": res.grip[keep, j].tolist() for j in range(3)},
        "centroid_z_m": res.centroid[keep, 2].tolist(),
    }}
    return out


GRAVITY_SETTLE = TrialKind(name="gravity_settle", run=run_settle, params=DynamicParams,
                           seconds_per_trial=10.0, description="MSD body settling on a floor",
                           factors=("shape", "mass_kg"),
                           optional_factors=("nodes", "integrator"))
DYNAMIC_GRASP = TrialKind(name="dynamic_grasp", run=run_grasp, params=DynamicParams,
                          seconds_per_trial=20.0,
                          description="RK4 dynamic grasp (closure, lift-off, hold) on the 45/45/-90 "
                                      "set + like-for-like checks",
                          factors=("shape", "mass_kg", "mu"),
                          optional_factors=("nodes", "model_preset", "damping_law"))
