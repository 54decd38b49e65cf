"""Compile the numba kernels into their on-disk cache once, at install time (``make install``).

``python -m graspcampaign.cli.warm`` runs a few studies at a tiny scale in a temporary results
root, which calls every ``njit(cache=True)`` kernel of the core layer with the argument types the
campaign uses. numba writes each compiled kernel beside its source (``__pycache__``, keyed by the
source file's modification time and size), so the next process -- a test session, a study run --
loads it instead of compiling it again; the report's rank kernels (``analysis.rank_kernel``) are
warmed by one call each. Nothing under ``results/`` is touched. The studies run in
parallel processes, one per core at most; the output is one line per study.

References
----------
numba documentation, "Notes on Caching":
https://numba.readthedocs.io/en/stable/developer/caching.html
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor

#: study -> overrides of a tiny run that reaches every compiled kernel the study uses
WARM_RUNS = {
    # the quasi-static path: face bounds, the narrow phase and the epsilon facets (core.kernels)
    "smoke": ["nodes=[144]", "seeds=1"],
    # every planner, Ferrari-Canny's epsilon facets among them (core.kernels)
    "baseline_grid": ["seeds=1", "shape=[sphere]", "mass_kg=[0.4]", "mu=[0.3]"],
    # the mass-spring body: RK4, its audit step, the implicit midpoint rule (core.msd_kernel)
    "gravity_settle": ["nodes=[144]", "+params.settle_t_max_s=0.01"],
    # the dynamic grasp: contact stage, compiled step and phase loop (grasp_kernel, phase_kernel)
    "friction_mass": ["nodes=[144]", "mu=[0.5]", "mass_kg=[0.4]", "+params.t_max_s=0.01"],
    # the particle swarm (core.pso_kernel)
    "pso_repeatability": ["seeds=1", "budget=[repeatability]"],
    # the virtual bench and the least-squares fits (core.bench_kernels, core.fit_kernel)
    "test1_bench": ["params.materials=[gel]", "params.specimens=[1,11]", "params.pso_restarts=1",
                    "params.pso_particles=4", "params.pso_iterations=2", "params.pso_max_reruns=1"],
}


def warm_one(study: str, root: str) -> str:
    """Run ``study`` at its tiny scale under ``root``; return one line saying how long it took."""
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.runner import run_study

    start = time.perf_counter()
    run_study(compose_study(study, ["runner.backend=sequential", "runner.progress=false",
                                    f"output.root={root}", *WARM_RUNS[study]]))
    return f"warm: {study} in {time.perf_counter() - start:.1f} s"


def main() -> int:
    """Warm every kernel; return the exit code (0, or 1 if a run failed)."""
    import numpy as np

    from graspcampaign.analysis.quasi_static import weighted_spearman
    from graspcampaign.analysis.rank_kernel import row_medians

    weighted_spearman([0.0, 1.0], [1.0, 0.0], [1.0, 1.0])  # the report's rank kernels (analysis)
    row_medians(np.zeros((1, 2), dtype=np.int32), np.zeros(1))
    jobs = max(1, min(len(WARM_RUNS), os.cpu_count() or 1))
    with tempfile.TemporaryDirectory(prefix="graspcampaign-warm-") as root:
        with ProcessPoolExecutor(jobs) as pool:
            futures = {s: pool.submit(warm_one, s, os.path.join(root, s)) for s in WARM_RUNS}
            failed = []
            for study, future in futures.items():
                try:
                    print(future.result(), flush=True)
                except Exception as exc:  # noqa: BLE001 - say which study failed, warm the rest
                    print(f"warm: {study} failed: {exc}", file=sys.stderr, flush=True)
                    failed.append(study)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
