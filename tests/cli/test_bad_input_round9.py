"""Bad input, round 9: what round 8 found and left (a near-miss material, a PLY claiming more
vertices than it holds, a gzipped mesh, a manifest of newer code, an escaped quote in a mapping
override, an output name whose suffix says another format) and the odd inputs of round 9's table
(the final report of branch bad9).
Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

import pytest
import trimesh
from cli_checks import refused


@pytest.fixture
def sphere(tmp_path):
    """A valid mesh file to plan on (40 mm sphere)."""
    path = tmp_path / "sphere.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=40.0).export(path)
    return path


@pytest.mark.parametrize(("material", "meant"), [
    ("silicone_rf", "did you mean 'silicone_ref'? "),  # it had no suggestion and no final period
    ("steel", ""),
])
def test_a_near_miss_material_is_suggested_in_a_sentence(tmp_path, sphere, material, meant):
    refused(tmp_path, ["plan", sphere, "--mass-kg", "0.1", "--material", material, "--png",
                       tmp_path / "p.png"],
            f"unknown material '{material}'; {meant}use one of gel, silicone_soft, bio_foam, "
            "silicone_ref.")
