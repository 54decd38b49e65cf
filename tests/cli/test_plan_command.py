"""`graspcampaign plan` on an STL of each of the five shapes."""

from __future__ import annotations

import json
import math
import re

import pytest
from typer.testing import CliRunner

from graspcampaign.cli.main import app
from graspcampaign.core.mesh import SHAPES, make_object

runner = CliRunner()


@pytest.fixture(scope="module")
def stl_files(tmp_path_factory):
    root = tmp_path_factory.mktemp("meshes")
    paths = {}
    for shape in SHAPES:
        mesh = make_object(shape, 390).copy()
        mesh.apply_scale(1000.0)  # written in millimetres, read back with --unit mm
        paths[shape] = root / f"{shape}.stl"
        mesh.export(paths[shape])
    return paths


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_plan_prints_a_plan_and_writes_its_picture(stl_files, shape):
    png = stl_files[shape].with_suffix(".png")
    result = runner.invoke(app, ["plan", str(stl_files[shape]), "--mass-kg", "0.05",
                                 "--material", "silicone_ref", "--png", str(png), "--json"])
    assert result.exit_code == 0, result.output
    plan = json.loads(result.stdout)
    assert png.is_file() and png.stat().st_size > 10_000
    assert len(plan["contacts"]) == 3
    sf, weight = plan["sf_predicted"], plan["weight_n"]
    expected = weight * math.sqrt(sf**2 - 1.0) if sf >= 1.0 else 0.0  # Sec. 9.1
    assert plan["f_lat_n"] == pytest.approx(expected, rel=1e-9, abs=1e-12)
    assert plan["f_down_n"] == pytest.approx(max(weight * (sf - 1.0), 0.0), rel=1e-9, abs=1e-12)


def test_plan_human_output(stl_files):
    result = runner.invoke(app, ["plan", str(stl_files["sphere"]), "--mass-kg", "0.05"])
    assert result.exit_code == 0, result.output
    assert "predicted limits: F_lat =" in result.stdout and "finger 3: vertex" in result.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--mass-kg", "-1"], r"mass_kg must lie in \(0, 50\] kg, got -1\.0\."),
        (["--mass-kg", "0.1", "--material", "unobtainium"],
         r"unknown material 'unobtainium': use one of gel, silicone_soft, bio_foam, silicone_ref"),
        (["--mass-kg", "0.1", "--unit", "furlong"], r"unknown unit 'furlong': use one of 'm', 'cm', 'mm'"),
    ],
)
def test_plan_bad_values_exit_2(stl_files, args, message):
    result = runner.invoke(app, ["plan", str(stl_files["sphere"]), *args])
    assert result.exit_code == 2
    assert re.fullmatch(r"error: " + message + r"\n", result.stderr), result.stderr


def test_plan_bad_mesh_exit_2(tmp_path):
    bad = tmp_path / "open.stl"
    bad.write_text("solid nothing\nendsolid nothing\n")
    result = runner.invoke(app, ["plan", str(bad), "--mass-kg", "0.1"])
    assert result.exit_code == 2
    assert result.stderr == "error: mesh 'open.stl' is empty: it has no faces\n"
