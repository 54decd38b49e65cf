"""Report section of ``test1_bench``: Tables 4-5 and Figs. 23-26 beside the paper's values.

Built from a reduced engine run (gel and reference silicone, specimens 1 and 11, normal-lab:
568 events) and from specimen 1's events ingested as a measured run (no finalize tables). Numbers
are checked against the rig's summaries of the in-process fits, not against the section's code.
"""

from __future__ import annotations

import pandas as pd
import pytest
from PIL import Image
from statsmodels.stats.proportion import proportion_confint

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.ingest import ingest_files
from graspcampaign.campaign.runner import run_study
from graspcampaign.report.build import build_reports
from graspcampaign.rig import test1 as T

SEED = 701
SELECT = {"materials": ["gel", "silicone_ref"], "specimens": [1, 11],
          "environments": ["normal_lab"]}
OVERRIDES = ["params.materials=[gel,silicone_ref]", "params.specimens=[1,11]",
             "params.environments=[normal_lab]", "params.pso_restarts=3",
             "params.pso_particles=12", "params.pso_iterations=40", "params.pso_max_reruns=1",
             "runner.backend=sequential", "runner.progress=false"]
FIGURES = ("fig23_normal_law", "fig24_tangential", "fig25_relaxation_cycling",
           "fig26_identification")


@pytest.fixture(scope="module")
def reported(tmp_path_factory):
    root = tmp_path_factory.mktemp("t1report")
    study = compose_study("test1_bench", [f"output.root={root}", *OVERRIDES])
    run_study(study)
    schedule = T.test1_schedule(SEED, **SELECT)
    ref = T.run_virtual_bench(schedule, SEED, keep_waveforms=True)
    path = root / "waves.parquet"  # the measured run: specimen 1's events, ingested
    ids = set(schedule.loc[schedule["specimen"] == 1, "event_id"])
    ref.waveforms[ref.waveforms["event_id"].isin(ids)].to_parquet(path, index=False)
    ingest_files(study, [str(path)])
    build_reports(["test1_bench"], root=root, formats=["md", "csv"])
    return root, ref


def _tables(root, run):
    folder = root / "test1_bench" / run / "report"
    return folder, (folder / "report.md").read_text()


def test_report_labels_virtual_rig_data(reported):
    root, _ = reported
    _, text = _tables(root, "default")
    assert "VIRTUAL RIG" in text
    assert "not hardware measurements" in text


def test_table4_is_the_rig_summary_beside_the_paper(reported):
    root, ref = reported
    folder, _ = _tables(root, "default")
    table = pd.read_csv(folder / "tables" / "table4.csv")
    assert table["row"].tolist() == ["ours", "paper", "ours", "paper"]
    ours = table[table["row"] == "ours"].set_index("material")
    want = T.table4(ref.fits, ref.truths).set_index("material")
    for col in ("exponent_n", "k_n_per_mm_n", "f05_n", "mu_s", "mu_k", "k_t_n_per_mm", "rho",
                "tau_s"):
        pd.testing.assert_series_equal(ours[col], want[col], check_names=False, rtol=1e-12)
    paper = table[table["row"] == "paper"].set_index("material")
    assert paper.loc["gel", "exponent_n"] == 0.473 and paper.loc["silicone_ref", "mu_s"] == 0.509
    assert paper.loc["gel", "modulus_kpa"] == 40.1 and paper.loc["gel", "modulus_sd_kpa"] == 6.2


def test_table5_and_transfer_beside_the_paper(reported):
    root, _ = reported
    folder, _ = _tables(root, "default")
    t5 = pd.read_csv(folder / "tables" / "table5.csv").set_index("parameter")
    assert list(t5.index) == ["lambda1", "lambda2", "n", "b", "k", "c"]
    assert t5.loc["n", "paper_mean"] == 0.483 and t5.loc["n", "paper_cv_pct"] == 20.5
    assert t5.loc["lambda1", "simulation_table3"] == 0.332
    assert (t5["n_runs"] >= 3).all()
    transfer = pd.read_csv(folder / "tables" / "transfer.csv")
    paper = transfer.set_index(["quantity", "split"])["paper_pct"]
    assert paper[("normal_force", "unseen_speed")] == 3.64
    assert paper[("flat_to_curved", "flat_to_curved")] == 4.3
    assert set(transfer["split"]) == set(T.SPLITS)


def test_section_7_claims_and_counts(reported):
    root, ref = reported
    folder, _ = _tables(root, "default")
    claims = pd.read_csv(folder / "tables" / "test1_claims.csv").set_index("quantity")
    acc = ref.fits[(ref.fits["block"] == "normal") & ref.fits["accepted"]]
    row = claims.loc["contact exponent n, accepted fits (mean ± SD)"]
    assert row["paper"] == "0.46 ± 0.07"
    assert row["ours_value"] == pytest.approx(acc["exponent_n"].mean(), rel=1e-12)
    ob = T.oblique_summary(ref.fits).groupby("angle_deg")["margin_n"].mean()
    assert claims.loc["slip margin μs fn − ft at 45° (mean, N)", "ours_value"] == pytest.approx(
        ob[45.0], rel=1e-12)
    assert claims.loc["slip margin μs fn − ft at 45° (mean, N)", "paper"] == "-0.16"
    counts = pd.read_csv(folder / "tables" / "test1_counts.csv").set_index("quantity")
    assert counts.loc["completed events (fitted)", "ours"] == 568
    assert counts.loc["commanded attempts", "ours"] == len(ref.attempts)
    assert counts.loc["normal fits accepted", "paper"] == 4888


def test_figures_23_to_26_are_written(reported):
    root, _ = reported
    folder, text = _tables(root, "default")
    for name in FIGURES:
        path = folder / "figures" / f"{name}.png"
        assert path.stat().st_size > 20_000, name
        width, height = Image.open(path).size
        assert width > 1000 and height > 400
        assert f"figures/{name}.png" in text


def test_ingested_run_reports_without_finalize_tables(reported):
    root, _ = reported
    folder, text = _tables(root, "measured")
    assert (folder / "tables" / "table4.csv").exists()
    assert "finalize stage of `graspcampaign run`" in text
    assert "its files carried `source = virtual`" in text  # ingested exports stay labelled
    assert not (folder / "tables" / "table5.csv").exists()
    for name in FIGURES[:3]:
        assert (folder / "figures" / f"{name}.png").exists()


def test_every_figure_is_labelled_virtual_in_its_title(reported, monkeypatch):
    from graspcampaign.report.build import LegacyReport as Report

    root, _ = reported
    titles = {}
    monkeypatch.setattr(Report, "figure", lambda self, name, fig, caption: titles.setdefault(
        name, fig._suptitle.get_text() if fig._suptitle else ""))
    build_reports(["test1_bench"], run="default", root=root, formats=["md"])
    assert sorted(titles) == sorted(FIGURES)
    for name, title in titles.items():
        assert "VIRTUAL RIG data" in title and "not hardware measurements" in title, name


def test_oblique_shares_carry_n_and_wilson_interval(reported):
    root, _ = reported
    folder, _ = _tables(root, "default")
    claims = pd.read_csv(folder / "tables" / "test1_claims.csv").set_index("quantity")
    ours = claims.loc["Coulomb class = measured slip (%)", "ours"]
    k, n = (int(v) for v in ours.split(" = ")[0].split("/"))
    low, high = proportion_confint(k, n, method="wilson")
    assert ours == f"{k}/{n} = {100 * k / n:.1f} % ({100 * low:.1f}–{100 * high:.1f})"
