"""Campaign-level benchmark: the full baseline grid on 2 cores, and the report at 1e5 records.

1. `baseline_grid` (2700 trials, 45 PSO identifications) through the engine with the loky
   backend on every core (issue 4 target: under 60 s).
2. The full report (tables, bootstrap intervals, McNemar, figures) for 1e5 quasi-static records
   (issue 5 target: under 10 s). The records are the real baseline-grid records of step 1,
   replicated under new trial ids and seed indices (37 copies), so every column has real values.
   Reference in the same run: the same report at the real 2700 records.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import time
from pathlib import Path

import pandas as pd
import pyarrow as pa
from _common import print_table

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study
from graspcampaign.report.build import build_reports

COPIES = 37  # 37 x 2700 = 99,900 records


def main() -> None:
    root = Path(tempfile.mkdtemp(prefix="gc-bench-campaign-"))
    rows = []
    try:
        study = compose_study("baseline_grid", [f"output.root={root}", "runner.progress=false"])
        t0 = time.perf_counter()
        summary = run_study(study)
        grid_s = time.perf_counter() - t0
        rows.append(("baseline_grid, 2700 trials + 45 identifications, loky on "
                     f"{os.cpu_count()} cores", f"{grid_s:.1f} s", "", "< 60 s"))

        t0 = time.perf_counter()
        build_reports(["baseline_grid"], run="default", root=root)
        small_s = time.perf_counter() - t0

        records = RunStore(summary.path).read().to_pandas()
        copies = []
        for k in range(COPIES):
            copy = records.copy()
            copy["trial_id"] = copy["trial_id"] + f"-c{k}"
            copy["run"] = "big"  # the records of run big (another run's would be refused)
            copy["scene_id"] = copy["scene_id"] + f"-c{k}"
            copy["seed"] = copy["seed"] + k * int(records["seed"].max() + 1)
            copies.append(copy)
        big = pd.concat(copies, ignore_index=True)
        big_dir = root / "baseline_grid" / "big"
        store = RunStore(big_dir)
        (big_dir / "records").mkdir(parents=True)
        import pyarrow.parquet as pq

        pq.write_table(pa.Table.from_pandas(big, preserve_index=False),
                       big_dir / "records" / "part-all.parquet")
        shutil.copytree(summary.path / "prepared", big_dir / "prepared")
        manifest = json.loads((summary.path / "manifest.json").read_text())
        manifest.update(run="big", n_trials=len(big))
        manifest["config"]["seeds"] = int(big["seed"].max() + 1)
        (big_dir / "manifest.json").write_text(json.dumps(manifest, default=str))
        t0 = time.perf_counter()
        build_reports(["baseline_grid"], run="big", root=root)
        big_s = time.perf_counter() - t0
        assert store.read(columns=["trial_id"]).num_rows == len(big)
        rows.append((f"full report, {len(big):,} records", f"{big_s:.1f} s",
                     f"same report at 2,700 records: {small_s:.1f} s", "< 10 s"))
    finally:
        shutil.rmtree(root, ignore_errors=True)
    print()
    print_table(["measure", "value", "reference in the same run", "target"], rows)


if __name__ == "__main__":
    main()
