"""Test 1 bench specimens: fingertip constants, the Table 4 families, drawn specimens, environments.

Units are SI (m, s, N, N/m, N s/m); ``K`` is in N mm^-n, as in the paper (§3.5, §7.2).

References
----------
Paper Eq. 14 (K from the effective modulus), §7.1-7.4 and Table 4 (families, constants),
Table 2 (fingertip). Mullins, L. (1969). Softening of rubber by deformation. *Rubber Chem.
Technol.* 42, 339.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from graspcampaign.core.contact import effective_modulus as _psi
from graspcampaign.core.plausible import FINGERTIP_RADIUS

__all__ = [
    "CYCLES_TO_STABILISE",
    "CYCLIC_REFERENCE_DEPTH",
    "ENVIRONMENT_FRICTION",
    "FAMILIES",
    "FINGERTIP_MODULUS",
    "FINGERTIP_POISSON",
    "FINGERTIP_RADIUS",
    "REFERENCE_DEPTH_MM",
    "SET_EXPONENT",
    "SOFTENING_EXPONENT",
    "SPECIMEN_POISSON",
    "STICK_SLIP_SPEED",
    "FamilyParams",
    "SpecimenParams",
    "SpreadParams",
    "draw_specimen",
    "environment_friction_factors",
    "force_at_reference_depth",
    "specimen_effective_modulus",
    "with_environment",
]


FINGERTIP_MODULUS = 89.3e3
"""Fingertip Young's modulus E_1 [Pa] (§7.1 "about 89 kPa", Table 2: 0.0893 MPa)."""
FINGERTIP_POISSON = 0.5
"""Fingertip Poisson's ratio nu_1 (§7.1, Table 2)."""
SPECIMEN_POISSON = 0.45
"""Specimen Poisson's ratio nu_2 (Table 2, object)."""
REFERENCE_DEPTH_MM = 0.5
"""Reference indentation of f_0.5 = K (0.5 mm)^n [mm] (Table 4; K is in N mm^-n)."""


def force_at_reference_depth(k_n_per_mm_n: float, n: float) -> float:
    """Return Table 4's force at the reference indentation, ``K (0.5 mm)^n`` [N]."""
    return k_n_per_mm_n * REFERENCE_DEPTH_MM**n


@dataclass(frozen=True)
class FamilyParams:
    """Constants of one material family (Table 4 plus documented virtual-bench choices).

    Attributes
    ----------
    name, label : str
        Key (``"gel"``) and Table 4 label.
    modulus_mean, modulus_sd : float
        Young's modulus across the 12 specimens, mean and SD [Pa] (Table 4).
    n : float
        Contact exponent of Eq. 13 (Table 4).
    k_n_per_mm_n : float
        Contact stiffness K [N mm^-n] (Table 4).
    c : float
        Contact damping C [N s/m] (Table 4).
    mu_s, mu_k : float
        Static and kinetic friction coefficients, mean over environments (Table 4).
    k_t : float
        Tangential stick stiffness [N/m] (Table 4, 1.97-4.96 N/mm).
    rho, tau : float
        Relaxation ratio and time constant [s] (Table 4).
    softening_ref : float
        Stabilised ``1 - K/K_1`` after cycling at ``CYCLIC_REFERENCE_DEPTH`` (decision; §7.4
        says silicones "essentially unchanged", gel and foam "mild" and above 0.85).
    set_ref : float
        Stabilised permanent set at the same depth [m] (decision within §7.4's 0.08-0.36 mm).
    adhesion : float
        Tensile pull-off force at separation [N] (decision; §7.1 "small", tacky specimens).
    """

    name: str
    label: str
    modulus_mean: float
    modulus_sd: float
    n: float
    k_n_per_mm_n: float
    c: float
    mu_s: float
    mu_k: float
    k_t: float
    rho: float
    tau: float
    softening_ref: float
    set_ref: float
    adhesion: float

    @property
    def f05(self) -> float:
        """Force at the 0.5 mm reference indentation, K 0.5^n [N] (Table 4)."""
        return force_at_reference_depth(self.k_n_per_mm_n, self.n)


FAMILIES: dict[str, FamilyParams] = {
    f.name: f
    for f in (
        FamilyParams("gel", "Gel, soft (hydrogel)", 40.1e3, 6.2e3, 0.473, 0.346, 0.055,
                     0.772, 0.544, 1.97e3, 0.64, 7.1, 0.10, 0.36e-3, 0.015),
        FamilyParams("silicone_soft", "Silicone, soft", 74.6e3, 10.6e3, 0.462, 0.507, 0.062,
                     0.619, 0.440, 3.33e3, 0.80, 11.7, 0.02, 0.10e-3, 0.008),
        FamilyParams("bio_foam", "Bio fruit-like foam", 114.4e3, 28.1e3, 0.483, 0.582, 0.062,
                     0.684, 0.506, 4.42e3, 0.65, 8.3, 0.08, 0.25e-3, 0.006),
        FamilyParams("silicone_ref", "Silicone, reference", 145.5e3, 8.0e3, 0.432, 0.693,
                     0.060, 0.509, 0.364, 4.96e3, 0.88, 15.4, 0.01, 0.08e-3, 0.003),
    )
}
"""The four Table 4 families, keyed by short name, in Table 4 order."""

ENVIRONMENT_FRICTION = {"cool_dry": 0.59, "warm_humid": 0.70}
"""Campaign-mean mu_s in the two extreme environment groups (§7.3)."""

CYCLIC_REFERENCE_DEPTH = 2.0e-3
"""Depth at which ``softening_ref`` and ``set_ref`` are stated [m] (decision)."""
SOFTENING_EXPONENT = 2.0
"""Stabilised softening grows as (depth / reference depth)^2 (decision)."""
SET_EXPONENT = 1.5
"""Stabilised permanent set grows as (depth / reference depth)^1.5 (decision)."""
CYCLES_TO_STABILISE = 25.0
"""e-folding cycle count of Mullins-type softening: 98 % of the asymptote by cycle 100 (§7.4)."""
STICK_SLIP_SPEED = 1.0e-3
"""Speed scale of re-stick aging [m/s]: sawtooth amplitude ~ exp(-v / v_c), < 1 mN above ~5 mm/s,
so the contact slides steadily above ~3 mm/s (§7.3)."""


def specimen_effective_modulus(modulus: float) -> float:
    """Return Eq. 14's effective modulus Psi [Pa] of the bench fingertip on a specimen.

    Parameters
    ----------
    modulus : float
        Specimen Young's modulus E_2 [Pa].

    Returns
    -------
    psi : float
        Via :func:`graspcampaign.core.contact.effective_modulus` with the §7.1 fingertip.
    """
    return float(_psi(FINGERTIP_MODULUS, FINGERTIP_POISSON, modulus, SPECIMEN_POISSON))


def environment_friction_factors(families: dict[str, FamilyParams] | None = None
                                 ) -> dict[str, float]:
    """Return the multiplicative friction factor of each environment group.

    §7.3 reports the campaign mean of mu_s rising from 0.59 (cool/dry) to 0.70
    (warm/humid); Table 4 gives each family's mean over all environments. We scale every
    family's mu_s and mu_k by ``f_env = mu_env / mean_f(mu_s,f)`` for the two extremes and
    set normal-lab so that the three factors average to one, which keeps each family's
    environment mean equal to its Table 4 value.

    Returns
    -------
    factors : dict
        ``{"cool_dry": 0.913, "normal_lab": 1.003, "warm_humid": 1.084}`` for Table 4.
    """
    fams = FAMILIES if families is None else families
    mean_mu_s = float(np.mean([f.mu_s for f in fams.values()]))
    cool = ENVIRONMENT_FRICTION["cool_dry"] / mean_mu_s
    warm = ENVIRONMENT_FRICTION["warm_humid"] / mean_mu_s
    return {"cool_dry": cool, "normal_lab": 3.0 - cool - warm, "warm_humid": warm}


@dataclass(frozen=True)
class SpecimenParams:
    """True constants of one specimen in one environment group (virtual bench).

    Attributes
    ----------
    family, environment : str
    specimen : int
        Specimen number within its family, 1-12.
    modulus : float
        Drawn Young's modulus [Pa].
    k_n_per_mm_n, n, c : float
        Eq. 13 constants of the fingertip-specimen pair [N mm^-n, -, N s/m].
    mu_s, mu_k : float
        Friction coefficients in this environment.
    k_t : float
        Tangential stick stiffness [N/m].
    rho, tau : float
        QLV relaxation ratio and time constant [s].
    toe : float
        Length scale of the compliant onset toe [m].
    adhesion : float
        Pull-off force at separation [N].
    softening_ref, set_ref : float
        Stabilised ``1 - K/K_1`` and permanent set [m] at ``CYCLIC_REFERENCE_DEPTH``.
    """

    family: str
    specimen: int
    environment: str
    modulus: float
    k_n_per_mm_n: float
    n: float
    c: float
    mu_s: float
    mu_k: float
    k_t: float
    rho: float
    tau: float
    toe: float
    adhesion: float
    softening_ref: float
    set_ref: float

    @property
    def f05(self) -> float:
        """Force at 0.5 mm, K 0.5^n [N]."""
        return force_at_reference_depth(self.k_n_per_mm_n, self.n)


@dataclass(frozen=True)
class SpreadParams:
    """Specimen-to-specimen spread of the virtual bench (all decisions, docs/decisions.md).

    Relative spreads are lognormal sigmas; absolute ones are normal SDs.
    """

    n_sd: float = 0.03
    c_rel: float = 0.10
    mu_rel: float = 0.04
    mu_ratio_rel: float = 0.02
    k_t_rel: float = 0.10
    rho_sd: float = 0.02
    tau_rel: float = 0.08
    toe_mean: float = 5e-6
    toe_rel: float = 0.3
    cyclic_rel: float = 0.15


def draw_specimen(family: FamilyParams, specimen: int, environment: str,
                  rng: np.random.Generator, spread: SpreadParams | None = None
                  ) -> SpecimenParams:
    """Draw one specimen's true constants around its family's Table 4 values.

    The modulus is drawn from N(mean, SD) of Table 4 (truncated at 30 % of the mean); the
    force at 0.5 mm scales with the effective modulus Psi of Eq. 14 relative to the family
    mean, ``f05 = f05_family * Psi(E) / Psi(E_mean)``, and ``K = f05 / 0.5^n`` with the
    specimen's own exponent, so K keeps its n-dependent unit consistent. Friction is scaled
    by the environment factor of :func:`environment_friction_factors`.

    Parameters
    ----------
    family : FamilyParams
    specimen : int
        Specimen number (recorded only).
    environment : str
        ``"cool_dry"``, ``"normal_lab"`` or ``"warm_humid"``.
    rng : numpy.random.Generator
        Must depend on (study seed, family, specimen) only -- not on the environment -- so
        that the same physical specimen is drawn in every environment group.
    spread : SpreadParams, optional

    Returns
    -------
    SpecimenParams
    """
    sp = SpreadParams() if spread is None else spread
    factors = environment_friction_factors()
    if environment not in factors:
        raise ValueError(f"unknown environment {environment!r}; expected one of "
                         f"{sorted(factors)}")
    z = rng.standard_normal(10)
    modulus = max(family.modulus_mean + family.modulus_sd * z[0], 0.3 * family.modulus_mean)
    n = family.n + sp.n_sd * z[1]
    f05 = family.f05 * specimen_effective_modulus(modulus) / specimen_effective_modulus(
        family.modulus_mean)
    k = f05 / REFERENCE_DEPTH_MM**n
    mu_s = family.mu_s * math.exp(sp.mu_rel * z[2]) * factors[environment]
    mu_k = mu_s * (family.mu_k / family.mu_s) * math.exp(sp.mu_ratio_rel * z[3])
    cyc = math.exp(sp.cyclic_rel * z[9])
    return SpecimenParams(
        family=family.name, specimen=int(specimen), environment=environment,
        modulus=modulus, k_n_per_mm_n=k, n=n,
        c=family.c * math.exp(sp.c_rel * z[4]),
        mu_s=mu_s, mu_k=min(mu_k, 0.98 * mu_s),
        k_t=family.k_t * math.exp(sp.k_t_rel * z[5]),
        rho=float(np.clip(family.rho + sp.rho_sd * z[6], 0.05, 0.99)),
        tau=family.tau * math.exp(sp.tau_rel * z[7]),
        toe=sp.toe_mean * math.exp(sp.toe_rel * z[8]),
        adhesion=family.adhesion,
        softening_ref=family.softening_ref * cyc,
        set_ref=family.set_ref * cyc,
    )


def with_environment(spec: SpecimenParams, environment: str) -> SpecimenParams:
    """Return ``spec`` moved to another environment group (friction rescaled)."""
    f = environment_friction_factors()
    scale = f[environment] / f[spec.environment]
    return replace(spec, environment=environment, mu_s=spec.mu_s * scale,
                   mu_k=spec.mu_k * scale)
