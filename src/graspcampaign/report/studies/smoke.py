"""Report of ``smoke`` (kind ``mesh_features``): the objects' meshes and sharp features (Sec. 3.1)."""

from __future__ import annotations

import math

import pandas as pd

from graspcampaign.analysis.records import flag
from graspcampaign.analysis.vocabulary import colour, label, ordered
from graspcampaign.core.words import counted
from graspcampaign.report import format as fmt
from graspcampaign.report.document import Col, cols
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Claims, Figure, Finding, ReportSpec, Table

#: What of a smooth shape a coarse mesh cannot keep under the vertex threshold, as DECISION explains it
#: (the records hold counts and extremes of the features, not where they lie nor the shapes' dimensions).
CAUSE = {"ellipsoid": "the ellipsoid's 60 mm tips", "pear": "the pear's top lobe"}
#: The resolution [nodes] and vertex threshold [rad] DECISION's explanation is of.
EXPLAINED_NODES, EXPLAINED_DEFECT_RAD = 144, 0.2
DECISION = "`docs/decisions.md`, *Geometry and metric*"
FEATURES = (("sharp vertex", "sharp vertices"), ("sharp edge", "sharp edges"))
SHARP_ROW = "sharp vertices and edges, {}, {} nodes"  # claims rows the opening reads: shape label, nodes
DIHEDRAL_ROW = "largest dihedral departure, sphere, {} nodes"  # and the sphere's at the paper's nodes


def _smooth(run: Run) -> pd.DataFrame:
    """The executed meshes of the shapes the paper calls smooth (Sec. 3.1), in its order, then by resolution,
    with their sharp features."""
    smooth = _meshes(run, list(run.paper.smooth_sharp_features))
    return smooth.assign(sharp=smooth["n_sharp_vertex"] + smooth["n_sharp_edge"])


def _sphere(run: Run, nodes: int, column: str) -> tuple[float, str]:
    """The recorded ``column`` of the sphere's mesh of ``nodes`` requested nodes, and why it is not
    compared ("": it is; NaN and the reason where the run has no such mesh)."""
    at = run.ok.loc[(run.ok["shape"] == "sphere") & (run.ok["nodes"] == nodes), column]
    missing = f"not compared: this run has no {nodes}-node sphere"
    return (float(at.iloc[0]), "") if len(at) else (math.nan, missing)


def _rows(run: Run):
    """Sec. 3.1 beside ours: the sharp features of each smooth shape at each resolution, the sphere's
    largest angular defect and its largest dihedral departure at the resolutions the paper names."""
    p = run.paper
    for m in _smooth(run).itertuples():
        yield (SHARP_ROW.format(label("shape", m.shape), m.nodes), "Sec. 3.1", m.sharp,
               p.smooth_sharp_features[m.shape], "", 0)
    value, because = _sphere(run, p.sphere_defect_nodes, "max_vertex_defect_rad")
    yield (f"largest angular defect, sphere, {p.sphere_defect_nodes} nodes", "Sec. 3.1", value,
           p.sphere_defect_rad, "rad", 2, because)
    value, because = _sphere(run, p.sphere_dihedral_nodes, "max_edge_deviation_deg")
    yield (DIHEDRAL_ROW.format(p.sphere_dihedral_nodes), "Sec. 3.1", value,
           (None, p.sphere_dihedral_below_deg), "°", 1, because, "the paper's bound")


def finding(run: Run) -> str:
    ok, levels = run.ok, run.ok["nodes"].nunique()
    text = (f"{int(flag(ok, 'watertight').sum())} of {len(ok)} meshes are closed (watertight) across "
            f"{ok['shape'].nunique()} shapes and {counted(levels, 'resolution')} (table meshes)")
    smooth = _smooth(run) if run.paper is not None else []
    if not len(smooth):
        return text + "."
    which, claims = "any" if levels > 1 else "this", run.tables["paper_comparison"].set_index("quantity")
    judged = claims.loc[[SHARP_ROW.format(label("shape", m.shape), m.nodes) for m in smooth.itertuples()]]
    sharp = smooth[judged["differs"].eq(True).to_numpy()]  # as the claims table judged them
    if not len(sharp):
        names = ", ".join(label("shape", s) for s in smooth["shape"].unique())
        return text + (f"; the smooth shapes ({names}) have no sharp vertex or edge at {which} resolution, "
                       "as the paper states (Sec. 3.1)." + _dihedral(claims, run, DECISION))
    found = "; ".join(f"the {label('shape', m.shape)} at {m.nodes} nodes has " + " and ".join(
        counted(int(n), *nouns) for n, nouns in zip((m.n_sharp_vertex, m.n_sharp_edge), FEATURES, strict=True)
        if n) for m in sharp.itertuples())
    f = run.config["features"]  # the decision's explanation is of the fixed 0.2 rad threshold at 144 nodes
    explained = sharp["shape"].isin(CAUSE) & (sharp["nodes"] == EXPLAINED_NODES) & (
        sharp["n_sharp_vertex"] > 0) & (f["vertex_defect_rad"] == EXPLAINED_DEFECT_RAD) & (
        not f.get("resolution_aware"))
    parts = " and ".join(CAUSE[s] for s in sharp.loc[explained, "shape"].unique())
    why = (f" {DECISION} explains: at {EXPLAINED_NODES} nodes the mesh is too coarse to keep the real "
           f"curvature of {parts} under {fmt.number(EXPLAINED_DEFECT_RAD)} rad a vertex."
           ) if explained.any() else ""
    return (f"{text}. **Unlike the paper**, whose thresholds \"cleanly separate the smooth test meshes\" "
            f"(Sec. 3.1), {found}.{why}{_dihedral(claims, run, 'the same entry' if why else DECISION)}")


def _dihedral(claims: pd.DataFrame, run: Run, entry: str) -> str:
    """The sphere's largest dihedral departure where the ``claims`` table (by quantity) judged it outside
    the paper's bound (Sec. 3.1); ``entry`` names the decision that records it."""
    p, threshold = run.paper, run.config["features"]["edge_dihedral_deg"]
    ours, differs = claims.loc[DIHEDRAL_ROW.format(p.sphere_dihedral_nodes), ["value", "differs"]]
    if pd.isna(differs) or not differs:  # not compared (the run has no such mesh), or within the bound
        return ""
    return (f" The sphere's largest dihedral departure at {p.sphere_dihedral_nodes} nodes is "
            f"{fmt.number(ours, 1)}°, above the paper's \"below about "
            f"{fmt.number(p.sphere_dihedral_below_deg)}°\" (Sec. 3.1)"
            + (f" but under the {fmt.number(threshold)}° threshold, so no edge of it is sharp ({entry})"
               if ours <= threshold else "") + ".")


def _meshes(run: Run, shapes: list[str] | None = None) -> pd.DataFrame:
    """The executed meshes of ``shapes`` in their order (default: every shape, in the vocabulary's order),
    then by resolution."""
    ok = run.ok if shapes is None else run.ok[run.ok["shape"].isin(shapes)]
    shapes = ordered("shape", ok["shape"], run.order.get("shape", ())) if shapes is None else shapes
    rank = {s: i for i, s in enumerate(shapes)}
    return ok.sort_values(["shape", "nodes"], key=lambda c: c.map(rank) if c.name == "shape" else c)


def _caption(run: Run) -> str:
    """The meshes table's caption, with the run's sharpness thresholds (Sec. 3.1)."""
    f = run.config["features"]
    return ("Object meshes: requested (nodes) and built node counts, closure, sharp features and build time; "
            "Sec. 3.1: a vertex is sharp when its angular defect (2π minus the sum of its face angles) "
            f"exceeds {fmt.number(f['vertex_defect_rad'])} rad, an edge when its dihedral angle departs from "
            f"180° by more than {fmt.number(f['edge_dihedral_deg'])}°"
            + (" (raised on coarse meshes: resolution-aware thresholds)" if f.get("resolution_aware")
               else ""))


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
               xlabel="requested mesh nodes [count]", title=f"sharp {what}")
        ax.grid(False, axis="x")  # no grid line through a group's bars
    fig.axes[0].set_ylabel("sharp features [count]")
    fig.legend(*fig.axes[0].get_legend_handles_labels(), loc="outside lower center", ncol=len(groups))


SPEC = ReportSpec("smoke", [
    Finding(finding),
    Table("meshes", _caption, _meshes, [
        Col("n_nodes", "built nodes"), *cols("node_count_error_pct"), Col("n_faces", "faces"),
        *cols("watertight"), Col("n_sharp_vertex", "sharp vertices"), Col("n_sharp_edge", "sharp edges"),
        Col("max_vertex_defect_rad", "largest angular defect [rad]", sig=3),
        Col("max_edge_deviation_deg", "largest dihedral departure [°]", sig=3), *cols("build_time_s")],
        by=["shape", "nodes"]),
    Claims("paper_comparison", "Ours beside the paper (Sec. 3.1): the smooth shapes' sharp features per "
           "resolution, and the sphere's largest angular defect and dihedral departure where the paper "
           "states them", lambda run: _rows(run) if run.paper is not None else ()),
    Figure("sharp_features", "Sharp vertices and edges per object at each requested mesh resolution (bar "
           "labels: the counts)", _features, (9.0, 4.2)),
])
