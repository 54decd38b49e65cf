"""Report of ``smoke`` (kind ``mesh_features``): the objects' meshes and sharp features (Sec. 3.1)."""

from __future__ import annotations

import pandas as pd

from graspcampaign.analysis.records import flag
from graspcampaign.analysis.vocabulary import colour, label, ordered
from graspcampaign.core.words import counted
from graspcampaign.report.document import Col, cols
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Figure, Finding, ReportSpec, Table, Value


def _worst(column: str):
    """The function of the run giving the sphere's largest ``column`` (a sharp-feature count) over
    the run's resolutions: a :class:`Value`'s ``value``."""
    def value(run: Run) -> int:
        sphere = run.ok.loc[run.ok["shape"] == "sphere", column]
        if not len(sphere):
            raise ValueError("no sphere in this run")
        return int(sphere.max())
    return value


def finding(run: Run) -> str:
    ok = run.ok
    levels = ok["nodes"].nunique()
    text = (f"{int(flag(ok, 'watertight').sum())} of {len(ok)} meshes are closed (watertight) across "
            f"{ok['shape'].nunique()} shapes and {counted(levels, 'resolution')} (table meshes)")
    if not (ok["shape"] == "sphere").any():
        return text + "."
    n, which = _worst("n_sharp_vertex")(run) + _worst("n_sharp_edge")(run), "any" if levels > 1 else "this"
    return text + (f"; the sphere has no sharp vertex or edge at {which} resolution, as the paper states "
                   "(Sec. 3.1)." if n == 0 else "; **unlike the paper (Sec. 3.1)**, the sphere has sharp "
                   f"features ({n} at the worst resolution).")


def _meshes(run: Run) -> pd.DataFrame:
    """The executed meshes in the vocabulary's shape order, then by resolution."""
    rank = {s: i for i, s in enumerate(ordered("shape", run.ok["shape"], run.order.get("shape", ())))}
    return run.ok.sort_values(["shape", "nodes"], key=lambda c: c.map(rank) if c.name == "shape" else c)


def _caption(run: Run) -> str:
    """The meshes table's caption, with the run's sharpness thresholds (Sec. 3.1)."""
    f = run.config["features"]
    return ("Object meshes: requested (nodes) and built node counts, closure, sharp features and build "
            "time; Sec. 3.1: a vertex is sharp when its angular defect (2π minus the sum of its face angles) "
            f"exceeds {f['vertex_defect_rad']:g} rad, an edge when its dihedral angle departs from 180° by "
            f"more than {f['edge_dihedral_deg']:g}°" + (" (raised on coarse meshes: resolution-aware "
                                                        "thresholds)" if f.get("resolution_aware") else ""))


def _features(run: Run, fig) -> None:
    """Grouped bars (one per shape, labelled with its count) per requested resolution: equal counts
    of different shapes, or of vertices and edges, no longer hide one another's markers."""
    meshes = _meshes(run)
    levels, groups = sorted(meshes["nodes"].unique()), list(meshes.groupby("shape", sort=False))
    width = 0.8 / len(groups)
    panels = (("n_sharp_vertex", "vertices"), ("n_sharp_edge", "edges"))
    for ax, (column, what) in zip(fig.subplots(1, 2, sharey=True), panels, strict=True):
        for j, (shape, g) in enumerate(groups):
            x = [levels.index(n) + (j - (len(groups) - 1) / 2) * width for n in g["nodes"]]
            bars = ax.bar(x, g[column], width, color=colour("shape", shape, j), label=label("shape", shape))
            ax.bar_label(bars, fontsize=7)
        ax.set(xticks=range(len(levels)), xticklabels=[str(n) for n in levels],
               xlabel="requested mesh nodes [–]", title=f"sharp {what}")
        ax.grid(False, axis="x")  # no grid line through a group's bars
    fig.axes[0].set_ylabel("sharp features [–]")
    fig.legend(*fig.axes[0].get_legend_handles_labels(), loc="outside lower center", ncol=len(groups))


SPEC = ReportSpec("smoke", [
    Finding(finding),
    Table("meshes", _caption, _meshes, [
        Col("n_nodes", "built nodes"), *cols("node_count_error_pct"), Col("n_faces", "faces"),
        *cols("watertight"), Col("n_sharp_vertex", "sharp vertices"), Col("n_sharp_edge", "sharp edges"),
        Col("max_vertex_defect_rad", "largest angular defect [rad]", sig=3),
        Col("max_edge_deviation_deg", "largest dihedral departure [°]", sig=3), *cols("build_time_s")],
        by=["shape", "nodes"]),
    Value("sharp vertices on the sphere (worst resolution)", "Sec. 3.1", _worst("n_sharp_vertex"),
          paper=lambda p: p.sphere_sharp_vertices, digits=0),
    Value("sharp edges on the sphere (worst resolution)", "Sec. 3.1", _worst("n_sharp_edge"),
          paper=lambda p: p.sphere_sharp_edges, digits=0),
    Figure("sharp_features", "Sharp vertices and edges per object at each requested mesh resolution (bar "
           "labels: the counts)", _features, (9.0, 4.2)),
])
