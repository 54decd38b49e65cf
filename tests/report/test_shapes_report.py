"""The shapes report and the fingertip radius the quasi-static reports judge depths against: the
validity gate's counts and Fig. 15's marks, from the records (split from
``test_quasi_static_report.py``)."""

from __future__ import annotations

import pandas as pd
import pytest
from synthetic_runs import SHAPES, caption, make_run, ok_records, quasi_static_outputs, read_table, report_md

from graspcampaign.analysis.vocabulary import label
from graspcampaign.report import format as fmt
from graspcampaign.report.build import build_reports


def test_shapes_table_checks_and_fig15_mark_contacts_beyond_the_fingertip_radius(tmp_path):
    """A trial with a contact deeper than r = 5 mm (valid_geometry false) fails the gate whatever its
    first failing check: counted per shape, out of the δmax median, said in the failure-check
    caption, hatched in Fig. 15, whose panel (c) draws τ_T (the rounded cube fails on torque)."""
    import json

    import matplotlib.pyplot as plt
    from synthetic_runs import make_run

    from graspcampaign.campaign.paper import study_paper
    from graspcampaign.report.render import Run
    from graspcampaign.report.studies import quasi_static as report

    def outputs(factors, rng):
        out = quasi_static_outputs(factors, rng)
        shape = factors["shape"]
        deep = shape in ("sphere", "pear") or (shape == "ellipsoid" and rng.random() < 0.5)
        out.update(success=False, failure_check="torque" if shape == "rounded_cube" else "residual",
                   success_unbounded=False, valid_geometry=not deep,
                   delta_max_mm=float(rng.uniform(6, 20) if deep else rng.uniform(0.5, 4.5)))
        return out

    store = make_run(tmp_path, "shapes", "quasi_static",
                     {"shape": SHAPES, "mass_kg": [0.4], "mu": [0.3], "planner": ["heuristic"]},
                     seeds=4, paper=None, outputs=outputs)
    build_reports(["shapes"], root=tmp_path)
    ok = ok_records(store)
    table = read_table(store, "shapes").set_index("shape")
    deep = ~ok["valid_geometry"].astype(bool)
    assert table["beyond_radius"].to_dict() == deep.groupby(ok["shape"]).sum().to_dict()
    physical = ok[~deep].groupby("shape")["delta_max_mm"].median().reindex(table.index)
    pd.testing.assert_series_equal(table["delta_max_mm"], physical, check_names=False)
    assert table.loc["sphere", "delta_max_mm"] != table.loc["sphere", "delta_max_mm"]  # none: nan
    assert (f"{int(deep.sum())} of {len(ok)} trials have a contact deeper than r = 5 mm"
            in caption(store, "failure_checks"))
    manifest = json.loads(store.manifest_path.read_text())
    run = Run(store.read().to_pandas(), manifest, study_paper("shapes"))
    run.tables["shapes"] = table.reset_index()
    fig = plt.figure()
    report.fig15(run, fig)
    torque_axis = fig.axes[2]
    lines = {round(float(line.get_ydata()[0]), 6) for line in torque_axis.get_lines()}
    hatched = [bool(p.get_hatch()) for p in torque_axis.patches]
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    plt.close(fig)
    assert manifest["config"]["evaluator"]["tau_t_nm"] in lines
    assert hatched == (table["beyond_radius"] > 0).tolist()
    assert any("τ_T" in t for t in legend) and any("deeper than r" in t for t in legend)


def test_shapes_finding_names_another_failing_check_and_counts_deep_contacts_from_the_records(tmp_path):
    """The opening names the shapes whose outcome differs from the paper's (each shape's checks are
    table shapes', not restated); the SI explanation (contacts deeper than r, released contacts) is
    given with the records' counts, and not at all on a run without them (it was printed whatever the
    run held)."""
    import json

    from graspcampaign.campaign.paper import study_paper
    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.quasi_static import shapes_finding

    def finding(deep_shapes):
        def outputs(factors, rng):
            out = quasi_static_outputs(factors, rng)
            deep = factors["shape"] in deep_shapes
            return {**out, "success": False, "failure_check": "residual", "valid_geometry": not deep,
                    "n_released": int(deep), "delta_max_mm": 8.0 if deep else 2.0}

        root = tmp_path / "-".join(deep_shapes or ["none"])
        store = make_run(root, "shapes", "quasi_static",
                         {"shape": SHAPES, "mass_kg": [0.4], "mu": [0.3], "planner": ["heuristic"]},
                         seeds=2, paper=None, outputs=outputs)
        build_reports(["shapes"], root=root)
        manifest = json.loads(store.manifest_path.read_text())
        run = Run(store.read().to_pandas(), manifest, study_paper("shapes"))
        run.tables["shapes"] = read_table(store, "shapes")
        return shapes_finding(run), ok_records(store)

    text, ok = finding([])
    paper = study_paper("shapes")
    n = int((ok["shape"] == "handle").sum())
    assert paper.failure_check["handle"] == "slip" and paper.failure_check["ellipsoid"] == "residual"
    differ = [label("shape", s) for s in SHAPES if paper.success[s]]  # every trial fails here
    ours = int(ok.groupby("shape")["success"].mean().ge(0.5).sum())
    papers = sum(map(bool, paper.success.values()))
    assert text.startswith(f"Ours succeeds on {ours} of {len(SHAPES)} shapes (on at least half of a "
                           f"shape's trials; {len(ok)} trials), the paper on {papers} (Fig. 15); "
                           f"{len(SHAPES) - len(differ)} of {len(SHAPES)} reach the paper's outcome; "
                           f"ours differs on {fmt.listed(differ)} (each shape's first failing "
                           "checks: table shapes).")
    assert "ours residual" not in text and f"×{n}" not in text  # table shapes' "ours: checks" column
    assert "deeper than r" not in text and "SPEC §8" not in text and "released" not in text
    text, ok = finding(["sphere", "pear"])
    deep = int(ok["shape"].isin(["sphere", "pear"]).sum())
    assert (f"{deep} of {len(ok)} trials have a contact deeper than r = 5 mm: in SI the paper's contact "
            f"constants cannot carry the object at a sane indentation; Algorithm 2's sign step released a "
            f"contact in {deep} of {len(ok)} trials (SPEC §8;") in text


def test_shapes_table_counts_depths_beyond_the_radius_in_records_without_the_gate(tmp_path):
    """Records written before the validity gate have no ``valid_geometry``: a trial is still beyond
    the fingertip radius when its δmax exceeds r (the shapes table counted none of them)."""
    def outputs(factors, rng):
        out = quasi_static_outputs(factors, rng)
        out.pop("valid_geometry")
        deep = factors["shape"] in ("sphere", "pear")
        return {**out, "delta_max_mm": float(rng.uniform(6, 20) if deep else rng.uniform(0.5, 4.5))}

    store = make_run(tmp_path, "shapes", "quasi_static",
                     {"shape": SHAPES, "mass_kg": [0.4], "mu": [0.3], "planner": ["heuristic"]},
                     seeds=6, paper=None, outputs=outputs)
    build_reports(["shapes"], root=tmp_path)
    ok = ok_records(store)
    assert "valid_geometry" not in ok
    deep = ok["delta_max_mm"] > 5.0  # Table 2's r = 5 mm: the run's config names no other
    table = read_table(store, "shapes").set_index("shape")
    assert deep.sum() > 0
    assert table["beyond_radius"].to_dict() == deep.groupby(ok["shape"]).sum().to_dict()


def test_run_radius_reads_the_model_config_and_defaults_to_table_2():
    from graspcampaign.report.render import Run

    configured = Run(pd.DataFrame(), {"config": {"model": {"fingertip_radius_m": 4e-3}}})
    assert configured.radius_mm == pytest.approx(4.0)
    assert Run(pd.DataFrame(), {"config": {}}).radius_mm == 5.0  # Table 2's fingertip radius


def test_design_limit_and_failure_checks_count_the_trials_deeper_than_the_run_radius():
    """The spec items themselves split off the trials deeper than the run's fingertip radius (a
    study once had to wrap them for it): counted from the records with pandas."""
    from graspcampaign.report.render import Run
    from graspcampaign.report.spec import DesignLimit, FailureChecks

    records = pd.DataFrame({"status": ["ok"] * 6 + ["error"], "planner": ["a"] * 4 + ["b"] * 3,
                            "delta_max_mm": [0.5, 3.9, 4.1, 900.0, 2.0, 4.5, 50.0],
                            "success": [True, False, False, False, True, False, None],
                            "failure_check": ["none", "slip", "residual", "residual", "none", "torque",
                                              None]})
    run = Run(records, {"config": {"model": {"fingertip_radius_m": 4e-3}}})
    [limit] = DesignLimit(["planner"]).render(run)
    ok = records[records["status"] == "ok"]
    deep = ok["delta_max_mm"] > 4.0
    assert limit.frame.set_index("planner")["beyond_radius"].to_dict() == \
        deep.groupby(ok["planner"]).sum().to_dict()
    assert limit.frame.set_index("planner").loc["a", "delta_max_max_mm"] == 3.9  # δmax ≤ r only
    assert "δmax > r (non-physical)" in [c.label for c in limit.cols] and "r = 4 mm" in limit.caption
    [checks] = FailureChecks(["planner"]).render(run)
    assert f"{int(deep.sum())} of {len(ok)} trials have a contact deeper than r = 4 mm" in checks.caption


def test_a_shape_that_succeeds_on_half_its_trials_counts_as_succeeding(tmp_path):
    """The opening counts a shape as ours succeeding "on at least half of a shape's trials": the
    sphere here succeeds on 1 of its 2 trials, the ellipsoid on both, the others on none."""
    calls: dict[str, int] = {}

    def outputs(factors, rng):
        shape = factors["shape"]
        calls[shape] = calls.get(shape, 0) + 1
        won = shape == "ellipsoid" or (shape == "sphere" and calls[shape] == 1)
        return {**quasi_static_outputs(factors, rng), "success": won,
                "failure_check": "none" if won else "slip"}

    store = make_run(tmp_path, "shapes", "quasi_static",
                     {"shape": SHAPES, "mass_kg": [0.4], "mu": [0.3], "planner": ["heuristic"]},
                     seeds=2, paper=None, outputs=outputs)
    build_reports(["shapes"], root=tmp_path)
    assert ok_records(store).groupby("shape")["success"].sum().to_dict() == {
        shape: {"sphere": 1, "ellipsoid": 2}.get(shape, 0) for shape in SHAPES}
    opening = "Ours succeeds on 2 of 5 shapes (on at least half of a shape's trials; 10 trials)"
    assert opening in report_md(store)
