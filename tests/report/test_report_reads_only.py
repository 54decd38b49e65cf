"""``report`` never fits a model or times anything (issue 14 item 4): two reports of the same records
give byte-identical tables, and the report path never imports scikit-learn."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import graspcampaign
from graspcampaign.report.build import build_reports


@pytest.mark.parametrize("study", ["surrogate", "test1_bench"])
def test_two_reports_of_the_same_records_give_identical_tables(sim_root, tmp_path, study):
    root = tmp_path / "results"
    shutil.copytree(sim_root / study / "default", root / study / "default",
                    ignore=shutil.ignore_patterns("report"))
    out = root / study / "default" / "report"
    tables = []
    for _ in range(2):
        assert build_reports([study], root=root, formats=["csv", "json"]).failed == []
        tables.append({p.name: p.read_bytes() for p in [*(out / "tables").iterdir(), out / "tables.json"]})
        shutil.rmtree(out)
    assert tables[0] == tables[1] and len(tables[0]) > 5


def test_the_report_path_never_imports_scikit_learn(sim_root, tmp_path):
    root = tmp_path / "results"
    for study in ("surrogate", "test1_bench"):
        shutil.copytree(sim_root / study / "default", root / study / "default",
                        ignore=shutil.ignore_patterns("report"))
    code = ("import sys\nfrom graspcampaign.report.build import build_reports\n"
            f"batch = build_reports(root={str(root)!r})\n"
            "assert batch.failed == [], batch.failed\n"
            "print(sorted(m for m in sys.modules if m == 'sklearn' or m.startswith('sklearn.')))\n")
    env = {**os.environ, "PYTHONPATH": str(Path(graspcampaign.__file__).parents[1])}  # this tree
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip() == "[]"
    assert (root / "surrogate" / "default" / "report" / "tables" / "surrogate_timing.csv").exists()
