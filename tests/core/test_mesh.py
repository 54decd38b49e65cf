"""Tests for core.mesh: parametric objects (§6.2) and user-mesh loading/validation (SPEC §2.1).

References are closed forms (volumes of a ball, an ellipsoid, a Minkowski-rounded cube and a half
torus by Pappus) and trimesh's own watertightness/winding checks.
"""

import numpy as np
import pytest
import trimesh

from graspcampaign.core import mesh as mesh_mod
from graspcampaign.core.mesh import SHAPES, MeshError, check_mesh, load_mesh, make_object

STUDY_NODES = [144, 356, 390, 1750]


@pytest.mark.parametrize("shape", sorted(SHAPES))
@pytest.mark.parametrize("n_nodes", STUDY_NODES)
def test_objects_are_closed_outward_centred_and_sized(shape, n_nodes):
    m = make_object(shape, n_nodes)
    assert m.is_watertight
    assert m.is_winding_consistent
    assert m.volume > 0.0  # outward winding
    assert np.allclose(m.center_mass, 0.0, atol=1e-9)
    assert abs(len(m.vertices) - n_nodes) <= 0.02 * n_nodes
    if shape != "handle":  # star-shaped constructions hit the count exactly
        assert len(m.vertices) == n_nodes
    assert np.isfinite(m.vertices).all()


def test_make_object_default_is_390_nodes():
    assert len(make_object("sphere").vertices) == 390


@pytest.mark.parametrize("n_nodes", list(range(50, 2001, 37)))
def test_handle_node_count_within_two_percent(n_nodes):
    n_u, n_v = mesh_mod._handle_grid(n_nodes)
    assert abs(n_u * n_v + 2 - n_nodes) <= 0.02 * n_nodes


# Closed-form volumes [m^3]; the inscribed polyhedron is slightly smaller than the solid.
R = 0.050
A, B, C = 0.060, 0.045, 0.035
CORE, FILLET = 0.028, 0.012
VOLUMES = {
    "sphere": 4.0 / 3.0 * np.pi * R**3,
    "ellipsoid": 4.0 / 3.0 * np.pi * A * B * C,
    # Minkowski sum of a cube of side 2*CORE with a ball of radius FILLET (Steiner formula).
    "rounded_cube": (2 * CORE) ** 3 + 6 * (2 * CORE) ** 2 * FILLET
    + 3 * np.pi * (2 * CORE) * FILLET**2 + 4.0 / 3.0 * np.pi * FILLET**3,
    # Pappus: tube cross-section area times the path length of its centroid (half circle).
    "handle": np.pi * 0.012**2 * np.pi * 0.036,
}


@pytest.mark.parametrize("shape", sorted(VOLUMES))
def test_volume_matches_closed_form(shape):
    m = make_object(shape, 1750)
    assert m.volume == pytest.approx(VOLUMES[shape], rel=0.015)
    assert m.volume < VOLUMES[shape]  # inscribed polyhedron


def test_dimensions():
    assert np.allclose(make_object("sphere", 1750).extents, 2 * R, rtol=0.005)
    assert np.allclose(make_object("ellipsoid", 1750).extents, [2 * A, 2 * B, 2 * C], rtol=0.01)
    assert np.allclose(make_object("rounded_cube", 390).extents, 0.080, rtol=1e-6)
    sphere = make_object("sphere", 390)
    radii = np.linalg.norm(sphere.vertices - sphere.vertices.mean(axis=0), axis=1)
    assert np.allclose(radii, R, rtol=2e-3)
    pear = make_object("pear", 390)
    assert 0.080 < pear.extents[2] < 0.100 and 0.055 < pear.extents[0] < 0.070
    assert pear.extents[2] > pear.extents[0]  # taller than wide, axis along z
    handle = make_object("handle", 390)
    assert np.allclose(handle.extents, [0.096, 0.048, 0.024], rtol=0.01)


def test_pear_is_star_shaped_about_its_ray_origin():
    # One boundary crossing per ray is what makes the radial construction valid.
    directions = mesh_mod.fibonacci_directions(2000)
    t = np.linspace(1e-4, 0.15, 3000)
    points = t[None, :, None] * directions[:, None, :]
    points += mesh_mod._PEAR_STAR_CENTRE  # in place: one 144 MB array, not two
    signs = np.sign(mesh_mod._pear_sdf(points))
    assert (np.count_nonzero(np.diff(signs, axis=1), axis=1) == 1).all()


def test_fibonacci_directions_are_unit_and_area_uniform():
    u = mesh_mod.fibonacci_directions(1000)
    assert np.allclose(np.linalg.norm(u, axis=1), 1.0)
    # Area-uniform: z is uniform on [-1, 1], so each hemisphere holds half the points.
    assert (u[:, 2] > 0).sum() == 500
    assert np.allclose(u.mean(axis=0), 0.0, atol=2e-3)


def test_make_object_is_deterministic_and_returns_copies():
    a = make_object("pear", 390)
    b = make_object("pear", 390)
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    a.vertices[:] = 0.0
    c = make_object("pear", 390)
    assert np.array_equal(c.vertices, b.vertices)


def test_make_object_errors():
    with pytest.raises(MeshError, match=r"unknown shape 'cube'; allowed shapes are sphere, "):
        make_object("cube")
    with pytest.raises(MeshError, match="n_nodes must be at least 12, got 11"):
        make_object("sphere", 11)
    with pytest.raises(MeshError, match="n_nodes must be an integer"):
        make_object("sphere", 390.0)


# ---------------------------------------------------------------------------------------------
# User meshes
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("suffix", [".stl", ".obj", ".ply"])
@pytest.mark.parametrize(("unit", "scale"), [("mm", 1e3), ("cm", 1e2), ("m", 1.0)])
def test_load_mesh_round_trip_units(tmp_path, suffix, unit, scale):
    ref = make_object("ellipsoid", 144)
    exported = ref.copy()
    exported.apply_scale(scale)
    exported.apply_translation([3.0 * scale, 0.0, 0.0])  # load_mesh must re-centre it
    path = tmp_path / f"obj{suffix}"
    exported.export(path)
    loaded = load_mesh(path, unit=unit)
    assert len(loaded.vertices) == len(ref.vertices)
    assert loaded.volume == pytest.approx(ref.volume, rel=1e-6)
    assert np.allclose(loaded.extents, ref.extents, rtol=1e-6)
    assert np.allclose(loaded.center_mass, 0.0, atol=1e-9)


def test_load_mesh_fixes_globally_inverted_winding(tmp_path):
    inverted = make_object("sphere", 144)
    inverted.invert()
    assert inverted.volume < 0
    path = tmp_path / "inverted.stl"
    inverted.export(path, file_type="stl")
    loaded = load_mesh(path, unit="m")
    assert loaded.volume == pytest.approx(-inverted.volume, rel=1e-9)


def test_load_mesh_errors(tmp_path):
    with pytest.raises(MeshError) as unit:  # the sentence plan gives (--unit on the command line)
        load_mesh(tmp_path / "x.stl", unit="in")
    assert str(unit.value) == ("unit = 'in' is not a length unit a mesh is read in; use one of m, cm, "
                               "mm (the unit of the mesh file's coordinates).")
    with pytest.raises(MeshError, match=r"^unit = 'MM' is not .* in; did you mean 'mm'\? use one"):
        load_mesh(tmp_path / "x.stl", unit="MM")
    with pytest.raises(MeshError, match=r"mesh file '.*missing\.stl' does not exist"):
        load_mesh(tmp_path / "missing.stl")
    (tmp_path / "shape.step").write_text("solid")
    with pytest.raises(MeshError, match="unsupported type '.step': use .stl, .obj, .ply"):
        load_mesh(tmp_path / "shape.step")
    (tmp_path / "empty.obj").write_text("# nothing here\n")
    with pytest.raises(MeshError, match="'empty.obj' is empty"):
        load_mesh(tmp_path / "empty.obj")

    sphere = make_object("sphere", 144)
    opened = trimesh.Trimesh(sphere.vertices, sphere.faces[:-3], process=False)
    path = tmp_path / "open.stl"
    opened.export(path)
    with pytest.raises(MeshError, match=r"mesh 'open.stl' is not watertight: \d+ boundary edges"):
        load_mesh(path)


def test_check_mesh_rejects_bad_meshes():
    sphere = make_object("sphere", 144)
    faces = sphere.faces.copy()
    faces[0] = faces[0][::-1]  # one flipped face
    flipped = trimesh.Trimesh(sphere.vertices, faces, process=False)
    with pytest.raises(MeshError, match="'flip' is inconsistently wound: 3 edges"):
        check_mesh(flipped, "flip")

    vertices = np.vstack([sphere.vertices, sphere.vertices[faces[0, 0]]])
    degenerate_faces = np.vstack([sphere.faces, [[faces[0, 0], len(vertices) - 1, faces[0, 1]]]])
    degenerate = trimesh.Trimesh(vertices, degenerate_faces, process=False)
    with pytest.raises(MeshError, match=r"^mesh 'deg' has 1 degenerate \(zero-area\) face\.$"):
        check_mesh(degenerate, "deg")

    doubled = trimesh.Trimesh(sphere.vertices, np.vstack([sphere.faces, sphere.faces[:1]]),
                              process=False)
    with pytest.raises(MeshError, match="not watertight: 3 non-manifold edges"):
        check_mesh(doubled, "dup")

    with pytest.raises(MeshError, match="'none' is empty: it has no faces"):
        check_mesh(trimesh.Trimesh(), "none")

    bad = sphere.vertices.copy()
    bad[0, 0] = np.nan
    with pytest.raises(MeshError, match=r"^mesh 'nan' has non-finite coordinates at 1 vertex\.$"):
        check_mesh(trimesh.Trimesh(bad, sphere.faces, process=False), "nan")


def test_check_mesh_returns_centred_copy():
    m = make_object("pear", 144)
    m.apply_translation([1.0, 2.0, 3.0])
    out = check_mesh(m, "pear")
    assert np.allclose(out.center_mass, 0.0, atol=1e-9)
    assert np.allclose(m.center_mass, [1.0, 2.0, 3.0])  # input untouched
