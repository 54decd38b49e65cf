"""A virtual rig's executed trials of a Tests 2-3 schedule, as a rig would export them: shared by
test_ingest.py and test_ingest_cell_types.py.

Imported by name (``from virtual_exports import ...``), as pytest puts this directory on the path.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from graspcampaign.rig.plan import predict_trial
from graspcampaign.rig.virtual import virtual_trial


def virtual_run(schedule: pd.DataFrame, n_executed: int) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame]:
    """The faulted and second-attempt rows and the first ``n_executed`` clean first attempts of
    ``schedule``, in run order; the planner's predictions and the virtual rig's measurements of each."""
    rows = pd.concat([schedule[schedule["rig_fault"] | (schedule["attempt"] == 2)],
                      schedule[~schedule["rig_fault"] & (schedule["attempt"] == 1)]
                      .head(n_executed)])
    rows = rows.sort_values("run_order")
    preds = pd.DataFrame([predict_trial(r) for r in rows.to_dict("records")])
    meas = pd.DataFrame([virtual_trial(r, p, np.random.default_rng(i)) for i, (r, p) in
                         enumerate(zip(rows.to_dict("records"), preds.to_dict("records"),
                                       strict=True))])
    meas.insert(0, "trial_id", rows["trial_id"].to_numpy())
    return rows.reset_index(drop=True), preds, meas
