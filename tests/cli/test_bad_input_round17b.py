"""Bad input, round 17's leftovers: a Test 1 waveform header written as a spreadsheet labels its
columns ('Time (s)') and a waveform file far beyond anything Test 1's protocol makes. Each refusal:
exit 2, one sentence naming the file (and the header's column), nothing stored changed (``refused``)."""

from __future__ import annotations

import pytest
from cli_checks import T1, bench_press, refused

TEMPLATE1 = "(`graspcampaign schedule test1_bench --template` writes a sheet with every column)."
COLUMNS = ("event_id, time_s, displacement_mm, normal_force_n, tangential_force_n, "
           "tangential_displacement_mm, attempt, anomaly, source")


@pytest.mark.parametrize("header", ["Time (s)", "time (s)", "time [s]", "Time(s)"])
def test_a_time_column_labelled_with_its_unit_is_told_it_means_time_s(results, tmp_path, header):
    # the old code named 'Time (s)', 'time (s)' and 'time [s]' without "did you mean 'time_s'?",
    # which 'Time(s)' and 'Displacement (mm)' had: the name alone was too short for the cutoff
    bench_press().rename(columns={"time_s": header}).to_csv(tmp_path / "waves.csv", index=False)
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results],
            "waves.csv, header: a required column is missing: time_s; a column is not part of the sheet: "
            f"'{header}' (did you mean 'time_s'?); its columns are {COLUMNS} {TEMPLATE1}")
