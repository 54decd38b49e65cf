"""The files of the three hardware protocols, told apart by their columns: what a header that is
not the sheet an ingest reads looks like instead (another test's measured records, or a
commanded sheet from ``graspcampaign schedule``).

A file given to the wrong study's ingest was refused for the columns it lacks and the columns it
has, listed in full (a Test 2 file given to Test 3 "lacks threshold_measured_n, ..."), without
saying what the file is. :func:`other_files` gives each ingest the columns of every other file of
the protocols, for :func:`graspcampaign.rig.measured_file.header_problems` to name the one a
header holds.
"""

from __future__ import annotations

from graspcampaign.rig.protocol_design import (
    SCHEDULE_FRONT,
    STUDY_TEST1,
    STUDY_TEST2,
    STUDY_TEST3,
    TEST2_COLUMNS,
    TEST3_COLUMNS,
)
from graspcampaign.rig.record_schema import schema_for
from graspcampaign.rig.test1_protocol import SCHEDULE_COLUMNS
from graspcampaign.rig.test1_summary import WAVEFORM_COLUMNS

__all__ = ["other_files"]

_TESTS = {STUDY_TEST1: "Test 1", STUDY_TEST2: "Test 2", STUDY_TEST3: "Test 3"}


def _required(study: str) -> tuple[str, ...]:
    """The columns every measured file of ``study`` has."""
    if study == STUDY_TEST1:
        return tuple(WAVEFORM_COLUMNS)
    return tuple(s.name for s in schema_for(study) if not s.optional)


def other_files(study: str) -> list[tuple[str, str, tuple[str, ...]]]:
    """``(what, advice, columns)`` of the files an ingest of ``study`` may be given by mistake:
    the other tests' measured files (advice, from its separator on: the study whose ingest takes
    it), a larger set of columns before a smaller one it holds (Test 3's records hold Test 2's
    columns), then every test's commanded sheet (advice: the template to fill in)."""
    measured = [(f"a {_TESTS[owner]} measured-records file",
                 f"; ingest it with `graspcampaign ingest {owner} FILE`", _required(owner))
                for owner in (STUDY_TEST1, STUDY_TEST3, STUDY_TEST2) if owner != study]
    sheets = [(f"the commanded sheet `graspcampaign schedule {owner}` writes",
               ", not measured records; fill in the template instead", columns)
              for owner, columns in ((STUDY_TEST1, SCHEDULE_COLUMNS),
                                     (STUDY_TEST3, (*SCHEDULE_FRONT, *TEST3_COLUMNS)),
                                     (STUDY_TEST2, (*SCHEDULE_FRONT, *TEST2_COLUMNS)))]
    return measured + sheets
