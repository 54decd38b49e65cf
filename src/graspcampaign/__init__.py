"""graspcampaign: reproducible experiment campaigns for soft-object grasp planning."""

__version__ = "0.1.0"
