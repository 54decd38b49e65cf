"""graspcampaign: reproducible experiment campaigns for soft-object grasp planning.

The Python API (see ``graspcampaign.api``): ``compose_study``, ``run_study``, ``load_records``,
and the statistics ``graspcampaign.stats``. They are imported on first use, so
``import graspcampaign`` stays instant.
"""

__version__ = "0.1.0"
__all__ = ["compose_study", "run_study", "load_records", "stats"]


def __getattr__(name: str):
    if name == "stats":  # the submodule, imported on first use (about a second: scipy, statsmodels)
        import importlib

        return importlib.import_module("graspcampaign.stats")
    if name in __all__:
        from graspcampaign import api

        return getattr(api, name)
    raise AttributeError(f"module 'graspcampaign' has no attribute {name!r}")
