"""What the tests of the ``test2_grasp`` and ``test3_disturbance`` kinds share: the reduced sheet
they run (and ingest beside it), the timing columns no two runs agree on, a cell-by-cell
comparison, and the command-line runner.

Imported by name (``from hardware_checks import ...``), as pytest puts this directory on the path.
"""

from __future__ import annotations

import math

import pandas as pd
from typer.testing import CliRunner

REDUCED = ["params.fraction=0.06"]
TIMING = {"wall_time_s", "plan_time_s", "worker", "host", "run"}
cli = CliRunner()


def same(a: pd.Series, b: pd.Series) -> bool:
    """Equal cell by cell, None/NaN meaning the same (not measured)."""
    for x, y in zip(a.tolist(), b.tolist(), strict=True):
        xn = x is None or (isinstance(x, float) and math.isnan(x))
        yn = y is None or (isinstance(y, float) and math.isnan(y))
        if xn != yn or (not xn and x != y):
            return False
    return True
