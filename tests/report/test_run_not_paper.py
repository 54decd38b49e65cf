"""What a report says the run did comes from the run, never from its paper values.

A sentence, caption or figure line that states a setting of the run (a command, a probability, a
commanded level) once read the paper's value: wrench_balance's opening said "Under the fixed 70 N grip
command" for a run given ``paper.finger_force_command_n=70``, whose fingers closed at 65 N. Found by
perturbing every numeric paper field of every study's reference run and diffing its report; each place
found is pinned here twice: the run's part does not move when the paper field does, and it equals what
the run used, read from the records or the code that ran it (not from the report).
"""

from __future__ import annotations

import dataclasses
import re

import pytest
from matplotlib.colors import to_hex
from synthetic_runs import draw_figure, run_reduced

from graspcampaign.campaign.paper import study_paper
from graspcampaign.campaign.records import RunStore
from graspcampaign.report import style
from graspcampaign.report.build import spec_for
from graspcampaign.report.document import Document, Figure, Table, Text
from graspcampaign.report.render import Run, render

#: the three runs, reduced further than the report tests' shared tree (~10 s together, so these stay in
#: the fast suite): Test 1 on one specimen with a two-iteration PSO, Test 2 at the fraction that keeps
#: Fig. 30's trial (a stable proposed natural-friction sphere grasp)
REDUCED = {
    "wrench_balance": [],
    "test1_bench": ["params.materials=[gel]", "params.specimens=[1]", "params.pso_restarts=1",
                    "params.pso_particles=4", "params.pso_iterations=2", "params.pso_max_reruns=0"],
    "test2_grasp": ["params.fraction=0.08"],
}


@pytest.fixture(scope="module")
def root(tmp_path_factory):
    """A results root holding the :data:`REDUCED` runs, run by the engine (not reported)."""
    return run_reduced(tmp_path_factory.mktemp("run_not_paper") / "results", REDUCED)


def _run(root, study: str, **paper) -> Run:
    """The reduced run of ``study`` with ``paper`` replacing fields of its paper values (not rendered:
    a reader that needs the report's tables renders them)."""
    store = RunStore(root / study / "default")
    values = dataclasses.replace(study_paper(study), **paper)
    return Run(store.read().to_pandas(), store.check(), values, store)


def _item(study: str, kind: type, name: str):
    return next(i for i in spec_for(study, "").items if isinstance(i, kind) and i.name == name)


def _caption(study: str, name: str):
    caption = _item(study, Table, name).caption
    return lambda run: caption(run) if callable(caption) else caption


def _lines(study: str, name: str):
    """The figure's lines other than the paper's (drawn in ``style.PAPER``): label and points."""
    item = _item(study, Figure, name)

    def read(run: Run) -> list:
        fig = draw_figure(run, item.draw, item.size)
        return [(i, ln.get_label(), ln.get_xydata().round(9).tolist()) for i, ax in enumerate(fig.axes)
                for ln in ax.lines if to_hex(ln.get_color()) != to_hex(style.PAPER)]
    return read


def _finding(study: str):
    spec = spec_for(study, "")

    def read(run: Run) -> list[str]:  # an opening reads the tables: every item rendered first
        return [b.markdown for b in render(spec, run, Document("", run.source, [])).blocks
                if isinstance(b, Text) and b.kind == "finding"]
    return read


#: (study, paper field, the part of its report that states what the run did)
RUN_SIDE = [
    ("wrench_balance", "finger_force_command_n", _finding("wrench_balance")),
    ("test1_bench", "events_aborted", _caption("test1_bench", "test1_counts")),
    ("test1_bench", "events_commanded", _caption("test1_bench", "test1_counts")),
    ("test2_grasp", "lift_height_mm", _lines("test2_grasp", "fig30_representative_grasp")),
]


@pytest.mark.parametrize(("study", "field", "read"), RUN_SIDE, ids=[f"{s}-{f}" for s, f, _ in RUN_SIDE])
def test_what_the_run_did_does_not_follow_a_paper_value(root, study, field, read):
    value = getattr(study_paper(study), field)
    moved = type(value)(value * 1.37 if isinstance(value, float) else round(value * 1.37))
    assert read(_run(root, study, **{field: moved})) == read(_run(root, study))


def test_test1_counts_caption_gives_the_virtual_benchs_abort_probability(root):
    # the caption said "p = 61/19229 per attempt" from the paper's events_aborted/events_commanded;
    # the bench draws its aborts with its own SensorParams.abort_rate (the test1 kind passes none)
    from graspcampaign.core.bench import SensorParams

    run = _run(root, "test1_bench", events_aborted=7, events_commanded=100)
    assert run.source == "virtual"
    got = re.search(r"\(p = (\d+)/(\d+) per attempt, a random realisation\)", _caption(
        "test1_bench", "test1_counts")(run))
    assert got is not None and "7/100" not in got.group(0)
    # the records hold each event's aborted attempts (a realisation), not the probability drawn with
    assert int(got.group(1)) / int(got.group(2)) == pytest.approx(SensorParams().abort_rate, rel=1e-12)
    measured = Run(run.records.assign(source="measured"), {**run.manifest, "source": "measured"},
                   run.paper, run.store)
    assert measured.source == "measured"  # a rig's aborts are its own, drawn with no probability
    assert "per attempt" not in _caption("test1_bench", "test1_counts")(measured)


def test_fig30_draws_the_protocols_lift_not_the_papers(root):
    # Fig. 30's "lift height, commanded" level and its lift phase's end read paper.lift_height_mm; the
    # records hold no lift height, and the rig commands its protocol's LIFT_HEIGHT_MM whatever the paper
    # block says
    from graspcampaign.report.studies.test2 import CLOSING_TRAVEL_MM, representative
    from graspcampaign.rig.protocol_design import LIFT_HEIGHT_MM

    run = _run(root, "test2_grasp", lift_height_mm=80.0)
    lift = next(pts for _, what, pts in _lines("test2_grasp", "fig30_representative_grasp")(run)
                if what == "lift height, commanded [mm]")
    trial = run.records.set_index("trial_id").loc[representative(run)["trial_id"]]
    t0 = CLOSING_TRAVEL_MM / trial["closing_speed_mm_per_s"]
    t1 = t0 + LIFT_HEIGHT_MM / trial["lift_speed_mm_per_s"]
    expected = [0, 0, t0, 0, t1, LIFT_HEIGHT_MM, t1 + trial["hold_s"], LIFT_HEIGHT_MM]
    assert [v for point in lift for v in point] == pytest.approx(expected, abs=1e-8)
