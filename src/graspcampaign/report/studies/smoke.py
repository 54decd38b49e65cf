"""Report of ``smoke`` (kind ``mesh_features``): the objects' meshes and sharp features (Sec. 3.1)."""

from __future__ import annotations

import pandas as pd

from graspcampaign.analysis.vocabulary import colour, label, ordered
from graspcampaign.report import style
from graspcampaign.report.document import cols
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Figure, Finding, ReportSpec, Table, Value


def _worst(column: str):
    def value(run: Run) -> int:
        sphere = run.ok.loc[run.ok["shape"] == "sphere", column]
        if not len(sphere):
            raise ValueError("no sphere in this run")
        return int(sphere.max())
    return value


def finding(run: Run) -> str:
    ok = run.ok
    text = (f"{int(ok['watertight'].astype(bool).sum())} of {len(ok)} meshes are closed (watertight) across "
            f"{ok['shape'].nunique()} shapes and {ok['nodes'].nunique()} resolutions; their built node "
            f"counts lie within {ok['node_count_error_pct'].abs().max():.1f}% of the requested ones. ")
    if (ok["shape"] == "sphere").any():
        n = _worst("n_sharp_vertex")(run) + _worst("n_sharp_edge")(run)
        text += ("The sphere has no sharp vertex or edge at any resolution, as the paper states "
                 "(Sec. 3.1)." if n == 0 else f"**Unlike the paper (Sec. 3.1)**, the sphere has "
                 f"sharp features ({n} at the worst resolution).")
    return text


def _meshes(run: Run) -> pd.DataFrame:
    """The executed meshes in the vocabulary's shape order, then by resolution."""
    rank = {s: i for i, s in enumerate(ordered("shape", run.ok["shape"], run.order.get("shape", ())))}
    return run.ok.sort_values(["shape", "nodes"], key=lambda c: c.map(rank) if c.name == "shape" else c)


def _features(run: Run, fig) -> None:
    ax = fig.subplots()
    for i, (column, what) in enumerate((("n_sharp_vertex", "vertices"), ("n_sharp_edge", "edges"))):
        for j, (shape, g) in enumerate(_meshes(run).groupby("shape", sort=False)):
            ax.plot(g["n_nodes"], g[column], marker="os"[i], linestyle="-:"[i],
                    color=colour("shape", shape, j), label=f"{label('shape', shape)}, sharp {what}")
    ax.set(xlabel="mesh nodes [–]", ylabel="sharp features [–]")
    style.legend_below(ax, ncol=2)


SPEC = ReportSpec("smoke", [
    Finding(finding),
    Table("meshes", "Object meshes: requested and built node counts, closure, sharp features and build "
          "time", _meshes, cols("n_nodes", "node_count_error_pct", "n_faces", "watertight", "n_sharp_vertex",
               "n_sharp_edge", "max_vertex_defect_rad", "max_edge_deviation_deg", "build_time_s"),
          by=["shape", "nodes"]),
    Value("sharp vertices on the sphere (worst resolution)", "Sec. 3.1", _worst("n_sharp_vertex"),
          lambda p: p.sphere_sharp_vertices, digits=0),
    Value("sharp edges on the sphere (worst resolution)", "Sec. 3.1", _worst("n_sharp_edge"),
          lambda p: p.sphere_sharp_edges, digits=0),
    Figure("sharp_features", "Sharp vertices and edges per object against mesh resolution", _features,
           (6.4, 4.8)),
])
