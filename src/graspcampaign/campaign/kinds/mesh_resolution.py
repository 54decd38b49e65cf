"""``mesh_resolution``: Sec. 6.7 (Fig. 20) plus the two budget questions the paper leaves open (Sec. 11).

Panels (the ``panel`` column), emitted as one trial list by :func:`design`:

``resolution``
    The sphere at eight resolutions (144-1750 nodes). Contact parameters are identified once, on
    the ``identify_nodes`` mesh, and held fixed across resolutions (Sec. 12: "holds the identified
    parameters fixed across resolutions"). Each trial records its grasp outcome (final residual,
    Fig. 20b) and the cost of one evaluation, timed ``timing_repeats`` times *interleaved* with
    the same evaluation on the ``reference_nodes`` mesh inside the same trial; the ratio
    ``cost_ratio_vs_reference`` is that of the two meshes' fastest repeats (Fig. 20a).
``budget``
    Success against the candidate budget N_cand (Algorithm 1 line 1) on each shape, plus the
    ``reference`` planner (exhaustive on meshes with at most 3e6 triples, e.g. 144 nodes).
    ``n_cand`` is a method factor: every budget of one seed draws from the same stream, so the
    first candidates of a larger budget are those of a smaller one (before the redraw of
    repeated vertices).
``n_max``
    The baseline grid's trials (Sec. 6.5) re-derived exactly -- the same study seed, scene
    streams, identification streams and evaluator -- and evaluated at N_max = 100 and at the
    doubled budget (Sec. 11). A failure at 100 that passes at 200 was budget-capped.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from graspcampaign.campaign.grid import stream_key
from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common, quasi_static
from graspcampaign.campaign.kinds.sensitivity import plan_and_evaluate
from graspcampaign.campaign.schema import NODES, config_field
from graspcampaign.core.words import meant
from graspcampaign.errors import ConfigError

PANELS = ("resolution", "budget", "n_max")

BASELINE_STUDY = "baseline_grid"
"""The study whose trials the ``n_max`` panel re-derives (campaigns/baseline_grid.yaml)."""

FIVE_SHAPES = ["sphere", "ellipsoid", "rounded_cube", "pear", "handle"]


@dataclass
class MeshResolutionParams:
    """Design of the three panels; the ``baseline_*`` values must equal baseline_grid.yaml."""

    panels: list[str] = config_field(list(PANELS))
    shape: str = config_field("sphere", choices="shape")
    planner: str = config_field("heuristic", choices="planner")
    mass_kg: float = config_field(0.4, gt=0.0)
    mu: float = config_field(0.3, ge=0.0)
    # resolution panel (Sec. 6.7)
    resolutions: list[int] = config_field([144, 250, 356, 390, 600, 900, 1300, 1750], **NODES)
    identify_nodes: int = config_field(356, **NODES)  # Sec. 5.1 operating mesh
    reference_nodes: int = config_field(144, **NODES)  # timing reference
    timing_repeats: int = config_field(7, ge=1)
    # budget panel (Sec. 11: success vs N_cand, future work in the paper)
    budgets: list[int] = config_field([1, 3, 10, 30, 100, 300, 1000])
    budget_shapes: list[str] = config_field(FIVE_SHAPES)
    budget_nodes: list[int] = config_field([144, 390], **NODES)
    budget_seeds: int = config_field(20, ge=1)
    # n_max panel (Sec. 11: doubled-budget re-run of the baseline grid)
    nmax_rerun: int = config_field(200, ge=1)
    baseline_seed: int = config_field(605, ge=0)
    baseline_shapes: list[str] = config_field(FIVE_SHAPES)
    baseline_masses_kg: list[float] = config_field([0.2, 0.4, 0.6])
    baseline_mus: list[float] = config_field([0.1, 0.3, 0.5])
    baseline_seeds: int = config_field(15, ge=1)
    baseline_planners: list[str] = config_field(["heuristic", "antipodal", "random", "centroid",
                                          "ferrari_canny"])

    def __post_init__(self) -> None:
        unknown = [p for p in self.panels if p not in PANELS]
        if unknown or not self.panels:
            raise ConfigError(f"params.panels has unknown panel {unknown[0]!r}; "
                              f"{meant(unknown[0], PANELS)}allowed: {', '.join(PANELS)}." if unknown else
                              "params.panels must name at least one panel.")
        for key in ("resolutions", "budgets", "budget_nodes"):
            values = getattr(self, key)
            if not values or any(int(v) != v or v < 1 for v in values):
                raise ConfigError(f"params.{key} must be a non-empty list of positive ints, "
                                  f"got {values!r}.")


def design(study, params: MeshResolutionParams) -> list[dict[str, Any]]:
    """Return the trials of the selected panels (resolution, budget, n_max)."""
    rows: list[dict[str, Any]] = []
    base = {"shape": params.shape, "mass_kg": params.mass_kg, "mu": params.mu}
    if "resolution" in params.panels:
        for nodes in params.resolutions:
            for seed in range(study.seeds):
                rows.append({"panel": "resolution", **base, "planner": params.planner,
                             "nodes": int(nodes), "seed": seed})
    if "budget" in params.panels:
        for shape in params.budget_shapes:
            for nodes in params.budget_nodes:
                common_ = {"panel": "budget", "shape": shape, "mass_kg": params.mass_kg,
                           "mu": params.mu, "nodes": int(nodes)}
                for seed in range(params.budget_seeds):
                    for n_cand in params.budgets:
                        rows.append({**common_, "planner": "heuristic", "n_cand": int(n_cand),
                                     "seed": seed})
                # deterministic when exhaustive; one draw of the sampled reference otherwise
                rows.append({**common_, "planner": "reference", "n_cand": 0, "seed": 0})
    if "n_max" in params.panels:
        for shape in params.baseline_shapes:
            for mass in params.baseline_masses_kg:
                for mu in params.baseline_mus:
                    for planner in params.baseline_planners:
                        for seed in range(params.baseline_seeds):
                            rows.append({"panel": "n_max", "shape": shape, "mass_kg": float(mass),
                                         "mu": float(mu), "planner": planner, "seed": seed})
    return rows


def _baseline_body(factors: dict[str, Any]) -> dict[str, Any]:
    """The body key the baseline grid's runner used for this scene (quasi_static.body_key)."""
    return quasi_static.body_key({k: factors[k] for k in ("shape", "mass_kg", "mu")})


def body_key(factors: dict[str, Any]) -> dict[str, Any]:
    """Bodies: fixed identification (resolution), per mesh (budget), the baseline's (n_max)."""
    panel = factors["panel"]
    if panel == "n_max":
        return {**_baseline_body(factors), "reproduces": BASELINE_STUDY}
    return {"shape": factors["shape"], "nodes": None if panel == "resolution" else factors["nodes"],
            "mass_kg": factors["mass_kg"], "mu": factors["mu"], "panel": panel}


def prepare(study, params: MeshResolutionParams, body, rng: np.random.Generator) -> dict[str, Any]:
    """Identify a body by PSO as ``quasi_static`` does (Sec. 4).

    The resolution panel's one body is identified on ``identify_nodes``. A ``n_max`` body uses
    the baseline grid's identification stream (its study seed and body key), so the re-derived
    trials see exactly the parameters the baseline grid's trials saw.
    """
    qparams = quasi_static.QuasiStaticParams()
    core = {k: body[k] for k in ("shape", "nodes", "mass_kg", "mu")}
    if body.get("reproduces") == BASELINE_STUDY:
        rng = np.random.default_rng(np.random.SeedSequence(
            params.baseline_seed, spawn_key=stream_key({"prepare": core})))
    elif body.get("panel") == "resolution":
        core["nodes"] = params.identify_nodes
    return quasi_static.prepare(study, qparams, core, rng)


def _timed(fn, *args) -> float:
    start = time.perf_counter()
    fn(*args)
    return time.perf_counter() - start


def _resolution(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Outcome on this mesh plus its per-evaluation cost against the reference mesh."""
    from graspcampaign.core.planner import PLANNERS, evaluate_triple, identification_contacts

    f, study, params = inp.trial.factors, inp.study, inp.params
    contact = quasi_static.body_contact(study, inp.prepared)
    ctx, _, out = plan_and_evaluate(study, f["shape"], f["nodes"], f["mass_kg"], f["mu"], contact,
                                    f["planner"], rng)
    ref_ctx, _, _ = plan_and_evaluate(study, f["shape"], params.reference_nodes, f["mass_kg"],
                                      f["mu"], contact, f["planner"],
                                      np.random.default_rng(rng.integers(2**63)))
    planner = PLANNERS[f["planner"]]
    timing_rng = np.random.default_rng(rng.integers(2**63))
    own, ref, search, loop = [], [], [], []
    for _ in range(params.timing_repeats):  # interleaved: both meshes see the same machine load
        own.append(_timed(planner, ctx, timing_rng))
        ref.append(_timed(planner, ref_ctx, timing_rng))
        start = time.perf_counter()
        _, points, normals = identification_contacts(ctx, timing_rng)  # Alg. 1 lines 1-2
        middle = time.perf_counter()
        evaluate_triple(ctx, points, normals)  # Alg. 2 + line 6
        end = time.perf_counter()
        search.append(middle - start)
        loop.append(end - middle)
    out.update({
        "eval_time_s": float(np.median(own)),
        "eval_time_min_s": float(np.min(own)),
        "eval_time_reference_s": float(np.median(ref)),
        "eval_time_reference_min_s": float(np.min(ref)),
        # the fastest repeats: a repeat another process slowed is slower, never faster (docs/decisions.md)
        "cost_ratio_vs_reference": float(np.min(own) / np.min(ref)),
        "reference_nodes": params.reference_nodes,
        "search_time_s": float(np.median(search)),
        "equilibrium_time_s": float(np.median(loop)),
        "timing_repeats": params.timing_repeats,
        "identify_nodes": params.identify_nodes,
        "n_faces": int(len(ctx.faces)),
    })
    return out


def _budget(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    f, study = inp.trial.factors, inp.study
    contact = quasi_static.body_contact(study, inp.prepared)
    n_cand = f["n_cand"] if f["planner"] != "reference" else study.evaluator.n_cand
    _, _, out = plan_and_evaluate(study, f["shape"], f["nodes"], f["mass_kg"], f["mu"], contact,
                                  f["planner"], rng, n_cand=n_cand)
    out.pop("n_cand")  # a factor of this panel (0 for the reference row)
    return out


def _n_max(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Re-derive one baseline-grid trial and evaluate its grasp at N_max and at the re-run budget."""
    from graspcampaign.core.planner import evaluate_triple

    f, study, params = inp.trial.factors, inp.study, inp.params
    scene = {"shape": f["shape"], "mass_kg": f["mass_kg"], "mu": f["mu"], "seed": f["seed"],
             "repeat": 0}
    baseline_rng = np.random.default_rng(np.random.SeedSequence(
        params.baseline_seed, spawn_key=stream_key({"study": BASELINE_STUDY, "scene": scene})))
    contact = quasi_static.body_contact(study, inp.prepared)
    ctx, plan, out = plan_and_evaluate(study, f["shape"], common.DEFAULT_NODES, f["mass_kg"],
                                       f["mu"], contact, f["planner"], baseline_rng)
    doubled = replace(ctx, evaluator=replace(ctx.evaluator, n_max=params.nmax_rerun))
    rerun = evaluate_triple(doubled, plan.points, plan.normals, contact=contact)
    again = common.verdict_columns(rerun, doubled.evaluator)
    out.update({
        "nodes": common.DEFAULT_NODES,
        "n_max": ctx.evaluator.n_max,
        "n_max_rerun": params.nmax_rerun,
        "success_rerun": again["success"],
        "success_unbounded_rerun": again["success_unbounded"],
        "success_norm_rerun": again["success_norm"],
        "success_vertical_rerun": again["success_vertical"],
        "failure_check_rerun": str(rerun.failure_labels()[0]),
        "residual_norm_rerun_n": float(rerun.residual_norm[0]),
        "residual_z_rerun_n": float(rerun.residual_z[0]),
        "slip_margin_rerun_n": float(rerun.slip_margin[0]),
        "iterations_rerun": int(rerun.iterations[0]),
        "budget_capped": bool(not out["success"] and rerun.success[0]),
        "baseline_seed": params.baseline_seed,
    })
    return out


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Dispatch on the trial's panel."""
    out = {"resolution": _resolution, "budget": _budget, "n_max": _n_max}[
        inp.trial.factors["panel"]](inp, rng)
    out["pso_at_bound"] = common.at_bound_text(inp.prepared)
    return out


MESH_RESOLUTION = TrialKind(
    name="mesh_resolution",
    run=run,
    params=MeshResolutionParams,
    seconds_per_trial=0.02,
    body_key=body_key,
    prepare=prepare,
    design=design,
    trial_keys=("panel",),  # the figure panel a design row belongs to
    description="Fig. 20 runtime/residual vs nodes; success vs N_cand; N_max = 200 re-run",
    stages="a PSO identification of each body before its trials (Sec. 4)",
)
