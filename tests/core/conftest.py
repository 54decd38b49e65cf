"""Fixtures shared by the core tests."""

from __future__ import annotations

import pytest

from graspcampaign.core import dynamics, grasp_phases, msd
from graspcampaign.core.contact import ContactParams
from graspcampaign.core.mesh import make_object

# The firm preset of conf/model/firm.yaml (docs/decisions.md): Shore 30A fingertip, Shore 50A
# object (Gent 1958), Hertz contact (lambda1 = 2/3, n = 3/2).
FIRM = ContactParams(lambda1=2.0 / 3.0, lambda2=0.88, n=1.5, e_finger=1.1424e6,
                     e_object=2.4558e6, nu_finger=0.5, nu_object=0.5)


@pytest.fixture(scope="session")
def firm_setup():
    """A small firm-preset grasp that holds (144 nodes, 0.2 kg, mu = 0.3, default phases), not
    yet run: ``(setup, initial_state)`` (for tests that need no numpy reference run: that run
    takes about 5 s)."""
    mesh = make_object("sphere", 144)
    params = msd.msd_params_from_modulus(mesh, youngs_modulus=FIRM.e_object, mass=0.2)
    return dynamics.prepare_grasp(mesh, 0.3, params, FIRM)


@pytest.fixture(scope="session")
def firm_grasp(firm_setup):
    """:func:`firm_setup` run once per session on the numpy reference step:
    ``(setup, initial_state, result)``."""
    setup, state = firm_setup
    return setup, state, grasp_phases.run_grasp_phases(setup, state)
