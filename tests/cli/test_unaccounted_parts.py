"""What a run keeps account of, where it keeps none, and a preparation moved aside by the repair.

A run stored before its records kept account of the trials' other parts (trace tables,
preparations) cannot name one of those parts lost: ``status`` says so. ``ingest`` writes the same
account as ``run`` (its trials store nothing else). A preparation the repair would move aside for
a conflict is refused under drifted preparation settings, as a lost one is.

Each case damages its own copy of the finished tiny baseline_grid run (``results``, conftest.py).
"""

from __future__ import annotations

import pyarrow.compute as pc
import pyarrow.parquet as pq
from cli_checks import BG, BG_QUOTED, grid_run, invoke, refused, replaced, resume_grid

from graspcampaign.campaign.records import _write_atomic


def test_a_preparation_moved_aside_for_a_conflict_is_not_computed_again_under_other_settings(results):
    # a second file of prepared/ holding the run's body with other values: the repair moves both
    # aside and the old code computed the body again with the drifted pso.n_particles=3 (exit 0,
    # the recorded trials' identification replaced by another)
    run = grid_run(results)
    (own,) = (run / "prepared").glob("*.parquet")
    table = pq.read_table(own)
    (body,) = table.column("body_id").to_pylist()
    where = table.column_names.index("lambda1")
    other = table.set_column(where, "lambda1", pc.multiply(table.column(where), 2.0))
    _write_atomic(other.replace_schema_metadata(None), run / "prepared" / "compact-0000000000.parquet")
    drifted = ["run", "baseline_grid", *replaced(BG, "pso.n_particles=3"), "--allow-drift",
               "--root", results]
    refused(results, drifted,
            f"run baseline_grid/default at {run} has lost 1 preparation its recorded trials used "
            f"(first body {body}), which this session cannot compute again as they were: they "
            "were computed with the settings the run was started with (pso.n_particles 2 -> 3); "
            f"resume it as started (graspcampaign run baseline_grid {BG_QUOTED} --run default "
            f"--root {results}) to compute them again as they were, or start a new run for this "
            "config (output.run=NAME or --run NAME).")
    # the advice works: resumed as started, both files go aside and the body is computed as the
    # recorded trials used it (seeded by the body alone), the value stored before the damage
    assert resume_grid(results).stderr.count("moved to") == 2
    (again,) = (run / "prepared").glob("*.parquet")
    assert pq.read_table(again).column("lambda1").to_pylist() == table.column("lambda1").to_pylist()
    assert invoke(*drifted).exit_code == 0


def test_a_copy_of_a_preparation_moved_aside_leaves_it_to_a_drifted_run(results):
    # a byte-for-byte copy is a duplicate: moved aside, its body stays in the file it copies, so
    # nothing is computed again and the drifted session runs (as on the old code)
    run = grid_run(results)
    (own,) = (run / "prepared").glob("*.parquet")
    (run / "prepared" / "compact-0000000000.parquet").write_bytes(own.read_bytes())
    kept = own.read_bytes()
    drifted = invoke("run", "baseline_grid", *replaced(BG, "pso.n_particles=3"), "--allow-drift",
                     "--root", results)
    assert drifted.exit_code == 0, drifted.output
    assert drifted.stderr.count("moved to") == 1 and "duplicate" in drifted.stderr
    assert [p.read_bytes() for p in (run / "prepared").glob("*.parquet")] == [kept]
