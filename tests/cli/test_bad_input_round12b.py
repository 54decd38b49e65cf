"""Bad input, round 12 (a fresh adversary): what stored wrong data, lost records or printed a
traceback. Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored
changed (``refused``; for Tests 2-3 on a run that already holds records, ``stored``)."""

from __future__ import annotations

import test_bad_ingest_round10 as round10
from cli_checks import refused

T2, _records = round10.T2, round10._records
stored = round10.stored  # the fixture: a measured Test 2 run holding two trials


def test_a_number_with_an_underscore_in_a_measured_cell_is_refused(stored, tmp_path):
    # the old code stored sf_actual '1_4' as 14.0 (Python's float reads '_' as digit grouping)
    frame = _records(tmp_path, slice(2, 4)).astype({"sf_actual": object})
    frame.loc[1, "sf_actual"] = "1_4"
    frame.to_csv(tmp_path / "day2.csv", index=False)
    refused(stored, ["ingest", "test2_grasp", tmp_path / "day2.csv", *T2, "--root", stored],
            "day2.csv, row 2, column 'sf_actual': value '1_4' is not a number.")
