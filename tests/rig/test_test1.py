"""Tests of graspcampaign.rig.test1: schedule, virtual bench recovery, ingest, PSO.

The virtual-bench tests run a reduced schedule (specimen 1 of each family, all three
environments, all five blocks: 1,624 events, about 5 s) once per module.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from graspcampaign.core.bench import SensorParams
from graspcampaign.rig import test1 as T
from graspcampaign.rig import test1_pso
from graspcampaign.rig.test1_ingest import PEAK_FACTOR

SEED = 7
KEY = ["material", "specimen", "environment"]


@pytest.fixture(scope="module")
def full_schedule():
    return T.test1_schedule(SEED)


@pytest.fixture(scope="module")
def reduced():
    schedule = T.test1_schedule(SEED, specimens=[1])
    return schedule, T.run_virtual_bench(schedule, SEED)


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
    ("normal", "exponent_n", 0.0, 0.015), ("sliding", "mu_s", 0.02, 0.0),
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
    truth = res.truths.groupby("material")[["exponent_n", "mu_s", "rho"]].mean()
    np.testing.assert_allclose(t4["exponent_n"], truth.loc[t4.index, "exponent_n"], atol=0.015)
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


# ----------------------------------------------------------------------------- ingest


@pytest.fixture(scope="module")
def small(reduced):
    schedule, res = reduced
    ids = (res.fits.groupby("block").head(6)["event_id"].tolist()
           + res.fits.loc[res.fits["anomaly"] != "", "event_id"].head(3).tolist())
    wav = res.waveforms[res.waveforms["event_id"].isin(ids)].reset_index(drop=True)
    return schedule, res, wav


@pytest.mark.parametrize("suffix", ["csv", "parquet"])
def test_ingest_gives_the_in_process_fits(small, tmp_path, suffix):
    schedule, res, wav = small
    path = tmp_path / f"waves.{suffix}"
    if suffix == "csv":
        wav.to_csv(path, index=False)
    else:
        wav.to_parquet(path, index=False)
    valid = T.validate_waveforms(path, schedule["event_id"], schedule=schedule)
    fits = T.fit_waveforms(valid, schedule).set_index("event_id").sort_index()
    ref = res.fits.set_index("event_id").loc[fits.index]
    pd.testing.assert_frame_equal(fits, ref[fits.columns], check_dtype=False)


def test_the_bench_reaches_its_commanded_depth_and_stroke_within_the_peak_factor(small):
    """The virtual bench's own events, the rule's reference: peak over command per block, from
    the waveforms with pandas (an oblique press at 45 deg reaches 1/cos 45 of its depth)."""
    schedule, _, wav = small
    peaks = wav.assign(d=wav["displacement_mm"].abs(), t=wav["tangential_displacement_mm"].abs())
    peaks = peaks.groupby("event_id")[["d", "t"]].max().join(schedule.set_index("event_id"))
    ratios = pd.concat([peaks["d"] / peaks["depth_mm"], peaks["t"] / peaks["stroke_mm"]]).dropna()
    assert ratios.max() == pytest.approx(1.0 / math.cos(math.radians(45.0)), rel=0.01)
    assert 1.0 / PEAK_FACTOR < ratios.min() and ratios.max() < PEAK_FACTOR


@pytest.mark.parametrize(("column", "scale", "what"), [
    ("displacement_mm", 1e-3, "depth"),               # the tester's file: written in metres
    ("displacement_mm", 10.0, "depth"),               # in tenths of a millimetre
    ("tangential_displacement_mm", 0.1, "stroke"),    # in centimetres
], ids=["m", "tenths", "cm"])
def test_ingest_refuses_a_displacement_in_another_unit(small, tmp_path, column, scale, what):
    schedule, _, wav = small
    command = {"depth": "depth_mm", "stroke": "stroke_mm"}[what]
    events = schedule.set_index("event_id")[command].dropna()
    one = wav[wav["event_id"] == next(e for e in wav["event_id"] if e in events.index)]
    bad = one.assign(**{column: one[column] * scale}).reset_index(drop=True)
    path = tmp_path / "w.csv"
    bad.to_csv(path, index=False)
    row = int(bad[column].abs().idxmax())  # the peak sample
    event = bad["event_id"].iloc[0]
    peak, commanded = abs(bad[column].iloc[row]), events[event]
    with pytest.raises(T.IngestError) as info:
        T.validate_waveforms(path, schedule["event_id"], schedule=schedule)
    assert str(info.value) == (
        f"w.csv, row {row + 1}, column '{column}': event '{event}' peaks at {peak:g} mm where the "
        f"schedule commands a {what} of {commanded:g} mm (ratio {peak / commanded:.3g}, outside "
        "1/3 to 3: wrong units?).")


@pytest.fixture
def good(small):
    schedule, _, wav = small
    df = wav[wav["event_id"] == wav["event_id"].iloc[0]].iloc[:30].reset_index(drop=True)
    return schedule["event_id"], df


def _write(df, tmp_path):
    path = tmp_path / "bad.csv"
    df.to_csv(path, index=False)
    return path


def _set(df, row, column, value):
    """Return a copy of ``df`` with one cell replaced (the column widened to object for text)."""
    out = df.astype({column: object}) if isinstance(value, str) else df.copy()
    out.loc[row, column] = value
    return out


def _force_in_mn(df):
    """Normal force written in mN under the N header, after five zero samples."""
    out = df.assign(normal_force_n=df["normal_force_n"] * 1000.0)
    out.loc[:4, "normal_force_n"] = 0.0
    out.loc[5, "normal_force_n"] = 250.0
    return out


TEMPLATE = r" \(`graspcampaign schedule test1_bench --template` writes a sheet with every column\)\."
# Each case: how the bad table is made from the good 30-sample event, and the message after
# "bad.csv, " ({event} is the good event's id).
BAD_WAVEFORMS = {
    "missing_column": (lambda d: d.drop(columns="normal_force_n"),
                       r"header: a required column is missing: normal_force_n" + TEMPLATE),
    "missing_columns_all_named": (lambda d: d.drop(columns=["normal_force_n", "time_s"]),
                                  r"header: required columns are missing: time_s, normal_force_n"
                                  + TEMPLATE),
    "wrong_unit_column": (lambda d: d.rename(columns={"displacement_mm": "displacement_m"}),
                          r"header: 'displacement_m' has unit 'm' where 'displacement_mm' "
                          r"\(mm\) is expected" + TEMPLATE),
    "attempt_not_an_integer": (lambda d: _set(d, 3, "attempt", "two"),
                               r"row 4, column 'attempt': value 'two' is not an attempt number "
                               r"\(an integer 1 to 99 counting the tries of the event\)\."),
    "attempt_fractional": (lambda d: d.astype({"attempt": float}).assign(attempt=1.5),
                           r"row 1, column 'attempt': value 1\.5 is not an attempt number \(an "
                           r"integer 1 to 99 counting the tries of the event\)\."),
    "attempt_beyond_the_limit": (lambda d: d.assign(attempt=1000000),  # stored as 999999 aborts
                                 r"row 1, column 'attempt': value 1000000 is not an attempt number "
                                 r"\(an integer 1 to 99 counting the tries of the event\)\."),
    "two_sources": (lambda d: _set(d.assign(source="measured"), 6, "source", "virtual"),
                    r"row 7, column 'source': value 'virtual' differs from 'measured' in bad\.csv, "
                    r"row 1; a run holds the records of one source \(measured or virtual\): ingest "
                    r"the others into another run with --run\."),
    "a_misspelt_optional_column": (lambda d: d.rename(columns={"source": "Source"}),
                                   r"header: a column is not part of the sheet: 'Source' \(did you "
                                   r"mean 'source'\?\); its columns are event_id, time_s, "
                                   r"displacement_mm, normal_force_n, tangential_force_n, "
                                   r"tangential_displacement_mm, attempt, anomaly, source" + TEMPLATE),
    "attempt_negative": (lambda d: d.assign(attempt=-4),
                         r"row 1, column 'attempt': value -4 is not an attempt number \(an "
                         r"integer 1 to 99 counting the tries of the event\)\."),
    "attempt_changes_within_event": (lambda d: _set(d, 6, "attempt", 2),
                                     r"row 7, column 'attempt': value 2 differs from 1 earlier in "
                                     r"event '{event}' \(one value per event\)\."),
    "unknown_source": (lambda d: _set(d, 2, "source", "bogus"),
                       r"row 3, column 'source': value 'bogus' is not one of measured, "
                       r"virtual\."),
    "empty_source": (lambda d: _set(d, 5, "source", ""),
                     r"row 6, column 'source': value is empty; expected one of measured, "
                     r"virtual\."),
    "no_rows": (lambda d: d.iloc[:0], r"header, column 'event_id': the file has no data rows\."),
    "values_in_wrong_units": (_force_in_mn, r"row 6, column 'normal_force_n': value 250 lies "
                                            r"outside the 10 N load-cell range \(wrong units\?\)\."),
    "non_numeric": (lambda d: _set(d, 3, "time_s", "0.3s"),
                    r"row 4, column 'time_s': value '0\.3s' is not a number\."),
    "non_finite": (lambda d: _set(d, 7, "tangential_force_n", np.nan),
                   r"row 8, column 'tangential_force_n': value nan \(an empty cell or NaN\) is "
                   r"not finite\."),
    "non_monotonic_time": (lambda d: _set(d, 10, "time_s", d.loc[8, "time_s"] - 1e-4),
                           r"row 11, column 'time_s': time .* s does not increase within event "
                           r"'{event}' \(previous sample .* s\)\."),
    "unknown_event": (lambda d: _set(d, 12, "event_id", "t1-000000000000"),
                      r"row 13, column 'event_id': event id 't1-000000000000' is not in the "
                      r"schedule\."),
    "empty_event_id": (lambda d: _set(d, 2, "event_id", ""),
                       r"row 3, column 'event_id': event id is empty\."),
    "duplicate_rows": (lambda d: pd.concat([d, d.iloc[[4]]], ignore_index=True),
                       r"row 31, column 'time_s': duplicate sample of event '{event}' at .* s "
                       r"\(first seen in row 5\)\."),
}


@pytest.mark.parametrize("case", list(BAD_WAVEFORMS))
def test_ingest_rejects(good, tmp_path, case):
    ids, df = good
    make, message = BAD_WAVEFORMS[case]
    path = _write(make(df), tmp_path)
    message = message.format(event=re.escape(df["event_id"].iloc[0]))
    with pytest.raises(T.IngestError, match=rf"^bad\.csv, {message}$"):
        T.validate_waveforms(path, ids)


def test_ingest_names_the_sheet_behind_an_empty_first_sheet(good, tmp_path):
    ids, df = good
    path = tmp_path / "waves.xlsx"
    with pd.ExcelWriter(path) as book:
        pd.DataFrame().to_excel(book, sheet_name="Sheet1", index=False)
        df.to_excel(book, sheet_name="data", index=False)
    with pytest.raises(T.IngestError) as info:
        T.validate_waveforms(path, ids)
    assert str(info.value) == (
        "waves.xlsx, header: ingest reads the workbook's first sheet, which is empty; sheet 'data' "
        "has every required column: move it to the front or save it as CSV (`graspcampaign "
        "schedule test1_bench --template` writes a sheet with every column).")


def test_ingest_refuses_a_formula_without_its_computed_value(good, tmp_path):
    from openpyxl import load_workbook

    ids, df = good
    path = tmp_path / "waves.xlsx"
    df.to_excel(path, index=False)
    book = load_workbook(path)
    book.active.cell(row=5, column=list(df.columns).index("displacement_mm") + 1).value = "=0.1*2"
    book.save(path)
    with pytest.raises(T.IngestError) as info:
        T.validate_waveforms(path, ids)
    assert str(info.value) == (
        "waves.xlsx, row 4, column 'displacement_mm': the cell holds a formula (=0.1*2) with no "
        "computed value; open and save the file in a spreadsheet program, which stores the values.")


def test_ingest_rejects_unknown_file_type(good, tmp_path):
    ids, df = good
    path = tmp_path / "waves.txt"
    path.write_text("x")
    with pytest.raises(T.IngestError, match=r"^waves\.txt: unsupported file "
                                            r"type '\.txt' \(expected \.csv, \.parquet or "
                                            r"\.xlsx\)\.$"):
        T.validate_waveforms(path, ids)


def test_ingest_error_is_a_value_error_and_labels_dataframes(good):
    ids, df = good
    with pytest.raises(ValueError, match=r"^<dataframe>, header: a required column is missing: "
                                         r"event_id" + TEMPLATE + "$"):
        T.validate_waveforms(df.drop(columns="event_id"), ids)


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
    np.testing.assert_allclose(best["n"], truth.loc[best.index, "exponent_n"], atol=0.03)
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
    got = [(r.material, r.run, r.lambda1, r.lambda2, r.n, r.b, r.k, r.c, r.converged)
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
