"""The example of docs/ARCHITECTURE.md, "Adding a study": its study file composes (its paper block
checked against baseline_grid's schema through compare_with) and its spec, run as written, renders
over a synthetic run of that design with no item failing; its numbers are the records' own."""

from __future__ import annotations

import re
from pathlib import Path

import pandas as pd
from synthetic_runs import make_run, quasi_static_outputs

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.paper import check_paper
from graspcampaign.campaign.provenance import read_manifest
from graspcampaign.report.document import Document, Figure
from graspcampaign.report.render import Run, render

DOC = Path(__file__).resolve().parents[2] / "docs" / "ARCHITECTURE.md"


def example(language: str) -> str:
    """The first ``language`` code block of the "Adding a study" section."""
    section = DOC.read_text().split("## Adding a study (config and report)")[1].split("\n## ")[0]
    return re.findall(rf"```{language}\n(.*?)```", section, re.S)[0]


def test_the_documented_study_composes_and_its_spec_renders(tmp_path):
    path = tmp_path / "grid_2x2.yaml"
    path.write_text(example("yaml"))
    study = compose_study(str(path), ["runner.backend=sequential"])
    assert (study.name, study.kind, study.compare_with, study.extension) == (
        "grid_2x2", "quasi_static", "baseline_grid", True)
    store = make_run(tmp_path, "grid_2x2", "quasi_static", dict(study.factors), study.seeds, study.paper,
                     quasi_static_outputs, seed=study.seed, compare_with=study.compare_with)
    namespace: dict = {}
    exec(compile(example("python"), str(DOC), "exec"), namespace)  # the spec module, as written
    records = store.read().to_pandas()
    run = Run(records, read_manifest(store.manifest_path),
              check_paper("baseline_grid", study.paper, "the example's paper block"), store)
    doc = render(namespace["SPEC"], run, Document("grid_2x2", run.source, []))
    assert run.failures == []
    assert len(records) == 2 * 2 * study.seeds  # 2 masses x 2 planners x seeds
    rates = doc.tables["success_by_planner"].set_index("planner")
    expected = records.groupby("planner")["success"].mean() * 100
    pd.testing.assert_series_equal(rates["rate_pct"], expected, check_names=False)
    assert rates["paper_pct"].to_dict() == {"heuristic": 67.6, "random": 11.0}
    depth = doc.tables["depth_by_mass"].set_index(["planner", "mass_kg"])["delta_max_median_mm"]
    pd.testing.assert_series_equal(depth, records.groupby(["planner", "mass_kg"])["delta_max_mm"].median(),
                                   check_names=False)
    assert any(isinstance(b, Figure) and b.images["png"] for b in doc.blocks)
    page = doc.markdown()
    assert page.index("## What this shows") < page.index("success_by_planner.csv")
    assert f"Success over {len(records)} executed trials: proposed H(G) " in page
    assert "Fig. 18, whole grid: proposed H(G) 67.6%, random 11%." in page
