"""A run whose design is not its study file's default says so: the manifest keeps the overrides as
given, each report's provenance names them with the trial count of the default design, and the
headline page marks the run's rows. The default counts are read from the study files here."""

from __future__ import annotations

import json
import math

import yaml
from cli_checks import invoke

from graspcampaign.campaign.compose import project_dirs


def default_trials(study: str) -> int:
    """The trial count of a study file's own Cartesian design, read from the file."""
    data = yaml.safe_load((project_dirs()[1] / f"{study}.yaml").read_text())
    return math.prod(len(levels) for levels in data["factors"].values()) * data.get("seeds", 1)


def test_a_reduced_run_names_its_overrides_and_size_in_every_report(tmp_path):
    result = invoke("run", "smoke", "nodes=[144]", "runner.n_jobs=1", "--root", tmp_path, "--report")
    assert result.exit_code == 0, result.output
    run = tmp_path / "smoke" / "default"
    manifest = json.loads((run / "manifest.json").read_text())
    assert manifest["overrides"] == ["nodes=[144]", "runner.n_jobs=1"]
    # the stored overrides are as typed; the line names those that change the design (not runner.*)
    line = ("- **Reduced/modified run:** overrides `nodes=[144]`; "
            f"5 of the study's {default_trials('smoke')} trials")
    assert line in (run / "report" / "report.md").read_text().splitlines()
    assert invoke("report", "smoke", "--root", tmp_path, "--format", "html").exit_code == 0
    assert ("<dt>Reduced/modified run</dt><dd>overrides <code>nodes=[144]</code>; "
            "5 of the study&#x27;s") in (run / "report" / "report.html").read_text()
    # an old run's manifest records no default: its report says nothing of one
    for key in ("overrides", "default_design"):
        del manifest[key]
    (run / "manifest.json").write_text(json.dumps(manifest, indent=2))
    assert invoke("report", "smoke", "--root", tmp_path).exit_code == 0
    assert "Reduced/modified run" not in (run / "report" / "report.md").read_text()


def test_a_run_of_the_default_design_is_not_marked(tmp_path):
    # where and how trials run (runner.*) changes no result: the design is the study's own
    assert invoke("run", "smoke", "runner.n_jobs=1", "--root", tmp_path, "--report").exit_code == 0
    run = tmp_path / "smoke" / "default"
    assert json.loads((run / "manifest.json").read_text())["overrides"] == ["runner.n_jobs=1"]
    assert "Reduced/modified run" not in (run / "report" / "report.md").read_text()


def test_the_headline_marks_a_reduced_run(tmp_path):
    result = invoke("run", "baseline_grid", "shape=[sphere,pear]", "mass_kg=[0.4]", "mu=[0.3]",
                    "seeds=1", "planner=[heuristic]", "runner.n_jobs=1", "--root", tmp_path, "--report")
    assert result.exit_code == 0, result.output
    headline = (tmp_path / "headline.md").read_text()
    row = next(line for line in headline.splitlines() if line.startswith("| Baseline grid |"))
    assert row.startswith("| Baseline grid | simulation: 2 shapes † (reduced run: 2 of the study's "
                          f"{default_trials('baseline_grid')} trials) |")
    assert "*† A reduced or modified run: its design is not the study file's default" in headline
