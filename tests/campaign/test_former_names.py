"""campaign.former_names: a column's former name read under its current name."""

from __future__ import annotations

import pyarrow as pa
import pytest

from graspcampaign.campaign.former_names import current_names, renamed

# ----------------------------------------------------------------------------- current_names


def test_a_former_name_is_renamed_in_its_place():
    table = pa.table({"a": [1, 2], "exponent_n": [0.4, 0.5], "b": ["x", "y"]})
    out = current_names(table, {"exponent_n": "n_exp", "shifted_m": "shifted_m_exp"})
    assert out.column_names == ["a", "n_exp", "b"]
    assert out.column("n_exp").to_pylist() == [0.4, 0.5]


def test_both_names_become_one_column_no_value_lost():
    # a compacted file of shards written before and after the rename (a resumed run)
    table = pa.table({"slip_margin_ratio": [None, 0.8, None], "x": [1, 2, 3],
                      "slip_margin_n": [0.3, None, -0.2]})
    out = current_names(table, {"slip_margin_n": "slip_margin_ratio"})
    assert out.column_names == ["slip_margin_ratio", "x"]
    assert out.column("slip_margin_ratio").to_pylist() == [0.3, 0.8, -0.2]
    # a current column with no type of its own (all missing) takes the former's values and type
    table = pa.table({"n_exp": pa.nulls(2), "exponent_n": pa.array([1, 2], pa.int32())})
    out = current_names(table, {"exponent_n": "n_exp"})
    assert out.column_names == ["n_exp"] and out.column("n_exp").type == pa.int32()


def test_a_table_without_former_names_is_unchanged():
    table = pa.table({"slip_margin_n": [1.5], "slip_margin_ratio": [0.7]})
    assert current_names(table, renamed("quasi_static")).equals(table)


@pytest.mark.parametrize("kind", ["quasi_static", "wrench_balance", "pso_repeatability",
                                  "sensitivity"])
def test_a_newton_slip_margin_keeps_its_name(kind):
    """The quasi-static kinds' ``slip_margin_n`` is min_j f_n,j (μ − |η|) in newtons; mapping it
    onto their ``slip_margin_ratio`` would overwrite the ratio."""
    assert "slip_margin_n" not in renamed(kind)
