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


def test_a_waveform_file_far_beyond_any_the_protocol_makes_is_refused_unread(results, tmp_path):
    # the old code read it whole: an 83 MB file took 9 s and 0.87 GB before its refusal, and a file
    # of several GiB would fill the memory; the full schedule in one CSV is 1.7-3.9 GiB
    # (benchmarks/test1_file_size.py), the limit twice the larger
    huge = tmp_path / "waves.csv"
    with huge.open("wb") as out:  # sparse: 9 GiB on the file system, none of it written
        out.truncate(9 * 2**30)
    refused(results, ["ingest", "test1_bench", huge, *T1, "--root", results],
            "waves.csv: the file is 9 GiB, and a file of Test 1 waveforms is at most 8 GiB (all 19,168 "
            "events of the full schedule in one CSV are 3.9 GiB with every float64 digit, 1.7 GiB as the "
            "sensors resolve them); check it is the right file.", seconds=10)


def test_a_waveform_file_just_over_the_limit_is_not_said_to_be_at_it(results, tmp_path):
    # a size is rounded up: 8 GiB and one byte is not "8 GiB, and ... at most 8 GiB"
    huge = tmp_path / "waves.csv"
    with huge.open("wb") as out:
        out.truncate(8 * 2**30 + 1)
    refused(results, ["ingest", "test1_bench", huge, *T1, "--root", results],
            "waves.csv: the file is 8.1 GiB, and a file of Test 1 waveforms is at most 8 GiB (all 19,168 "
            "events of the full schedule in one CSV are 3.9 GiB with every float64 digit, 1.7 GiB as the "
            "sensors resolve them); check it is the right file.", seconds=10)
