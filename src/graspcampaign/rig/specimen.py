"""The virtual world's truth for Tests 2-3: each object's specimen and each day's ambient group.

Each physical object's constants are drawn once, around its Table 4 family, by the Test 1 virtual
bench's own :func:`graspcampaign.core.bench.draw_specimen` (modulus from Table 4 mean/SD, K scaled
through Eq. 14's effective modulus, friction, k_t, rho, tau, cyclic damage), from a generator keyed
by (protocol seed, object id) -- so all trials on an object see the same specimen. The day's
ambient group (cool/dry, normal-lab, warm/humid) scales the natural friction as in §7.3. Coatings
replace the surface friction by the coating's value with a per-object spread. The true damage
depth follows the specimen's cyclic constants (§7.4). No planner sees these values
(:mod:`graspcampaign.rig.belief`); the virtual rig (:mod:`graspcampaign.rig.virtual`) executes
on them.

References
----------
Paper §7.3-7.4, §8.1, Table 4; SPEC §4.
"""

from __future__ import annotations

import functools
import hashlib
import math
from dataclasses import dataclass

import numpy as np

from graspcampaign.core import bench
from graspcampaign.rig import belief as rigbelief

__all__ = [
    "COATING_MU_REL",
    "ENVIRONMENT_PROBABILITIES",
    "Specimen",
    "day_environment",
    "key_rng",
    "specimen_truth",
]

ENVIRONMENT_PROBABILITIES = {"cool_dry": 0.25, "normal_lab": 0.5, "warm_humid": 0.25}
"""Ambient group of a campaign day (decision: the Test 1 groups, normal-lab twice as likely)."""
COATING_MU_REL = 0.10
"""Lognormal sigma of a coating's friction from object to object (decision: 10 %)."""


def key_rng(*parts: object) -> np.random.Generator:
    """Return a generator keyed by ``parts`` (SHA-256 of their text): the same key, the same draws."""
    digest = hashlib.sha256("|".join(map(str, parts)).encode()).digest()
    words = [int.from_bytes(digest[i:i + 4], "little") for i in range(0, 32, 4)]
    return np.random.default_rng(np.random.SeedSequence(words))


@functools.lru_cache(maxsize=256)
def day_environment(seed: int, study: str, day: int) -> str:
    """Return the ambient group of one campaign day (a draw keyed by seed, study and day)."""
    names = list(ENVIRONMENT_PROBABILITIES)
    rng = key_rng("environment", seed, study, day)
    return str(rng.choice(names, p=list(ENVIRONMENT_PROBABILITIES.values())))


@dataclass(frozen=True)
class Specimen:
    """True constants of one object surface in one environment.

    Attributes
    ----------
    mu_s, mu_k : float
        True friction of the contacted surface.
    k_n_per_mm_n, n : float
        True Eq. 13 law.
    k_t : float
        Tangential stick stiffness [N/m].
    rho, tau : float
        Relaxation ratio and time constant [s].
    damage_depth : float
        True damage depth [m].
    environment : str
    """

    mu_s: float
    mu_k: float
    k_n_per_mm_n: float
    n: float
    k_t: float
    rho: float
    tau: float
    damage_depth: float
    environment: str


@functools.lru_cache(maxsize=1024)
def specimen_truth(seed: int, object_id: str, material: str, object_index: int,
                   friction_level: str, environment: str,
                   coating_mu_rel: float = COATING_MU_REL) -> Specimen:
    """Return the true constants of an object (the same for all its trials in one environment).

    Parameters
    ----------
    seed : int
        Protocol seed.
    object_id, material : str
    object_index : int
        Specimen number (recorded by the bench draw only).
    friction_level : str
        ``natural`` or a coating of :data:`graspcampaign.rig.belief.COATING_MU_S`.
    environment : str
        Ambient group of the trial's day (scales natural friction, §7.3).

    Returns
    -------
    Specimen
    """
    fam = bench.FAMILIES[material]
    spec = bench.draw_specimen(fam, object_index, "normal_lab", key_rng("specimen", seed, object_id))
    spec = bench.with_environment(spec, environment)
    mu_s, mu_k = spec.mu_s, spec.mu_k
    if friction_level != "natural":
        z = key_rng("coating", seed, object_id, friction_level).standard_normal()
        mu_s = rigbelief.COATING_MU_S[friction_level] * math.exp(coating_mu_rel * z)
        mu_k = mu_s * spec.mu_k / spec.mu_s
    depth = rigbelief.family_damage_depth(fam, spec.softening_ref / fam.softening_ref)
    return Specimen(mu_s=mu_s, mu_k=mu_k, k_n_per_mm_n=spec.k_n_per_mm_n, n=spec.n, k_t=spec.k_t,
                    rho=spec.rho, tau=spec.tau, damage_depth=depth, environment=environment)
