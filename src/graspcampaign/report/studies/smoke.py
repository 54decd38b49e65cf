"""Report of ``smoke`` (trial kind ``mesh_features``): the five objects and their sharp features.

The paper's only statement here is Sec. 3.1: the sphere has no sharp vertex or edge at 144-1750
nodes (SmokePaper). Every other object is listed with its closure and feature counts.
"""

from __future__ import annotations

from graspcampaign.report.document import cols
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Figure, Finding, ReportSpec, Table, Value


def _sphere(run: Run):
    return run.ok[run.ok["shape"] == "sphere"]


def _worst(column: str):
    def value(run: Run) -> float:
        sphere = _sphere(run)
        if not len(sphere):
            raise ValueError("no sphere in this run")
        return int(sphere[column].max())
    return value


def finding(run: Run) -> str:
    sphere, ok = _sphere(run), run.ok
    closed = int(ok["watertight"].astype(bool).sum())
    text = (f"{closed} of {len(ok)} meshes are closed (watertight) across "
            f"{ok['shape'].nunique()} shapes and {ok['nodes'].nunique()} resolutions; their "
            f"built node counts lie within {ok['node_count_error_pct'].abs().max():.1f}% of the "
            "requested ones. ")
    if len(sphere):
        n = int(sphere["n_sharp_vertex"].max() + sphere["n_sharp_edge"].max())
        text += ("The sphere has no sharp vertex or edge at any resolution, as the paper states "
                 "(Sec. 3.1)." if n == 0 else f"**Unlike the paper (Sec. 3.1)**, the sphere has "
                 f"sharp features ({n} at the worst resolution).")
    return text


def _meshes(run: Run):
    return run.ok.sort_values(["shape", "nodes"])


def _features(run: Run, fig) -> None:
    ax = fig.subplots()
    data = _meshes(run)
    for i, (column, what) in enumerate((("n_sharp_vertex", "sharp vertices"),
                                        ("n_sharp_edge", "sharp edges"))):
        for j, (shape, grp) in enumerate(data.groupby("shape", sort=False)):
            ax.plot(grp["n_nodes"], grp[column], marker="os"[i], linestyle="-:"[i],
                    color=f"C{j}", label=f"{shape}, {what}")
    ax.set_xlabel("mesh nodes [–]")
    ax.set_ylabel("sharp features [–]")
    ax.legend(ncol=2, loc="upper left", fontsize=6.5)


SPEC = ReportSpec("smoke", [
    Finding(finding),
    Table("meshes", "Object meshes: requested and built node counts, closure, sharp features "
          "and build time", _meshes, [
              *cols("shape", "nodes", "n_nodes", "node_count_error_pct", "n_faces",
                    "watertight", "n_sharp_vertex", "n_sharp_edge", "max_vertex_defect_rad",
                    "max_edge_deviation_deg", "build_time_s")]),
    Value("sharp vertices on the sphere (worst resolution)", "Sec. 3.1",
          _worst("n_sharp_vertex"), lambda p: p.sphere_sharp_vertices, digits=0),
    Value("sharp edges on the sphere (worst resolution)", "Sec. 3.1",
          _worst("n_sharp_edge"), lambda p: p.sphere_sharp_edges, digits=0),
    Figure("sharp_features", "Sharp vertices and edges per object against mesh resolution",
           _features, (6.4, 3.4)),
])
