"""The Python API of the README: compose, run, load records (DataFrame and dataset)."""

from __future__ import annotations

import subprocess
import sys

import pandas as pd
import pytest

import graspcampaign as gc
from graspcampaign.errors import ConfigError, UserInputError


def test_compose_run_and_load_records(tmp_path):
    study = gc.compose_study("smoke", ["shape=[sphere,pear]", "nodes=[144]",
                                       f"output.root={tmp_path}", "runner.backend=sequential"])
    summary = gc.run_study(study, run="nb")
    assert (summary.n_trials, summary.n_ok) == (2, 2)
    df = gc.load_records("smoke", "nb", root=tmp_path)
    assert isinstance(df, pd.DataFrame) and sorted(df["shape"]) == ["pear", "sphere"]
    dataset = gc.load_records("smoke", "nb", root=tmp_path, dataset=True)
    import pyarrow.dataset as ds

    table = dataset.to_table(columns=["trial_id", "n_nodes"], filter=ds.field("shape") == "pear")
    assert table.num_rows == 1 and table.column("n_nodes")[0].as_py() == 144
    assert set(dataset.schema.names) == set(df.columns)


def test_bad_input_raises_the_command_line_sentence(tmp_path):
    with pytest.raises(ConfigError, match=r"^unknown study 'nosuch'; available studies: "):
        gc.compose_study("nosuch")
    with pytest.raises(UserInputError, match=rf"^no run at {tmp_path}/smoke/default; run "
                                             rf"`graspcampaign run smoke --root {tmp_path}` first\.$"):
        gc.load_records("smoke", root=tmp_path)
    # an unknown study is not one to run (as `graspcampaign status nosuch` says)
    with pytest.raises(UserInputError, match=rf"^unknown study 'nosuch': not on the config search "
                                             rf"path and no records under {tmp_path}; available "
                                             r"studies: ablation, baseline_grid, "):
        gc.load_records("nosuch", root=tmp_path)
    # the API's argument names, not the command line's options
    with pytest.raises(UserInputError, match=r"^run = '\.\./x' is not allowed; use ASCII letters "):
        gc.load_records("smoke", "../x", root=tmp_path)
    with pytest.raises(UserInputError, match=rf"^root {tmp_path}/f: is a file, not a directory\.$"):
        (tmp_path / "f").write_text("")
        gc.load_records("smoke", root=tmp_path / "f")


def test_import_graspcampaign_loads_no_layer():
    code = ("import sys, graspcampaign; heavy = [m for m in ('numpy', 'pandas', 'hydra', "
            "'pyarrow', 'graspcampaign.campaign') if m in sys.modules]; print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
