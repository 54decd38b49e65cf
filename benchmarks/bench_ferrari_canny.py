"""Benchmark the Ferrari-Canny epsilon and the ferrari_canny planner (issue 17).

Run: ``python benchmarks/bench_ferrari_canny.py``. Prints a Markdown table with every cost as a
ratio against references measured in the same run (no asserts on time):

- epsilon per triple with the exact facet enumeration (compiled kernel, and its numpy reference),
  against one plain ``scipy.spatial.ConvexHull`` per triple on the same wrenches (the reference
  implementation; target: <= 0.5 ms per triple, about 6 ms for ConvexHull on this machine), on
  two sets: N_CAND candidate triples of the 390-node ellipsoid (mostly not in force closure, which
  the enumeration detects early) and N_CAND triples with random normals, about half in force
  closure (the enumeration's full cost);
- the whole ferrari_canny plan (sampling, epsilon of every candidate, H(G) of every candidate,
  Algorithm 2 on the choice) against the heuristic plan on the same candidates;
- the largest deviation from ConvexHull over the timed triples (relative, force-closure ones).
"""

from __future__ import annotations

import time

import numpy as np
from _common import best_of, print_table

from graspcampaign.core.candidate import candidate_epsilon
from graspcampaign.core.contact import ContactParams
from graspcampaign.core.feature import sharp_features
from graspcampaign.core.ferrari_canny import epsilon_metric, epsilon_qhull, primitive_wrenches
from graspcampaign.core.mesh import make_object
from graspcampaign.core.planner import PLANNERS, plan_context, sample_triples

N_CAND = 1000
N_HULL = 150  # ConvexHull triples timed (about 1 s)
N_PLANS = 20
CONTACT = ContactParams(lambda1=1.5, lambda2=0.5, n=1.0)  # bench placeholder, not an identification


def main() -> None:
    mesh = make_object("ellipsoid", 390)
    ctx = plan_context(mesh, sharp_features(mesh), mass=0.4, mu=0.3, contact=CONTACT,
                       n_cand=N_CAND)
    triples = sample_triples(ctx.sampling_weights, N_CAND, np.random.default_rng(0))
    points, normals = ctx.vertices[triples], ctx.normals[triples]
    args = (ctx.mu, ctx.centroid, ctx.torque_length)
    candidate_epsilon(ctx, triples[:2])  # load the compiled kernel from its cache

    rng = np.random.default_rng(1)
    random_normals = rng.normal(size=(N_CAND, 3, 3))
    random_normals /= np.linalg.norm(random_normals, axis=2, keepdims=True)
    sets = {"mesh candidates": (points, normals, args),
            "random normals": (0.05 * random_normals + 0.01 * rng.normal(size=(N_CAND, 3, 3)),
                               random_normals, (rng.uniform(0.2, 1.0, N_CAND), np.zeros(3), 0.06))}
    rows, notes = [], []
    for label, (p, n, a) in sets.items():
        fast = best_of(lambda p=p, n=n, a=a: epsilon_metric(p, n, *a), 5) / N_CAND
        numpy_path = best_of(lambda p=p, n=n, a=a: epsilon_metric(p, n, *a, backend="numpy"),
                             3) / N_CAND
        mu = np.broadcast_to(a[0], (N_CAND,))[:N_HULL]
        wrenches = primitive_wrenches(p[:N_HULL], n[:N_HULL], mu, *a[1:])
        start = time.perf_counter()
        reference = epsilon_qhull(wrenches)
        hull = (time.perf_counter() - start) / N_HULL
        got = epsilon_metric(p[:N_HULL], n[:N_HULL], mu, *a[1:])
        closure = reference > 1e-9
        deviation = float(np.max(np.abs(got[closure] - reference[closure]) / reference[closure]))
        notes.append(f"{label}: force closure {closure.mean():.0%}, max relative deviation from "
                     f"ConvexHull {deviation:.1e}")
        rows += [
            (f"{label}: epsilon, facet enumeration (numba)", f"{1e3 * fast:.3f} ms/triple",
             f"{hull / fast:.0f}x faster than ConvexHull", "<= 0.5 ms/triple"),
            (f"{label}: epsilon, facet enumeration (numpy)", f"{1e3 * numpy_path:.3f} ms/triple",
             f"{hull / numpy_path:.0f}x faster than ConvexHull", ""),
            (f"{label}: epsilon, ConvexHull per triple (reference)", f"{1e3 * hull:.2f} ms/triple",
             "1", "~6 ms"),
        ]

    def plans(name):
        return best_of(lambda: [PLANNERS[name](ctx, np.random.default_rng(s))
                                for s in range(N_PLANS)], 3) / N_PLANS

    fc_plan, heuristic_plan = plans("ferrari_canny"), plans("heuristic")
    print(f"ellipsoid, 390 nodes, N_cand = {N_CAND}, mu = 0.3, 8 cone edges; " + "; ".join(notes))
    rows += [
        ("ferrari_canny plan (1000 candidates)", f"{1e3 * fc_plan:.1f} ms",
         f"{fc_plan / heuristic_plan:.1f}x the heuristic plan", ""),
        ("heuristic plan (same candidates, reference)", f"{1e3 * heuristic_plan:.1f} ms", "1", ""),
    ]
    print_table(["what", "cost", "ratio", "target"], rows, ["---", "---:", "---:", "---:"])


if __name__ == "__main__":
    main()
