"""Campaign-level benchmark: the full baseline grid on every core, then its report.

1. `baseline_grid` (3375 trials, 45 PSO identifications) through the engine with the loky
   backend on every core (issue 4 target: under 60 s).
2. Its full report (tables, bootstrap intervals, McNemar, figures) at the real 3375 records. The
   report at 10^5 records (issue 5 target: under 10 s) is measured by ``bench_report.py``, which
   tiles real records of two studies into runs the run checks accept.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from pathlib import Path

from _common import print_table

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.runner import run_study
from graspcampaign.report.build import build_reports


def main() -> None:
    root = Path(tempfile.mkdtemp(prefix="gc-bench-campaign-"))
    rows = []
    try:
        study = compose_study("baseline_grid", [f"output.root={root}", "runner.progress=false"])
        t0 = time.perf_counter()
        summary = run_study(study)
        grid_s = time.perf_counter() - t0
        rows.append((f"baseline_grid, {summary.n_trials} trials + 45 identifications, loky on "
                     f"{os.cpu_count()} cores", f"{grid_s:.1f} s", "", "< 60 s"))
        t0 = time.perf_counter()
        build_reports(["baseline_grid"], run="default", root=root)
        rows.append((f"its full report, {summary.n_trials:,} records",
                     f"{time.perf_counter() - t0:.1f} s", "", ""))
    finally:
        shutil.rmtree(root, ignore_errors=True)
    print()
    print_table(["measure", "value", "reference in the same run", "target"], rows)


if __name__ == "__main__":
    main()
