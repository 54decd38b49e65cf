"""Per-kind report sections (tables and figures beside the paper)."""
