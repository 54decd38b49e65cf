"""Reports of the dynamic studies render from real (reduced) runs and match their records."""

from __future__ import annotations

import pandas as pd

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study
from graspcampaign.report.build import build_reports


def test_friction_mass_and_settle_reports(tmp_path):
    common = ["runner.backend=sequential", f"output.root={tmp_path}", "nodes=[144]"]
    run_study(compose_study("friction_mass", [*common, "mu=[0.1,0.5]", "mass_kg=[0.2]",
                                              "model_preset=[table2]", "+params.t_max_s=0.03"]))
    # the current report reads RK4 audit columns only; the integrator comparison comes with the
    # new report framework (issue 17)
    run_study(compose_study("gravity_settle", [*common, "integrator=[rk4]",
                                               "+params.settle_t_max_s=0.2"]))
    build_reports(["friction_mass", "gravity_settle"], root=tmp_path)
    fm = tmp_path / "friction_mass" / "default"
    records = RunStore(fm).read().to_pandas().sort_values("mu").reset_index(drop=True)
    table = pd.read_csv(fm / "report" / "tables" / "friction_mass.csv")
    assert list(table["dynamic_status"]) == list(records["dynamic_status"])
    assert (table["paper"] == "stable").all()
    like = pd.read_csv(fm / "report" / "tables" / "like_for_like.csv")
    assert list(like["lp_status_mu0"]) == list(records["lp_status_mu0"])
    assert (fm / "report" / "figures" / "fig12_13_dynamic.png").stat().st_size > 10_000
    settle = tmp_path / "gravity_settle" / "default" / "report"
    assert (settle / "figures" / "fig10_settle.png").exists()
    assert "settl" in (settle / "report.md").read_text()
    audit = pd.read_csv(settle / "tables" / "integrator_audit.csv")
    record = RunStore(tmp_path / "gravity_settle" / "default").read().to_pandas().iloc[0]
    assert audit["rk4_observed_order"].iloc[0] == record["rk4_observed_order"]
    assert (settle / "figures" / "integrator_audit.png").stat().st_size > 10_000
    assert "Sec. 12 lists both as missing" in (settle / "report.md").read_text()
