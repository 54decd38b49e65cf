"""``mesh_features``: build an object mesh and record its size, closure and sharp features."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from graspcampaign.campaign.kind import TrialInput, TrialKind


def _features_cfg(study):
    from graspcampaign.core.feature import FeatureThresholds

    f = study.features
    return FeatureThresholds(vertex_defect_rad=f.vertex_defect_rad,
                             edge_dihedral_deg=f.edge_dihedral_deg,
                             edge_proximity_factor=f.edge_proximity_factor,
                             resolution_aware=f.resolution_aware)


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Build ``shape`` at ``nodes`` nodes and measure it (the build time is part of the record)."""
    from graspcampaign.core.feature import sharp_features
    from graspcampaign.core.mesh import SHAPES

    factors = inp.trial.factors
    start = time.perf_counter()
    mesh = SHAPES[factors["shape"]](factors["nodes"])  # uncached: the build time is measured
    build_time = time.perf_counter() - start
    feats = sharp_features(mesh, _features_cfg(inp.study))
    edges = mesh.edges_unique_length
    return {
        "n_nodes": int(len(mesh.vertices)),
        "n_faces": int(len(mesh.faces)),
        "node_count_error_pct": 100.0 * (len(mesh.vertices) - factors["nodes"]) / factors["nodes"],
        "watertight": bool(mesh.is_watertight),
        "winding_consistent": bool(mesh.is_winding_consistent),
        "volume_m3": float(mesh.volume),
        "area_m2": float(mesh.area),
        "mean_edge_length_m": float(edges.mean()),
        "n_sharp_vertex": int(np.count_nonzero(feats.sharp_vertices)),
        "n_sharp_edge": int(len(feats.sharp_edges)),
        "max_vertex_defect_rad": float(feats.vertex_defects.max()),
        "max_edge_deviation_deg": float(np.degrees(feats.edge_deviation_rad.max())),
        "build_time_s": build_time,
    }


MESH_FEATURES = TrialKind(
    name="mesh_features",
    run=run,
    seconds_per_trial=0.05,
    factors=("shape", "nodes"), optional_factors=(),
    description="object mesh construction, closure and sharp-feature counts",
)
