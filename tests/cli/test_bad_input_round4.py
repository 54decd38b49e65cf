"""Bad input, round 4: the inputs least tried (damaged run directories, report options, the
notebook API). Each case: exit 2 (or the API's exception), one sentence naming what is wrong and
where, nothing stored changed."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from statsmodels.stats.proportion import proportion_confint

import graspcampaign

#: this checkout's package first on a child interpreter's path
SRC = {**os.environ, "PYTHONPATH": str(Path(graspcampaign.__file__).parents[1])}


def test_gc_stats_works_after_import_graspcampaign_alone_and_stays_lazy():
    """README's notebook user writes ``gc.stats.wilson_interval`` after ``import graspcampaign as
    gc`` (an AttributeError before); ``import graspcampaign`` alone still imports no scipy."""
    code = ("import sys, graspcampaign as gc\n"
            "lazy = 'scipy' not in sys.modules and 'graspcampaign.stats' not in sys.modules\n"
            "ci = gc.stats.wilson_interval(3, 10)\n"
            "print(lazy, repr(ci.low), repr(ci.high))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                          env=SRC)
    lazy, low, high = done.stdout.split()
    assert lazy == "True"
    assert (float(low), float(high)) == pytest.approx(proportion_confint(3, 10, method="wilson"),
                                                      abs=1e-12)
