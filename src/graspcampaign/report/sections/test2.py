"""LEGACY PATH shim: the three names ``report/sections/test1.py`` still imports from here.

The Test 2 report is the spec :mod:`graspcampaign.report.studies.test2`; this module only keeps the
Test 1 section importable until its own port lands, and is deleted with ``sections/test1.py``.
"""

from __future__ import annotations

import pandas as pd
from matplotlib.figure import Figure

from graspcampaign.report import style

RC = style.RC
PAPER = style.PAPER


def new_figure(records: pd.DataFrame, title: str, size: tuple[float, float], ncols: int,
               nrows: int = 1, **kw):
    """A headless figure with its subplots; the title says which data it shows."""
    virtual = "source" in records and bool((records["source"] == "virtual").any())
    fig = Figure(figsize=size, layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False, **kw)
    tag = ("VIRTUAL RIG data (synthetic model output, not hardware measurements)" if virtual
           else "measured on hardware (ingested records)")
    fig.suptitle(f"{title}\n{tag}", fontsize=9.5, color="#b00020" if virtual else "black")
    return fig, axes.ravel()
