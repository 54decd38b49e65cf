"""Bad input, round 20: new users' wrong inputs (docs/decisions.md, "Bad input, round 20", lists
every one tried). Each is one sentence naming what is wrong and where, exit 2, nothing stored
changed (``cli_checks.refused``).
"""

from __future__ import annotations

import pytest
from cli_checks import HEADER, refused

#: the factors of the one-trial mesh_features study the study-file tests write
FACTORS = "factors: {shape: [sphere], nodes: [144]}\n"


@pytest.mark.parametrize(("line", "said"), [
    ('"seeds ": 2', "the key 'seeds ' ends with a space, which no setting's name has; write 'seeds'"),
    ('" seeds": 2', "the key ' seeds' begins with a space, which no setting's name has; write 'seeds'"),
    ('runner: {"n_jobs ": 2}',
     "the key 'n_jobs ' ends with a space, which no setting's name has; write 'n_jobs'"),
    ('"": 2', "the key '' is empty, and no setting is named so; write the name of the setting"),
    ('"  ": 2', "the key '  ' is only spaces, and no setting is named so; write the name of the "
                "setting")])
def test_a_study_file_key_empty_or_with_a_space_at_an_end_is_named_as_written(tmp_path, line, said):
    """Quoted, YAML keeps the space: it was "seeds  is not a known key of the study config; did
    you mean seeds?", the space unseen, and an empty key was "mine.yaml:  is not a known key"."""
    study = tmp_path / "mine.yaml"
    study.write_text(f"{HEADER}name: mine\nkind: mesh_features\n{line}\n{FACTORS}")
    refused(tmp_path, ["show", study, "--root", tmp_path / "results"], f"{study}, line 5: {said}.")
