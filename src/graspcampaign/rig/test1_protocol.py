"""Test 1 protocol definition (paper §7.1-7.6): environment groups, blocks, held-out splits, the
published counts, the factors of the matrix, and each event's stable id and random streams.

Shared by the schedule (:mod:`graspcampaign.rig.test1`), the virtual bench
(:mod:`graspcampaign.rig.test1_bench`) and PSO re-identification (:mod:`graspcampaign.rig.test1_pso`).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

from graspcampaign.analysis.vocabulary import OBLIQUE_ANGLES_DEG

__all__ = [
    "BLOCKS",
    "ENVIRONMENTS",
    "PUBLISHED",
    "SPLITS",
    "Test1Protocol",
    "event_id_for",
    "event_rng",
    "keyed_rng",
]


ENVIRONMENTS = ("cool_dry", "normal_lab", "warm_humid")
"""Environment groups of §7.1."""
BLOCKS = ("normal", "relaxation", "sliding", "oblique", "cyclic")
"""The five test blocks of §7.1."""
SPLITS = ("train", "unseen_specimen", "unseen_speed", "unseen_load", "flat_to_curved",
          "extended_relaxation")
"""Training split and the held-out splits of §7.6."""
SCHEDULE_COLUMNS = ("event_id", "material", "specimen", "specimen_id", "environment", "block",
                    "split", "surface", "surface_radius_mm", "angle_deg", "speed_mm_per_s",
                    "depth_mm", "normal_load_n", "load_level", "hold_s", "stroke_mm", "cycle_index",
                    "repeat", "profile", "accel_mm_per_s2", "max_speed_mm_per_s", "daq_hz", "day",
                    "session", "run_order")
"""The columns of the Test 1 commanded-event sheet (``test1_schedule``), in order."""

PUBLISHED = {
    "events_commanded": 19229,
    "events_completed": 19168,
    "events_aborted": 61,
    "normal_fits": 5040,
    "normal_fits_accepted": 4888,
    "oblique_events": 1728,
    "cycle_measurements": 1600,
    "pso_runs_logged": 124,
    "pso_runs_converged": 120,
}
"""Counts the paper reports for Test 1 (§7.1-7.5)."""



@dataclass(frozen=True)
class Test1Protocol:
    """Factors of the Test 1 matrix (§7.1-7.6); defaults reproduce the published counts.

    Per specimen and environment group (4 x 12 x 3 = 144 cells): 35 normal indentations
    (5 speeds x 7 depths), 30 hold relaxations (3 depths x 2 ramp speeds x 4 repeats at
    60 s, plus 3 depths x 2 repeats at the extended hold), 45 slides (5 speeds x 3 loads x
    3 repeats) and 12 oblique presses (4 angles x 2 flat + 1 curved): 122 x 144 = 17,568.
    Cyclic fatigue (normal-lab only, the 10 training specimens of each family): 200 cycles
    as a two-level depth staircase, every 5th cycle measured, 40 x 40 = 1,600. Total 19,168
    planned events, i.e. the 19,168 completed events of §7.1; 5,040 = 144 x 35 normal fits
    and 1,728 = 144 x 12 oblique events as published.
    """

    n_specimens: int = 12
    held_out_specimens: tuple[int, ...] = (11, 12)
    accel_mm_per_s2: float = 300.0
    max_speed_mm_per_s: float = 50.0
    normal_speeds_mm_per_s: tuple[float, ...] = (0.5, 1.0, 2.0, 5.0, 10.0)
    normal_depths_mm: tuple[float, ...] = (0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75)
    normal_dwell_s: float = 0.2
    relaxation_depths_mm: tuple[float, ...] = (0.5, 1.0, 1.5)
    relaxation_speeds_mm_per_s: tuple[float, ...] = (2.0, 10.0)
    relaxation_repeats: int = 4
    relaxation_hold_s: float = 60.0
    extended_hold_s: float = 180.0
    extended_speed_mm_per_s: float = 10.0
    extended_repeats: int = 2
    relaxation_daq_hz: float = 50.0
    sliding_speeds_mm_per_s: tuple[float, ...] = (0.5, 1.0, 2.0, 5.0, 10.0)
    sliding_load_depths_mm: tuple[float, ...] = (0.5, 1.0, 1.5)
    sliding_repeats: int = 3
    sliding_stroke_mm: float = 3.0
    oblique_angles_deg: tuple[float, ...] = OBLIQUE_ANGLES_DEG
    oblique_depth_mm: float = 1.5
    oblique_speed_mm_per_s: float = 1.0
    oblique_dwell_s: float = 0.5
    oblique_flat_repeats: int = 2
    oblique_curved_repeats: int = 1
    curved_radius_mm: float = 25.0
    cyclic_levels: tuple[tuple[float, int], ...] = ((1.0, 100), (2.0, 100))
    cyclic_measure_every: int = 5
    cyclic_speed_mm_per_s: float = 2.0
    cyclic_environment: str = "normal_lab"
    unseen_speed_mm_per_s: float = 5.0
    unseen_load_level: int = 2
    min_loading_samples: int = 100
    max_slide_step_um: float = 2.0

    def cyclic_depths_mm(self) -> np.ndarray:
        """Indentation of every cycle of the fatigue run, shape (c,) [mm]."""
        return np.concatenate([np.full(n, d) for d, n in self.cyclic_levels])

    def measured_cycles(self) -> np.ndarray:
        """1-based indices of the measured cycles: every ``cyclic_measure_every``-th of each
        level, starting with the level's first cycle."""
        out, first = [], 1
        for _, n in self.cyclic_levels:
            out.extend(range(first, first + n, self.cyclic_measure_every))
            first += n
        return np.asarray(out)


def _hash_int(text: str, nbytes: int = 8) -> int:
    return int.from_bytes(hashlib.blake2b(text.encode(), digest_size=nbytes).digest(), "big")


def event_id_for(material: str, specimen: int, environment: str, block: str,
                 condition: str, repeat: int) -> str:
    """Return the stable, content-derived id of one planned event.

    ``"t1-" + blake2b(material|specimen|environment|block|condition|repeat)[:12 hex]``; the
    id depends on what the event is, never on the seed or on its position in the sheet.
    """
    key = f"{material}|{specimen}|{environment}|{block}|{condition}|{repeat}"
    return "t1-" + hashlib.blake2b(key.encode(), digest_size=6).hexdigest()


def keyed_rng(seed: int, *key: str) -> np.random.Generator:
    """Generator of one named stream: ``SeedSequence(seed, spawn_key=(h(k) for k in key))``."""
    words = [_hash_int(k, 4) for k in key]
    return np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=tuple(words)))


def event_rng(seed: int, event_id: str, attempt: int) -> np.random.Generator:
    """Generator of one attempt: ``SeedSequence(seed, spawn_key=(h(event_id), attempt))``."""
    return np.random.default_rng(np.random.SeedSequence(
        int(seed), spawn_key=(_hash_int(event_id, 4), _hash_int("attempt", 4), int(attempt))))
