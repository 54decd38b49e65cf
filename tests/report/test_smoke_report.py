"""smoke report (mesh_features): shape labels from the vocabulary and a legend clear of the data.

A synthetic run with the kind's record columns (docs/records.md) is reported as the CLI does.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from test_studies import SHAPES, make_run

from graspcampaign.analysis.vocabulary import label
from graspcampaign.report.build import build_reports
from graspcampaign.report.render import Run
from graspcampaign.report.studies.smoke import _features


def mesh_outputs(factors: dict, rng: np.random.Generator) -> dict:
    sharp = 0 if factors["shape"] == "sphere" else int(rng.integers(1, 100))
    return {"n_nodes": factors["nodes"], "node_count_error_pct": 0.0, "n_faces": 2 * factors["nodes"] - 4,
            "watertight": True, "n_sharp_vertex": sharp, "n_sharp_edge": sharp, "max_vertex_defect_rad": 0.1,
            "max_edge_deviation_deg": 10.0, "build_time_s": 0.01}


def test_smoke_labels_shapes_and_keeps_its_legend_off_the_lines(tmp_path):
    store = make_run(tmp_path, "smoke", "mesh_features", {"shape": SHAPES, "nodes": [144, 390]}, seeds=1,
                     paper=None, outputs=mesh_outputs)
    build_reports(["smoke"], root=tmp_path)
    md = (store.path / "report" / "report.md").read_text()
    rows = [line.split(" | ")[0].lstrip("| ") for line in md.splitlines()
            if line.startswith("| ") and " | 144 | " in line]
    assert rows == [label("shape", s) for s in SHAPES]  # "rounded cube", not rounded_cube, in order
    fig = plt.figure(figsize=(6.4, 4.8))
    _features(Run(store.read().to_pandas(), {"config": {"factors": {}}}), fig)
    fig.canvas.draw()
    ax = fig.axes[0]
    legend, axes_box = ax.get_legend().get_window_extent(), ax.get_window_extent()
    plt.close(fig)
    assert legend.y1 < axes_box.y0  # below the axes: no line runs through its text
