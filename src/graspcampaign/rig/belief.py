"""What each hardware planner can know before execution (§8.1, §9.3; issue 13).

The paper's Tests 2-3 ranking rests on one stated mechanism: "each planner sizes its grip from the
quality it *believes* it has achieved, so a weak planner under-grips and fails even when a
feasible grasp exists" (§8.1), and "the baselines over-estimate their own force-closure quality"
(§9.1, §9.3). This module states, per planner, what that belief is built from -- one
:class:`PlannerBelief` per plan -- and every source is in docs/decisions.md ("Planner beliefs on
the virtual rig (issue 13)").

=================  ===============  ==========================  ==============================
planner            ``model``        friction mu_s believed      contact law / creep / geometry
=================  ===============  ==========================  ==============================
heuristic          calibrated       Test 1 calibration of the   Table 4 law of the material
(proposed)                          material (Table 4 mean;     (the PSO-identified family law),
                                    a coating's nominal value)  QLV creep (Table 4 rho, tau),
                                                                5 % characteristic grip cap;
                                                                its own G_geo on the mesh
                                                                normals of its contacts
no_pso             nominal_law      :data:`NOMINAL_MU_S` on     nominal Hertzian law (n = 1.5,
                                    every surface (no Test 1    lambda1 = lambda2 = 1, SPEC §2.8),
                                    record)                     no creep; its own G_geo on the
                                                                mesh normals of its contacts
centroid,          nominal_geometry :data:`NOMINAL_MU_S`        nominal Hertzian law, no creep;
force_balance,                                                  G_geo of the *planar* geometry
random                                                          its construction assumes: the
                                                                horizontal parts of its contact
                                                                normals (:func:`planar_normals`)
any, with          actual           the true mu_s of the        the specimen's true law, creep,
``belief_error =                    trial (specimen, day,       damage depth; G_geo of the
none``                              coating)                    *realised* contacts
=================  ===============  ==========================  ==============================

No planner knows the designed pose offset (a displacement of the object from the pose the planner
plans on, §8.1) or the day's ambient friction shift (§7.3; the Test 2-3 rig logs no ambient
channel, §8.1). Every planner knows the material's characteristic damage depth (a published
property of the material, §7.4) and its own hand's 5 mm fingertip radius (§8.1): the grip cap
keeps the most loaded finger within the shallower of the two (deeper, the fingertip would be
buried, no contact of Eq. 13 any more); what differs is the law that converts it into a force. Each
planner then sizes its grip from its own belief (:func:`graspcampaign.rig.plan.predictions_from_plan`,
SPEC §2.10); the rig executes it on the true specimen and the realised contacts.

References
----------
Paper §7.3-7.5, §8.1, §8.4, §9.1, §9.3, §9.6, Table 4; SPEC §2.8, §2.10; EN 1990 Annex D.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

import numpy as np

from graspcampaign.core import bench
from graspcampaign.core import disturbance as dist
from graspcampaign.core.contact import NOMINAL_CONTACT, ContactParams, effective_modulus
from graspcampaign.core.words import meant

__all__ = [
    "BELIEF_ERRORS",
    "BELIEF_MODELS",
    "CHARACTERISTIC_Z",
    "COATING_MU_S",
    "NOMINAL_MU_S",
    "MaterialModel",
    "PlannerBelief",
    "actual_belief",
    "believed_contact_law",
    "family_damage_depth",
    "material_model",
    "planar_normals",
    "planner_belief",
]

BELIEF_ERRORS = ("paper", "none")
"""``paper``: every planner believes what it can know (the table above, the paper's mechanism);
``none``: every planner believes the actual quantities of the trial (the counterfactual that shows
how much of the ranking the mechanism explains)."""

BELIEF_MODELS = {"heuristic": "calibrated", "no_pso": "nominal_law",
                 "centroid": "nominal_geometry", "force_balance": "nominal_geometry",
                 "random": "nominal_geometry"}
"""Knowledge tier of each hardware planner under ``belief_error = paper``."""

NOMINAL_MU_S = float(np.mean([f.mu_s for f in bench.FAMILIES.values()]))
"""Friction an uncalibrated planner assumes on every surface: the campaign mean of mu_s over the
four Table 4 families (0.646; §7.3 quotes the campaign mean rising from 0.59 to 0.70 across the
ambient groups). It knows the object is one of the campaign's soft materials, not which one, nor
its coating."""


COATING_MU_S = {"high": 0.90, "medium": 0.35, "low": 0.15}
"""Static friction of the surface coatings on the silicone fingertip (decision, docs/decisions.md:
low = a PTFE-like film, medium = a powdered (talc) skin, high = a tacky rubber coating, at the
values typical of such pairs; the paper reports only their effect, §9.2). Keyed by name, not by the
order of the vocabulary's :data:`~graspcampaign.analysis.vocabulary.COATINGS` (a display order);
the names are its words (tests/rig/test_belief.py)."""

CHARACTERISTIC_Z = 1.645
"""The grip cap uses the 5 % characteristic (lower-fractile) stiffness and damage depth of the
material's Test 1 specimen distribution (decision: the lower 5 % fractile is the usual
characteristic value of a resistance, EN 1990 Annex D)."""



def family_damage_depth(family: bench.FamilyParams, cyclic_scale: float = 1.0) -> float:
    """Return the damage depth [m] of a family from the Test 1 cyclic model (§7.4).

    The closed form :func:`graspcampaign.core.bench.true_damage_depth` of the family's
    stabilised softening and permanent set (scaled by ``cyclic_scale``): the depth at which K/K_1
    falls to 0.85 or the permanent set reaches 0.5 mm, whichever is first.
    """
    scaled = replace(family, softening_ref=family.softening_ref * cyclic_scale,
                     set_ref=family.set_ref * cyclic_scale)
    return float(bench.true_damage_depth(scaled).depth)


@dataclass(frozen=True)
class MaterialModel:
    """Contact and material constants of one object surface as a planner knows them.

    Attributes
    ----------
    material : str
        Table 4 family key.
    friction_level : str
        ``natural`` or a coating (``high``, ``medium``, ``low``).
    mu_s, mu_k : float
        Static and kinetic friction [-] (Table 4 mean, or the coating's).
    k_n_per_mm_n, n : float
        Eq. 13 law of the fingertip-material pair (Table 4).
    c_n_s_per_m : float
        Damping C [N s/m] (Table 4).
    k_t : float
        Tangential stick stiffness [N/m] (Table 4).
    rho, tau : float
        Relaxation ratio and time constant [s] (Table 4).
    modulus, modulus_sd : float
        Young's modulus mean and SD [Pa] (Table 4).
    damage_depth : float
        Damage depth of the family's mean specimen [m] (§7.4).
    cap_depth : float
        Characteristic (5 %) damage depth used by the grip cap [m].
    cap_k_n_per_mm_n : float
        Characteristic (5 %) stiffness used by the grip cap [N mm^-n].
    fingertip_radius : float
        Fingertip radius the stiffnesses are scaled to [m] (Eq. 14: K grows with sqrt(R)).
    """

    material: str
    friction_level: str
    mu_s: float
    mu_k: float
    k_n_per_mm_n: float
    n: float
    c_n_s_per_m: float
    k_t: float
    rho: float
    tau: float
    modulus: float
    modulus_sd: float
    damage_depth: float
    cap_depth: float
    cap_k_n_per_mm_n: float
    fingertip_radius: float = bench.FINGERTIP_RADIUS

    def contact_params(self, fingertip_radius: float = bench.FINGERTIP_RADIUS) -> ContactParams:
        """Return ContactParams whose Eq. 14 K and C reproduce this model's K and C.

        ``fingertip_radius`` [m] must be the radius this model was built for
        (:func:`material_model`'s). ``k_n_per_mm_n`` is already scaled to that radius, so lambda1
        is solved there; ``c_n_s_per_m`` is Table 4's 5 mm bench value, so lambda2 is solved at
        the bench radius and Eq. 14 scales C with R.
        """
        psi = effective_modulus(bench.FINGERTIP_MODULUS, bench.FINGERTIP_POISSON, self.modulus,
                                bench.SPECIMEN_POISSON)
        lambda1 = self.k_n_per_mm_n / (2.0 * psi / 1e6 * math.sqrt(fingertip_radius * 1e3))
        lambda2 = self.c_n_s_per_m / (4.0 * math.pi * bench.FINGERTIP_RADIUS)
        return ContactParams(lambda1=lambda1, lambda2=lambda2, n=self.n,
                             fingertip_radius=fingertip_radius,
                             e_finger=bench.FINGERTIP_MODULUS, e_object=self.modulus,
                             nu_finger=bench.FINGERTIP_POISSON, nu_object=bench.SPECIMEN_POISSON)


@functools.lru_cache(maxsize=64)
def material_model(material: str, friction_level: str = "natural",
                   fingertip_radius: float = bench.FINGERTIP_RADIUS) -> MaterialModel:
    """Return the planner's constants for a Table 4 family and surface.

    Parameters
    ----------
    material : str
        One of ``gel``, ``silicone_soft``, ``bio_foam``, ``silicone_ref``.
    friction_level : str
        ``natural`` (Table 4 friction) or a coating of :data:`COATING_MU_S` (mu_k keeps the
        family's mu_k/mu_s ratio).
    fingertip_radius : float
        [m]; K scales with sqrt(R) (Eq. 14) from the 5 mm bench fingertip.

    Raises
    ------
    ValueError
        Unknown material or friction level.
    """
    if material not in bench.FAMILIES:
        raise ValueError(f"unknown material {material!r}; {meant(material, bench.FAMILIES)}use one of "
                         f"{', '.join(bench.FAMILIES)}.")
    fam = bench.FAMILIES[material]
    if friction_level == "natural":
        mu_s, mu_k = fam.mu_s, fam.mu_k
    elif friction_level in COATING_MU_S:
        mu_s = COATING_MU_S[friction_level]
        mu_k = mu_s * fam.mu_k / fam.mu_s
    else:
        raise ValueError(f"unknown friction level {friction_level!r}: use natural, "
                         f"{', '.join(COATING_MU_S)}")
    scale = math.sqrt(fingertip_radius / bench.FINGERTIP_RADIUS)
    psi = bench.specimen_effective_modulus
    low_modulus = max(fam.modulus_mean - CHARACTERISTIC_Z * fam.modulus_sd, 0.3 * fam.modulus_mean)
    cap_k = fam.k_n_per_mm_n * scale * psi(low_modulus) / psi(fam.modulus_mean)
    cyclic_high = math.exp(CHARACTERISTIC_Z * bench.SpreadParams().cyclic_rel)
    return MaterialModel(
        material=material, friction_level=friction_level, mu_s=mu_s, mu_k=mu_k,
        k_n_per_mm_n=fam.k_n_per_mm_n * scale, n=fam.n, c_n_s_per_m=fam.c, k_t=fam.k_t,
        rho=fam.rho, tau=fam.tau, modulus=fam.modulus_mean, modulus_sd=fam.modulus_sd,
        damage_depth=family_damage_depth(fam), cap_depth=family_damage_depth(fam, cyclic_high),
        cap_k_n_per_mm_n=cap_k, fingertip_radius=fingertip_radius)



# --------------------------------------------------------------------------------------------
# Beliefs
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PlannerBelief:
    """What a planner believes about one grasp before execution (module table).

    Attributes
    ----------
    model : str
        ``calibrated``, ``nominal_law``, ``nominal_geometry`` or ``actual``.
    mu_s : float
        Believed static friction of the contacted surface [-].
    points : (3, 3) float
        Contact points the planner's statics uses [m].
    normals : (3, 3) float
        Outward unit normals the planner's statics uses (G_geo, load sharing, first finger).
    k_n_per_mm_n, n : float
        Believed Eq. 13 law for predicted indentations [N mm^-n, -].
    cap_k_n_per_mm_n : float
        Stiffness of the grip cap [N mm^-n].
    cap_depth : float
        Indentation the grip cap keeps the most loaded finger within [m]: the believed damage
        depth, or the fingertip radius if shallower.
    rho, tau : float or None
        Relaxation ratio and time constant [-, s] of the believed creep; None: no creep model.
    """

    model: str
    mu_s: float
    points: np.ndarray
    normals: np.ndarray
    k_n_per_mm_n: float
    n: float
    cap_k_n_per_mm_n: float
    cap_depth: float
    rho: float | None = None
    tau: float | None = None

    @property
    def belief_error(self) -> str:
        """``none`` for the actual quantities, ``paper`` otherwise."""
        return "none" if self.model == "actual" else "paper"

    def creep(self, t: float) -> float:
        """Return the believed creep compliance J(t) after ``t`` [s] under grip (1 without creep)."""
        if self.rho is None or self.tau is None:
            return 1.0
        return float(dist.creep_compliance(t, self.rho, self.tau))

    def g_geo(self) -> float:
        """Return the believed G_geo (:func:`graspcampaign.core.disturbance.geometric_efficiency`)."""
        return float(dist.geometric_efficiency(self.normals, self.mu_s))


def _nominal_k(material: MaterialModel) -> float:
    """Eq. 14 K of the nominal Hertzian law at the material model's fingertip radius."""
    return replace(NOMINAL_CONTACT, fingertip_radius=material.fingertip_radius).k_n_per_mm_n


def believed_contact_law(planner: str, material: MaterialModel) -> tuple[float, float]:
    """Return the Eq. 13 law (K [N mm^-n], n) a planner believes for this material.

    The calibrated planner believes the material's Table 4 law; every other planner the nominal
    Hertzian law of SPEC §2.8 (n = 1.5, lambda1 = lambda2 = 1).
    """
    if BELIEF_MODELS.get(planner) == "calibrated":
        return material.k_n_per_mm_n, material.n
    return _nominal_k(material), NOMINAL_CONTACT.n


def planar_normals(normals, points, centroid) -> np.ndarray:
    """Return the normals of the planar grasp a geometric planner assumes.

    Parameters
    ----------
    normals : (3, 3) float
        Outward normals at the planned contacts.
    points : (3, 3) float
        Planned contact points [m].
    centroid : (3,) float
        Object centroid [m].

    Returns
    -------
    planar : (3, 3) float
        The horizontal part of each normal, renormalised: a geometric planner models a grasp in
        the plane normal to gravity (the centroid planner's construction, §6.5; the S1 term of the
        force-balance planner scores force directions without gravity), so every contact looks
        horizontal to it. A vertical normal falls back to the horizontal direction from the
        vertical through the centroid to the point (and to +x on that axis).
    """
    n = np.array(normals, dtype=float, copy=True)
    n[:, 2] = 0.0
    length = np.linalg.norm(n, axis=1)
    radial = np.asarray(points, dtype=float) - np.asarray(centroid, dtype=float)
    radial[:, 2] = 0.0
    r_len = np.linalg.norm(radial, axis=1)
    fallback = np.where(r_len[:, None] > 1e-12, radial / np.maximum(r_len, 1e-300)[:, None],
                        np.array([1.0, 0.0, 0.0]))
    return np.where(length[:, None] > 1e-9, n / np.maximum(length, 1e-300)[:, None], fallback)


def planner_belief(planner: str, points, normals, material: MaterialModel,
                   centroid=(0.0, 0.0, 0.0)) -> PlannerBelief:
    """Return what ``planner`` believes about its planned contacts (``belief_error = paper``).

    Parameters
    ----------
    planner : str
        A hardware planner (:data:`BELIEF_MODELS`).
    points, normals : (3, 3) float
        Planned contacts [m] and the normals the planner's construction hands over (mesh normals;
        the centroid planner's are horizontal by construction).
    material : MaterialModel
        The material and surface as the calibrated planner knows them.
    centroid : (3,) float
        Object centroid [m].

    Returns
    -------
    PlannerBelief
    """
    if planner not in BELIEF_MODELS:
        raise ValueError(f"unknown hardware planner {planner!r}: use one of "
                         f"{', '.join(BELIEF_MODELS)}")
    model = BELIEF_MODELS[planner]
    points = np.asarray(points, dtype=float)
    normals = np.asarray(normals, dtype=float)
    cap_depth = min(material.cap_depth, material.fingertip_radius)
    if model == "calibrated":
        return PlannerBelief(model=model, mu_s=material.mu_s, points=points, normals=normals,
                             k_n_per_mm_n=material.k_n_per_mm_n, n=material.n,
                             cap_k_n_per_mm_n=material.cap_k_n_per_mm_n, cap_depth=cap_depth,
                             rho=material.rho, tau=material.tau)
    k, n = believed_contact_law(planner, material)
    if model == "nominal_geometry":
        normals = planar_normals(normals, points, centroid)
    return PlannerBelief(model=model, mu_s=NOMINAL_MU_S, points=points, normals=normals,
                         k_n_per_mm_n=k, n=n, cap_k_n_per_mm_n=k, cap_depth=cap_depth)


def actual_belief(points, normals, *, mu_s: float, k_n_per_mm_n: float, n: float, rho: float,
                  tau: float, damage_depth: float,
                  fingertip_radius: float = bench.FINGERTIP_RADIUS) -> PlannerBelief:
    """Return the belief of a planner that knows the trial's actual quantities (``none``).

    ``points`` and ``normals`` are the realised contacts, the rest the true specimen of the trial
    (friction in the day's ambient group and coating, its law, creep and damage depth). The same
    design rules then apply (target SF; cap at the damage depth, or the fingertip radius if
    shallower, of the most loaded finger), so the believed G_geo, mu_s and SF equal the achieved
    ones. The force controller's tracking error stays unknown to every planner.
    """
    return PlannerBelief(model="actual", mu_s=float(mu_s), points=np.asarray(points, dtype=float),
                         normals=np.asarray(normals, dtype=float),
                         k_n_per_mm_n=float(k_n_per_mm_n), n=float(n),
                         cap_k_n_per_mm_n=float(k_n_per_mm_n),
                         cap_depth=float(min(damage_depth, fingertip_radius)),
                         rho=float(rho), tau=float(tau))
