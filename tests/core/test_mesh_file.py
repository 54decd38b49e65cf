"""Tests for core.mesh_file: user meshes made of more than one closed surface, OBJ structure.

References: trimesh's own component count (``Trimesh.split``, ``body_count``) and the closed form
of a point inside or outside a ball (winding number 1 or 0).
"""

import numpy as np
import pytest
import trimesh

from graspcampaign.core.mesh_file import (
    MeshError,
    check_mesh,
    check_one_body,
    load_mesh,
    winding_numbers,
)


def _ball(radius: float, centre=(0.0, 0.0, 0.0), inward: bool = False) -> trimesh.Trimesh:
    ball = trimesh.creation.icosphere(subdivisions=2, radius=radius)
    ball.apply_translation(centre)
    if inward:
        ball.invert()
    return ball


def test_winding_numbers_of_a_ball_are_one_inside_and_zero_outside():
    ball = _ball(0.02)
    inscribed = 0.02 * np.cos(np.radians(20.0))  # the subdivision-2 icosphere's faces lie beyond
    points = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.9 * inscribed], [0.0, 0.03, 0.0],
                       [1.0, 0.0, 0.0]])
    assert winding_numbers(points, ball.triangles) == pytest.approx([1.0, 1.0, 0.0, 0.0], abs=1e-9)
    inverted = _ball(0.02, inward=True)
    assert winding_numbers(points[:2], inverted.triangles) == pytest.approx([-1.0, -1.0], abs=1e-9)


def test_one_ball_passes():
    check_one_body(_ball(0.02))
    assert check_mesh(_ball(0.02)).is_watertight


@pytest.mark.parametrize("n_balls", [2, 3])
def test_separate_bodies_are_refused_with_trimesh_count(n_balls):
    mesh = trimesh.util.concatenate([_ball(0.02, (0.1 * k, 0.0, 0.0)) for k in range(n_balls)])
    count = len(mesh.split(only_watertight=False))  # trimesh's own count of the bodies
    assert count == mesh.body_count == n_balls
    with pytest.raises(MeshError) as info:
        check_mesh(mesh, "balls.stl")
    assert str(info.value) == (f"mesh 'balls.stl' has {count} separate bodies: the planner grasps "
                               "one object, so put each body in a file of its own and plan it alone.")


@pytest.mark.parametrize("inward", [True, False])  # a well-wound cavity, and one wound like a body
def test_a_hollow_shell_is_refused_as_a_cavity(inward):
    mesh = trimesh.util.concatenate([_ball(0.04), _ball(0.03, inward=inward)])
    assert len(mesh.split(only_watertight=False)) == 2
    with pytest.raises(MeshError, match=r"^mesh 'shell.stl' has an internal cavity \(1 of its 2 "
                                        r"closed surfaces lies inside the outer one\), whose surface "
                                        r"no finger reaches: keep only the outer surface in the file "
                                        r"\(the plan then takes the object as solid\)\.$"):
        check_mesh(mesh, "shell.stl")


def test_a_ball_in_a_cavity_is_a_second_body():
    rattle = trimesh.util.concatenate([_ball(0.04), _ball(0.03, inward=True), _ball(0.01)])
    with pytest.raises(MeshError, match="^mesh 'rattle.stl' has 2 separate bodies: "):
        check_one_body(rattle, "rattle.stl")


def test_surfaces_passing_through_each_other_are_refused():
    mesh = trimesh.util.concatenate([_ball(0.02), _ball(0.02, (0.03, 0.0, 0.0))])
    with pytest.raises(MeshError, match=r"^mesh 'pair.stl' has 2 closed surfaces that pass through "
                                        r"each other: merge them into one closed surface \(a boolean "
                                        r"union\) before planning\.$"):
        check_one_body(mesh, "pair.stl")


def _sphere_obj(path, extra: str = "") -> int:
    """Write a trimesh icosphere (mm) as OBJ plus ``extra`` lines; return its vertex count."""
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=40.0)
    path.write_text(sphere.export(file_type="obj") + extra)
    return len(sphere.vertices)


def test_an_obj_face_beyond_the_vertices_is_named(tmp_path):
    path = tmp_path / "bad_index.obj"
    n_vertices = _sphere_obj(path, "f 1 2 99999\n")
    line = len(path.read_text().splitlines())  # the appended face is the last line
    with pytest.raises(MeshError) as info:
        load_mesh(path)
    assert str(info.value) == (f"mesh 'bad_index.obj' has a face (line {line}) that refers to vertex "
                               f"99999, but the file has only {n_vertices} vertices.")


@pytest.mark.parametrize("index", [0, -9999])
def test_an_obj_face_before_the_first_vertex_is_named(tmp_path, index):
    path = tmp_path / "back.obj"
    n_vertices = _sphere_obj(path, f"f 1 2 {index}\n")
    line = len(path.read_text().splitlines())
    with pytest.raises(MeshError, match=rf"^mesh 'back.obj' has a face \(line {line}\) that refers to "
                                        rf"vertex {index}, but {n_vertices} vertices precede it: OBJ "
                                        r"indices count from 1, or back from -1\.$"):
        load_mesh(path)


def test_an_obj_of_vertices_only_is_named(tmp_path):
    path = tmp_path / "points_only.obj"
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=40.0)
    path.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in sphere.vertices))
    with pytest.raises(MeshError) as info:
        load_mesh(path)
    assert str(info.value) == (f"mesh 'points_only.obj' has {len(sphere.vertices)} vertices but no "
                               "faces: a point cloud is no surface; export the mesh with its faces "
                               "(OBJ 'f' lines).")


def test_obj_faces_with_slashes_and_negative_indices_are_read(tmp_path):
    box = trimesh.creation.box(extents=(30.0, 30.0, 30.0))  # mm
    lines = [f"v {x} {y} {z}" for x, y, z in box.vertices] + ["vn 0 0 1"]
    n = len(box.vertices)
    lines += [f"f {a - n}//1 {b - n}//1 {c - n}//1" for a, b, c in box.faces]  # -n..-1 is 0..n-1
    path = tmp_path / "box.obj"
    path.write_text("\n".join(lines) + "\n")
    mesh = load_mesh(path)
    assert len(mesh.faces) == len(box.faces)
    assert mesh.volume == pytest.approx(box.volume * 1e-9)  # trimesh's own volume, mm^3 -> m^3


def test_an_stl_numbers_its_vertices_whatever_the_winding_or_triangle_order(tmp_path):
    """An STL has no vertex list: the merged vertices must not depend on corner or triangle
    order, or an inside-out copy of a file plans differently (the planner samples vertices)."""
    ball = _ball(30.0)
    ball.export(tmp_path / "out.stl")
    shuffled = _ball(30.0, inward=True)
    shuffled.faces = shuffled.faces[np.random.default_rng(1).permutation(len(shuffled.faces))]
    shuffled.export(tmp_path / "inv.stl")
    outward, inward = load_mesh(tmp_path / "out.stl"), load_mesh(tmp_path / "inv.stl")
    # the same numbering (coordinates equal up to the centring's summation order, ~1e-19 m)
    np.testing.assert_allclose(inward.vertices, outward.vertices, rtol=0.0, atol=1e-15)
    # the same triangles (each a cyclic turn of the other's, wound the same way)
    def triangles(mesh):
        turned = [np.roll(f, -int(np.argmin(f))) for f in np.asarray(mesh.faces)]
        return sorted(map(tuple, turned))
    assert triangles(inward) == triangles(outward)
    assert inward.volume == pytest.approx(ball.volume * 1e-9)  # outward, in m^3


@pytest.mark.parametrize("file_type", ["obj", "stl_ascii", "ply"])
def test_a_mesh_with_a_byte_order_mark_is_read_in_place(tmp_path, monkeypatch, file_type):
    """A text mesh behind a UTF-8 byte-order mark reads as the same mesh without it, and nothing is
    written meanwhile (it was copied, past the mark, to a temporary file)."""
    import builtins

    ball = _ball(40.0)
    text = ball.export(file_type=file_type, encoding="ascii") if file_type == "ply" else \
        ball.export(file_type=file_type)
    text = text if isinstance(text, bytes) else text.encode()
    suffix = ".stl" if file_type == "stl_ascii" else f".{file_type}"
    plain, marked = tmp_path / f"plain{suffix}", tmp_path / f"marked{suffix}"
    plain.write_bytes(text)
    marked.write_bytes(b"\xef\xbb\xbf" + text)
    expected = load_mesh(plain)
    opened, real = [], builtins.open

    def watched(file, mode="r", *args, **kwargs):
        opened.append(mode)
        return real(file, mode, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", watched)
    mesh = load_mesh(marked)
    monkeypatch.undo()
    assert opened and not [mode for mode in opened if set(mode) & set("wax+")]
    np.testing.assert_array_equal(mesh.vertices, expected.vertices)
    np.testing.assert_array_equal(mesh.faces, expected.faces)


def test_a_file_holding_only_a_byte_order_mark_is_an_empty_mesh(tmp_path):
    path = tmp_path / "mark.obj"
    path.write_bytes(b"\xef\xbb\xbf")
    # it said "the file has 0 bytes" of a file of 3
    with pytest.raises(MeshError, match=r"^mesh 'mark.obj' is empty: the file holds only a "
                                        r"byte-order mark\.$"):
        load_mesh(path)


def test_a_mesh_file_this_user_may_not_read_is_a_mesh_error(tmp_path, monkeypatch):
    """As root no permission bit stops the read, so the open is refused as the system refuses a
    chmod 000 file to its owner (tests/cli/test_unreadable_places.py does it for real)."""
    import errno
    import os

    from graspcampaign.core import mesh_file

    path = tmp_path / "ball.stl"
    _ball(20.0).export(path)

    def denied(name, *args, **kwargs):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), name)

    monkeypatch.setattr(mesh_file, "open", denied, raising=False)
    with pytest.raises(MeshError) as refused:
        load_mesh(path)
    assert str(refused.value) == (f"mesh file {str(path)!r} cannot be read by this user: permission "
                                  "denied (its permissions, or those of the directory holding it, "
                                  "keep this user out); give this user access (chmod, chown), or run "
                                  "the command as the user who owns it.")
