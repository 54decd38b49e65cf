"""Record columns renamed since runs were stored: the former names, per trial kind and stored
part, and their mapping to the current ones when a run is read.

A stored file keeps the names it was written with (its digest is of its values under them, so a
renamed column is not a damaged file). Every read for reports, ``status`` and the API goes through
:meth:`graspcampaign.campaign.records.RunStore.read`, which gives each file's columns their
current names here: a run stored before a rename reads as one stored after it. A run resumed with
``--allow-drift`` across a rename holds the former name in its older shards and the current one in
the newer (a compacted file of both holds both columns, each missing where the other is set);
the two become one column.

A renamed *factor* (:data:`FORMER_FACTORS`) is also a name in the study config and in the hash of
each trial's id and random stream: a stored run keeps its config, and ``grid.expand`` hashes the
factor under its former name, so the run's trial ids, streams and (read as the current config,
``provenance.config_hash``) config hash are those of a run stored now.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pyarrow on use only: the schema, the grid and `graspcampaign list` import this
    import pyarrow as pa

#: Factors renamed since runs were stored: the former name -> (the current one, what it holds)
#: (docs/decisions.md, "sensitivity's factor b: named as it holds").
FORMER_FACTORS: dict[str, tuple[str, str]] = {
    "b_n_s_per_m": ("b", "the MSD nodal damping in the simulator's internal units, never N·s/m")}
#: The former -> current name of each renamed factor; a stored run's records hold the former.
RENAMED_FACTORS = {former: current for former, (current, _) in FORMER_FACTORS.items()}
#: The current -> former name of each renamed factor: the name trial ids and streams are hashed by.
FIRST_NAMES = {current: former for former, current in RENAMED_FACTORS.items()}

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
    "sensitivity": {"records": {"b_n_s_per_m": "b"}},  # the n_b panel's factor (FORMER_FACTORS)
}


def former_factor(name: str, key: str, typed: str | None = None, fixed: str | None = None) -> str:
    """The sentence refusing ``key``, which names factor ``name`` by its former name (in the
    override ``typed``, if one): the current name, and ``fixed``, the key or override with it."""
    current, holds = FORMER_FACTORS[name]
    rejected = f"; override {typed!r} rejected" if typed else ""
    fixed = fixed or (typed or key).replace(name, current)
    return f"{key} is the former name of factor {current} ({holds}{rejected}); write {fixed}."


def current_config(config: dict) -> dict:
    """A stored run's resolved config (its manifest's) with each renamed factor by its current
    name, in ``factors``, ``zip`` and ``method_factors``: the config the study is now."""
    def name(n):
        return RENAMED_FACTORS.get(n, n) if isinstance(n, str) else n

    out = dict(config)
    if isinstance(config.get("factors"), dict):
        out["factors"] = {name(k): v for k, v in config["factors"].items()}
    if isinstance(config.get("zip"), list):
        out["zip"] = [[name(n) for n in g] if isinstance(g, list) else g for g in config["zip"]]
    if isinstance(config.get("method_factors"), list):
        out["method_factors"] = [name(n) for n in config["method_factors"]]
    return out


def renamed(kind: str | None, part: str = "records") -> dict[str, str]:
    """The former -> current column names of part ``part`` of a run of trial kind ``kind`` (none
    for another kind or part)."""
    return FORMER_NAMES.get(kind or "", {}).get(part, {})


def current_names(table: pa.Table, names: Mapping[str, str]) -> pa.Table:
    """Return ``table`` with each former column name of ``names`` (former -> current) replaced by
    the current one, in the former column's place; a table holding both names gets one column
    (the current name's place, the type both fit): the current name's value where it has one, else
    the former's."""
    import pyarrow as pa
    import pyarrow.compute as pc

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
