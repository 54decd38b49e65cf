"""The gates of the verdict (Algorithm 1 line 6 and the validity gate) at their edges.

Outside references: a box's interior (|x|, |y|, |z| < half its side) for the fingertip centres, a
torque recomputed with ``np.cross`` from the normal forces alone, and numbers that are exact in
binary, so that a contact lies exactly on its friction cone.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from graspcampaign.core.equilibrium import EvaluatorParams, static_checks
from graspcampaign.core.geometry import deepest_per_finger, sphere_mesh_contacts
from graspcampaign.core.verdict import candidate_batch, geometry_valid, judge

RADIUS = 5e-3  # the fingertip radius r of Table 2
HALF = 0.05  # half the side of the test box


def _finger_depths(centres):
    box = trimesh.creation.box(extents=(2 * HALF,) * 3)
    hits = sphere_mesh_contacts(np.asarray(centres), RADIUS, box.vertices, box.faces)
    return hits.depths[deepest_per_finger(hits)]


def test_a_fingertip_whose_centre_is_inside_the_object_invalidates_the_grasp():
    # two fingertips pressed 3 and 4 mm into the box, the third 6 mm: its centre is inside
    centres = np.array([[HALF + 0.002, 0.01, 0.02], [-HALF - 0.001, -0.02, 0.01],
                        [0.013, -0.01, HALF - 0.001]])
    inside = np.all(np.abs(centres) < HALF, axis=1)
    assert inside.tolist() == [False, False, True]
    depths = _finger_depths(centres)
    np.testing.assert_array_equal(geometry_valid(depths[:, None], RADIUS), ~inside)
    # one buried fingertip is enough to make the whole grasp invalid
    assert geometry_valid(depths[None, :], RADIUS).tolist() == [False]
    assert geometry_valid(depths[None, :2], RADIUS).tolist() == [True]


def test_a_fingertip_centred_on_the_surface_is_not_buried():
    # depth exactly r: the centre on the face, not inside the object ("deeper than its radius")
    depths = _finger_depths([[HALF, 0.01, 0.02]])
    assert depths.tolist() == [RADIUS]
    assert geometry_valid(depths[None, :], RADIUS).tolist() == [True]


# Two side contacts at different heights and a pole contact: friction along +z at the side contacts
# adds a torque about the centroid that the normal forces alone do not have.
POINTS = np.array([[0.05, 0.0, 0.0], [-0.05, 0.01, 0.0], [0.0, 0.0, -0.05]])
NORMALS = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
DEPTHS = np.array([[1e-3, 2e-3, 1e-3]])


@pytest.mark.parametrize("law", ["paper", "slip"])
def test_the_torque_check_reads_the_normal_only_torque_under_the_paper_law_the_full_one_else(law):
    first = static_checks(POINTS, NORMALS, np.zeros(3), 0.5, 0.5, DEPTHS, 0.3, 1.5)
    f = first.normal_forces[0]
    normal_only = np.linalg.norm(sum(np.cross(POINTS[k], -NORMALS[k] * f[k]) for k in range(3)))
    full = first.full_torque_norm[0]
    assert abs(full - normal_only) > 1e-3  # the friction torque matters here
    params = EvaluatorParams(tau_t=(normal_only + full) / 2, grip_law=law)
    result = static_checks(POINTS, NORMALS, np.zeros(3), 0.5, 0.5, DEPTHS, 0.3, 1.5, params)
    # Algorithm 1 line 6: the normal-only residuals returned by Algorithm 2 (paper law); the laws
    # that resolve friction themselves check the full torque
    checked = normal_only if law == "paper" else full
    assert result.torque_ok[0] == (checked < params.tau_t)


def test_a_contact_exactly_on_its_friction_cone_fails_the_slip_check():
    # Algorithm 1 line 6 asks min_j (mu f_n - |f_t|) > 0: a contact at the cone's edge is
    # incipient slip. K = 1 N/mm, n = 1, delta = 2^-9 m: f_n = 1.953125 N, mu f_n = 0.9765625 N.
    points = np.array([[0.05, 0.0, 0.0], [-0.025, 0.04, 0.0], [-0.025, -0.04, 0.0]])
    normals = points / np.linalg.norm(points, axis=1, keepdims=True)
    params = EvaluatorParams()
    batch = candidate_batch(points[None], normals[None], np.zeros(3), 0.1, 0.5, 1.0, 1.0, params)
    depths = np.full((1, 3), 2.0**-9)
    on_cone = np.zeros((1, 3, 3))
    on_cone[..., 2] = 0.5 * 1000 * 2.0**-9
    inside_cone = on_cone * 0.5
    result = judge(batch, depths, params, np.zeros(1, dtype=int), None, friction=on_cone)
    assert result.slip_margin[0] == 0.0
    assert not result.slip_ok[0]
    assert judge(batch, depths, params, np.zeros(1, dtype=int), None, friction=inside_cone).slip_ok[0]
