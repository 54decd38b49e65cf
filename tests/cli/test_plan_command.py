"""`graspcampaign plan` on an STL of each of the five shapes."""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path

import numpy as np
import pytest
from cli_checks import refused
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


TAU_F_N = 0.0886  # the paper's residual tolerance (§8.1), typed from the paper


@pytest.mark.parametrize(("mass", "verdict"), [
    ("0.05", "yes (SF > 1 with every finger loaded, §9.5)"),
    ("0.3", "no (SF <= 1: friction does not carry the weight, §9.5)"),
], ids=["stable", "sf_below_one"])
def test_plan_verdict_and_residual_check_each_follow_their_own_criterion(stl_files, mass, verdict):
    args = ["plan", str(stl_files["sphere"]), "--mass-kg", mass]
    result = runner.invoke(app, [*args, "--json"])
    assert result.exit_code == 0, result.output
    plan = json.loads(result.stdout)
    # plan_mesh's documented criteria: §9.5 SF_predicted > 1 with every finger loaded; the §8.1
    # residual check |R| <= tau_F reported on its own
    assert plan["predicted_stable"] is (plan["sf_predicted"] > 1.0 and not plan["unloaded_fingers"])
    assert plan["tau_f_n"] == TAU_F_N
    assert plan["predicted_stable_residual"] is (plan["residual_n"] <= TAU_F_N)
    assert not plan["predicted_stable_residual"]  # |R| > tau_F beside either verdict: the report's case
    text = runner.invoke(app, args).stdout
    assert f"SF = {plan['sf_predicted']:.3f}  predicted stable: {verdict}\n" in text
    assert (f"\nresidual check (§8.1: Algorithm 2, normal forces only, friction ignored): |R| = "
            f"{plan['residual_n']:.3f} N > tau_F = 0.0886 N, not passed; not part of the verdict "
            "above\n") in text


def test_plan_without_friction_reports_no_hold_and_no_numpy_warning(stl_files):
    result = runner.invoke(app, ["plan", str(stl_files["sphere"]), "--mass-kg", "0.1", "--mu", "0"])
    assert result.exit_code == 0, result.output
    assert result.stderr == ""
    # SF = mu ... / W (§8.1) is 0 without friction: the verdict says so
    assert "SF = 0.000  predicted stable: no (SF <= 1: friction does not carry the weight, §9.5)\n" \
        in result.stdout


MASS = ("below 0.1 g an object weighs less than the rig's 1 mN force resolution, and a "
        "three-finger hand lifts at most ~10 kg")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--mass-kg", "-1"], f"--mass-kg -1.0 is out of range; allowed: >= 0.0001 and <= 10 kg "
                              f"({MASS})."),
        (["--mass-kg", "500"], f"--mass-kg 500.0 is out of range; allowed: >= 0.0001 and <= 10 kg "
                               f"({MASS})."),
        (["--mass-kg", "0.1", "--mu", "50"], "--mu 50.0 is out of range; allowed: >= 0 and <= 3 (dry "
                                             "friction of soft materials stays below 3)."),
        (["--mass-kg", "0.1", "--mu", "nan"], "--mu nan is not a number; give a finite number."),
        (["--mass-kg", "0.1", "--fingertip-radius-mm", "-5"],
         "--fingertip-radius-mm -5.0 is out of range; allowed: >= 1 and <= 50 mm (below 1 mm the "
         "evaluator's 0.5 mm seed penetration sinks half a fingertip's radius, and robot pads "
         "stay below 50 mm)."),
        (["--mass-kg", "0.1", "--material", "unobtainium"],
         "--material 'unobtainium' is not a Table 4 material family; use one of gel, "
         "silicone_soft, bio_foam, silicone_ref."),
        (["--mass-kg", "0.1", "--unit", "furlong"], "--unit 'furlong' is not a length unit a mesh is "
                                                   "read in; use one of m, cm, mm (the unit of the "
                                                   "mesh file's coordinates)."),
        (["--mass-kg", "abc"], "--mass-kg 'abc' is not a number; see graspcampaign plan --help."),
        (["--mass-kg", "0.1", "--png", ""], "--png is empty; give a picture path ending in .png, such "
                                            "as plan.png."),
        (["--mass-kg", "0.1", "--unit", "m"],
         "mesh 'sphere.stl' is 99.8 m across read with --unit m, outside the 10-500 mm a "
         "three-finger hand grasps; its coordinates look like millimetres: pass --unit mm."),
    ],
)
def test_plan_bad_values_exit_2(stl_files, args, message):
    result = runner.invoke(app, ["plan", str(stl_files["sphere"]), *args])
    assert result.exit_code == 2
    assert result.stderr == f"error: {message}\n"


def test_plan_names_a_folder_or_an_empty_path_given_as_the_mesh(tmp_path):
    folder = f"{tmp_path} is a directory, not a file; give a mesh file (STL, OBJ or PLY)."
    for mesh, message in ((tmp_path, folder),
                          ("", "the mesh path is empty; give a mesh file (STL, OBJ or PLY).")):
        result = runner.invoke(app, ["plan", str(mesh), "--mass-kg", "0.1"])
        assert (result.exit_code, result.stdout, result.stderr) == (2, "", f"error: {message}\n")
    assert not any(tmp_path.iterdir())


def test_plan_help_names_units_and_the_default_material():
    from graspcampaign.rig import DEFAULT_PLAN_MATERIAL

    text = " ".join(runner.invoke(app, ["plan", "--help"], env={"COLUMNS": "200"}).stdout.split())
    assert "Object mass in kg. [required]" in text and " . " not in text
    assert f"Table 4 material family. [default: {DEFAULT_PLAN_MATERIAL}]" in text
    assert "Fingertip radius in mm. [default: 5.0]" in text


def test_plan_picture_has_one_scale_on_every_axis(stl_files, tmp_path, monkeypatch):
    """A sphere is drawn round: every axis spans the same length in a cubic box, and holds the
    mesh's extent (so no axis is stretched, whatever the arrows and labels add)."""
    from matplotlib.figure import Figure

    drawn, savefig = [], Figure.savefig
    monkeypatch.setattr(Figure, "savefig", lambda fig, *a, **k: drawn.append(fig) or savefig(fig, *a, **k))
    result = runner.invoke(app, ["plan", str(stl_files["sphere"]), "--mass-kg", "0.1", "--png",
                                 str(tmp_path / "plan.png")])
    assert result.exit_code == 0, result.output
    (ax,) = drawn[0].axes
    spans = [np.ptp(limits) for limits in (ax.get_xlim(), ax.get_ylim(), ax.get_zlim())]
    assert np.allclose(spans, spans[0]) and np.allclose(ax.get_box_aspect(), ax.get_box_aspect()[0])
    import trimesh

    assert spans[0] >= np.ptp(trimesh.load(stl_files["sphere"]).vertices, axis=0).max()  # mm


def _mesh_file(tmp_path, name: str) -> tuple:
    """Write one bad mesh of each class; return (path, the whole message)."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=2, radius=40.0)  # mm
    path = tmp_path / name
    if name == "huge.obj":
        v = sphere.vertices.copy()
        v[3] = [1e200, 0.0, 0.0]
        trimesh.Trimesh(v, sphere.faces, process=False).export(path)
        return path, ("mesh 'huge.obj' has a coordinate of 1e+200 mm at vertex 4, beyond the 1e+06 mm "
                      "(1000 m) any graspable object fits in; check the file and its unit (--unit).")
    if name == "nan.obj":
        sphere.export(path)
        lines = path.read_text().splitlines()
        first = next(i for i, line in enumerate(lines) if line.startswith("v "))
        lines[first + 1] = "v nan 0 0"
        path.write_text("\n".join(lines) + "\n")
        return path, ("mesh 'nan.obj' has a non-finite coordinate at vertex 2 (nan, 0, 0): every "
                      "coordinate must be a finite number.")
    if name == "inf.stl":
        v = sphere.vertices.copy()
        v[sphere.faces[4, 1]] = [0.0, np.inf, 0.0]
        with np.errstate(invalid="ignore"):  # the exporter's face normals of an infinite corner
            trimesh.Trimesh(v, sphere.faces, process=False).export(path)  # binary STL
        return path, ("mesh 'inf.stl' has a non-finite coordinate at triangle 5 (0, inf, 0): every "
                      "coordinate must be a finite number.")
    if name == "garbage.stl":
        path.write_bytes(np.random.default_rng(0).integers(0, 256, 3000, dtype=np.uint8).tobytes())
        return path, ("mesh 'garbage.stl' is not an STL file: 3000 bytes are neither a binary STL "
                      "(84 bytes plus 50 per triangle) nor an ASCII STL (text starting with 'solid').")
    if name == "empty.stl":
        path.write_bytes(b"")
        return path, "mesh 'empty.stl' is empty: the file has 0 bytes."
    if name == "facetless.stl":
        path.write_text("solid nothing\nendsolid nothing\n")
        return path, "mesh 'facetless.stl' is empty: it has no faces."
    if name == "text.ply":
        path.write_text("hello\n")
        return path, "mesh 'text.ply' cannot be read as PLY (Not a ply file!)."
    if name == "sphere.step":
        path.write_text("ISO-10303-21;\n")
        return path, (f"mesh file '{path}' has unsupported type '.step': use .stl, .obj, .ply.")
    if name == "open.stl":
        hole = sorted(tuple(v) for v in sphere.vertices[sphere.faces[0]].astype(np.float32))  # STL
        sphere.update_faces(np.arange(len(sphere.faces)) > 0)
        sphere.export(path)
        a, b, c = (f"({x:g}, {y:g}, {z:g})" for x, y, z in hole)
        return path, ("mesh 'open.stl' is not watertight: 3 boundary edges (on one face only) between "
                      f"the vertices at {a}, {b} and {c} mm.")
    if name == "metres.stl":
        sphere.apply_scale(1e-3)
        sphere.export(path)
        return path, ("mesh 'metres.stl' is 0.08 mm across read with --unit mm, outside the 10-500 mm "
                      "a three-finger hand grasps; its coordinates look like metres: pass --unit m.")
    if name == "two_spheres.stl":  # the tester's file: two r = 20 mm balls 100 mm apart
        far = trimesh.creation.icosphere(subdivisions=2, radius=20.0)
        far.apply_translation((100.0, 0.0, 0.0))
        both = trimesh.util.concatenate([trimesh.creation.icosphere(subdivisions=2, radius=20.0), far])
        both.export(path)
        count = len(trimesh.load(path).split(only_watertight=False))  # trimesh's own count: 2
        return path, (f"mesh 'two_spheres.stl' has {count} separate bodies: the planner grasps one "
                      "object, so put each body in a file of its own and plan it alone.")
    if name == "hollow.stl":  # a ball with a ball-shaped cavity, the cavity's surface wound inward
        cavity = trimesh.creation.icosphere(subdivisions=2, radius=30.0)
        cavity.invert()
        trimesh.util.concatenate([sphere, cavity]).export(path)
        return path, ("mesh 'hollow.stl' has an internal cavity (1 of its 2 closed surfaces lies "
                      "inside the outer one), whose surface no finger reaches: keep only the outer "
                      "surface in the file (the plan then takes the object as solid).")
    if name == "bad_index.obj":  # a face beyond the vertices
        path.write_text(sphere.export(file_type="obj") + "f 1 2 99999\n")
        line = len(path.read_text().splitlines())
        return path, (f"mesh 'bad_index.obj' has a face (line {line}) that refers to vertex 99999, "
                      f"but the file has only {len(sphere.vertices)} vertices.")
    if name == "points_only.obj":
        path.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in sphere.vertices))
        return path, (f"mesh 'points_only.obj' has {len(sphere.vertices)} vertices but no faces: a "
                      "point cloud is no surface; export the mesh with its faces (OBJ 'f' lines).")
    if name == "bad_index.ply":  # the tester's file: a face refers to vertex 7 of 3
        path.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                        "property float y\nproperty float z\nelement face 1\n"
                        "property list uchar int vertex_indices\nend_header\n"
                        "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
        return path, ("mesh 'bad_index.ply' has a face (face 1, line 13) that refers to vertex 7, but "
                      "the file has only 3 vertices: PLY indices count from 0.")
    if name == "truncated.ply":  # the header declares every face, the file ends after the first
        text = sphere.export(file_type="ply", encoding="ascii").decode()
        lines = text.splitlines()
        header = lines.index("end_header") + 1
        path.write_text("\n".join(lines[:header + len(sphere.vertices) + 1]) + "\n")
        return path, (f"mesh 'truncated.ply' is truncated: its header declares {len(sphere.faces)} "
                      f"face elements, but the file ends after 1 of them (line "
                      f"{header + len(sphere.vertices) + 1}).")
    if name == "letter.obj":
        path.write_text("v 0 0 x\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        return path, "mesh 'letter.obj' has a vertex (line 1) whose coordinate 'x' is not a number."
    if name == "nano.stl":  # a 60 nm ball: trimesh's fixed 1e-8 merge fused its corners
        trimesh.creation.icosphere(subdivisions=2, radius=3e-8).export(path)
        return path, ("mesh 'nano.stl' is 6e-08 mm across read with --unit mm, outside the 10-500 mm "
                      "a three-finger hand grasps; no length unit makes it graspable.")
    if name == "nano.obj":  # the same ball, written to 8 decimals: its faces are lost in rounding
        trimesh.creation.icosphere(subdivisions=2, radius=3e-8).export(path)
        merged = trimesh.load(path, process=True)
        n_zero = int((merged.area_faces == 0.0).sum())  # trimesh's own areas of the rounded faces
        return path, (f"mesh 'nano.obj' has {n_zero} degenerate (zero-area) faces and is only 6e-08 "
                      "mm across read with --unit mm: check the file and its unit (--unit).")
    if name == "stl_as.obj":  # a binary STL saved under the wrong suffix
        path.write_bytes(sphere.export(file_type="stl"))
        return path, ("mesh 'stl_as.obj' is not an OBJ file: it looks like a binary STL (84 bytes "
                      "plus 50 per triangle); rename it to .stl.")
    raise AssertionError(name)


@pytest.mark.parametrize("name", ["huge.obj", "nan.obj", "inf.stl", "garbage.stl", "empty.stl",
                                  "facetless.stl", "text.ply", "sphere.step", "open.stl",
                                  "metres.stl", "two_spheres.stl", "hollow.stl", "bad_index.obj",
                                  "points_only.obj", "bad_index.ply", "truncated.ply", "letter.obj",
                                  "nano.stl", "nano.obj", "stl_as.obj"])
def test_plan_bad_mesh_exit_2(tmp_path, name):
    path, message = _mesh_file(tmp_path, name)
    before = sorted(p.name for p in tmp_path.iterdir())
    result = runner.invoke(app, ["plan", str(path), "--mass-kg", "0.1"])
    assert result.exit_code == 2
    assert result.stderr == f"error: {message}\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # no picture of a refused mesh


COARSE_BOX = (  # the mean angular defect of a smooth closed surface of N vertices is 4 pi / N
    "warning: mesh 'box.stl' has only 8 vertices and the planner places fingers on vertices only: a "
    "surface this coarse leaves it few places to choose from and its smooth regions look sharp (mean "
    f"angular defect {4 * math.pi / 8:.3f} rad against the 0.2 rad sharp-vertex threshold); remesh or "
    "subdivide it finer for a better plan (the paper's objects have 390 vertices)\n")


def test_plan_on_a_box_never_calls_a_grasp_with_an_unloaded_finger_stable(tmp_path):
    import trimesh

    path = tmp_path / "box.stl"
    trimesh.creation.box(extents=(40.0, 30.0, 20.0)).export(path)  # 8 vertices, in mm
    text = runner.invoke(app, ["plan", str(path), "--mass-kg", "0.1"])
    assert text.exit_code == 0, text.output
    debug = runner.invoke(app, ["--debug", "plan", str(path), "--mass-kg", "0.1"])
    assert debug.stderr == COARSE_BOX  # --debug shows logs, but the warning is no log record
    # the coarse-mesh warning once, as one line, with a remedy a command-line user can apply
    assert text.stderr == COARSE_BOX
    assert "{" not in text.stdout and "[" not in text.stdout and "np." not in text.stdout
    result = runner.invoke(app, ["plan", str(path), "--mass-kg", "0.1", "--json"])
    assert result.exit_code == 0, result.output
    plan = json.loads(result.stdout)
    unloaded = [c["finger"] for c in plan["contacts"] if not c["normal_force_n"] > 1e-6]
    assert plan["unloaded_fingers"] == unloaded
    assert unloaded, "the box plan no longer has an unloaded finger: this test checks nothing"
    assert plan["predicted_stable"] is False
    assert "predicted stable: no (finger " in text.stdout
    assert plan["mesh"]["size_mm"] == pytest.approx(40.0)


def _never_plan(*args, **kwargs):
    raise AssertionError("planning started before the picture path was checked")


@pytest.mark.parametrize("where", ["directory", "no_suffix", "jpg", "missing_parent", "file_parent"])
def test_plan_refuses_a_picture_path_before_planning(stl_files, tmp_path, monkeypatch, where):
    monkeypatch.setattr("graspcampaign.core.mesh.load_mesh", _never_plan)
    (tmp_path / "pictures").mkdir()
    (tmp_path / "notes.txt").write_text("")
    png, message = {
        "directory": (tmp_path / "pictures", f"--png {tmp_path / 'pictures'} is a directory: give a "
                      f"file path ending in .png, such as {tmp_path / 'pictures' / 'plan.png'}."),
        "no_suffix": (tmp_path / "plan", f"--png {tmp_path / 'plan'} does not end in .png: the "
                      f"picture is a PNG file, so give a path such as {tmp_path / 'plan.png'}."),
        "jpg": (tmp_path / "plan.jpg", f"--png {tmp_path / 'plan.jpg'} does not end in .png: the "
                f"picture is a PNG file, so give a path such as {tmp_path / 'plan.png'}."),
        "missing_parent": (tmp_path / "nowhere" / "plan.png", f"--png {tmp_path / 'nowhere' / 'plan.png'}"
                           f": directory {tmp_path / 'nowhere'} does not exist."),
        "file_parent": (tmp_path / "notes.txt" / "plan.png", f"--png {tmp_path / 'notes.txt' / 'plan.png'}"
                        f": {tmp_path / 'notes.txt'} is a file, not a directory."),
    }[where]
    before = sorted(p.name for p in tmp_path.rglob("*"))
    result = runner.invoke(app, ["plan", str(stl_files["sphere"]), "--mass-kg", "0.1", "--png", str(png)])
    assert result.exit_code == 2, result.output
    assert result.stderr == f"error: {message}\n"
    assert sorted(p.name for p in tmp_path.rglob("*")) == before  # nothing written, no probe left


@pytest.mark.parametrize("target", ["pic.png", "nowhere/pic.png"])
def test_a_picture_path_through_a_dangling_symlink_is_probed_where_it_would_be_written(
        stl_files, tmp_path, target):
    """The probe creates nothing through the link (opening it to append would create its
    target) and probes the directory the target would be created in."""
    link = tmp_path / "link.png"
    link.symlink_to(target)
    bad_mass = f"--mass-kg -1.0 is out of range; allowed: >= 0.0001 and <= 10 kg ({MASS})."
    message = bad_mass if target == "pic.png" else \
        f"--png {link}: cannot write there (No such file or directory)."
    refused(tmp_path, ["plan", stl_files["sphere"], "--mass-kg", "-1", "--png", link], message)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.png"]


def test_a_named_pipe_as_the_picture_path_is_refused_at_once(stl_files, tmp_path, monkeypatch):
    monkeypatch.setattr("graspcampaign.core.mesh.load_mesh", _never_plan)
    pipe = tmp_path / "pipe.png"
    os.mkfifo(pipe)  # opening it to write would wait for a reader
    refused(tmp_path, ["plan", stl_files["sphere"], "--mass-kg", "0.1", "--png", pipe],
            f"--png {pipe}: is a named pipe (FIFO), not a regular file.", seconds=5)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc takes no new files on Linux")
def test_plan_refuses_an_unwritable_picture_path(stl_files, monkeypatch):
    monkeypatch.setattr("graspcampaign.core.mesh.load_mesh", _never_plan)
    result = runner.invoke(app, ["plan", str(stl_files["sphere"]), "--mass-kg", "0.1",
                                 "--png", "/proc/x.png"])
    assert result.exit_code == 2
    assert result.stderr == ("error: --png /proc/x.png: cannot write there (No such file or "
                             "directory).\n")


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0,
                    reason="permission bits do not stop root")
def test_plan_refuses_a_read_only_directory(stl_files, tmp_path, monkeypatch):
    monkeypatch.setattr("graspcampaign.core.mesh.load_mesh", _never_plan)
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    result = runner.invoke(app, ["plan", str(stl_files["sphere"]), "--mass-kg", "0.1",
                                 "--png", str(locked / "plan.png")])
    assert result.exit_code == 2
    assert result.stderr == (f"error: --png {locked / 'plan.png'}: cannot be written by this user: "
                             "permission denied (its permissions, or those of the directory holding "
                             "it, keep this user out); give this user access (chmod, chown), or run "
                             "the command as the user who owns it.\n")


def test_plan_names_the_default_picture_it_cannot_write(stl_files, tmp_path, monkeypatch):
    monkeypatch.setattr("graspcampaign.core.mesh.load_mesh", _never_plan)
    mesh = tmp_path / "ball.stl"
    mesh.write_bytes(stl_files["sphere"].read_bytes())
    (tmp_path / "ball.plan.png").mkdir()  # where the default picture would go
    result = runner.invoke(app, ["plan", str(mesh), "--mass-kg", "0.1"])
    assert result.exit_code == 2
    assert result.stderr == (f"error: the default picture {tmp_path / 'ball.plan.png'} is a directory: "
                             f"give a file path ending in .png, such as "
                             f"{tmp_path / 'ball.plan.png' / 'plan.png'}; pass --png with a path where "
                             "the picture can be written.\n")


def test_plan_checks_the_picture_path_once(stl_files, tmp_path, monkeypatch):
    import graspcampaign.rig.plan as rp

    checked = []
    check = rp.check_picture_path
    monkeypatch.setattr(rp, "check_picture_path", lambda *a: checked.append(a) or check(*a))
    result = runner.invoke(app, ["plan", str(stl_files["sphere"]), "--mass-kg", "0.1",
                                 "--png", str(tmp_path / "plan.png")])
    assert result.exit_code == 0, result.output
    assert checked == [(tmp_path / "plan.png", "--png")]


def test_plan_prints_the_path_it_wrote(stl_files, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["plan", str(stl_files["sphere"]), "--mass-kg", "0.1",
                                 "--png", "Plan.PNG"])
    assert result.exit_code == 0, result.output
    assert result.stdout.endswith("\npicture: Plan.PNG\n")
    assert sorted(p.name for p in Path().iterdir()) == ["Plan.PNG"]
    assert Path("Plan.PNG").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_an_inside_out_stl_plans_exactly_what_the_outward_stl_plans(tmp_path):
    """The tester's file: an icosphere exported after ``invert()`` (every triangle's corners
    reversed). load_mesh turns it outward; the plan must not depend on the file's winding."""
    import trimesh

    ball = trimesh.creation.icosphere(subdivisions=2, radius=30.0)  # mm
    ball.export(tmp_path / "out.stl")
    ball.invert()
    ball.export(tmp_path / "inv.stl")
    assert trimesh.load(tmp_path / "inv.stl").volume < 0.0  # the file really is inside out
    plans = []
    for name in ("out.stl", "inv.stl"):
        result = runner.invoke(app, ["plan", str(tmp_path / name), "--mass-kg", "0.3",
                                     "--material", "gel", "--json"])
        assert result.exit_code == 0, result.output
        plan = json.loads(result.stdout)
        assert plan.pop("mesh")["name"] == name and plan.pop("png").endswith(".plan.png")
        plans.append(plan)
    assert plans[1] == plans[0]


def test_plan_and_the_simulated_fingertip_default_to_the_papers_5_mm_radius(stl_files):
    # Table 2: R = 5 mm, for the simulated fingertip and for what `plan` assumes unless told
    from graspcampaign.campaign.schema import ContactModelCfg

    assert ContactModelCfg().fingertip_radius_m == pytest.approx(5e-3)
    args = ["plan", str(stl_files["sphere"]), "--mass-kg", "0.2", "--json"]
    default, explicit = (json.loads(runner.invoke(app, args + extra).stdout)
                         for extra in ([], ["--fingertip-radius-mm", "5"]))
    assert default["fingertip_radius_mm"] == pytest.approx(5.0)
    for plan in (default, explicit):
        plan.pop("png")
    assert default == explicit
