"""Campaign-engine benchmark: overhead per trial, 1 -> 2 worker speed-up, reading 1e5 records.

Every figure is a ratio against a reference measured in this same run:
- engine overhead per trial = (run_study time - bare joblib.Parallel time) / n_trials, for the
  same trials and the same function (target < 1 ms);
- speed-up = run_study with 1 worker / with 2 workers on ~10 ms trials (target >= 1.7x);
- reading a 1e5-record run back (target < 2 s), before and after compaction.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from _common import print_table
from joblib import Parallel, delayed, parallel_config

from graspcampaign.campaign.grid import content_hash, expand
from graspcampaign.campaign.kind import TrialKind, register_kind
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study
from graspcampaign.campaign.schema import OutputCfg, RunnerCfg, StudyCfg

_WORK = {"n": 1}


def _busy(n_rounds: int, rng: np.random.Generator) -> float:
    """Deterministic single-threaded numpy work (elementwise only, no BLAS threads)."""
    x = rng.random(20_000)
    acc = 0.0
    for _ in range(n_rounds):
        x = np.sin(x) * 1.0001 + 0.1
        acc += float(x[0])
    return acc


@dataclass
class BusyParams:
    rounds: int = 1


def _trial(inp, rng):
    return {"value": _busy(inp.params.rounds, rng)}


def _bare(stream_key, seed, rounds):
    """The same work with nothing around it: the reference for the engine's overhead."""
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=stream_key))
    return _busy(rounds, rng)


KIND = TrialKind(name="bench_busy", run=_trial, params=BusyParams, seconds_per_trial=0.01)


def _study(root: Path, n: int, rounds: int, n_jobs: int, backend: str = "loky") -> StudyCfg:
    study = StudyCfg(name="bench", kind="bench_busy", seeds=n, factors={"mu": [0.3]},
                     runner=RunnerCfg(backend=backend, n_jobs=n_jobs, progress=False),
                     output=OutputCfg(root=str(root), run=f"r{n_jobs}-{rounds}-{time.time_ns()}"))
    study.params = {"rounds": rounds}
    return study


def _time_engine(study: StudyCfg) -> float:
    t0 = time.perf_counter()
    run_study(study)
    return time.perf_counter() - t0


def _calibrate_rounds(target_s: float) -> int:
    rng = np.random.default_rng(0)
    t0 = time.perf_counter()
    _busy(200, rng)
    per_round = (time.perf_counter() - t0) / 200
    return max(1, int(target_s / per_round))


def main() -> None:
    root = Path(tempfile.mkdtemp(prefix="gc-bench-"))
    rows = []
    try:
        register_kind(KIND)
        # 1. overhead per trial against a bare joblib loop over the same trials
        n, rounds = 4000, _calibrate_rounds(0.0005)
        study = _study(root, n, rounds, 2)
        trials = expand(study)
        with parallel_config(backend="loky", n_jobs=2):
            Parallel()(delayed(_bare)(t.stream_key, study.seed, rounds) for t in trials[:50])
            t0 = time.perf_counter()
            list(Parallel(return_as="generator_unordered", batch_size="auto")(
                delayed(_bare)(t.stream_key, study.seed, rounds) for t in trials))
            bare = time.perf_counter() - t0
        engine = _time_engine(study)
        overhead_ms = 1e3 * (engine - bare) / n
        rows.append(("engine overhead per trial (4000 x 0.5 ms trials, 2 workers)",
                     f"{overhead_ms:.3f} ms", f"bare joblib {bare:.2f} s vs engine {engine:.2f} s",
                     "< 1 ms"))

        # 2. speed-up 1 -> 2 workers on ~10 ms trials
        n, rounds = 600, _calibrate_rounds(0.010)
        one = _time_engine(_study(root, n, rounds, 1))
        two = _time_engine(_study(root, n, rounds, 2))
        rows.append(("speed-up 1 -> 2 workers (600 x ~10 ms trials)", f"{one / two:.2f}x",
                     f"1 worker {one:.2f} s, 2 workers {two:.2f} s", ">= 1.7x"))

        # 3. reading 1e5 records back: 1000 task shards of 100 rows, then compacted
        store = RunStore(root / "read" / "run")
        rng = np.random.default_rng(1)
        for shard in range(1000):
            store.write_shard("records", content_hash(shard), [
                {"trial_id": f"t{shard}-{i}", "status": "ok", "shape": "sphere",
                 "mass_kg": 0.4, "mu": 0.3, "success": bool(rng.random() < 0.5),
                 "residual_norm_n": float(rng.random()), "delta_max_mm": float(rng.random()),
                 "wall_time_s": 0.01} for i in range(100)])
        t0 = time.perf_counter()
        n_read = store.read().num_rows
        shards = time.perf_counter() - t0
        store.compact()
        t0 = time.perf_counter()
        n_read2 = store.read().num_rows
        compacted = time.perf_counter() - t0
        assert n_read == n_read2 == 100_000
        rows.append(("read 1e5 records (1000 shards)", f"{shards:.2f} s", "", "< 2 s"))
        rows.append(("read 1e5 records (compacted)", f"{compacted:.2f} s", "", "< 2 s"))
    finally:
        shutil.rmtree(root, ignore_errors=True)

    print(f"\nCampaign engine ({os.cpu_count()} cores)\n")
    print_table(["measure", "value", "reference in the same run", "target"], rows)


if __name__ == "__main__":
    main()
