"""Our 356-node soft sphere in MuJoCo, the map of our constants onto it, and checks of that map.

Used by ``bench_mujoco.py`` (and its test). MuJoCo builds our surface as a ``flexcomp`` of type
``direct``, ``dim=2``, with our vertices and faces: one body with three world-aligned slide
joints per node, mass ``m/n`` each. Two deformation models, the two of MuJoCo's manual
("Modeling > Deformable objects"):

- ``edge``: every mesh edge a soft equality constraint (``<edge equality="true">``) under
  ``implicitfast``. MuJoCo 4.0 rejects a passive ``<edge stiffness>`` for ``dim=2``, so this is
  the construct closest to our edge-spring network. At rest a soft constraint row obeys
  ``R f = a_ref = -B v - K imp r`` (Computation chapter, soft constraints), a linear spring
  ``K imp / R`` and damper ``B / R`` along the edge. With the direct ``solref = (-kappa, -beta)``
  and a constant impedance ``d`` (``K = kappa / d^2``, ``imp = d``, ``B = beta / d``,
  ``R = (1 - d) A / d`` with ``A`` MuJoCo's diagonal inverse inertia of the row) these are
  ``kappa / ((1 - d) A)`` and ``beta / ((1 - d) A)``; we set them to our k and c.
- ``membrane``: continuum Saint Venant-Kirchhoff stretching of the triangles
  (``<elasticity elastic2d="stretch">``) under ``discrete``, the setup of MuJoCo 4.0's "Model
  tuning > Deformables" for accurate deformation. A triangular lattice of springs k is, in the
  small-strain limit, a membrane with ``E t = 2 k / sqrt(3)`` and ``nu = 1/3``; the edge dampers
  c share the springs' projectors (stiffness-proportional), i.e. Rayleigh damping ``c / k`` [s].

In both, the absolute nodal damping b is the joint damping of the slide joints. Contacts are
MuJoCo soft contact constraints mapped like the edges: static stiffness the secant of our
Hunt-Crossley law (Eq. 13) at the 0.5 mm seed of §5.1, damping our C (Eq. 14), friction mu with
MuJoCo's default pyramidal cone. The fingertips are mocap spheres of our radius on our approach
lines, moved out by the flex radius so that penetrations equal ours.

The map is checked by the squeeze stiffness of the whole shell (two antipodal nodes pushed
together by a small load): ours from our linearised stiffness, MuJoCo's simulated to rest.

References
----------
MuJoCo 4.0 documentation, bundled in the wheel under ``mujoco/doc``: Computation chapter (soft
constraints, diagonal approximation, integrators ``implicitfast`` and ``discrete``), Modeling
chapter (``solref``/``solimp`` in the direct format, deformable objects, model tuning), XML
reference (``flexcomp``, ``flex/edge``, ``flex/elasticity``). Ostoja-Starzewski, M. (2002),
"Lattice models in micromechanics", Appl. Mech. Rev. 55(1):35-60 (triangular spring lattice in
2D: lambda = mu = sqrt(3) k / 4, hence E = 2 k / sqrt(3), nu = 1/3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from graspcampaign.core import dynamics, jacobian, msd
from graspcampaign.core.contact import ContactParams, normal_force

try:
    import mujoco
except ImportError:  # the optional `bench` extra
    mujoco = None

MJ_TIMESTEP = 2e-3  # [s] MuJoCo's default option/timestep
FLEX_RADIUS = 1e-4  # [m] must be > 0 in 2D; fingertips are moved out by it (same penetration)
IMPEDANCE = 0.9  # constant solimp d of edge and contact rows: MuJoCo's default d0
CONTACT_REF_DEPTH = 5e-4  # [m] secant point of the Hunt-Crossley law: the §5.1 seed depth
SQUEEZE_FORCE = 1e-4  # [N] small load: the pure shell softens nonlinearly above ~1 mN

VARIANTS = {
    "edge": ("edge equality (soft constraints)", "implicitfast", "CG"),
    "membrane": ("SVK membrane (elasticity)", "discrete", "CG"),
}
"""Variant -> (body model, integrator, solver). CG, MuJoCo's matrix-free primal solver, at its
default tolerance: on this squeeze it took 1.9 / 2.9 ms of CPU per step (edge / membrane) against
3.5 / 5.1 ms for Newton (measured while building this benchmark, best of 5), so the peer runs
with its faster solver."""


@dataclass(frozen=True)
class WindowTrace:
    """Per-step contact statistics of one simulator over the window (shape letters: s steps).

    Attributes
    ----------
    times : (s,) float
        Start time of each step [s].
    touching : (s, 3) bool
        Fingertip in contact.
    n_points : (s,) int
        Contact points (ours: one per touching fingertip; MuJoCo: one per flex element touched).
    normal_forces : (s, 3) float
        Total normal force of each fingertip on the sphere [N].
    depths : (s, 3) float
        Deepest penetration of each fingertip [m].
    """

    times: np.ndarray
    touching: np.ndarray
    n_points: np.ndarray
    normal_forces: np.ndarray
    depths: np.ndarray


def point_inverse_weight(params: msd.MsdParams, n_nodes: int) -> float:
    """Return MuJoCo's diagonal inverse inertia of an edge or flex-contact row [1/kg].

    Each node is a body with three world-aligned slide joints and mass ``m/n``: its translational
    ``body_invweight0`` is ``n/m``; an edge row (``flexedge_invweight0``) and a contact row on a
    triangle (barycentric average over its vertices) get the same value.
    """
    return n_nodes / params.mass


def edge_solref(params: msd.MsdParams, inverse_weight: float, impedance: float = IMPEDANCE):
    """Return the direct ``solref = (-kappa, -beta)`` whose static edge spring is k and damper c.

    ``kappa = k (1-d) A``, ``beta = c (1-d) A``: at rest ``f = -(K imp r + B v) / R`` with
    ``K = kappa/d^2``, ``imp = d``, ``B = beta/d``, ``R = (1-d) A / d``.
    """
    scale = (1.0 - impedance) * inverse_weight
    return -params.k * scale, -params.c * scale


def contact_secant(contact: ContactParams) -> float:
    """Return ``f_n(delta_ref) / delta_ref`` [N/m]: our Eq. 13 at rest, secant at the 0.5 mm seed."""
    f_ref = normal_force(CONTACT_REF_DEPTH, 0.0, contact.k_n_per_mm_n, contact.n, contact.c_n_s_per_m)
    return float(f_ref) / CONTACT_REF_DEPTH


def contact_solref(contact: ContactParams, inverse_weight: float, impedance: float = IMPEDANCE):
    """Return the contact ``solref`` whose static stiffness is :func:`contact_secant` and whose
    damping is our C (Eq. 14), mapped as in :func:`edge_solref`."""
    scale = (1.0 - impedance) * inverse_weight
    return -contact_secant(contact) * scale, -contact.c_n_s_per_m * scale


def membrane_elasticity(params: msd.MsdParams) -> dict[str, float]:
    """Return young [Pa], poisson, thickness [m], damping [s] of the lattice-equivalent membrane."""
    thickness = 2.0 * FLEX_RADIUS  # the manual's suggestion; only young * thickness matters
    return {"young": 2.0 * params.k / (np.sqrt(3.0) * thickness), "poisson": 1.0 / 3.0,
            "thickness": thickness, "damping": params.c / params.k}


def mujoco_xml(mesh, params: msd.MsdParams, contact: ContactParams, mu: float, variant: str,
               timestep: float = MJ_TIMESTEP) -> str:
    """Return the MJCF of the flex sphere and three mocap fingertips (gravity off, friction mu)."""
    _, integrator, solver = VARIANTS[variant]
    inverse_weight = point_inverse_weight(params, len(mesh.vertices))
    d = IMPEDANCE
    solimp = f"{d} {d} 0.001 0.5 2"
    kc, bc = contact_solref(contact, inverse_weight)
    contact_attrs = f'friction="{mu} 0.005 0.0001" solref="{kc:.9g} {bc:.9g}" solimp="{solimp}"'
    if variant == "edge":
        ke, be = edge_solref(params, inverse_weight)
        body = f'<edge equality="true" solref="{ke:.9g} {be:.9g}" solimp="{solimp}"/>'
    else:
        e = membrane_elasticity(params)
        body = (f'<elasticity young="{e["young"]:.9g}" poisson="{e["poisson"]:.9g}" '
                f'thickness="{e["thickness"]:.9g}" elastic2d="stretch" damping="{e["damping"]:.9g}"/>')
    points = " ".join(f"{v:.17g}" for v in np.asarray(mesh.vertices).ravel())
    elements = " ".join(str(i) for i in np.asarray(mesh.faces).ravel())
    tips = "\n".join(
        f'  <body name="tip{j}" mocap="true" pos="0 0 {1.0 + j}"><geom name="tip{j}" type="sphere" '
        f'size="{contact.fingertip_radius}" {contact_attrs}/></body>' for j in range(3)
    )
    return f"""<mujoco model="graspcampaign_sphere_{variant}">
 <option timestep="{timestep}" integrator="{integrator}" solver="{solver}" gravity="0 0 0"/>
 <worldbody>
{tips}
  <flexcomp name="S" type="direct" dim="2" radius="{FLEX_RADIUS}" mass="{params.mass}"
            point="{points}" element="{elements}">
   {body}
   <contact selfcollide="none" {contact_attrs}/>
  </flexcomp>
 </worldbody>
</mujoco>"""


def build_mujoco(mesh, params: msd.MsdParams, contact: ContactParams, mu: float, variant: str,
                 timestep: float = MJ_TIMESTEP):
    """Compile the MuJoCo model of :func:`mujoco_xml`; nodal damping b as joint damping."""
    model = mujoco.MjModel.from_xml_string(mujoco_xml(mesh, params, contact, mu, variant, timestep))
    model.dof_damping[:] = params.b  # every dof is a node's slide joint (mocap bodies have none)
    return model, mujoco.MjData(model)


def mocap_paths(setup, grips: np.ndarray, dt_ours: float, times: np.ndarray) -> np.ndarray:
    """Return (s, 3, 3) fingertip centres at MuJoCo step ``times``: our paths, moved out by the
    flex radius so that penetrations into the inflated triangles equal ours."""
    t_ours = dt_ours * np.arange(len(grips))
    grip = np.stack([np.interp(times, t_ours, grips[:, j]) for j in range(3)], axis=1)
    centers = np.array([dynamics.finger_centers(setup, g) for g in grip])
    return centers + FLEX_RADIUS * setup.approach[None]


def run_mujoco(model, data, paths: np.ndarray) -> None:
    """Reset and step once per row of ``paths`` (the mocap fingertip centres)."""
    mujoco.mj_resetData(model, data)
    for centers in paths:
        data.mocap_pos[:] = centers
        mujoco.mj_step(model, data)


def trace_mujoco(model, data, paths: np.ndarray) -> WindowTrace:
    """Run :func:`run_mujoco` step by step, recording the contacts of each step."""
    tips = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f"tip{j}") for j in range(3)]
    wrench = np.zeros(6)
    mujoco.mj_resetData(model, data)
    touching, points, forces, depths = [], [], [], []
    for centers in paths:
        data.mocap_pos[:] = centers
        mujoco.mj_step(model, data)  # contacts and forces of the state at the start of the step
        f, dep, hit = np.zeros(3), np.zeros(3), np.zeros(3, dtype=bool)
        for c in range(data.ncon):
            finger = [j for j in range(3) if tips[j] in data.contact.geom[c]]
            if not finger:
                continue
            mujoco.mj_contactForce(model, data, c, wrench)
            j = finger[0]
            hit[j] = True
            f[j] += wrench[0]
            dep[j] = max(dep[j], -data.contact.dist[c])
        touching.append(hit)
        points.append(data.ncon)
        forces.append(f)
        depths.append(dep)
    return WindowTrace(times=model.opt.timestep * np.arange(len(paths)), touching=np.array(touching),
                       n_points=np.array(points), normal_forces=np.array(forces),
                       depths=np.array(depths))


def mujoco_squeeze_stiffness(mesh, params, contact, variant, pair) -> float:
    """Return F / closure [N/m] of the same two nodes, simulated to rest in MuJoCo."""
    model, data = build_mujoco(mesh, params, contact, 0.0, variant, timestep=4e-3)
    model.dof_damping[:] = 0.5  # [N*s/m] settles in ~0.4 s; statics do not depend on it
    mujoco.mj_resetData(model, data)
    data.mocap_pos[:] = 1.0  # fingertips away
    forces = squeeze_forces(np.asarray(mesh.vertices), pair, SQUEEZE_FORCE)
    data.xfrc_applied[model.flex_vertbodyid[list(pair)], :3] = forces[list(pair)]
    for _ in range(150):
        mujoco.mj_step(model, data)
    return SQUEEZE_FORCE / closure(np.asarray(mesh.vertices), data.qpos.reshape(-1, 3), pair)


def edge_rows_at_rest(model, data) -> tuple[float, float, float]:
    """Return the mean static spring ``K imp / R`` [N/m], damper ``B / R`` [N*s/m] and
    constraint-space frequency ``sqrt(K imp)`` [rad/s] of the equality rows, as MuJoCo computes
    them in the initial configuration.

    With a uniform regulariser ``R = r I`` the solve ``a_c = A (A+R)^-1 a_ref + R (A+R)^-1 a_u``
    moves a mode of our (undamped) network at frequency w at ``w / sqrt(1 + w^2 / w_c^2)``,
    ``w_c = sqrt(K imp)``: the stiffest modes approach w_c, so ``2 / w_c`` is the
    explicit-in-position step limit ``h < 2 / w_max`` of the Computation chapter for these rows.
    """
    mujoco.mj_resetData(model, data)
    mujoco.mj_forward(model, data)
    rows = data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    kbip, r = data.efc_KBIP[rows], data.efc_R[rows]
    k_imp = kbip[:, 0] * kbip[:, 2]
    return (float(np.mean(k_imp / r)), float(np.mean(kbip[:, 1] / r)),
            float(np.sqrt(np.mean(k_imp))))


def our_rest_stiffness(mesh, params: msd.MsdParams) -> tuple[np.ndarray, np.ndarray]:
    """Return our body's dense (3n, 3n) rest stiffness ``K = -dF/dx`` [N/m] (``core.jacobian``)
    and its rest positions (n, 3) [m]."""
    body = msd.msd_body_from_mesh(mesh, params)
    state = msd.state_from_positions(body.rest_positions)
    return -jacobian.body_jacobian(body, params, state).dense_d_position(), body.rest_positions


def our_elastic_frequencies(mesh, params: msd.MsdParams) -> tuple[float, float]:
    """Return the lowest and highest elastic angular frequencies of our body at rest [rad/s]."""
    stiffness, positions = our_rest_stiffness(mesh, params)
    omega = np.sqrt(np.clip(np.linalg.eigvalsh(stiffness) * len(positions) / params.mass, 0.0, None))
    elastic = omega[omega > 1e-6 * omega[-1]]  # the six rigid modes are numerically zero
    return float(elastic[0]), float(elastic[-1])


def ours_squeeze_stiffness(mesh, params: msd.MsdParams, pair: tuple[int, int]) -> float:
    """Return F / closure [N/m] of two nodes pushed together, from our linearised stiffness.

    ``K`` is singular along the six rigid motions; the load is self-equilibrated (orthogonal to
    them), so adding ``s Q Q^T`` (Q an orthonormal basis of the rigid motions) leaves the elastic
    solution unchanged and makes the system solvable.
    """
    stiffness, positions = our_rest_stiffness(mesh, params)
    x = positions - positions.mean(axis=0)
    rigid = np.zeros((x.shape[0], 3, 6))
    rigid[:, :, :3] = np.eye(3)
    rigid[:, :, 3:] = -jacobian.skew(x)  # omega x x_i = -[x_i]_x omega
    q, _ = np.linalg.qr(rigid.reshape(-1, 6))
    stiffness += np.mean(np.diag(stiffness)) * (q @ q.T)
    forces = squeeze_forces(positions, pair, SQUEEZE_FORCE)
    u = np.linalg.solve(stiffness, forces.ravel()).reshape(-1, 3)
    return SQUEEZE_FORCE / closure(positions, u, pair)


def squeeze_pair(vertices: np.ndarray) -> tuple[int, int]:
    """Return the nodes at +x and -x (an antipodal pair on the sphere)."""
    return int(np.argmax(vertices[:, 0])), int(np.argmin(vertices[:, 0]))


def squeeze_forces(vertices, pair, force) -> np.ndarray:
    """Return (n, 3) forces [N]: ``force`` on each node of ``pair``, pushing them together."""
    i, j = pair
    axis = (vertices[i] - vertices[j]) / np.linalg.norm(vertices[i] - vertices[j])
    forces = np.zeros_like(vertices)
    forces[i], forces[j] = -force * axis, force * axis
    return forces


def closure(vertices, displacements, pair) -> float:
    """Return how much the nodes of ``pair`` approached each other [m]."""
    i, j = pair
    axis = (vertices[i] - vertices[j]) / np.linalg.norm(vertices[i] - vertices[j])
    return float(-(displacements[i] - displacements[j]) @ axis)

