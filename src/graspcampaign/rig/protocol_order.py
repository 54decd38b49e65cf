"""Trial ids, randomised run order and rig faults of the Tests 2-3 sheets.

A ``trial_id`` is a readable key plus a hash of the slot's design values (the seed only changes run
order and which slots carry a rig fault, never an id). The run order is randomised, blocked by
session and day (matched-set units stay in one session); the paper's aborted slots get
``rig_fault = True`` on attempt 1 and an attempt-2 row that re-runs them.

References
----------
Paper §8.1 (1785 commanded / 1755 executed), §9.1 (1245 / 1230).
"""

from __future__ import annotations

import hashlib
import json
from collections import Counter, defaultdict
from typing import Any

import numpy as np
import pandas as pd

from graspcampaign.rig.protocol_design import PAPER_COUNTS, PLANNER_LABELS, SCHEDULE_FRONT, SESSION_SLOTS

__all__ = [
    "check_seed",
    "schedule_slots",
]


# --------------------------------------------------------------------------------------------
# Ids, run order, rig faults
# --------------------------------------------------------------------------------------------
_HASH_LEN = 10


def _canonical(obj: Any) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=str)


def _digest(obj: Any, length: int = _HASH_LEN) -> str:
    return hashlib.sha256(_canonical(obj).encode()).hexdigest()[:length]


_SHORT = {"heuristic": "prop", "no_pso": "nopso", "centroid": "cent", "force_balance": "fb",
          "random": "rand"}


def _with_ids(slots: list[dict[str, Any]], study: str, prefix: str, key: str) -> None:
    """Give every slot a readable, content-derived id; identical slots get repeat indices."""
    seen: Counter = Counter()
    for s in slots:
        design = {k: v for k, v in s.items() if k not in ("repeat", "unit")}
        cell = _canonical(design)
        s["repeat"] = seen[cell]
        seen[cell] += 1
        digest = _digest({"study": study, **design, "repeat": s["repeat"]})
        s["slot_id"] = f"{prefix}{s[key]}-{s['object_id']}-{_SHORT[s['planner']]}-{digest}"


def _plan_keys(slots: list[dict[str, Any]]) -> None:
    """Plans are shared per (object, planner); the random planner draws a new triple per slot."""
    for s in slots:
        if s["planner"] == "random":
            s["plan_key"] = f"{s['object_id']}:random:{s['slot_id']}"
        else:
            s["plan_key"] = f"{s['object_id']}:{s['planner']}"


def _order(slots: list[dict[str, Any]], rng: np.random.Generator, n_faults: int) -> list[dict]:
    """Shuffle units into sessions of SESSION_SLOTS, shuffle inside sessions, add fault re-runs."""
    units: dict[str, list[int]] = defaultdict(list)
    for i, s in enumerate(slots):
        units[s.get("unit") or s["slot_id"]].append(i)
    keys = list(units)
    rng.shuffle(keys)
    sessions: list[list[int]] = [[]]
    for k in keys:
        if sessions[-1] and len(sessions[-1]) + len(units[k]) > SESSION_SLOTS:
            sessions.append([])
        sessions[-1].extend(units[k])
    faulty = set(rng.choice(len(slots), size=n_faults, replace=False).tolist())
    rows: list[dict] = []
    order = 0
    for index, members in enumerate(sessions):
        members = list(members)
        rng.shuffle(members)
        reruns = []
        day, half = divmod(index, 2)
        session = f"d{day + 1:02d}-{'am' if half == 0 else 'pm'}"
        for position, i in enumerate(members, start=1):
            order += 1
            row = {**slots[i], "attempt": 1, "rig_fault": i in faulty, "day": day + 1,
                   "session": session, "session_position": position, "run_order": order}
            rows.append(row)
            if i in faulty:
                reruns.append(i)
        for i in reruns:  # aborted slots are re-run at the end of their session
            order += 1
            rows.append({**slots[i], "attempt": 2, "rig_fault": False, "day": day + 1,
                         "session": session, "session_position": len(members) + 1 + reruns.index(i),
                         "run_order": order})
    return rows


def _finish(rows: list[dict], study: str, seed: int, columns: tuple[str, ...]) -> pd.DataFrame:
    for r in rows:
        r["trial_id"] = r["slot_id"] if r["attempt"] == 1 else f"{r['slot_id']}-a{r['attempt']}"
        r["study"] = study
        r["protocol_seed"] = int(seed)
        r["planner_label"] = PLANNER_LABELS[r["planner"]]
        r.pop("unit", None)
    df = pd.DataFrame(rows)
    front = list(SCHEDULE_FRONT)
    rest = [c for c in columns if c not in front]
    extra = [c for c in df.columns if c not in front + rest]
    return df[front + rest + extra].reset_index(drop=True)


def schedule_slots(slots: list[dict[str, Any]], study: str, prefix: str, key: str, seed: int,
                   columns: tuple[str, ...]) -> pd.DataFrame:
    """Id, plan-key, order (with the paper's rig faults) and tabulate one study's slots."""
    _with_ids(slots, study, prefix, key)
    _plan_keys(slots)
    rows = _order(slots, _rng(seed, study), PAPER_COUNTS[study]["aborted"])
    return _finish(rows, study, seed, columns)


def check_seed(seed: object) -> int:
    """Return ``seed`` as an int; refuse anything but a non-negative integer."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative int, got {seed!r}")
    return int(seed)


def _rng(seed: int, study: str) -> np.random.Generator:
    word = int.from_bytes(hashlib.sha256(study.encode()).digest()[:4], "little")
    return np.random.default_rng(np.random.SeedSequence([seed, word]))
