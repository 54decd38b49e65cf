"""A records file's account (``campaign.account``): the stored form is the one docs/records.md
describes (values written out here by hand), both forms read back, and every value the tool never
writes refused with a sentence saying how it differs."""

from __future__ import annotations

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from graspcampaign.campaign.account import Account, NotAnAccount, decode, encode, merge

A, B, C = "a-0000000001", "b-0000000002", "c-0000000003"
#: three trials' entries as ``run`` makes them: A two trace tables and a body, B nothing besides
#: its record, C one table and another body
ENTRIES = {A: {"tables": {"trace": 3, "candidates": 50}, "body": "body000001"}, B: {},
           C: {"tables": {"trace": 1}, "body": "body000000"}}


def test_the_stored_form_is_one_entry_per_row_with_the_body_ids_listed_once():
    """Rows B, A, C, A (A recorded twice: each row takes its entry): every list in row order, the
    body ids sorted and referred to by place; no trial id written."""
    raw = encode(Account.from_entries(ENTRIES), [B, A, C, A])
    assert json.loads(raw) == {"v": 2, "tables": {"trace": [0, 3, 1, 3], "candidates": [0, 50, 0, 50]},
                               "bodies": ["body000000", "body000001"], "body": [None, 1, 0, 1]}
    assert A.encode() not in raw
    assert raw == (b'{"bodies":["body000000","body000001"],"body":[null,1,0,1],'
                   b'"tables":{"candidates":[0,50,0,50],"trace":[0,3,1,3]},"v":2}')


def test_a_file_whose_trials_stored_nothing_else_writes_neither_table_nor_body():
    """Trials not in the account (a file of records stored before it was kept, compacted with
    newer ones) stored nothing besides their records, as far as it says."""
    assert json.loads(encode(Account.from_entries({B: {}}), [B, A])) == {"v": 2, "tables": {}}


def test_each_form_is_read_back_as_what_each_trial_stored():
    """Version 2 as written, version 1 (the mapping of trial ids written before) as it was: an
    entry of a trial the file does not record left out."""
    ids = [C, A, B]
    assert decode(encode(Account.from_entries(ENTRIES), ids), ids, frozenset(ids)).entries() == {
        C: ENTRIES[C], A: ENTRIES[A], B: {}}
    old = json.dumps({**ENTRIES, "gone-0000000009": {"tables": {"trace": 2}}}).encode()
    read = decode(old, [A, B, C], frozenset({A, B, C}))
    assert read.entries() == ENTRIES
    assert read.traces() == {"candidates": {A: 50}, "trace": {A: 3, C: 1}}
    assert read.used() == {A: "body000001", C: "body000000"}


def test_a_row_without_a_trial_id_is_no_trial_of_the_account():
    raw = b'{"v":2,"tables":{"trace":[2,5]}}'
    assert decode(raw, [None, A], frozenset({A})).entries() == {A: {"tables": {"trace": 5}}}


def test_a_compaction_keeps_every_trial_of_its_files_in_the_merged_rows():
    first = Account.from_entries({A: ENTRIES[A]})
    second = Account.from_entries({C: ENTRIES[C], B: {}})
    both = merge([first, second])
    assert both.entries() == {A: ENTRIES[A], C: ENTRIES[C], B: {}}
    assert json.loads(encode(both, [A, B, C]))["tables"] == {"candidates": [50, 0, 0],
                                                              "trace": [3, 0, 1]}


_ENTRY = st.fixed_dictionaries({}, optional={
    "tables": st.dictionaries(st.sampled_from(["trace", "candidates", "belief_none"]),
                              st.integers(1, 10**6), min_size=1),
    "body": st.sampled_from(["body000000", "body000001", "body000002"])})


@given(st.dictionaries(st.from_regex(r"[a-z]{1,4}-[0-9a-f]{10}", fullmatch=True), _ENTRY),
       st.randoms())
def test_what_is_written_is_read_back_in_any_row_order(entries, random):
    ids = list(entries)
    random.shuffle(ids)
    read = decode(encode(Account.from_entries(entries), ids), ids, frozenset(ids))
    assert read.entries() == entries and list(read.trials) == ids


WHY = [
    (b'{"pear', "it is not JSON"),
    (b"[1, 2]", "it is no mapping of trial ids"),
    (b'{"v": 3, "tables": {}}', "it is of version 3, not 2"),
    (b'{"v": 2.0, "tables": {}}', "it is of version 2.0, not 2"),
    (b'{"v": 2, "tables": {}, "trials": []}',
     "it has a key 'trials', not one of v, tables, bodies and body"),
    (b'{"v": 2, "tables": [3, 3]}', "tables is [3, 3], not a mapping of trace table names"),
    (b'{"v": 2, "tables": {"trace": [3, 3]}}', "table trace has 2 values for the file's 3 rows"),
    (b'{"v": 2, "tables": {"trace": 3}}',
     "table trace is 3, not a list of one value per row of the file"),
    (b'{"v": 2, "tables": {"trace": [3, -1, 3]}}',
     "table trace has -1 at row 1, not a whole number of 0 or more"),
    (b'{"v": 2, "tables": {"trace": [3, "3", 3]}}',
     'table trace has "3" at row 1, not a whole number of 0 or more'),
    (b'{"v": 2, "tables": {"trace": [3, true, 3]}}',
     "table trace has true at row 1, not a whole number of 0 or more"),
    (b'{"v": 2, "tables": {}, "bodies": ["body000000"]}', "it has bodies without body"),
    (b'{"v": 2, "tables": {}, "body": [0, 0, 0]}', "it has body without bodies"),
    (b'{"v": 2, "tables": {}, "bodies": [7], "body": [0, 0, 0]}',
     "bodies is [7], not a list of body ids"),
    (b'{"v": 2, "tables": {}, "bodies": ["body000000"], "body": [0, 1, null]}',
     "body has 1 at row 1, not null or a place in its 1 body"),
    (b'{"v": 2, "tables": {}, "bodies": ["body000000"], "body": [0]}',
     "body has 1 value for the file's 3 rows"),
    # version 1, as the release before read it
    (b'{"a-0000000001": {"tables": {"trace": 0}}}',
     'trial a-0000000001 has {"tables": {"trace": 0}}, not its rows per trace table (whole '
     "numbers above 0) and the body id of its preparation"),
    (b'{"a-0000000001": {"body": 7}}',
     'trial a-0000000001 has {"body": 7}, not its rows per trace table (whole numbers above 0) '
     "and the body id of its preparation"),
]


@pytest.mark.parametrize(("raw", "why"), WHY)
def test_a_value_the_tool_never_writes_is_refused_saying_how_it_differs(raw, why):
    with pytest.raises(NotAnAccount) as refused:
        decode(raw, [A, B, C], frozenset({A, B, C}))
    assert str(refused.value) == why
