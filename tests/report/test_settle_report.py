"""gravity_settle finding: only what the records show (one settle step per integrator), in words.

A two-row settle table (the columns docs/records.md gives gravity_settle) is read by the report's
finding; its numbers are the rows' own.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pandas as pd

from graspcampaign.analysis.vocabulary import label
from graspcampaign.report.render import Run
from graspcampaign.report.studies.dynamic import settle_finding


def test_the_finding_claims_nothing_about_steps_the_records_do_not_hold():
    rows = [{"integrator": i, "dt_s": dt, "dt_over_rk4_limit": ratio, "settled": True, "squash_ratio": 0.855,
             "newton_iterations_per_step": nit, "lu_factorizations": lu, "shape_difference_max_mm": diff,
             "observed_order": order, "expected_order": order, "energy_balance_rel_error": 1e-4,
             "energy_balance_rel_error_half_dt": 1e-5, "energy_audit_steps": 100, "energy_increases": 0,
             "simulated_time_s": 0.2}
            for i, dt, ratio, nit, lu, diff, order in (("rk4", 1.08e-4, 0.5, float("nan"), 0, 0.0, 4),
                                                       ("implicit", 2.5e-4, 1.16, 5.3, 607, 0.0585, 2))]
    run = Run(pd.DataFrame(rows), {}, SimpleNamespace(settles=True))
    run.tables["settle"] = pd.DataFrame(rows)
    text = settle_finding(run)
    assert "departs" not in text and "larger steps" not in text  # one step per integrator recorded
    assert "implicit midpoint settles within 0.200 s at 1.16× RK4's stable step" in text
    assert "the final shapes differ by at most 0.0585 mm" in text
    # a rule that did not settle is never said to settle (the report said so beside 'settled = no')
    unsettled = [{**r, "settled": r["integrator"] == "rk4"} for r in rows]
    run = Run(pd.DataFrame(unsettled), {}, SimpleNamespace(settles=True))
    run.tables["settle"] = pd.DataFrame(unsettled)
    text = settle_finding(run)
    assert "implicit midpoint **does not settle** within 0.200 s at 1.16× RK4's stable step" in text
    assert "settles at" not in text and "its shape within" not in text
    assert f"{label('integrator', 'implicit')} **does not" in text and "rk4 " not in text


def test_an_unsettled_run_says_within_what_time_and_calls_no_shape_settled():
    # a 0.2 s run that did not settle read "does not settle ... The settled shapes differ by ..."
    rows = [{"integrator": i, "dt_s": 2e-4, "dt_over_rk4_limit": 0.5, "settled": False, "squash_ratio": q,
             "newton_iterations_per_step": float("nan"), "lu_factorizations": 0, "shape_difference_max_mm": d,
             "observed_order": 4, "expected_order": 4, "energy_balance_rel_error": e,
             "energy_balance_rel_error_half_dt": 7.5e-5, "energy_audit_steps": 200, "energy_increases": 0,
             "simulated_time_s": 0.2} for i, d, q, e in (("rk4", 0.0, 0.899, 1.4e-3),
                                                         ("implicit", 0.0181, 0.899085, 2.8e-5))]
    run = Run(pd.DataFrame(rows), {}, SimpleNamespace(settles=True))
    run.tables["settle"] = pd.DataFrame(rows)
    text = settle_finding(run)
    # the simulated time as the settle table prints it (0.200), not Python's "g" (0.2)
    assert text.count("**does not settle** within 0.200 s") == 2 and "settled shape" not in text
    assert "the final shapes differ by at most 0.0181 mm" in text
    # small numbers read as plain decimals, as the tables print them (they read 8.5e-05, 2.8e-05)
    assert "e-0" not in text


def test_fig10_draws_the_floor_at_the_lowest_rest_node_not_at_the_deepest_settled_one():
    # core.msd.settle_on_floor sets the floor at the lowest rest node; the figure drew it at the
    # lowest settled node, i.e. below the floor by the penetration
    import matplotlib.pyplot as plt

    from graspcampaign.report.studies.dynamic import fig10

    z0 = np.array([-0.05, 0.0, 0.05])
    shape = pd.DataFrame({"trial_id": "t", "node": range(3), "x0_m": 0.0, "z0_m": z0, "x_m": 0.0,
                          "y_m": 0.0, "z_m": z0 * 0.9 - 0.006})  # 1.0 mm below the floor at the bottom
    run = Run(pd.DataFrame({"trial_id": ["t"]}), {}, SimpleNamespace(settles=True))
    run.tables["settle"] = pd.DataFrame([{"trial_id": "t", "integrator": "rk4", "settled": True,
                                          "squash_ratio": 0.9}])
    run.memo("tables/shape", lambda: shape)
    run.memo("tables/settle", lambda: pd.DataFrame({"trial_id": "t", "time_s": [0.0, 1.0],
                                                    "kinetic_energy_j": [1e-3, 1e-9]}))
    fig = plt.figure()
    fig10(run, fig)
    floor = [line for line in fig.axes[0].get_lines() if line.get_label() == "floor"]
    plt.close(fig)
    assert len(floor) == 1 and floor[0].get_ydata()[0] == 1e3 * z0.min()
