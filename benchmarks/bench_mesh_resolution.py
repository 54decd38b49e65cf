"""Benchmark the per-evaluation cost at 144 vs 1750 nodes (Sec. 6.7, Fig. 20a), in one run.

Run: ``python benchmarks/bench_mesh_resolution.py``. One evaluation is what the
``mesh_resolution`` study times: Algorithm 1 with its N_cand = 1000 candidate search plus
Algorithm 2 and the checks on the chosen triple, on a prepared per-body context (built once,
excluded, reported separately). The two meshes are timed interleaved, round by round, so machine
load affects both alike; medians over rounds. Also split into the two stages. Prints a Markdown
table with the 1750/144 ratio (target <= 1.5; the paper's MATLAB figures 72/37 ms = 1.95). No
asserts.
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from graspcampaign.core.contact import ContactParams
from graspcampaign.core.feature import sharp_features
from graspcampaign.core.mesh import make_object
from graspcampaign.core.planner import PLANNERS, evaluate_triple, identification_contacts, plan_context

NODES = (144, 1750)
ROUNDS = 200
MASS_KG = 0.4
MU = 0.3
CONTACT = ContactParams.table3()  # fixed across resolutions, as the study holds them (Sec. 12)


def main() -> None:
    contexts, build = {}, {}
    for n in NODES:
        start = time.perf_counter()
        mesh = make_object("sphere", n)
        contexts[n] = plan_context(mesh, sharp_features(mesh), mass=MASS_KG, mu=MU,
                                   contact=CONTACT)
        build[n] = time.perf_counter() - start
    plan = PLANNERS["heuristic"]
    rngs = {n: np.random.default_rng(7) for n in NODES}
    for n in NODES:  # warm-up
        plan(contexts[n], rngs[n])
    full = {n: [] for n in NODES}
    search = {n: [] for n in NODES}
    loop = {n: [] for n in NODES}
    for _ in range(ROUNDS):
        for n in NODES:
            ctx, rng = contexts[n], rngs[n]
            start = time.perf_counter()
            plan(ctx, rng)
            full[n].append(time.perf_counter() - start)
            start = time.perf_counter()
            _, points, normals = identification_contacts(ctx, rng)
            middle = time.perf_counter()
            evaluate_triple(ctx, points, normals)
            search[n].append(middle - start)
            loop[n].append(time.perf_counter() - middle)
    lo, hi = NODES
    print(f"Per-evaluation cost, sphere, N_cand = {contexts[lo].n_cand}, {ROUNDS} interleaved "
          "rounds (medians, wall clock)\n")
    print(f"| quantity | {lo} nodes | {hi} nodes | ratio {hi}/{lo} | reference |")
    print("|---|---|---|---|---|")
    for name, data, ref in (("one evaluation [ms]", full, "target <= 1.5; paper 1.95"),
                            ("candidate search [ms]", search, ""),
                            ("Algorithm 2 + checks [ms]", loop, "")):
        a, b = statistics.median(data[lo]) * 1e3, statistics.median(data[hi]) * 1e3
        print(f"| {name} | {a:.3f} | {b:.3f} | {b / a:.2f} | {ref} |")
    print(f"| context build, once per body [ms] | {1e3 * build[lo]:.1f} | {1e3 * build[hi]:.1f} "
          f"| {build[hi] / build[lo]:.2f} | excluded from one evaluation |")
    print(f"| paper (MATLAB) one evaluation [ms] | 37 | 72 | {72 / 37:.2f} | Sec. 6.7 |")


if __name__ == "__main__":
    main()
