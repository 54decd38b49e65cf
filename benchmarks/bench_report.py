"""Benchmark the report at campaign scale: 10^5 synthetic quasi-static records per run.

Run: ``python benchmarks/bench_report.py``. Writes synthetic runs of the ``baseline_grid`` and
``ablation`` designs (the record columns of docs/records.md, outcomes drawn per planner) with
about 10^5 records each to a temporary results root, then times ``build_reports`` for each (every
table, the shape-clustered bootstraps, McNemar on matched pairs, the figures, the headline page)
and prints a Markdown table. Reference measured in the same run: reading the same records back
into pandas (the least any report must do). Issue 5 target: the full report under 10 s. No
asserts on time.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
from _common import best_of, print_table

from graspcampaign.campaign.provenance import new_manifest, write_manifest
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.schema import StudyCfg
from graspcampaign.report.build import build_reports

N_TARGET = 100_000
SHAPES = ["sphere", "ellipsoid", "rounded_cube", "pear", "handle"]
P_SUCCESS = {"heuristic": 0.68, "antipodal": 0.40, "random": 0.11, "centroid": 0.0,
             "no_s1": 0.7, "no_s2": 0.7, "no_s3": 0.7, "no_pc": 0.7, "no_pe": 0.7}
DESIGNS = {
    "baseline_grid": {"shape": SHAPES, "mass_kg": [0.2, 0.4, 0.6], "mu": [0.1, 0.3, 0.5],
                      "planner": ["heuristic", "antipodal", "random", "centroid"]},
    "ablation": {"shape": SHAPES, "mass_kg": [0.4], "mu": [0.3],
                 "planner": ["heuristic", "no_s1", "no_s2", "no_s3", "no_pc", "no_pe", "random",
                             "centroid"]},
}
PAPER = {"baseline_grid": {"success_pct": {"heuristic": 67.6, "antipodal": 40.0, "random": 11.0,
                                           "centroid": 0.0}, "trials_per_planner": 675},
         "ablation": {"success_pct": {"heuristic": 72.0, "random": 6.0, "centroid": 0.0},
                      "trials_per_variant": 50}}


def synthetic_run(root: Path, name: str, rng: np.random.Generator) -> tuple[RunStore, int]:
    """Write ~N_TARGET quasi_static records of study ``name`` (vectorised; no trial runs)."""
    factors = DESIGNS[name]
    cells = int(np.prod([len(v) for v in factors.values()]))
    seeds = -(-N_TARGET // cells)
    grid = pd.MultiIndex.from_product([*factors.values(), range(seeds)],
                                      names=[*factors, "seed"]).to_frame(index=False)
    n = len(grid)
    p = grid["planner"].map(P_SUCCESS).to_numpy()
    success = rng.random(n) < p
    check = np.where(success, "none", rng.choice(["residual", "torque", "slip"], n))
    deltas = rng.lognormal(np.log(2.0), 1.0, (n, 3))
    scene = (grid["shape"] + "-" + grid["mass_kg"].astype(str) + "-" + grid["mu"].astype(str)
             + "-" + grid["seed"].astype(str))
    df = grid.assign(
        trial_id=scene + "-" + grid["planner"], study=name, run="bench", kind="quasi_static",
        trial_index=np.arange(n), scene_id=scene, repeat=0, status="ok", error_type=None,
        error_message=None, wall_time_s=rng.uniform(0.005, 0.02, n), worker="w", host="h",
        source="simulation", nodes=390, n_cand=200, success=success, failure_check=check,
        residual_norm_n=np.where(success, rng.uniform(0, 0.5, n), rng.uniform(0.5, 5, n)),
        torque_norm_nm=rng.uniform(0, 0.05, n), slip_margin_n=rng.normal(0.5, 1, n),
        eta=rng.uniform(0, 1, n), delta_max_mm=deltas.max(axis=1),
        exceeds_1mm=deltas.max(axis=1) > 1, iterations=rng.integers(1, 100, n),
        h_total=rng.uniform(0.1, 0.5, n), lambda1=0.332, lambda2=0.88, n_exp=0.487,
        plan_time_s=rng.uniform(0.01, 0.03, n))
    for j in range(3):
        df[f"delta_{j + 1}_mm"] = deltas[:, j]
        df[f"normal_force_{j + 1}_n"] = rng.uniform(0, 10, n)
    errors = rng.random(n) < 0.002
    df.loc[errors, ["status", "error_type", "error_message"]] = ["error", "RuntimeError", "x"]
    df["success"] = pd.array(success, dtype="boolean")
    df.loc[errors, "success"] = pd.NA
    store = RunStore(root / name / "bench")
    for k, part in enumerate(np.array_split(np.arange(n), 20)):  # shards, as a run writes them
        store.write_shard("records", f"{k:03d}", df.iloc[part].to_dict(orient="records"))
    study = StudyCfg(name=name, kind="quasi_static", seed=605, seeds=seeds, factors=factors,
                     paper=PAPER[name])
    write_manifest(store.manifest_path, new_manifest(study, "bench", n, "simulation"))
    return store, n


def main() -> None:
    root = Path(tempfile.mkdtemp(prefix="gc-bench-report-"))
    rows = []
    try:
        rng = np.random.default_rng(0)
        for name in DESIGNS:
            store, n = synthetic_run(root, name, rng)
            read_s = best_of(lambda s=store: s.read().to_pandas(), repeat=2)
            report_s = best_of(lambda nm=name: build_reports([nm], run="bench", root=root), repeat=2)
            figures = len(list((store.path / "report" / "figures").glob("*.png")))
            tables = len(list((store.path / "report" / "tables").glob("*.csv")))
            rows.append((f"`{name}` report ({tables} tables, {figures} figures)", f"{n:,}",
                         f"{report_s:.2f} s", f"{read_s:.2f} s", f"{report_s / read_s:.1f}×",
                         "< 10 s"))
    finally:
        shutil.rmtree(root, ignore_errors=True)
    print()
    print_table(["measure", "records", "full report", "reference: read records", "ratio", "target"],
                rows)


if __name__ == "__main__":
    main()
