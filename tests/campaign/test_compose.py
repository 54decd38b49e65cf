"""Every YAML names its schema and validates against it; every study composes."""

from __future__ import annotations

from pathlib import Path

import pytest
from omegaconf import OmegaConf

from graspcampaign.campaign.compose import check_yaml_schemas, compose_study, list_studies, schema_of
from graspcampaign.campaign.schema import SCHEMAS, check_config, check_study
from graspcampaign.errors import ConfigError

SPEC_STUDIES = {"friction_mass", "gravity_settle", "heuristic_weights", "shapes", "ablation",
                "wrench_balance", "baseline_grid", "sensitivity", "mesh_resolution",
                "pso_repeatability", "test1_bench", "test2_grasp", "test3_disturbance",
                "surrogate", "smoke"}
SPEC_STUDIES |= {"grip_laws"}  # SPEC §8: the grip laws the paper flags as future work (issue 13)
SPEC_STUDIES |= {"dynamic_check"}  # SPEC §8: every quasi-static label re-simulated dynamically


def test_one_campaign_file_per_spec_study():
    found = set(list_studies())
    assert found == SPEC_STUDIES, (
        f"study files in campaigns/ but not in SPEC_STUDIES: {sorted(found - SPEC_STUDIES)}; in SPEC_STUDIES "
        f"without a file: {sorted(SPEC_STUDIES - found)}. A study added to campaigns/ is added to "
        "SPEC_STUDIES (tests/campaign/test_compose.py; docs/ARCHITECTURE.md, Adding a study)")


# Study files are checked through composition below.
GROUP_FILES = [(path, schema) for path, schema in check_yaml_schemas() if schema != "StudyCfg"]


@pytest.mark.parametrize(("path", "schema"), GROUP_FILES, ids=lambda v: getattr(v, "name", v))
def test_group_files_validate_against_their_schema(path, schema):
    data = OmegaConf.load(path)
    obj = OmegaConf.to_object(OmegaConf.merge(OmegaConf.structured(SCHEMAS[schema]), data))
    check_config(obj)


@pytest.mark.parametrize("study", sorted(SPEC_STUDIES))
def test_every_study_composes_and_names_paper_values(study):
    cfg = compose_study(study)
    check_study(cfg)
    assert cfg.name == study
    if study != "smoke":
        assert cfg.paper, f"{study} has no paper: block"


def test_schema_header_is_required(tmp_path):
    bad = tmp_path / "x.yaml"
    bad.write_text("# @package _global_\nname: x\n")
    assert schema_of(bad) is None


def test_zip_groups_must_have_equal_lengths():
    with pytest.raises(ConfigError, match=r"zip\[0\] groups factors of different lengths"):
        compose_study("baseline_grid", ["+zip=[[mass_kg,planner]]"])


def test_an_error_is_named_with_its_line_from_one_read_of_the_study_file(tmp_path, monkeypatch):
    """A key the composed study refuses (a parameter the trial kind lacks) is named with the line
    of the user's study file that writes it, the file read and parsed for lines once: the
    line's search and the message each read it (twice before)."""
    from graspcampaign.campaign import written
    from graspcampaign.campaign.studyfile import project_dirs

    text = (project_dirs()[1] / "smoke.yaml").read_text()
    study = tmp_path / "mine.yaml"
    study.write_text(text.replace("name: smoke", "name: mine").replace(
        "kind: mesh_features", "kind: mesh_features\nparams:\n  bogus: 1"))
    parsed, parse = [], written._key_nodes
    monkeypatch.setattr(written, "_key_nodes", lambda text: parsed.append(text) or parse(text))
    with pytest.raises(ConfigError) as info:
        compose_study(str(study))
    line = study.read_text().splitlines().index("  bogus: 1") + 1
    assert str(info.value) == (f"{study}, line {line}: params.bogus is not a parameter of trial "
                               "kind 'mesh_features', which takes none.")
    assert len(parsed) == 1


def test_every_yaml_file_is_read_by_one_loader_class(tmp_path, monkeypatch):
    """The checking loader's class (:func:`yamlfile._loader`) is built once per process, not once
    per file read: a compose reads a study file and its group files, a ``list`` every study's."""
    import yaml

    from graspcampaign.campaign.studyfile import read_yaml

    loaders, load = [], yaml.load
    monkeypatch.setattr(yaml, "load", lambda text, Loader: loaders.append(Loader) or load(text, Loader))
    for name in ("a", "b"):
        (tmp_path / f"{name}.yaml").write_text("seeds: 1\n")
        assert read_yaml(tmp_path / f"{name}.yaml") == {"seeds": 1}
    assert len(loaders) == 2 and loaders[0] is loaders[1]


def test_the_byte_order_mark_is_one_constant():
    """compose spelled the UTF-8 byte-order mark itself (``_BOM``) beside ``codecs.BOM_UTF8``, the
    constant the mesh readers use; no module spells its bytes again (a study file starting with the
    mark still composes: test_bad_configs)."""
    import graspcampaign

    root = Path(graspcampaign.__file__).parent
    spelled = sorted(p.relative_to(root).as_posix() for p in root.rglob("*.py")
                     if r"\xef\xbb\xbf" in p.read_text(encoding="utf-8"))
    assert spelled == []


@pytest.mark.parametrize("overrides", [[], ["name=mine2"]])
def test_composing_a_users_study_lists_the_study_files_once(tmp_path, monkeypatch, overrides):
    """find_study, the file's case-twin check and the rename check each listed the search path
    (twice per call, three times with ``name=``); one listing serves them all."""
    from graspcampaign.campaign import studyfile

    (tmp_path / "mine.yaml").write_text("# @package _global_\n# schema: StudyCfg\nname: mine\n"
                                        "kind: mesh_features\nfactors: {shape: [sphere], nodes: [144]}\n")
    monkeypatch.setenv("GRASPCAMPAIGN_PATH", str(tmp_path))
    listed, study_dirs = [], studyfile.study_dirs
    monkeypatch.setattr(studyfile, "study_dirs", lambda: listed.append(1) or study_dirs())
    assert compose_study("mine", overrides).name == (overrides[0][5:] if overrides else "mine")
    assert len(listed) == 1
