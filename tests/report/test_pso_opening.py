"""The pso_repeatability opening: which parameters it calls pinned to a bound of the search box.

A synthetic run with the kind's record columns (docs/records.md) is reported as the CLI does; the
expected set is read from the records (a constant value and ``at_bound_*`` true in every run).
"""

from __future__ import annotations

import re

from synthetic_runs import make_run, ok_records, report_md

from graspcampaign.analysis.vocabulary import label
from graspcampaign.report.build import build_reports

FLAGS = {"lambda1": "lambda1", "lambda2": "lambda2", "n_exp": "n", "b": "b", "k": "k", "c": "c"}


def test_a_constant_inside_the_search_box_is_not_called_pinned_to_a_bound(tmp_path):
    """n = 0.7 in every run, never on a bound, was listed with λ1 (on its bound in every run) under
    "Pinned in every run (CV 0, a bound of the search box)": a zero spread is not a bound."""
    def outputs(factors, rng):
        return {"lambda1": 1.5, "lambda2": rng.uniform(0.3, 1.4), "n_exp": 0.7, "b": rng.uniform(0.2, 1.5),
                "k": rng.uniform(0.05, 0.3), "c": rng.uniform(5e-4, 0.01), "best_cost": rng.uniform(0, 1),
                "n_evaluations": 120, **{f"at_bound_{f}": f == "lambda1" for f in FLAGS.values()}}

    store = make_run(tmp_path, "pso_repeatability", "pso_repeatability", {"shape": ["sphere"]}, seeds=5,
                     paper=None, outputs=outputs)
    build_reports(["pso_repeatability"], root=tmp_path)
    ok = ok_records(store)
    on_bound = {label("parameter", p) for p, flag in FLAGS.items()
                if ok[p].nunique() == 1 and ok[f"at_bound_{flag}"].all()}
    md = report_md(store)
    pinned = re.search(r"Pinned in every run \(CV 0, a bound of the search box\): (.+?)\.(?:\s|$)", md)
    assert {part.rsplit(" at ", 1)[0] for part in pinned.group(1).split(", ")} == on_bound == {"λ1"}
