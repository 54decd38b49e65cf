"""Record columns renamed since runs were stored: the former names, per trial kind and stored
part, and their mapping to the current ones when a run is read.

A stored file keeps the names it was written with (its digest is of its values under them, so a
renamed column is not a damaged file). Every read for reports, ``status`` and the API goes through
:meth:`graspcampaign.campaign.records.RunStore.read`, which gives each file's columns their
current names here: a run stored before a rename reads as one stored after it. A run resumed with
``--allow-drift`` across a rename holds the former name in its older shards and the current one in
the newer (a compacted file of both holds both columns, each missing where the other is set);
the two become one column.
"""

from __future__ import annotations

from collections.abc import Mapping

import pyarrow as pa
import pyarrow.compute as pc

#: Per trial kind and stored part (``records``, ``tables/<name>``, ``summary/<name>``), the former
#: column name -> the current one (docs/decisions.md, "Record columns named by what they hold").
#: The kind and the part decide: ``slip_margin_n`` of the quasi-static kinds is a margin in
#: newtons and keeps its name, and ``n`` is Test 1's exponent in its PSO log only.
FORMER_NAMES: dict[str, dict[str, dict[str, str]]] = {
    "dynamic_grasp": {"records": {"slip_margin_n": "slip_margin_ratio"}},
    "dynamic_check": {"records": {"slip_margin_n": "slip_margin_ratio"}},
    "test1_bench": {"records": {"exponent_n": "n_exp", "shifted_m": "shifted_m_exp"},
                    "summary/truths": {"exponent_n": "n_exp"},
                    "summary/pso_runs": {"n": "n_exp"}},
    "wrench_balance": {"tables/iterations": {"slip_margin_rel": "slip_margin_ratio"}},
    "test2_grasp": {"records": {"n_believed": "believed_n_exp"},
                    "tables/belief_none": {"n_believed": "believed_n_exp"}},
    "test3_disturbance": {"records": {"n_believed": "believed_n_exp"},
                          "tables/belief_none": {"n_believed": "believed_n_exp"}},
}


def renamed(kind: str | None, part: str = "records") -> dict[str, str]:
    """The former -> current column names of part ``part`` of a run of trial kind ``kind`` (none
    for another kind or part)."""
    return FORMER_NAMES.get(kind or "", {}).get(part, {})


def current_names(table: pa.Table, names: Mapping[str, str]) -> pa.Table:
    """Return ``table`` with each former column name of ``names`` (former -> current) replaced by
    the current one, in the former column's place; a table holding both names gets one column
    (the current name's place, the type both fit): the current name's value where it has one, else
    the former's."""
    for former, current in names.items():
        if former not in table.column_names:
            continue
        i, column = table.column_names.index(former), table.column(former)
        if current not in table.column_names:
            table = table.set_column(i, current, column)
            continue
        j, kept = table.column_names.index(current), table.column(current)
        # the type both fit, as a run's files are unified (int and double: double; a column all
        # missing: the other's type); cast to the current name's type, a former 1.5 failed to read
        common = pa.unify_schemas([pa.schema([(current, kept.type)]), pa.schema([(current, column.type)])],
                                  promote_options="permissive").field(current).type
        merged = pc.coalesce(kept.cast(common), column.cast(common))
        table = table.set_column(j, current, merged).remove_column(i)
    return table
