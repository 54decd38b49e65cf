"""One report spec per study (see graspcampaign.report.spec and docs/ARCHITECTURE.md)."""
