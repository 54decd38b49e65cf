"""Trial expansion: factors, zipped factors, seeds and repeats into an ordered list of trials.

Trial ids are a readable key plus a short hash of the trial's own factor values, so they are
stable across runs, machines and worker counts. The random stream of a trial is derived from the
study seed and the trial's *scene* (every factor but the method factors such as ``planner``), so
every planner of one scene draw faces the same object, mass, friction and random draws: this is
what the paired McNemar tests need. A renamed factor is hashed under its first name
(``former_names.FIRST_NAMES``): a run stored before the rename keeps its trials' ids and streams.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from graspcampaign.campaign.former_names import FIRST_NAMES
from graspcampaign.campaign.schema import StudyCfg, design_shape
from graspcampaign.errors import ConfigError

if TYPE_CHECKING:
    import numpy as np

_HASH_LEN = 10
_READABLE_MAX = 48  # the hash identifies the trial; the readable prefix only helps a human


def _canonical(obj: Any) -> str:
    """Return a canonical JSON text for hashing (sorted keys, repr-exact floats)."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=str)


def content_hash(obj: Any, length: int = _HASH_LEN) -> str:
    """Return a short hex SHA-256 of ``obj``'s canonical JSON."""
    return hashlib.sha256(_canonical(obj).encode()).hexdigest()[:length]


def _level_text(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


@dataclass(frozen=True)
class Trial:
    """One trial of a study: its position, id, factor values and random-stream key."""

    index: int
    trial_id: str
    factors: dict[str, Any]  # every factor level plus ``seed`` and ``repeat``
    scene_id: str  # hash of the scene factors: equal for all methods of one scene draw
    stream_key: tuple[int, ...]  # SeedSequence spawn key derived from the scene

    def rng(self, study_seed: int) -> np.random.Generator:
        """Return this trial's random generator (independent of order, workers and resume)."""
        import numpy as np  # here, not at import: `graspcampaign list` and `show` never need it

        return np.random.default_rng(np.random.SeedSequence(study_seed, spawn_key=self.stream_key))


def stream_key(scene: dict[str, Any]) -> tuple[int, ...]:
    """Derive a ``SeedSequence`` spawn key (four 32-bit words) from a scene's factor values."""
    digest = hashlib.sha256(_canonical(scene).encode()).digest()
    return tuple(int.from_bytes(digest[i : i + 4], "little") for i in range(0, 16, 4))


def check_zip(study: StudyCfg) -> None:
    """Check the zip groups: each names two or more of the factors, each factor once over all
    groups, and a group's factors have as many levels.

    Raises
    ------
    ConfigError
        For the first group that does not, naming it (``zip[i]``).
    """
    seen: set[str] = set()
    for i, group in enumerate(study.zip):
        key = f"zip[{i}]"
        if len(group) < 2:  # a group of one zips nothing to it
            named = f"only {group[0]}" if group else "no factor"
            first_two = ", ".join(list(study.factors)[:2]) or "shape, mass_kg"
            raise ConfigError(f"{key} names {named}; a zip group advances two or more factors "
                              f"together, level by level (e.g. zip: [[{first_two}]]), or leave "
                              "zip out.", key=key)
        for j, name in enumerate(group):
            if name not in study.factors:
                raise ConfigError(f"{key} names {name!r}, which is not among the factors.", key=key)
            if name in group[:j]:
                raise ConfigError(f"{key} names {name} twice; give each factor once.", key=key)
            if name in seen:
                raise ConfigError(f"{key} names {name!r}, which is already zipped.", key=key)
            seen.add(name)
        if len({len(study.factors[n]) for n in group}) > 1:
            raise ConfigError(f"{key} groups factors of different lengths: "
                              + ", ".join(f"{n} has {len(study.factors[n])}" for n in group) + ".",
                              key=key)


def design_axes(study: StudyCfg) -> list[list[dict[str, Any]]]:
    """Return the design's axes in order; each axis is a list of partial factor assignments.

    Factors are taken in file order; a zip group forms one axis at the position of its first
    factor. ``seed`` and ``repeat`` axes come last (innermost).
    """
    zipped = {name: group for group in study.zip for name in group}
    axes: list[list[dict[str, Any]]] = []
    done: set[str] = set()
    for name in study.factors:
        if name in done:
            continue
        group = zipped.get(name, [name])
        axes.append(
            [dict(zip(group, values, strict=True))
             for values in zip(*(study.factors[g] for g in group), strict=True)]
        )
        done.update(group)
    axes.append([{"seed": s} for s in range(study.seeds)])
    if study.repeats > 1:
        axes.append([{"repeat": r} for r in range(study.repeats)])
    return axes


def _cartesian(study: StudyCfg) -> Iterator[dict[str, Any]]:
    for combo in itertools.product(*design_axes(study)):
        factors: dict[str, Any] = {}
        for part in combo:
            factors.update(part)
        yield factors


def expand(study: StudyCfg, rows: list[dict[str, Any]] | None = None) -> list[Trial]:
    """Expand a study into its ordered trials with stable, content-derived ids.

    ``rows`` replaces the Cartesian design with an explicit list of factor assignments (a
    protocol's schedule: one row per commanded trial, see ``TrialKind.design``).
    """
    trials = []
    method = {FIRST_NAMES.get(name, name) for name in study.method_factors}
    for index, factors in enumerate(_cartesian(study) if rows is None else map(dict, rows)):
        factors.setdefault("seed", 0)
        factors.setdefault("repeat", 0)
        hashed = {FIRST_NAMES.get(k, k): v for k, v in factors.items()}  # the names ids were made by
        scene = {k: v for k, v in hashed.items() if k not in method}
        readable = "_".join(
            f"s{v}" if k == "seed" else f"r{v}" if k == "repeat" else _level_text(v)
            for k, v in factors.items() if k != "repeat" or study.repeats > 1
        )[:_READABLE_MAX]
        digest = content_hash({"study": study.name, "kind": study.kind, "factors": hashed})
        trials.append(
            Trial(
                index=index,
                trial_id=f"{readable}-{digest}",
                factors=factors,
                scene_id=content_hash({"study": study.name, "scene": scene}),
                stream_key=stream_key({"study": study.name, "scene": scene}),
            )
        )
    return trials


def n_trials(study: StudyCfg) -> int:
    """Return the trial count without expanding (nor listing the seeds)."""
    return math.prod(design_shape(study).values())
