"""Small real trial kinds used by the engine tests (registered at import)."""

from __future__ import annotations

import numpy as np

from graspcampaign.campaign.kind import TrialKind, register_kind


def _pi_estimate(inp, rng: np.random.Generator) -> dict:
    """Monte Carlo estimate of pi from 2000 uniform points in the unit square."""
    pts = rng.random((2000, 2))
    inside = np.count_nonzero((pts**2).sum(axis=1) <= 1.0)
    if inp.trial.factors.get("mu") == 13.0:
        raise ValueError("mu = 13 is unlucky")
    return {"pi_estimate": 4.0 * inside / 2000, "first_draw": float(pts[0, 0])}


def _pi_with_trace(inp, rng):
    out = _pi_estimate(inp, rng)
    out["__tables__"] = {"trace": {"step": [0, 1, 2], "value": [0.0, 1.0, out["pi_estimate"]]}}
    return out


def _pi_with_sparse_trace(inp, rng):
    """Two trace rows for a ``random`` planner's trial, none (an empty table) for the others."""
    out = _pi_estimate(inp, rng)
    n = 2 if inp.trial.factors.get("planner") == "random" else 0
    out["__tables__"] = {"trace": {"step": list(range(n)), "value": [out["pi_estimate"]] * n}}
    return out


def _prepare(study, params, body, rng):
    return {"identified_scale": float(rng.uniform(1, 2))}


def _pi_prepared(inp, rng):
    out = _pi_estimate(inp, rng)
    out["identified_scale"] = inp.prepared["identified_scale"]
    return out


def _pi_prepared_with_trace(inp, rng):
    """A prepared trial storing 1 to 3 trace rows (by its index)."""
    out = _pi_prepared(inp, rng)
    n = 1 + inp.trial.index % 3
    out["__tables__"] = {"trace": {"step": list(range(n)), "value": [out["pi_estimate"]] * n}}
    return out


PI = TrialKind(name="test_pi", run=_pi_estimate, seconds_per_trial=0.001)
PI_TRACE = TrialKind(name="test_pi_trace", run=_pi_with_trace, seconds_per_trial=0.001)
PI_SPARSE_TRACE = TrialKind(name="test_pi_sparse_trace", run=_pi_with_sparse_trace,
                            seconds_per_trial=0.001)
PI_PREPARED = TrialKind(name="test_pi_prepared", run=_pi_prepared, seconds_per_trial=0.001,
                        body_key=lambda f: {"mass_kg": f["mass_kg"]}, prepare=_prepare)
PI_PREPARED_TRACE = TrialKind(name="test_pi_prepared_trace", run=_pi_prepared_with_trace,
                              seconds_per_trial=0.001, body_key=lambda f: {"mass_kg": f["mass_kg"]},
                              prepare=_prepare)
for _k in (PI, PI_TRACE, PI_SPARSE_TRACE, PI_PREPARED, PI_PREPARED_TRACE):
    register_kind(_k)
