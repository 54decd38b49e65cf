"""sensitivity: the opening states the paper's stable region beside ours; the paper's Fig. 19 and
Sec. 6.6 words are judged by the one verdict rule where they are checkable, and said to be qualitative
where they are not.

Synthetic panel (a) and (c) trials are reported through the spec; rates are recomputed with pandas and
statsmodels' Wilson interval; the region's bounds are the study file's paper block.
"""

from __future__ import annotations

import math

import pandas as pd
import pytest
from statsmodels.stats.proportion import proportion_confint

from graspcampaign.campaign.paper import study_paper
from graspcampaign.report.render import Run
from graspcampaign.report.studies.sensitivity import BOUND, SPEC, _panels, _word_claims, finding

PAPER = study_paper("sensitivity")


def _run(cells: dict) -> Run:
    """Panel (a) trials from ``{(mass, μ): (successes, trials)}`` and a small panel (c) whose runtime
    doubles with n."""
    a = [{"panel": "mu_mass", "mass_kg": m, "mu": mu, "success": i < won, "runtime_ms": 1.0}
         for (m, mu), (won, n) in cells.items() for i in range(n)]
    c = [{"panel": "n_b", "n_exp": n, "b": b, "success": False, "runtime_ms": n}
         for n in (1.0, 2.0) for b in (0.1, 0.2)]
    records = pd.DataFrame(a + c).assign(status="ok", success_vertical=lambda f: f["success"],
                                         delta_max_mm=1.0, loop_capped=False)
    run = Run(records, {"config": {"evaluator": {"n_max": 50}}}, PAPER)
    run.tables["sensitivity_panels"] = _panels(run)
    claims = next(i for i in SPEC.items if getattr(i, "name", "") == "sensitivity_claims")
    run.tables["sensitivity_claims"] = claims.compute(run)
    return run


def _wilson(k: int, n: int) -> str:
    low, high = proportion_confint(k, n, method="wilson")
    return f"{100 * k / n:.1f}% ({100 * low:.1f}–{100 * high:.1f}%)"


def test_the_openings_p_values_of_equal_success_over_the_levels_are_the_claims_tables():
    """At paper scale the opening gave "Monte Carlo χ² p ≤ 1.0e-4" and "p = 1.0" over mass's and
    friction's 12 levels, in no table on the page: each is now a row of sensitivity_claims, and the
    opening names the test once. Here 40 of 200 against 10 of 200 by mass, 25 of 200 at each friction
    (p from scipy's chi-square on the records' table)."""
    from scipy.stats import chi2_contingency

    from graspcampaign.report import format as fmt

    run = _run({(0.1, 0.05): (20, 100), (0.1, 0.5): (20, 100), (0.8, 0.05): (5, 100), (0.8, 0.5): (5, 100)})
    a = run.records[run.records["panel"] == "mu_mass"]
    p = {k: chi2_contingency(pd.crosstab(a[k], a["success"]), correction=False).pvalue
         for k in ("mass_kg", "mu")}
    assert (f"Success varies with mass (χ² p = {fmt.p_value(p['mass_kg'])}) and does not detectably vary "
            f"with friction (p = {fmt.p_value(p['mu'])}). ") in finding(run)
    rows = run.tables["sensitivity_claims"].set_index("quantity")
    for factor, column in (("mass", "mass_kg"), ("friction", "mu")):
        row = rows.loc[f"(a) equal success at every {factor} level: p"]
        assert row["value"] == pytest.approx(p[column], rel=1e-12) and row["n"] == 400
        assert row["verdict"] == "no paper value"


@pytest.mark.parametrize(("won", "said"), [(0, "every trial failed"), (1, "every trial succeeded")])
def test_equal_success_with_one_outcome_throughout_is_said_as_the_finding_it_is(won, said):
    """A reduced run whose trials all fail has no difference between levels to test: its p rows read
    "not computed: no success or no failure to test", as if something broke; now the finding itself,
    in the value's place and as the row's reason, and the opening says the share does not vary."""
    run = _run({(m, mu): (won * 20, 20) for m in (0.1, 0.8) for mu in (0.05, 0.5)})
    rows = run.tables["sensitivity_claims"].set_index("quantity")
    for factor in ("mass", "friction"):
        row = rows.loc[f"(a) equal success at every {factor} level: p"]
        assert math.isnan(row["value"]) and row["differs"] is None
        assert row["why"] == row["verdict"] == f"{said}: no difference to test"
    assert f"does not vary with mass ({100.0 * won:.1f}% at each of its 2 levels)" in finding(run)


def test_the_opening_states_the_papers_stable_region_beside_ours():
    # the opening counted boundaries but never said where the paper's stable region lies; its edge
    # (m = 0.5 kg, μ = 0.2) belongs to it: "μ ≥ 0.2, m ≤ 0.5 kg"
    run = _run({(0.4, 0.5): (30, 50), (0.8, 0.5): (5, 50), (0.4, 0.05): (20, 40), (0.8, 0.05): (2, 40),
                (0.5, 0.2): (10, 10)})
    records = run.records[run.records["panel"] == "mu_mass"]
    inside = (records["mu"] >= PAPER.stable_mu_min) & (records["mass_kg"] <= PAPER.stable_mass_max_kg)
    said = {}
    for side, g in records.groupby(inside)["success"]:  # each rate with statsmodels' Wilson interval
        low, high = proportion_confint(g.sum(), len(g), method="wilson")
        said[side] = f"{100 * g.mean():.1f}% ({100 * low:.1f}–{100 * high:.1f}%) of {len(g)}"
    assert finding(run).startswith(f"Paper's stable region: μ ≥ {PAPER.stable_mu_min:g}, m ≤ "
                                   f"{PAPER.stable_mass_max_kg:g} kg (Fig. 19a); ours succeeds on "
                                   f"{said[True]} inside it, {said[False]} outside (Wilson 95%). ")


@pytest.mark.parametrize(("cells", "inside", "outside"), [
    ({(0.4, 0.5): (3, 10), (0.3, 0.3): (1, 10)}, _wilson(4, 20) + " of 20 inside it", "no trial outside"),
    ({(0.8, 0.5): (3, 10), (0.9, 0.05): (1, 10)}, "no trial inside it", _wilson(4, 20) + " of 20 outside")])
def test_a_sweep_on_one_side_of_the_stable_region_says_so(cells, inside, outside):
    # a sweep inside the region printed "— of <NA> outside"; one outside it left the region unsaid
    assert finding(_run(cells)).startswith(f"Paper's stable region: μ ≥ {PAPER.stable_mu_min:g}, m ≤ "
                                           f"{PAPER.stable_mass_max_kg:g} kg (Fig. 19a); ours succeeds "
                                           f"on {inside}, {outside} (Wilson 95%). ")


def test_the_papers_words_on_the_region_and_the_drop_are_judged_by_wilson_intervals_apart():
    # the rows printed "—, no paper value" though Fig. 19a and Sec. 6.6 state them in words
    run = _run({(0.4, 0.5): (30, 50), (0.8, 0.5): (5, 50), (0.4, 0.05): (20, 40), (0.8, 0.05): (2, 40)})
    claims = run.tables["sensitivity_claims"].set_index("quantity")
    region = claims.loc["(a) stable region: success inside it"]
    ok = run.records[run.records["panel"] == "mu_mass"]
    inside = (ok["mu"] >= 0.2) & (ok["mass_kg"] <= 0.5)
    apart = proportion_confint(ok.loc[inside, "success"].sum(), inside.sum(), method="wilson")[0] > \
        proportion_confint(ok.loc[~inside, "success"].sum(), (~inside).sum(), method="wilson")[1]
    assert apart and (region["paper"], region["differs"]) == ("higher than outside it", False)
    assert region["verdict"] == "as in the paper (higher than outside it)"
    # μ < 0.2: 2 of 40 above m = 0.5 against 20 of 40 at or below it, Wilson intervals apart: a drop
    drop = claims.loc["(a) sharp drop above the mass limit when μ < the friction limit"]
    assert proportion_confint(2, 40, method="wilson")[1] < proportion_confint(20, 40, method="wilson")[0]
    assert drop["verdict"] == "as in the paper (a drop: lower than at m ≤ the mass limit)"
    # no drop: 18 of 40 against 20 of 40, the intervals overlap
    claims = _run({(0.4, 0.5): (30, 50), (0.8, 0.5): (5, 50), (0.4, 0.05): (20, 40), (0.8, 0.05): (18, 40)}
                  ).tables["sensitivity_claims"].set_index("quantity")
    drop = claims.loc["(a) sharp drop above the mass limit when μ < the friction limit"]
    # overlapping intervals neither show the drop nor contradict it (it read "differs")
    assert drop["differs"] is None and drop["verdict"] == (
        f"not shown by ours: {_wilson(18, 40)} against {_wilson(20, 40)}, Wilson intervals overlap")


def test_the_runtime_claim_is_said_to_be_qualitative_not_given_a_number():
    run = _run({(0.4, 0.5): (30, 50), (0.8, 0.05): (2, 40)})
    claims = run.tables["sensitivity_claims"].set_index("quantity")
    row = claims.loc["(c) runtime max/min over n levels"]
    runtime = run.records[run.records["panel"] == "n_b"].groupby("n_exp")["runtime_ms"].median()
    assert row["value"] == runtime.max() / runtime.min() and row["paper"] == "nearly flat"  # Sec. 6.6
    assert row["differs"] is None and math.isnan(row["difference"])
    assert row["verdict"].startswith("not compared: the paper's words are qualitative")


def test_the_identified_lambda1_rows_carry_the_dimensionless_unit():
    # Table 3: λ1 is quoted as a pure number; the rows' unit cell was empty
    claims = SPEC.items[[getattr(i, "name", "") for i in SPEC.items].index("sensitivity_claims")]
    run = _run({(0.4, 0.5): (30, 50)})
    frame = claims.compute(run).set_index("quantity")
    assert frame.loc[[q for q in frame.index if "median identified λ1" in q], "unit"].tolist() == ["–", "–"]


def _on_bound(k: int, n: int) -> dict:
    """A λ1-bound claims row: k of n identifications on the bound, with statsmodels' Wilson interval."""
    low, high = proportion_confint(k, n, method="wilson")
    return {"value": 100 * k / n, "low": 100 * low, "high": 100 * high, "n": n}


@pytest.mark.parametrize(("low_mu", "high_mu", "expected"), [
    # 18 of 20 at μ < 0.1 (interval above 50%: most), 2 of 20 at μ ≥ 0.1 (intervals apart: fewer)
    ((18, 20), (2, 20), [(False, "as in the paper (pushed toward the bound)"),
                         (False, "as in the paper (fewer than at μ < 0.1)")]),
    # 2 of 2 at both (the golden run): neither shown; the point values (100% > 50%, 100% not fewer)
    # had read "as in the paper" and "differs"
    ((2, 2), (2, 2), [(None, f"not shown by ours: {_wilson(2, 2)} against 50%, Wilson intervals overlap"),
                      (None, f"not shown by ours: {_wilson(2, 2)} against {_wilson(2, 2)}, Wilson "
                             "intervals overlap")]),
    # 3 of 20 then 18 of 20: a minority on the bound, and more (not fewer) at μ ≥ 0.1: both differ
    ((3, 20), (18, 20), [(True, "differs: the paper reports pushed toward the bound, ours is "
                                f"{_wilson(3, 20)} against 50%, Wilson intervals apart the other way"),
                         (True, "differs: the paper reports fewer than at μ < 0.1, ours is "
                                f"{_wilson(18, 20)} against {_wilson(3, 20)}, Wilson intervals apart the "
                                "other way")]),
])
def test_lambda1_bound_words_are_judged_by_wilson_intervals_as_the_other_words(low_mu, high_mu, expected):
    frame = pd.DataFrame([{"quantity": BOUND + "< 0.1", **_on_bound(*low_mu)},
                          {"quantity": BOUND + "≥ 0.1", **_on_bound(*high_mu)}]).assign(
        paper=None, differs=None, verdict="")
    out = _word_claims(frame)
    assert list(zip(out["differs"], out["verdict"], strict=True)) == expected


def test_the_test_of_equal_success_over_a_factors_levels_runs_once_per_run(monkeypatch):
    """The opening (the mass test twice: its name, then its p) and table sensitivity_claims read one
    test per factor: its Monte Carlo p (9999 random tables) was drawn three times for mass, twice for
    friction. The p the opening prints is still scipy's."""
    from scipy.stats import chi2_contingency

    from graspcampaign.report import format as fmt
    from graspcampaign.report.studies import sensitivity

    calls = []
    real = sensitivity.equal_rates_test
    monkeypatch.setattr(sensitivity, "equal_rates_test", lambda *a, **k: calls.append(1) or real(*a, **k))
    run = _run({(0.1, 0.05): (20, 100), (0.1, 0.5): (20, 100), (0.8, 0.05): (5, 100), (0.8, 0.5): (5, 100)})
    text = finding(run)
    assert len(calls) == 2  # mass and friction, once each
    a = run.records[run.records["panel"] == "mu_mass"]
    p = chi2_contingency(pd.crosstab(a["mass_kg"], a["success"]), correction=False).pvalue
    assert f"Success varies with mass (χ² p = {fmt.p_value(p)})" in text
