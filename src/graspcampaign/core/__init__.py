"""Numerical core: meshes, features, contact geometry, contact law, MSD body, metric, evaluator,
planners, PSO, bench model, disturbance statics.

Imports numpy, scipy and trimesh only; never the campaign, rig, report or CLI layers.
"""
