"""A results tree of every ported simulation study, run reduced by the engine and reported once.

Shared by the inventory test (every table and figure each report produces) and the HTML test
(every page parsed, its tables equal to the CSV tables), so the runs are paid for once.
"""

from __future__ import annotations

import pytest

#: Reduced designs: every study of the spec path.
REDUCED = {
    "smoke": ["nodes=[144]"],
    "heuristic_weights": ["seeds=2"],
    "wrench_balance": [],
    "shapes": [],
    "ablation": ["seeds=1", "shape=[sphere,pear]"],
    "baseline_grid": ["seeds=1", "shape=[sphere,pear]", "mass_kg=[0.4]", "mu=[0.3]"],
    "grip_laws": ["seeds=1", "shape=[sphere,pear]", "mass_kg=[0.2]", "mu=[0.5]"],
    "pso_repeatability": ["seeds=2", "budget=[repeatability]"],
    # both integrators and both presets (issues 13, 17), at short simulated times; a 200-step
    # energy audit (default 2000, 3/4 of this study's cost) still fills every audit column and
    # both step sizes' rows of the energy_audit table the report draws
    "gravity_settle": ["nodes=[144]", "+params.settle_t_max_s=0.2", "+params.audit_steps=200"],
    # 0.1 s: the fingers touch at 0.05 s (1 mm gap at 20 mm/s), close by 0.086 s and lift, so the
    # contact path is covered (at 0.03 s no finger touched); measured ~5 s for the four trials either way
    "friction_mass": ["nodes=[144]", "mu=[0.1,0.5]", "mass_kg=[0.4]", "+params.t_max_s=0.1"],
    "sensitivity": ["params.levels=2", "seeds=1"],
    "mesh_resolution": ["seeds=1", "params.resolutions=[144,390]", "params.timing_repeats=1",
                        "params.budget_shapes=[sphere]", "params.budget_nodes=[144]",
                        "params.budget_seeds=1", "params.budgets=[1,30]",
                        "params.baseline_shapes=[sphere]", "params.baseline_masses_kg=[0.4]",
                        "params.baseline_mus=[0.3]", "params.baseline_seeds=1"],
    "surrogate": ["seeds=16"],
    # virtual rig, both belief readings; whole matched cells are kept, so small fractions still
    # pair every planner (a few Test 3 levels, e.g. the 1.8 W impulse, are then absent)
    "test2_grasp": ["params.fraction=0.08"],
    "test3_disturbance": ["params.fraction=0.1"],
    # Test 1 on the virtual bench: one family, a training and a held-out specimen, every block,
    # split and environment (772 events), and a short PSO so the finalize tables exist
    "test1_bench": ["params.materials=[gel]", "params.specimens=[1,11]", "params.pso_restarts=3",
                    "params.pso_particles=12", "params.pso_iterations=40", "params.pso_max_reruns=1"],
    # after baseline_grid, its source: two planners of its sphere and pear trials, both presets
    "dynamic_check": ["+factors.planner=[heuristic,centroid]", "+params.t_max_s=0.05"],
}


@pytest.fixture(scope="session")
def reduced() -> list[str]:
    """The studies :func:`sim_root` runs, sorted."""
    return sorted(REDUCED)


@pytest.fixture(scope="session")
def sim_root(tmp_path_factory):
    """Root of the reduced runs, reported in every format (tables, md, json, html)."""
    from synthetic_runs import run_reduced

    from graspcampaign.report.build import build_reports

    root = run_reduced(tmp_path_factory.mktemp("sim") / "results", REDUCED)
    batch = build_reports(root=root, formats=["md", "csv", "json", "html"])
    assert batch.failed == []
    return root


@pytest.fixture(scope="session")
def fresh_reports(sim_root, tmp_path_factory):
    """``(root, completed process)``: the ``synthetic_runs.FRESH_STUDIES`` runs' records copied without
    their reports and reported again by ``build_reports`` (SVG figures) in a new interpreter, which
    prints the sklearn modules it holds; written once per session (test_report_reads_only.py,
    test_test1_report.py, which reads its SVG figures). A module using it names ``sim_root`` too, so
    ``--dist loadscope`` puts it in the one scope of the tree it copies (tests/conftest.py)."""
    import os
    import shutil
    import subprocess
    import sys
    from pathlib import Path

    from synthetic_runs import FORMATS, FRESH_STUDIES

    import graspcampaign

    root = tmp_path_factory.mktemp("fresh") / "results"
    for study in FRESH_STUDIES:
        shutil.copytree(sim_root / study / "default", root / study / "default",
                        ignore=shutil.ignore_patterns("report"))
    code = ("import sys\nfrom graspcampaign.report.build import build_reports\n"
            f"batch = build_reports(root={str(root)!r}, formats={FORMATS!r}, figure_format='svg')\n"
            "assert batch.failed == [], batch.failed\n"
            "print(sorted(m for m in sys.modules if m == 'sklearn' or m.startswith('sklearn.')))\n")
    env = {**os.environ, "PYTHONPATH": str(Path(graspcampaign.__file__).parents[1])}  # this tree
    return root, subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                                env=env)


@pytest.fixture
def verdict_calls(monkeypatch):
    """Every call of the one verdict rule (``format.verdict``) while the test runs: its ``ours``, its
    keywords and the words it returned; a verdict cell that no call returned was written by a spec."""
    from graspcampaign.report import format as fmt

    calls, rule = [], fmt.verdict

    def spy(ours, paper, **kw):
        judged = rule(ours, paper, **kw)
        calls.append({"ours": ours, "paper": paper, **kw, "words": judged.words, "word": judged.word})
        return judged

    monkeypatch.setattr(fmt, "verdict", spy)
    return calls
