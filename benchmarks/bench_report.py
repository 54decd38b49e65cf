"""Benchmark the report at campaign scale: ~10^5 real engine records per run.

Run: ``python benchmarks/bench_report.py``. Where the records come from: each of the
``baseline_grid`` and ``ablation`` studies is run by the engine (``run_study``, sequential backend)
with one seed over its full factor grid (a few hundred trials each, ~10 s) in a temporary results
root. Its records, its ``tables/candidates`` (the ferrari_canny trials' sampled candidates, keyed
by ``trial_id``, which the ``h_epsilon`` table and figure read) and its ``prepared/``
identifications (one per body, shared by every seed, so copied as they are) are then tiled into a
run ``bench`` of about 10^5 records: copy ``k`` of every record gets ``c<k>`` in its ``trial_id``
(before the hash) and ``-c<k>`` after its ``scene_id`` (its candidates follow its ``trial_id``),
``seed`` offset by ``k`` seeds and ``trial_index`` by ``k`` runs, so ids stay unique and matched
pairs (McNemar pairs planners, and grip laws, on one ``scene_id``) stay matched within each copy.
Copies are therefore exact repeats of one seed's outcomes: the timings are at campaign scale, the
statistics are not a campaign's. The records are written in 20 shards as a run writes them; the
manifest is the real run's with the run name, ``n_trials`` and ``seeds`` (= copies, and so its
``config_hash``) changed, so the report finds the study's paper values and evaluator config. Then
``build_reports`` is timed for each run (every table, the shape-clustered bootstraps, McNemar on
matched pairs, the figures, the headline page) and a Markdown table printed. Reference measured in
the same run: reading the same records back into pandas (the least any report must do). Issue 5
target: the full report under 10 s. No asserts on time.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np
import pyarrow as pa
from _common import best_of, print_table

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.grid import content_hash
from graspcampaign.campaign.provenance import config_digest, read_manifest, write_manifest
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study
from graspcampaign.report.build import build_reports

N_TARGET = 100_000
STUDIES = ["baseline_grid", "ablation"]
N_SHARDS = 20


def real_run(src: Path, name: str) -> RunStore:
    """Run study ``name`` with the engine, one seed over its full factor grid, under ``src``."""
    summary = run_study(compose_study(name, ["runner.backend=sequential", "runner.progress=false",
                                             f"output.root={src}", "seeds=1"]))
    if summary.n_error:
        print(f"{name}: {summary.n_error} of {summary.n_trials} trials errored "
              f"(first: {summary.first_error})")
    return RunStore(summary.path)


def _string_columns(table: pa.Table) -> tuple[str, ...]:
    """The string columns of ``table`` (kept strings in shards where every value is missing)."""
    return tuple(f.name for f in table.schema if pa.types.is_string(f.type)
                 or pa.types.is_large_string(f.type))


def _tiled(trial_id: str, k: int) -> str:
    """Copy ``k``'s id of ``trial_id``: ``c<k>`` before its hash, so it keeps the tool's id form
    (``<name>-<10 hex>``, which a run's check requires)."""
    name, digest = trial_id.rsplit("-", 1)
    return f"{name}c{k:04d}-{digest}"


def _copy(rows: list[dict], k: int, n_seeds: int, n_trials: int) -> list[dict]:
    """Copy ``k`` of ``rows``: ids marked, seed and trial index offset by ``k`` runs."""
    out = []
    for r in rows:
        c = {**r, "trial_id": _tiled(r["trial_id"], k), "run": "bench"}
        if "scene_id" in r:
            c["scene_id"] = f"{r['scene_id']}-c{k:04d}"
        if r.get("seed") is not None:
            c["seed"] = r["seed"] + k * n_seeds
        if r.get("trial_index") is not None:
            c["trial_index"] = r["trial_index"] + k * n_trials
        out.append(c)
    return out


def tiled_run(real: RunStore, root: Path, name: str) -> tuple[RunStore, int]:
    """Write run ``bench`` of study ``name`` under ``root``: ~N_TARGET copies of ``real``'s trials."""
    records = real.read()
    rows, strings = records.to_pylist(), _string_columns(records)
    n_real = len(rows)
    copies = -(-N_TARGET // n_real)
    n_seeds = int(np.max(records.column("seed").to_numpy(zero_copy_only=False))) + 1
    n_index = int(np.max(records.column("trial_index").to_numpy(zero_copy_only=False))) + 1
    store = RunStore(root / name / "bench")
    for s, ks in enumerate(np.array_split(np.arange(copies), N_SHARDS)):  # shards, as a run writes
        part = [c for k in ks for c in _copy(rows, int(k), n_seeds, n_index)]
        store.write_shard("records", content_hash(s), part, strings=strings)  # a name the store writes
    tables = real.path / "tables"
    for table in sorted(p.name for p in tables.iterdir() if p.is_dir()) if tables.is_dir() else []:
        aux = real.read(f"tables/{table}")
        aux_rows, aux_strings = aux.to_pylist(), _string_columns(aux)
        for s, ks in enumerate(np.array_split(np.arange(copies), N_SHARDS)):
            part = [{**r, "trial_id": _tiled(r["trial_id"], int(k))} for k in ks for r in aux_rows]
            store.write_shard(f"tables/{table}", content_hash(s), part, strings=aux_strings)
    if (real.path / "prepared").is_dir():
        shutil.copytree(real.path / "prepared", store.path / "prepared")
    manifest = read_manifest(real.manifest_path)
    manifest.update(run="bench", n_trials=n_real * copies)
    manifest["config"]["seeds"] = n_seeds * copies
    manifest["config_hash"] = config_digest(manifest["config"])  # what the run's check recomputes
    write_manifest(store.manifest_path, manifest)
    return store, n_real * copies


def main() -> None:
    tmp = Path(tempfile.mkdtemp(prefix="gc-bench-report-"))
    src, root = tmp / "engine", tmp / "results"
    rows = []
    try:
        for name in STUDIES:
            real = real_run(src, name)
            store, n = tiled_run(real, root, name)
            read_s = best_of(lambda s=store: s.read().to_pandas(), repeat=2)
            report_s = best_of(lambda nm=name: build_reports([nm], run="bench", root=root), repeat=2)
            figures = len(list((store.path / "report" / "figures").glob("*.png")))
            tables = len(list((store.path / "report" / "tables").glob("*.csv")))
            rows.append((f"`{name}` report ({tables} tables, {figures} figures)", f"{n:,}",
                         f"{report_s:.2f} s", f"{read_s:.2f} s", f"{report_s / read_s:.1f}×",
                         "< 10 s"))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print()
    print_table(["measure", "records", "full report", "reference: read records", "ratio", "target"],
                rows)


if __name__ == "__main__":
    main()
