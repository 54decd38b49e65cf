"""The Python API for notebooks and scripts: compose a study, run it, load its records.

>>> import graspcampaign as gc
>>> study = gc.compose_study("baseline_grid", ["mu=[0.3]", "seeds=2"])
>>> summary = gc.run_study(study, run="mu03")
>>> df = gc.load_records("baseline_grid", "mu03")            # a pandas DataFrame
>>> ds = gc.load_records("baseline_grid", "mu03", dataset=True)  # a pyarrow.dataset, for large runs

``compose_study`` and ``run_study`` are the command line's own functions
(:func:`graspcampaign.campaign.compose.compose_study`,
:func:`graspcampaign.campaign.runner.run_study`); bad input raises
:class:`graspcampaign.errors.UserInputError` with the same one-sentence message the command line
prints.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.runner import RunSummary, run_study

__all__ = ["compose_study", "run_study", "load_records", "RunSummary"]


def load_records(study: str, run: str | None = None, *, root: str | Path | None = None,
                 dataset: bool = False) -> Any:
    """Return the records of a run: one row per trial, every column with its unit in its name.

    Parameters
    ----------
    study : str
        Study name (a directory under ``root``).
    run : str, optional
        Run name; default the study's configured run (``output.run``, normally ``default``).
    root : str or path, optional
        Results root; default the study's configured root (``output.root``, normally
        ``results``).
    dataset : bool
        Return a :class:`pyarrow.dataset.Dataset` instead of a DataFrame: nothing is read until
        asked, and filters and column selections are pushed down to the files (runs of millions
        of trials).

    Returns
    -------
    pandas.DataFrame or pyarrow.dataset.Dataset
        Every file verified in full first (``docs/records.md`` lists the columns). A run stored
        before a column was renamed reads under the current name
        (:mod:`graspcampaign.campaign.former_names`); its dataset is then held in memory.

    Raises
    ------
    graspcampaign.errors.UserInputError
        No such run, a run name leaving ``root``, or a run whose stored files are not what its
        manifest says (``DamagedRunError``: a damaged file, a duplicate or foreign shard).
    """
    from graspcampaign.campaign.paths import stored_root
    from graspcampaign.campaign.status import open_run
    from graspcampaign.campaign.studyfile import configured_output

    root = stored_root([study]) if root is None else root
    store, _ = open_run(root, study, configured_output(study, "run") if run is None else run, "")
    return store.dataset() if dataset else store.read().to_pandas()
