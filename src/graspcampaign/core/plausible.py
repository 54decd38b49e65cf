"""Physically plausible ranges of the quantities a user can set, each with its source.

A value outside its range is not a harder case of the same problem but a state that cannot exist
(a friction coefficient of 50, a negative mass) or a unit mistake (a mesh exported in metres read
as millimetres). The campaign schema (``campaign/schema.py``) and ``graspcampaign plan``
(``rig/plan.py``) refuse such values with the range and the reason below, from this one table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["FINGERTIP_RADIUS", "PLAUSIBLE", "PlausibleRange", "OBJECT_SIZE_MM", "bound_text"]

FINGERTIP_RADIUS = 5e-3
"""The paper's fingertip radius R [m] (Table 2, §7.1): the simulated fingertip's default, the Test 1
indenter and ``plan``'s default. Kept here, free of numpy, so the command line's help shows it."""


def bound_text(value: float) -> str:
    """A range's bound as every refusal prints it: a whole number without its ``.0`` (``<= 3``,
    ``<= 4294967295``), any other as Python's shortest text of it (``>= 0.0001``)."""
    return str(int(value)) if math.isfinite(value) and float(value).is_integer() else repr(float(value))


@dataclass(frozen=True)
class PlausibleRange:
    """A closed or half-open interval of physically meaningful values.

    Attributes
    ----------
    low, high : float
        Bounds, in the unit the quantity's name carries.
    low_open : bool
        Whether ``low`` itself is excluded (an exponent must be > 0, a friction coefficient may be 0).
    why : str
        The reason, short enough for an error message.
    source : str
        Where the bound comes from (paper section, reference, or physical argument).
    """

    low: float
    high: float
    low_open: bool
    why: str
    source: str

    def contains(self, value: float) -> bool:
        """Whether ``value`` is finite and inside the range."""
        if not math.isfinite(value):
            return False
        above = value > self.low if self.low_open else value >= self.low
        return above and value <= self.high

    def text(self) -> str:
        """The interval in words, e.g. ``> 0 and <= 10``."""
        return f"{'>' if self.low_open else '>='} {bound_text(self.low)} and <= {bound_text(self.high)}"

    def meta(self, scale: float = 1.0) -> dict:
        """Validation metadata for ``campaign.schema.check_value`` (``gt``/``ge``, ``le``, ``why``).

        ``scale`` converts the bounds to the unit of the field they check (``1e-3`` for a field in
        metres checked by a range in millimetres), so one range serves both spellings.
        """
        return {"gt" if self.low_open else "ge": self.low * scale, "le": self.high * scale,
                "why": self.why}


PLAUSIBLE: dict[str, PlausibleRange] = {
    "mass_kg": PlausibleRange(
        1e-4, 10.0, False, "below 0.1 g an object weighs less than the rig's 1 mN force "
        "resolution, and a three-finger hand lifts at most ~10 kg",
        "Fig. 22: the rig's load cell resolves 1 mN (0.1 g weighs 0.98 mN); Robotiq 3-Finger "
        "Adaptive Gripper datasheet: 10 kg encompassing-grip payload; the paper's objects weigh "
        "0.1-0.8 kg (Sec. 6.6, 8)"),
    "mu": PlausibleRange(
        0.0, 3.0, False, "dry friction of soft materials stays below 3",
        "Persson (2001) J. Chem. Phys. 115, 3840 (rubber friction rarely exceeds mu ~ 3); the "
        "paper's materials measure mu_s = 0.51-0.77 (Table 4)"),
    "fingertip_radius_mm": PlausibleRange(
        1.0, 50.0, False, "below 1 mm the evaluator's 0.5 mm seed penetration sinks half a "
        "fingertip's radius, and robot pads stay below 50 mm",
        "Algorithm 2 line 1 and Sec. 5: every contact is seeded 0.5 mm deep, and a contact deeper "
        "than R is outside the sphere model (the valid-geometry gate); Table 2 (R = 5 mm); human "
        "fingertips 7-10 mm, robot pads below 50 mm"),
    "n_exp": PlausibleRange(
        0.0, 3.0, True, "contact force exponents of soft bodies lie between ~0.4 and ~2",
        "Table 4 (n = 0.43-0.48), Hertz 1.5 (Johnson 1985, Contact Mechanics, Sec. 4.2); PSO "
        "bounds n in [0.1, 1.0] (Sec. 4)"),
    "lambda": PlausibleRange(
        0.0, 15.0, True, "the identification scale factors stay within 10x their PSO bounds",
        "PSO bounds lambda1, lambda2 in [0.05, 1.5] (Sec. 4, Sec. 11); sensitivity sweep "
        "[0.1, 1.5] (Sec. 6.6)"),
    "b": PlausibleRange(
        0.0, 20.0, False, "nodal damping stays within 10x its PSO bound",
        "PSO bounds b in [0.1, 2.0] (Sec. 4, Sec. 11)"),
}
"""Plausible ranges by quantity; each carries its reason and source."""

OBJECT_SIZE_MM = PlausibleRange(
    10.0, 500.0, False, "a three-finger hand grasps objects about 1 cm to 50 cm across",
    "fingertip radius 5 mm (Table 2) needs an object several radii wide; three-finger grippers "
    "open to ~155 mm (Robotiq 3F) and a human hand spans ~200 mm; the paper's objects are "
    "50-120 mm (Sec. 6.2, 8)")
"""Largest bounding-box side of an object to grasp [mm]."""
