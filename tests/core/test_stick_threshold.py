"""The stick-to-slip threshold of Eq. 16: a contact sticks while ``|f_stick| <= mu_s f_n``.

The existing stick tests load far below ``mu_k f_n``, so a threshold read from the kinetic
coefficient, or a strict ``<``, passed them. Here the trial force lies between the kinetic and the
static cone, and exactly on the static one (powers of two, so the product is exact), in the numpy
law and in the compiled contact stage of the dynamic grasp.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from graspcampaign.core import dynamics, grasp_kernel, msd
from graspcampaign.core.contact import (
    ContactParams,
    StickSlipParams,
    StickSlipState,
    tangential_force,
)
from graspcampaign.core.mesh import make_object

UP = np.array([[0.0, 0.0, 1.0]])


@pytest.mark.parametrize("displacement", [0.45 / 128, 2.0**-8], ids=["between-cones", "on-static-cone"])
def test_a_trial_force_inside_the_static_cone_sticks(displacement):
    # k_t xi = 0.45 N (between mu_k f_n = 0.25 N and mu_s f_n = 0.5 N) or exactly 0.5 N
    friction = StickSlipParams(mu_s=0.5, mu_k=0.25, k_t=128.0)
    state = StickSlipState.initial(np.zeros((1, 3)))
    point = np.array([[displacement, 0.0, 0.0]])
    forces, new = tangential_force(state, friction, point, np.array([1.0]), np.zeros((1, 3)), UP)
    assert not new.sliding[0]
    np.testing.assert_allclose(forces, [[-128.0 * displacement, 0.0, 0.0]])  # Hooke, not mu_k f_n
    np.testing.assert_array_equal(new.anchors, state.anchors)


def test_a_trial_force_beyond_the_static_cone_slides():
    friction = StickSlipParams(mu_s=0.5, mu_k=0.25, k_t=128.0)
    point = np.array([[0.51 / 128, 0.0, 0.0]])
    forces, new = tangential_force(StickSlipState.initial(np.zeros((1, 3))), friction, point,
                                   np.array([1.0]), np.zeros((1, 3)), UP)
    assert new.sliding[0]
    np.testing.assert_allclose(forces, [[-0.25, 0.0, 0.0]])


def test_compiled_contact_stage_sticks_between_the_kinetic_and_static_cones():
    """The campaign's dynamic grasp sets mu_s = mu_k, where the two thresholds coincide; the
    compiled stage still carries both, so give it distinct ones and a finger whose trial force lies
    between them: Coulomb's rule says it sticks."""
    setup, opened = dynamics.prepare_grasp(make_object("sphere", 92), 0.3, msd.MsdParams(mass=0.1),
                                           ContactParams(lambda1=15.8, lambda2=0.88, n=0.487))
    moved = replace(opened, grip=np.array([8e-4, 6e-4, 7e-4]),
                    slip_coords=np.array([[2e-4, 0.0, 0.0], [0.0, 1e-4, 0.0], [1e-4, 1e-4, 0.0]]))
    moved = replace(moved, stick=StickSlipState(np.zeros((3, 3)), np.zeros(3, dtype=bool)))
    # mu large enough that every finger sticks: the tangential force is then the trial force
    sticking = dynamics.grasp_forces(replace(setup, stick=replace(setup.stick, mu_s=1e6, mu_k=1e6)),
                                     moved)
    assert sticking.contacts.active.all() and not sticking.stick.sliding.any()
    ratio = np.linalg.norm(sticking.tangential, axis=1) / sticking.normal_forces
    assert (ratio > 0).all()
    # finger 0's trial force between the cones: mu_k f_n < |f_stick| < mu_s f_n
    between = replace(setup, stick=replace(setup.stick, mu_s=1.25 * ratio[0], mu_k=0.75 * ratio[0]))
    packed = grasp_kernel.packed_setup(between)
    _, _, flags, _, _, _ = grasp_kernel.contact_stage(
        moved.state.reshape(-1, 6), packed.edges, packed.faces, packed.targets, packed.approach,
        moved.grip, moved.grip_rate, moved.slip_coords, moved.stick.anchors, packed.law,
        packed.weight_z, between.msd_params.b, moved.load_fraction)
    assert flags[grasp_kernel.ACTIVE][0]
    assert not flags[grasp_kernel.SLIDING][0]
    np.testing.assert_array_equal(flags[grasp_kernel.SLIDING], ratio > 1.25 * ratio[0])
