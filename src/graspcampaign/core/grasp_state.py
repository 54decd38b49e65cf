"""Parameters, fixed setup, contact evaluation and evolving state of the dynamic three-finger grasp.

:class:`GraspSetup` is the fixed model and :class:`GraspState` everything that evolves, including
the command for the coming step and the contact evaluation at the state's own time
(:class:`GraspForces`); :func:`graspcampaign.core.dynamics.grasp_step` maps one state to the next.

Shape letters: ``n`` nodes, ``c`` fingers (contacts).

References
----------
§3 (Fig. 3), §3.2-3.7 (Eq. 10-19), §5.1 (seed and clamp guards), §5.5 (Fig. 11).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from graspcampaign.core.contact import ContactParams, StickSlipParams, StickSlipState
from graspcampaign.core.hand import FingerContacts
from graspcampaign.core.msd import MsdBody, MsdParams

__all__ = [
    "GraspForces",
    "GraspParams",
    "GraspSetup",
    "GraspState",
]


@dataclass(frozen=True)
class GraspParams:
    """Constants of the dynamic grasp (the step and the phases of Fig. 11).

    Attributes
    ----------
    tau_f : float
        Vertical-residual tolerance of Eq. 19 [N]. Default 0.5 N, the simulation criterion of
        §3.7 / §6.1.
    settle_time : float
        After lift-off the residual must stay below ``tau_f`` this long to declare the grasp
        stable [s]. Default 0.05 s, about one period of the lowest elastic mode of the 0.4 kg
        reference sphere.
    grip_speed : float
        Finger advance rate while closing, while ``|w R_z| >= tau_f`` after lift-off begins, and of
        any finger out of contact [m/s] (the grip increment is ``grip_speed * dt`` per step).
        Default 20 mm/s, a slow closing speed (§3.5: low approach speeds).
    settle_speed : float
        The centroid speed must also stay below this during ``settle_time`` [m/s]. Default
        5 mm/s. The residual test alone (§3.7) would accept a body sliding out of the hand at
        constant velocity (zero net force).
    seed_depth : float
        Closure target: each finger closes until its own penetration reaches this depth [m];
        0.5 mm, the contact seed of §5.1 and Algorithm 2 line 1.
    open_gap : float
        Fingers start this far outside the surface along their approach lines [m] (Fig. 11,
        "opening"); default 1 mm, the per-contact design limit of §5.5. Only the closure time
        depends on it: nothing touches the held body before the fingers do.
    lift_time : float
        Duration of the lift-off ramp of the load fraction ``w`` from 0 to 1 [s] (raised cosine:
        finite jerk). Default 0.1 s, over twice the period of the lowest elastic mode of the
        0.4 kg reference sphere (42 ms), so the weight reaches the fingers quasi-statically.
    t_max : float
        Simulated time budget of the whole grasp [s].
    dt : float or None
        RK4 step [s]; None: half of :func:`core.msd.body_step_limit` with the stick spring ``k_t``
        (plus the normal contact stiffness at the fingertip radius when ``n >= 1``) and the dampers
        ``c_t + C`` added per node.
    max_depth : float or None
        Stop (``"penetration_limit"``) when a fingertip penetrates deeper [m]; None: the fingertip
        radius r, the limit of ``valid_geometry`` (beyond it the sphere centre is behind the face
        plane and Eq. 11 no longer describes a surface contact). A larger value lets a run go on
        with invalid contacts, for the unbounded reading (``success_unbounded``).
    drop_distance : float
        Declare ``"dropped"`` when the centroid falls this far below its height at lift-off [m].
    k_t : float
        Tangential stick stiffness [N/m]; default 4.96 N/mm (Table 4, reference silicone,
        E = 145.5 kPa, the family closest to E2 = 0.14 MPa).
    c_t : float
        Tangential stabilising damping [N*s/m]; §3.5 leaves it unidentified ("small"). Default
        1.0 N*s/m: about 0.1 of critical for k_t on the three nodes of one face at 0.4 kg / 356.
    """

    tau_f: float = 0.5
    settle_time: float = 0.05
    grip_speed: float = 0.02
    settle_speed: float = 5e-3
    seed_depth: float = 5e-4
    open_gap: float = 1e-3
    lift_time: float = 0.1
    t_max: float = 1.0
    dt: float | None = None
    max_depth: float | None = None
    drop_distance: float = 0.02
    k_t: float = 4.96e3
    c_t: float = 1.0

    def __post_init__(self) -> None:
        for name in ("tau_f", "settle_time", "settle_speed", "t_max", "drop_distance", "k_t",
                     "seed_depth", "lift_time"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0.0:
                raise ValueError(f"GraspParams.{name} must be finite and > 0, got {value!r}")
        for name in ("grip_speed", "c_t", "open_gap"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0.0:
                raise ValueError(f"GraspParams.{name} must be finite and >= 0, got {value!r}")


@dataclass(frozen=True)
class GraspForces:
    """Contact evaluation at one state (held over the RK4 stages of the following step).

    Attributes
    ----------
    contacts : FingerContacts
    normal_forces : (c,) float
        f_n [N].
    tangential : (c, 3) float
        Tangential forces on the object [N].
    forces : (c, 3) float
        Total contact forces on the object ``f_n (-n_f) + f_t`` [N].
    residual : (3,) float
        Eq. 19 ``sum_j f_j + m g`` [N] (the fingers against the full weight).
    support_force : (3,) float
        Force of the support on the body [N]: ``-(1 - w)`` times the other net external force
        ``sum_j f_j + m g - b sum_i v_i`` (edge and volume forces are internal and sum to zero),
        with ``w`` the load fraction of the step that led to this state.
    nodal_forces : (n, 3) float
        ``Phi^T`` transfer of ``forces`` to the nodes [N].
    relative_velocity : (c, 3) float
        Face material point relative to the fingertip [m/s].
    stick : StickSlipState
        Stick-slip state after this evaluation (committed by the next step).
    """

    contacts: FingerContacts
    normal_forces: np.ndarray
    tangential: np.ndarray
    forces: np.ndarray
    residual: np.ndarray
    support_force: np.ndarray
    nodal_forces: np.ndarray
    relative_velocity: np.ndarray
    stick: StickSlipState


@dataclass(frozen=True, eq=False)
class GraspSetup:
    """Fixed model of one dynamic grasp (built by :func:`prepare_grasp`).

    Attributes
    ----------
    body : MsdBody
    msd_params : MsdParams
    contact : ContactParams
    grasp : GraspParams
    stick : StickSlipParams
        ``mu_s = mu_k = mu``, k_t, c_t.
    targets : (c, 3) float
        Planned contact points on the undeformed surface [m].
    approach : (c, 3) float
        Outward unit normals of the approach lines.
    dt : float
        RK4 step [s].
    max_depth : float
        Penetration at which a run stops (``"penetration_limit"``) [m].
    valid_depth : float
        Largest penetration of a physically valid contact: the fingertip radius r [m].
    """

    body: MsdBody
    msd_params: MsdParams
    contact: ContactParams
    grasp: GraspParams
    stick: StickSlipParams
    targets: np.ndarray
    approach: np.ndarray
    dt: float
    max_depth: float
    valid_depth: float

    @property
    def mu(self) -> float:
        """Friction coefficient [-]."""
        return self.stick.mu_k

    @property
    def weight(self) -> np.ndarray:
        """(3,) weight ``(0, 0, -m g)`` [N]."""
        return np.array([0.0, 0.0, -self.msd_params.mass * self.msd_params.g])

    @property
    def n_fingers(self) -> int:
        """Number of fingers c."""
        return int(len(self.targets))


@dataclass(frozen=True)
class GraspState:
    """Evolving state of a dynamic grasp; :func:`grasp_step` returns a new one, never mutates.

    Attributes
    ----------
    time : float
        [s].
    state : (6 n,) float
        MSD state (``core.msd`` layout).
    grip : (c,) float
        Finger advance past first touch [m] (negative: open).
    grip_rate : (c,) float
        Command: finger advance rate during the next step [m/s] (also the finger velocity used
        in ``contact``, the rate of the step that led here).
    load_fraction : float
        Command: share ``w`` of the net external wrench the support leaves to the body during the
        next step [-] (0: held, 1: free).
    stick : StickSlipState
        Per-finger stick anchors in the slip-coordinate space (committed).
    slip_coords : (c, 3) float
        Integrated relative displacement of the contact material point w.r.t. the fingertip [m].
    contact : GraspForces
        Contact evaluation at this state (positions, grip, stick state above).
    """

    time: float
    state: np.ndarray
    grip: np.ndarray
    grip_rate: np.ndarray
    load_fraction: float
    stick: StickSlipState
    slip_coords: np.ndarray
    contact: GraspForces

    def commanded(self, grip_rate, load_fraction: float) -> GraspState:
        """Return this state with the command for the next step replaced."""
        # The constructor, not dataclasses.replace: this runs once per step of every grasp, and
        # replace() costs several times more.
        return GraspState(self.time, self.state, self.grip,
                          np.asarray(grip_rate, dtype=np.float64), float(load_fraction),
                          self.stick, self.slip_coords, self.contact)
