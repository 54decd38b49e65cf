"""A number a finding says reads as the table beside it prints it (the one formatter, the table's digits).

Each case parses the sentence and the table cell from the same report.md of the reduced results tree
(conftest.py ``sim_root``); the sentence once printed its own rounding ("within 0.2 s" beside a
table's 0.200, "n = 0.465" beside 0.46, milliseconds beside a table in µs).
"""

from __future__ import annotations

import re

from synthetic_runs import md_table, report_md

NUMBER = r"([−\-]?[\d.]+)"


def _said(text: str, pattern: str) -> list[str]:
    found = re.search(pattern, text)
    assert found, f"no sentence matches {pattern!r}"
    return [g.replace("−", "-") for g in found.groups()]


def _first(cell: str) -> str:
    """A cell's value without its interval: ``2.008 (1.921-2.095)`` is 2.008."""
    return cell.split(" (")[0]


def test_the_settle_finding_says_the_simulated_time_the_table_prints(sim_root):
    page = report_md(sim_root / "gravity_settle" / "default")
    said = [t.replace("−", "-") for t in re.findall(r"settle\** within " + NUMBER + " s", page)]
    assert said == md_table(page, "settle")["simulated time [s]"].tolist()


def test_the_pso_finding_says_each_pinned_mean_as_the_cv_table(sim_root):
    page = report_md(sim_root / "pso_repeatability" / "default")
    pinned = re.search(r"Pinned in every run \(CV 0, a bound of the search box\): (.+?)\.(?:\s|$)", page)
    assert pinned, "the reduced run pins no parameter: nothing to compare"
    cv = md_table(page, "cv").set_index("parameter")
    said = dict(part.rsplit(" at ", 1) for part in pinned.group(1).split(", "))
    assert said == {p: cv.loc[p, "mean"] for p in said}


def test_the_surrogate_finding_says_the_timing_and_r2_tables_numbers(sim_root):
    page = report_md(sim_root / "surrogate" / "default")
    # each time with its count and its own paper time, as the table (the opening gave the medians
    # alone, then the MLP's 60 µs inside the PSO call's brackets, as if it were the call's)
    # each time with the SI prefix that fits it, the paper's in its own units (µs alone printed the
    # paper's 0.99 s as "990000" µs, digits it never printed)
    time = r"([\d.]+ [µmn]?s)"
    mlp, paper_mlp, ratio, pso, paper_pso, paper_ratio = _said(
        page, rf"An MLP prediction \({time}; paper {time}\) is {NUMBER}× "
              rf"faster than the brief PSO call \({time}; paper {time}\); the paper's is {NUMBER}×")
    timing = md_table(page, "surrogate_timing").set_index("call")
    assert [[mlp, paper_mlp], [pso, paper_pso]] == timing.loc[
        ["MLP 64-32", "brief PSO call"], ["time (ours)", "paper time"]].to_numpy().tolist()
    # Appendix A: "a single surrogate prediction ... takes 0.06 ms, versus 0.99 s for such a brief
    # pre-screening PSO call ... a 17,000 × speedup"
    assert [paper_mlp, paper_pso, paper_ratio] == ["0.06 ms", "0.99 s", "17000"]
    assert [ratio, paper_ratio] == \
        timing.loc["MLP 64-32", ["ours PSO/this [×]", "paper PSO/this [×]"]].tolist()
    (paper_r2,) = _said(page, rf"; paper {NUMBER} for \|R_z\|\)")
    regression = md_table(page, "surrogate_regression")
    mlp_rz = regression.query("target == '|R_z| [N]' and model == 'MLP 64-32'")
    assert paper_r2 == mlp_rz["paper R²"].item()


def test_the_test1_finding_says_n_and_lambda1_as_their_tables(sim_root):
    page = report_md(sim_root / "test1_bench" / "default")
    n, paper_n, paper_sd = _said(
        page, rf"accepted normal fits give n = {NUMBER} \(paper {NUMBER} ± {NUMBER},")
    claims = md_table(page, "test1_claims").set_index("quantity")
    mean, sd = (claims.loc[f"contact exponent n, accepted fits: {s}"] for s in ("mean", "SD"))
    assert [n, paper_n, paper_sd] == [_first(mean["ours (95%)"]), mean["paper"], sd["paper"]]
    lambda1, paper_lambda1 = _said(page, rf"λ1 = {NUMBER} \(paper {NUMBER}\)")
    table5 = md_table(page, "table5").set_index("parameter")
    row = table5.loc["λ1"]
    assert [lambda1, paper_lambda1] == [_first(row["ours mean (95%)"]), row["paper mean"]]


def test_the_sensitivity_finding_counts_the_boundaries_as_the_claims_table_prints_them(sim_root):
    from graspcampaign.report.studies.sensitivity import BOUNDARIES

    page = report_md(sim_root / "sensitivity" / "default")
    ours = md_table(page, "sensitivity_claims").set_index("quantity")["ours (95%)"]
    intervals = {q: [float(v) for v in re.findall(r"[\d.]+", cell.split(" (")[1])]
                 for q, cell in ours.items() if " (" in cell}
    tested = [pair for pair in BOUNDARIES.values() if all(q in intervals for q in pair)]
    apart = sum(intervals[first][0] > intervals[second][1] for first, second in tested)
    (said,) = _said(page, rf"{NUMBER} of {len(tested)} Fig. 19 boundaries separates? our rates")
    assert int(said) == apart
