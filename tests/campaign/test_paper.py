"""Typed paper blocks: every study file validates; a wrong or missing key exits 2 naming it."""

from __future__ import annotations

import shutil

import pytest
import yaml
from typer.testing import CliRunner

from graspcampaign.campaign.compose import list_studies, project_dirs
from graspcampaign.campaign.paper import check_paper, paper_types, study_paper
from graspcampaign.cli.main import app
from graspcampaign.errors import ConfigError

cli = CliRunner()


def test_every_study_file_has_a_valid_paper_block():
    assert set(paper_types()) <= set(list_studies())
    for study in list_studies():
        paper = study_paper(study)
        data = yaml.safe_load((project_dirs()[1] / f"{study}.yaml").read_text())
        like = data.get("compare_with") or study
        # a study of no schema of its own and no compare_with has no paper block: nothing is compared
        # (before, a KeyError for it, and for a compare_with variant other than grip_laws)
        assert type(paper) is paper_types()[like] if like in paper_types() else paper is None, study
    assert type(study_paper("grip_laws")) is paper_types()["baseline_grid"]  # its compare_with
    assert study_paper("baseline_grid").success_pct["heuristic"] == 67.6
    assert study_paper("test3_disturbance").table9["random"].wilson_pct == (10.9, 25.5)


@pytest.mark.parametrize(("edit", "message"), [
    (lambda p: p.update(trials_per_varian=p.pop("trials_per_variant")),
     "campaigns/ablation.yaml: paper.trials_per_varian is not a known key; "
     "allowed: figure, trials_per_variant, interval_half_width_pp, success_pct."),
    (lambda p: p.pop("figure"),
     "campaigns/ablation.yaml: paper.figure is missing (a required key)."),
    (lambda p: p["success_pct"].update(heuristc=p["success_pct"].pop("heuristic")),
     "campaigns/ablation.yaml: paper.success_pct.heuristc is not a known planner; allowed: "),
    (lambda p: p.update(trials_per_variant="fifty"),
     "campaigns/ablation.yaml: paper.trials_per_variant must be a whole number; got 'fifty'."),
])
def test_a_wrong_paper_key_exits_2_naming_it(tmp_path, monkeypatch, edit, message):
    conf, campaigns = project_dirs()
    home = tmp_path / "home"
    shutil.copytree(conf, home / "conf")
    shutil.copytree(campaigns, home / "campaigns")
    path = home / "campaigns" / "ablation.yaml"
    text = path.read_text()
    head = "".join(line + "\n" for line in text.splitlines() if line.startswith("#"))
    data = yaml.safe_load(text)
    edit(data["paper"])
    path.write_text(head + yaml.safe_dump(data, sort_keys=False))
    monkeypatch.setenv("GRASPCAMPAIGN_HOME", str(home))
    project_dirs.cache_clear()
    try:
        result = cli.invoke(app, ["show", "ablation"])
    finally:
        monkeypatch.delenv("GRASPCAMPAIGN_HOME")
        project_dirs.cache_clear()
    assert result.exit_code == 2, result.output
    assert f"error: {message}" in result.output.replace("\n", " ")


def test_nested_and_optional_fields():
    block = yaml.safe_load((project_dirs()[1] / "test3_disturbance.yaml").read_text())["paper"]
    block["table8"]["A"]["pred_err_pc"] = 1.0
    with pytest.raises(ConfigError, match=r"^p\.table8\.A\.pred_err_pc is not a known key; "
                                          r"allowed: "):
        check_paper("test3_disturbance", block, "p")
    del block["table8"]["A"]["pred_err_pc"]
    assert "headline" not in block["table8"]["D"]  # optional: no headline printed for D
    assert check_paper("test3_disturbance", block).table8["D"].headline is None
    with pytest.raises(ConfigError, match="p.h_range must be a list of 2 values; got 0.2."):
        check_paper("shapes", {**study_paper_block("shapes"), "h_range": 0.2}, "p")
    assert check_paper("my_own_study", {}) is None
    with pytest.raises(ConfigError, match="study 'my_own_study' has no paper schema"):
        check_paper("my_own_study", {"x": 1})


def study_paper_block(study: str) -> dict:
    return yaml.safe_load((project_dirs()[1] / f"{study}.yaml").read_text())["paper"]


def test_a_value_the_paper_marks_approximate_is_parsed_as_approximate_from_the_documented_list():
    """Table 1 prints the natural-friction rate as "∼86%" (Sec. 9.2 "roughly 86 %"): it is parsed as
    an Approximate 86.0 (compared as the number), while the study file keeps its stored 86.0 (a run's
    config hash must not move). Every listed field exists, and the words it cites are in the paper."""
    import dataclasses
    import typing
    from pathlib import Path

    from graspcampaign.campaign.paper import APPROXIMATE, Approximate

    natural = study_paper("test3_disturbance").natural_success_pct
    assert type(natural) is Approximate and natural == 86.0
    assert type(study_paper("test3_disturbance").proposed_success_pct) is float  # "80.8": not marked
    data = yaml.safe_load((project_dirs()[1] / "test3_disturbance.yaml").read_text())
    assert type(data["paper"]["natural_success_pct"]) is float  # the stored key is unchanged
    classes, todo = {}, list(paper_types().values())  # the study blocks and the blocks nested in them
    while todo:
        cls = todo.pop()
        classes[cls.__name__] = cls
        todo += [t for t in typing.get_type_hints(cls).values() if dataclasses.is_dataclass(t)]
    paper = " ".join(Path("/work/shared/paper.txt").read_text().split())
    plain = paper.replace("$\\text{CV} \\approx ", "CV ≈ ").replace("\\%$", "%")  # Fig. 21's "CV ≈ 19%"
    for (cls, name), source in APPROXIMATE.items():
        assert name in {f.name for f in dataclasses.fields(classes[cls])}, (cls, name)
        for quoted in source.split('"')[1::2]:
            assert quoted.replace("∼", "$\\sim ").replace("%", "\\%$") in paper or quoted in plain, quoted
