"""Synthetic executed Test 2/3 records with known answers, shared by test_hardware.py and
test_hardware_derive.py.

Imported by name (``from hardware_records import ...``), as pytest puts this directory on the path.
"""

from __future__ import annotations

import pandas as pd

PREDICTED = ("normal_force_mean_n", "normal_force_pred_mean_n", "deformation_mean_mm",
             "deformation_pred_mean_mm", "g_geo_believed", "g_geo_actual", "mu_s_believed")


def planner_records(planner_counts: dict[str, tuple[int, int]], **extra) -> pd.DataFrame:
    """Executed records with ``k`` successes out of ``n`` per planner, objects cycled over 10."""
    rows = []
    for planner, (k, n) in planner_counts.items():
        for i in range(n):
            ok = i < k
            rows.append({"trial_id": f"{planner}-{i}", "planner": planner, "status": "ok",
                         "object_id": f"obj-{i % 10}", "aborted": False, "success": ok,
                         "outcome": "stable" if ok else "failure_slip", "friction_level": "natural",
                         "condition": "c", "repeat": i, **{c: 1.0 for c in PREDICTED}, **extra})
    return pd.DataFrame(rows)
