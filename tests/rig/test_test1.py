"""Tests of graspcampaign.rig.test1: schedule, virtual bench recovery, PSO.

The virtual-bench tests share one reduced schedule (specimen 1 of each family, all three
environments, all five blocks: 1,624 events, about 5 s), run once (``reduced`` in conftest.py).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest
from test1_seed import KEY, SEED

from graspcampaign.core.bench import SensorParams
from graspcampaign.rig import test1 as T
from graspcampaign.rig import test1_pso


@pytest.fixture(scope="module")
def full_schedule():
    return T.test1_schedule(SEED)


# ---------------------------------------------------------------------------- schedule


def test_schedule_reproduces_the_published_counts(full_schedule):
    s = full_schedule
    assert len(s) == T.PUBLISHED["events_completed"] == 19168
    blocks = s["block"].value_counts()
    assert blocks["normal"] == T.PUBLISHED["normal_fits"] == 5040
    assert blocks["oblique"] == T.PUBLISHED["oblique_events"] == 1728
    assert blocks["cyclic"] == T.PUBLISHED["cycle_measurements"] == 1600
    assert blocks["relaxation"] + blocks["sliding"] == 19168 - 5040 - 1728 - 1600
    assert s["event_id"].is_unique
    assert s.groupby(KEY).ngroups == 4 * 12 * 3
    assert s["cycle_index"].max() <= 200


def test_schedule_protocol_limits_and_units(full_schedule):
    s = full_schedule
    assert s["daq_hz"].between(50, 500).all()
    assert (s["speed_mm_per_s"] <= s["max_speed_mm_per_s"]).all()
    assert (s["accel_mm_per_s2"] == 300.0).all() and (s["profile"] == "trapezoidal").all()
    assert set(s.loc[s["block"] == "oblique", "angle_deg"]) == {0.0, 15.0, 30.0, 45.0}
    dimensional = {"material", "specimen", "specimen_id", "environment", "block", "split",
                   "surface", "event_id", "profile", "load_level", "cycle_index", "repeat",
                   "day", "session", "run_order"}
    for c in set(s.columns) - dimensional:
        assert c.rsplit("_", 1)[-1] in {"mm", "deg", "s", "n", "hz", "s2"}, c


def test_schedule_ids_are_content_derived_and_order_is_seeded(full_schedule):
    other = T.test1_schedule(SEED + 1)
    assert set(other["event_id"]) == set(full_schedule["event_id"])
    assert not (other["event_id"].to_numpy() == full_schedule["event_id"].to_numpy()).all()
    again = T.test1_schedule(SEED)
    pd.testing.assert_frame_equal(again, full_schedule)
    sub = T.test1_schedule(SEED, materials=["gel"], specimens=[3])
    merged = sub.merge(full_schedule, on="event_id", suffixes=("", "_full"))
    assert len(merged) == len(sub)
    assert (merged["depth_mm"].fillna(-1) == merged["depth_mm_full"].fillna(-1)).all()


def test_run_order_is_blocked_by_day_and_session(full_schedule):
    s = full_schedule.sort_values("run_order")
    assert (s.groupby("session")["specimen_id"].nunique() == 1).all()
    assert (s.groupby("day")[["environment", "material"]].nunique() == 1).all().all()
    assert s["day"].is_monotonic_increasing and s["session"].is_monotonic_increasing
    # the destructive fatigue block runs last, cycles in sequence
    cyc = s[s["block"] == "cyclic"]
    assert cyc["run_order"].min() > s.loc[s["block"] != "cyclic", "run_order"].max()
    assert (cyc.groupby("session")["cycle_index"].apply(lambda c: c.is_monotonic_increasing)
            ).all()


def test_held_out_splits_of_section_7_6(full_schedule):
    s = full_schedule
    ids = T.split_event_ids(s)
    assert set(ids) == set(T.SPLITS) and sum(map(len, ids.values())) == len(s)
    assert set(s.loc[s["split"] == "unseen_specimen", "specimen"]) == {11, 12}
    train = s[s["split"] == "train"]
    assert 5.0 not in set(train["speed_mm_per_s"])
    assert 2 not in set(train.loc[train["block"] == "sliding", "load_level"])
    assert set(train["surface"]) == {"flat"}
    assert train.loc[train["block"] == "relaxation", "hold_s"].max() == 60.0
    ext = s[s["split"] == "extended_relaxation"]
    assert (ext["hold_s"] == 180.0).all() and len(ext) == 4 * 10 * 3 * 6


# -------------------------------------------------------------------- virtual bench


def test_every_row_is_virtual(reduced):
    _, res = reduced
    for df in (res.attempts, res.fits, res.waveforms, res.truths):
        assert (df["source"] == "virtual").all()


def test_aborted_attempts_are_rerun_and_carry_no_fit(reduced):
    schedule, res = reduced
    assert len(res.fits) == len(schedule) and res.fits["event_id"].is_unique
    done = res.attempts[res.attempts["status"] == "completed"]
    assert len(done) == len(schedule)
    aborted = res.attempts[res.attempts["status"] == "aborted"]
    fitted = res.fits.set_index("event_id")["attempt"]
    for _, a in aborted.iterrows():
        assert fitted[a["event_id"]] > a["attempt"]


def test_high_abort_rate_reruns_until_complete():
    schedule = T.test1_schedule(SEED, materials=["gel"], specimens=[1],
                                environments=["normal_lab"]).iloc[:40]
    res = T.run_virtual_bench(schedule, SEED, sensor=replace(SensorParams(), abort_rate=0.4))
    counts = res.attempts["status"].value_counts()
    assert counts["completed"] == 40 and counts["aborted"] > 5
    assert res.attempts.groupby("event_id")["attempt"].max().max() <= T.MAX_ATTEMPTS


def _median_vs_truth(res, block, column, truth_column=None):
    fits = res.fits[(res.fits["block"] == block) & res.fits["fit_ok"].astype(bool)]
    got = fits.groupby(KEY)[column].median()
    want = res.truths.set_index(KEY)[truth_column or column].reindex(got.index)
    return got, want


# Recovery tolerances on per-specimen medians (35 normal, 45 sliding, 30 relaxation
# events per specimen and environment): K, f0.5 3 %; n 0.015 absolute; mu_s 2 %;
# mu_k 1 %; k_t 4 %; rho 2 %; tau 2 %. C is not identifiable per event at bench speeds
# (docs/decisions.md) and is not tested here.
@pytest.mark.parametrize("block, column, rel, abs_", [
    ("normal", "k_n_per_mm_n", 0.03, 0.0), ("normal", "f05_n", 0.03, 0.0),
    ("normal", "n_exp", 0.0, 0.015), ("sliding", "mu_s", 0.02, 0.0),
    ("sliding", "mu_k", 0.01, 0.0), ("sliding", "k_t_n_per_mm", 0.04, 0.0),
    ("relaxation", "rho", 0.02, 0.0), ("relaxation", "tau_s", 0.02, 0.0),
])
def test_fits_recover_the_bench_truth(reduced, block, column, rel, abs_):
    _, res = reduced
    got, want = _median_vs_truth(res, block, column)
    assert len(got) == 12
    np.testing.assert_allclose(got.to_numpy(), want.to_numpy(), rtol=rel, atol=abs_)


def test_family_means_track_table4(reduced):
    # one specimen per family: within the specimen spread of the drawn truths
    _, res = reduced
    t4 = T.table4(res.fits, res.truths).set_index("material")
    truth = res.truths.groupby("material")[["n_exp", "mu_s", "rho"]].mean()
    np.testing.assert_allclose(t4["n_exp"], truth.loc[t4.index, "n_exp"], atol=0.015)
    np.testing.assert_allclose(t4["mu_s"], truth.loc[t4.index, "mu_s"], rtol=0.02)
    np.testing.assert_allclose(t4["rho"], truth.loc[t4.index, "rho"], rtol=0.02)
    assert t4["f05_n"].is_monotonic_increasing  # rises with modulus (Table 4)


def test_normal_fit_acceptance_rule(reduced):
    _, res = reduced
    nf = res.fits[res.fits["block"] == "normal"]
    flagged = nf[~nf["accepted"]]
    assert ((flagged["rmse_pct"] > T.REVIEW_RMSE_PCT) | (flagged["anomaly"] != "")).all()
    ok = nf[nf["accepted"]]
    assert (ok["rmse_pct"] <= T.REVIEW_RMSE_PCT).all() and (ok["anomaly"] == "").all()
    assert nf["accepted"].mean() > 0.9


def test_oblique_classification(reduced):
    _, res = reduced
    ob = T.oblique_summary(res.fits)
    assert len(ob) == 4 * 3 * 12
    by = ob.groupby("angle_deg")
    assert not by["slipped_measured"].any()[[0.0, 15.0]].any()
    assert by["slipped_measured"].all()[45.0]
    assert (by["margin_n"].mean().diff().dropna() < 0).all()  # falls with angle
    assert ob.loc[ob["angle_deg"] != 30.0, "classification_matches_margin"].all()
    assert ob["classification_matches_measured"].mean() > 0.95


def test_cyclic_softening_set_and_damage_depth(reduced):
    _, res = reduced
    cy = T.cyclic_summary(res.fits)
    assert len(cy) == 4 * 40
    last = cy.groupby("material").last()
    assert (last["k_ratio"] > 0.85).all()
    assert last["permanent_set_mm"].between(0.03, 0.5).all()
    dd = T.damage_depths(res.fits).merge(
        res.truths[["material", "specimen", "environment", "damage_depth_mm"]],
        on=KEY, suffixes=("", "_true"))
    assert len(dd) == 4
    # extrapolated beyond the 2 mm level from two levels: within 20 % of the truth
    np.testing.assert_allclose(dd["damage_depth_mm"], dd["damage_depth_mm_true"], rtol=0.2)


@pytest.mark.slow  # starts loky workers: `make test-slow`
def test_results_do_not_depend_on_order_or_workers(reduced):
    schedule, res = reduced
    sub = schedule.sample(60, random_state=1)
    again = T.run_virtual_bench(sub.iloc[::-1], SEED, n_jobs=2, chunk_size=7,
                                keep_waveforms=False)
    a = again.fits.set_index("event_id").sort_index()
    b = res.fits.set_index("event_id").loc[a.index]
    pd.testing.assert_frame_equal(a, b[a.columns])


def test_transfer_errors_on_held_out_splits(reduced):
    _, res = reduced
    te = T.transfer_errors(res.fits, res.waveforms)
    assert np.isfinite(te["error_pct"]).all() and (te["source"] == "virtual").all()
    mean = te.groupby(["quantity", "split"])["error_pct"].mean()
    assert set(mean.index) >= {("normal_force", "train"), ("normal_force", "unseen_speed"),
                               ("friction", "unseen_load"), ("relaxation", "extended_relaxation"),
                               ("flat_to_curved", "flat_to_curved")}
    # same-specimen calibration transfers within a few per cent on the virtual bench
    assert mean[("normal_force", "train")] < 3.0
    assert mean[("normal_force", "unseen_speed")] < 5.0
    assert mean[("friction", "unseen_load")] < 2.0
    assert mean[("relaxation", "extended_relaxation")] < 2.0
    assert mean[("flat_to_curved", "flat_to_curved")] < 10.0


# -------------------------------------------------------------------------------- PSO


def test_pso_reidentification_recovers_n_and_k(reduced):
    schedule, res = reduced
    wav = res.waveforms
    normal = res.fits[(res.fits["block"] == "normal") & (res.fits["environment"] == "normal_lab")
                      & (res.fits["depth_mm"] >= 1.0)]
    sub = wav[wav["event_id"].isin(normal["event_id"])]
    runs = T.pso_reidentify(sub, schedule, SEED, n_restarts=3, n_particles=12, n_iterations=60,
                            max_reruns=2)
    assert set(runs["material"]) == set(T.MATERIALS)
    best = runs.loc[runs.groupby("material")["cost_rmse_pct"].idxmin()].set_index("material")
    truth = res.truths[res.truths["environment"] == "normal_lab"].set_index("material")
    np.testing.assert_allclose(best["n_exp"], truth.loc[best.index, "n_exp"], atol=0.03)
    np.testing.assert_allclose(best["k_n_per_mm_n"], truth.loc[best.index, "k_n_per_mm_n"],
                               rtol=0.06)
    t5 = T.table5(runs)
    assert list(t5["parameter"]) == ["lambda1", "lambda2", "n", "b", "k", "c"]
    assert (runs["source"] == "virtual").all() and runs["converged"].any()
    assert math.isfinite(t5.loc[t5["parameter"] == "n", "cv_pct"].iloc[0])


def test_pso_cost_kernel_matches_the_numpy_reference(reduced):
    schedule, res = reduced
    normal = schedule[(schedule["block"] == "normal") & (schedule["material"] == "gel")]
    pool = T.normal_traces(res.waveforms[res.waveforms["event_id"].isin(normal["event_id"])],
                            T.PSO_POINTS_PER_TRACE, min_points=6)
    psi = T.bench.specimen_effective_modulus(T.FAMILIES["gel"].modulus_mean)
    from graspcampaign.core.identify import paper_bounds

    lower, upper = paper_bounds()
    upper[0] = T.PSO_LAMBDA1_UPPER
    pos = lower + np.random.default_rng(3).random((40, 6)) * (upper - lower)
    for pick in (range(12), range(len(pool) - 12, len(pool))):
        traces = [pool[i] for i in pick]
        np.testing.assert_allclose(test1_pso.pso_cost(traces, psi)(pos),
                                   test1_pso.pso_cost(traces, psi, backend="numpy")(pos), rtol=1e-13)


def _pso_run_by_run(waveforms, schedule, seed, n_restarts, max_reruns, **kw):
    """The re-run rule one run at a time (the implementation before run-level tasks)."""
    from graspcampaign.core.identify import paper_bounds

    lower, upper = paper_bounds()
    upper[0] = T.PSO_LAMBDA1_UPPER
    out = []
    for m in T.MATERIALS:
        ids = schedule.loc[(schedule["material"] == m) & (schedule["block"] == "normal"),
                           "event_id"]
        pool = T.normal_traces(waveforms[waveforms["event_id"].isin(ids)],
                                T.PSO_POINTS_PER_TRACE, min_points=6)
        psi = T.bench.specimen_effective_modulus(T.FAMILIES[m].modulus_mean)
        runs, costs = [], []
        for r in range(n_restarts + max_reruns):
            traces, rng = test1_pso.pso_draw(pool, seed, m, r, kw["traces_per_run"])
            res = test1_pso.pso_run(traces, psi, rng, (lower, upper), kw["n_particles"],
                                    kw["n_iterations"])
            runs.append(res)
            costs.append(test1_pso.pso_cost(traces, psi))
            if r + 1 >= n_restarts and test1_pso.converged_runs(runs, costs).sum() >= n_restarts:
                break
        out += [(m, r + 1, *res.best_x, bool(ok))
                for r, (res, ok) in enumerate(zip(runs, test1_pso.converged_runs(runs, costs),
                                                  strict=True))]
    return out


def test_pso_reidentify_reruns_follow_the_run_by_run_rule(reduced):
    # a tiny budget leaves runs unconverged, so re-runs are added in batches of the shortfall;
    # the logged runs must be those of adding one run at a time until n_restarts converge
    schedule, res = reduced
    normal = schedule[schedule["block"] == "normal"]
    kw = {"n_particles": 3, "n_iterations": 2, "traces_per_run": 4}
    runs = T.pso_reidentify(res.waveforms, normal, SEED, n_restarts=5, max_reruns=20, **kw)
    want = _pso_run_by_run(res.waveforms, normal, SEED, 5, 20, **kw)
    got = [(r.material, r.run, r.lambda1, r.lambda2, r.n_exp, r.b, r.k, r.c, r.converged)
           for r in runs.itertuples()]
    assert got == want
    counts = runs.groupby("material")["run"].size()
    assert counts.min() > 5 and counts.max() <= 25  # re-runs happened, within the limit


@pytest.mark.slow
def test_pso_reidentify_does_not_depend_on_n_jobs(reduced):
    schedule, res = reduced
    normal = schedule[schedule["block"] == "normal"]
    kw = {"n_restarts": 3, "n_particles": 6, "n_iterations": 20, "max_reruns": 4}
    pd.testing.assert_frame_equal(T.pso_reidentify(res.waveforms, normal, SEED, **kw),
                                  T.pso_reidentify(res.waveforms, normal, SEED, n_jobs=2, **kw))
