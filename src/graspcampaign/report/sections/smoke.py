"""Report section for ``mesh_features`` (the smoke study)."""

from __future__ import annotations

import pandas as pd

from graspcampaign.report.document import Report


def section(report: Report, records: pd.DataFrame, manifest: dict, store) -> None:
    """Mesh table: requested vs built node counts, closure, sharp features, build time."""
    ok = records[records["status"] == "ok"]
    cols = ["shape", "nodes", "n_nodes", "node_count_error_pct", "n_faces", "watertight",
            "n_sharp_vertex", "n_sharp_edge", "max_vertex_defect_rad", "max_edge_deviation_deg",
            "build_time_s"]
    table = ok[[c for c in cols if c in ok]].sort_values(["shape", "nodes"])
    report.table("meshes", table.reset_index(drop=True),
                 "Object meshes: requested and built node counts, closure and sharp features")
    sphere = ok[ok["shape"] == "sphere"]
    if len(sphere):
        rows = [
            {"quantity": "sharp vertices on the sphere", "paper": 0,
             "ours": int(sphere["n_sharp_vertex"].max()),
             "difference": int(sphere["n_sharp_vertex"].max()), "n": len(sphere),
             "source": "Sec. 3.1"},
            {"quantity": "sharp edges on the sphere", "paper": 0,
             "ours": int(sphere["n_sharp_edge"].max()),
             "difference": int(sphere["n_sharp_edge"].max()), "n": len(sphere),
             "source": "Sec. 3.1"},
        ]
        report.table("paper_comparison", pd.DataFrame(rows), "Beside the paper")
