"""Virtual rig benchmark: the cost of the ``belief_error = none`` counterfactual (issue 13).

Every figure is measured in this same run, on one core, over the full commanded sheet of a study
(Test 2: 1785 rows; ``python benchmarks/bench_virtual_rig.py test3_disturbance`` for Test 3):
- the planner's predictions alone (plans warmed into the per-process cache first), the reference;
- one trial executed under the ``paper`` reading (predictions + virtual execution);
- one trial executed under both readings (``params.belief_error = [paper, none]``, the default).
Ratios are to the reference. These are virtual-rig model outputs (source = "virtual").

Run: ``python benchmarks/bench_virtual_rig.py [study]``.
"""

from __future__ import annotations

import sys

import numpy as np
from _common import best_of, print_table

from graspcampaign.campaign.kinds import hardware as H
from graspcampaign.rig import protocol
from graspcampaign.rig.plan import predict_trial

SEEDS = {"test2_grasp": 801, "test3_disturbance": 901}  # campaigns/*.yaml


def main(study: str = "test2_grasp") -> None:
    maker = protocol.test2_schedule if study == "test2_grasp" else protocol.test3_schedule
    rows = maker(SEEDS[study]).to_dict("records")
    for r in rows:  # warm the per-process plan cache: the engine's workers keep theirs too
        predict_trial(r)

    def predict():
        for r in rows:
            predict_trial(r)

    def run(beliefs):
        def go():
            for i, r in enumerate(rows):
                H.execute(r, np.random.default_rng(i), beliefs)
        return go

    ref = best_of(predict, 2)
    paper = best_of(run(("paper",)), 2)
    both = best_of(run(("paper", "none")), 2)
    print(f"## Virtual rig, {study} ({len(rows)} rows, one core)\n")
    print_table(["stage", "wall time (s)", "ms per row", "ratio to predictions"],
                [["predictions (cached plans)", f"{ref:.2f}", f"{1e3 * ref / len(rows):.2f}", "1.00"],
                 ["paper reading", f"{paper:.2f}", f"{1e3 * paper / len(rows):.2f}",
                  f"{paper / ref:.2f}"],
                 ["paper + none readings", f"{both:.2f}", f"{1e3 * both / len(rows):.2f}",
                  f"{both / ref:.2f}"]],
                ["---", "---:", "---:", "---:"])
    print(f"\nThe counterfactual costs {both / paper:.2f}x the paper reading alone.")


if __name__ == "__main__":
    main(*sys.argv[1:])
