"""Tests of core.hand: the hand-reachable contact directions and the planned contacts on a mesh.

Outside references: the closed-form 45/45/-90 directions (§5.2, §6.1), the inscribed and
circumscribed radii of a faceted sphere, and brute-force ``geometry.sphere_triangle_contacts`` over
every face (the broad phase of the fingertip query must be exact).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from graspcampaign.core import geometry, hand, msd
from graspcampaign.core.mesh import make_object


@pytest.fixture(scope="module")
def sphere():
    return make_object("sphere", 92)


def test_hand_contact_directions_default_is_45_45_minus_90():
    d = hand.hand_contact_directions()
    s = np.sqrt(0.5)
    np.testing.assert_allclose(d, [[s, 0, s], [-s, 0, s], [0, 0, -1]], atol=1e-12)
    tilted = hand.hand_contact_directions(elevation_deg=30.0, third_elevation_deg=-60.0)
    np.testing.assert_allclose(np.degrees(np.arcsin(tilted[:, 2])), [30.0, 30.0, -60.0])
    np.testing.assert_allclose(np.linalg.norm(tilted, axis=1), 1.0)


def test_planned_contacts_hit_the_sphere_surface_along_the_rays(sphere):
    directions = hand.hand_contact_directions()
    points, faces, normals = hand.planned_contacts(sphere, directions)
    radii = np.linalg.norm(points - sphere.centroid, axis=1)
    # A faceted sphere lies between its inscribed and circumscribed radii.
    assert np.all(radii <= 0.05 + 1e-12) and np.all(radii > 0.045)
    np.testing.assert_allclose(
        (points - sphere.centroid) / radii[:, None], directions, atol=1e-9
    )
    np.testing.assert_allclose(normals, np.asarray(sphere.face_normals)[faces])
    assert np.all(np.einsum("ij,ij->i", normals, directions) > np.cos(np.radians(20.0)))


def test_planned_contacts_reports_a_missing_ray(sphere):
    class AwayFromTheMesh:  # a stand-in whose centroid is 1 m above the sphere
        triangles = sphere.triangles
        face_normals = sphere.face_normals
        centroid = np.array([0.0, 0.0, 1.0])

    with pytest.raises(ValueError, match=r"ray 1 along \[0\. 0\. 1\.\] misses the mesh"):
        hand.planned_contacts(AwayFromTheMesh(), [[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]])


@settings(max_examples=40, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.floats(-1.0, 1.0),
            st.floats(0.040, 0.056),
        ),
        min_size=3,
        max_size=3,
    )
)
def test_finger_contacts_broad_phase_is_exact(samples):
    mesh = make_object("sphere", 92)
    body = msd.msd_body_from_mesh(mesh, msd.MsdParams())
    centers = []
    for x, y, z, dist in samples:
        u = np.array([x, y, z]) + [1e-3, 0.0, 0.0]
        centers.append(dist * u / np.linalg.norm(u))
    centers = np.array(centers)
    approach = centers / np.linalg.norm(centers, axis=1)[:, None]
    got = hand.finger_contacts(mesh.vertices, body, centers, 0.005, approach)
    brute = geometry.sphere_triangle_contacts(centers, 0.005, np.asarray(mesh.triangles),
                                              backend="numpy")
    best = geometry.deepest_per_finger(brute)
    np.testing.assert_array_equal(got.active, best >= 0)
    for j in np.flatnonzero(best >= 0):
        assert got.depths[j] == pytest.approx(brute.depths[best[j]], abs=1e-15)
        assert got.faces[j] == brute.faces[best[j]]



def test_planned_contacts_take_the_outermost_crossing_of_a_ring():
    """A ray from a torus's centroid (the hole's centre) crosses the ring at R - r = 30 mm and
    leaves it at R + r = 50 mm; the planned contact is where it leaves (a faceted ring: 50 mm
    within the chord sag of its 32 x 64 sections, r (1 - cos(pi / 32)) + R (1 - cos(pi / 64)))."""
    import trimesh

    ring = trimesh.creation.torus(major_radius=0.04, minor_radius=0.01, major_sections=64,
                                  minor_sections=32)
    directions = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-0.6, -0.8, 0.0]])
    points, _, normals = hand.planned_contacts(ring, directions)
    distance = np.linalg.norm(points - ring.centroid, axis=1)
    sag = 0.01 * (1 - np.cos(np.pi / 32)) + 0.04 * (1 - np.cos(np.pi / 64))
    assert np.all(distance <= 0.05 + 1e-12) and np.all(distance >= 0.05 - sag)
    assert np.all(np.einsum("ij,ij->i", normals, directions) > 0.9)  # outward, away from the hole


def test_a_finger_off_the_object_stands_at_its_pad_point_nearest_the_object(sphere):
    """A fingertip 15 mm above the sphere's top vertex, approaching straight down, touches
    nothing; its contact point is its pad's lowest point, 5 mm below its centre (10 mm above the
    vertex), the side facing the object, not the far side 20 mm up."""
    body = msd.msd_body_from_mesh(sphere, msd.MsdParams())
    top = sphere.vertices[np.argmax(sphere.vertices[:, 2])]
    centres = np.array([top + [0.0, 0.0, 0.015]])
    got = hand.finger_contacts(sphere.vertices, body, centres, 0.005, np.array([[0.0, 0.0, 1.0]]))
    assert not got.active[0] and got.depths[0] == 0.0 and got.faces[0] == -1
    np.testing.assert_allclose(got.points[0], top + [0.0, 0.0, 0.010], atol=1e-15)
