"""Contact-level slip statics (paper §9.1, §9.3) against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from graspcampaign.core import slip as s
from graspcampaign.core.statics import GRAVITY


def _cone(tilt_rad: float, phase: float = 0.0) -> np.ndarray:
    """Three outward normals at 120 deg azimuth, all tilted by the same angle from horizontal."""
    az = phase + np.radians([0.0, 120.0, 240.0])
    return np.stack([np.cos(tilt_rad) * np.cos(az), np.cos(tilt_rad) * np.sin(az),
                     np.full(3, np.sin(tilt_rad))], axis=1)


def test_tangential_forces_symmetric_grasp_carry_a_third_each():
    normals = _cone(0.0)
    points = 0.05 * normals
    ft = s.contact_tangential_forces(points, normals, [1, 1, 1], np.zeros(3),
                                     [0, 0, -3.0], np.zeros(3))
    np.testing.assert_allclose(ft, [[0, 0, 1.0]] * 3, atol=1e-12)


def test_tangential_forces_balance_any_grasp():
    rng = np.random.default_rng(3)
    for _ in range(20):
        normals = rng.normal(size=(3, 3))
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        points = 0.04 * normals + 0.005 * rng.normal(size=(3, 3))
        fn = rng.uniform(0.5, 2.0, 3)
        force, moment = rng.normal(size=3), 0.01 * rng.normal(size=3)
        ft = s.contact_tangential_forces(points, normals, fn, np.zeros(3), force, moment)
        np.testing.assert_allclose(np.einsum("ij,ij->i", ft, normals), 0.0, atol=1e-10)
        total = ft - fn[:, None] * normals
        np.testing.assert_allclose(total.sum(axis=0) + force, 0.0, atol=1e-9)
        np.testing.assert_allclose(np.cross(points, total).sum(axis=0) + moment, 0.0, atol=1e-9)


def test_lateral_slip_scale_symmetric_closed_form():
    # Equatorial contacts, weight W, capacity c per contact, pull along finger 1's normal: only
    # fingers 2, 3 can resist it, each with a horizontal tangent at 30 deg to the pull, so
    # slip at F = sqrt(3) sqrt(c^2 - (W/3)^2).
    normals = _cone(0.0)
    points = 0.05 * normals
    w, c = 3.0, 1.68
    scales = s.slip_load_factors(points, normals, [1, 1, 1], np.zeros(3), np.full(3, c),
                                 [0, 0, -w], np.zeros(3), [1.0, 0, 0], np.zeros(3))
    assert np.isinf(scales[0])
    np.testing.assert_allclose(scales[1:], np.sqrt(3) * np.sqrt(c**2 - (w / 3) ** 2))
    assert s.first_slip_finger(points, normals, [1, 1, 1], np.zeros(3), w / GRAVITY, c / 2.4,
                               "lateral", 0.0) in (2, 3)


def test_a_downward_pull_adds_to_the_weight_an_upward_one_relieves_it():
    # Equatorial contacts with vertical tangents carry a third of the vertical load each: W + s
    # under a pull s downwards, W - s upwards. With W = 3 N and a capacity of 1.68 N per contact
    # the contacts saturate at 3 c - W = 2.04 N down and 3 c + W = 8.04 N up.
    normals = _cone(0.0)
    points, w, c = 0.05 * normals, 3.0, 1.68
    for kind, expected in (("down", 3 * c - w), ("up", 3 * c + w)):
        unit_force, unit_moment = s.disturbance_wrench(kind, 1.0)
        scales = s.slip_load_factors(points, normals, [1, 1, 1], np.zeros(3), np.full(3, c),
                                     [0, 0, -w], np.zeros(3), unit_force, unit_moment)
        np.testing.assert_allclose(scales, expected, rtol=1e-12)


def test_first_slip_finger_follows_the_weakest_contact():
    normals = _cone(0.0)
    points = 0.05 * normals
    assert s.first_slip_finger(points, normals, [0.5, 1.0, 1.0], np.zeros(3), 0.2, 0.6,
                               "none") == 1
    assert s.first_slip_finger(points, normals, [1.0, 1.0, 0.5], np.zeros(3), 0.2, 0.6,
                               "down") == 3


def test_microslip_limits():
    q, k = 1.2, 2.0e3
    assert s.microslip(0.0, q, k) == 0.0
    assert s.microslip(1e-6, q, k) == pytest.approx(1e-6 * q / k, rel=1e-5)
    assert s.microslip(1.0, q, k) == pytest.approx(1.5 * q / k)
    assert s.microslip(2.0, q, k) == pytest.approx(1.5 * q / k)


@pytest.mark.parametrize("kind, expected", [("up", 6.0), ("down", 0.0), ("none", np.inf)])
def test_a_contact_exactly_on_its_cone_sticks_until_the_disturbance_loads_it(monkeypatch, kind,
                                                                             expected):
    # Eq. 16 (§3.5): a contact sticks while |f_stick| <= mu_s f_n, so one exactly on its cone is
    # not slipping. Equatorial contacts under W = 3 N carry 1 N each, upwards, against a capacity
    # of exactly 1 N (the statics set exactly: lstsq leaves a ~1e-16 residue). A pull s upwards
    # unloads them, 1 - s/3, until they meet the cone again at s = 3c + W = 6 N; a pull down loads
    # them at once (3c - W = 0); a disturbance they do not carry leaves them sticking for ever.
    unit = {"up": 1.0 / 3.0, "down": -1.0 / 3.0, "none": 0.0}[kind]
    monkeypatch.setattr(s, "_tangential_solve", lambda *args: np.array(
        [[[0.0, 0.0, 1.0]] * 3, [[0.0, 0.0, 1.0 - unit]] * 3]))
    normals = _cone(0.0)
    scales = s.slip_load_factors(0.05 * normals, normals, [1, 1, 1], np.zeros(3), np.ones(3),
                                 [0, 0, -3.0], np.zeros(3), *s.disturbance_wrench(kind, 1.0))
    np.testing.assert_allclose(scales, expected, rtol=1e-12)
