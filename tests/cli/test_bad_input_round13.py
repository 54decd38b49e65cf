"""Bad input, round 13: characters that look like ASCII or like nothing (a digit of another
script, a full-width letter, a no-break or zero-width space) and bytes the terminal could not decode,
in an override and in a study file's key. Each refusal: exit 2, one sentence naming what is wrong,
where, and what to write, nothing stored changed (``refused``)."""

from __future__ import annotations

import pytest
from cli_checks import mesh_study, refused


@pytest.mark.parametrize(("typed", "said"), [
    # each was told to quote the character, which keeps it: seeds="٣" is the text '٣', no number
    ("seeds=\u0663", "'\u0663' (character 7) looks like '3' but is not ASCII; write 'seeds=3'."),
    ("seeds=\uff13", "'\uff13' (character 7) looks like '3' but is not ASCII; write 'seeds=3'."),
    ("nodes=[\uff1144]", "'\uff11' (character 8) looks like '1' but is not ASCII; write "
     "'nodes=[144]'."),
    ("shape=[\uff53phere]", "'\uff53' (character 8) looks like 's' but is not ASCII; write "
     "'shape=[sphere]'."),
    ("seeds=2\u200b", "U+200B (zero width space) (character 8) shows as nothing; write 'seeds=2'."),
    ("seeds=\xa02", "U+00A0 (no-break space) (character 7) looks like a space but is not ASCII; "
     "write 'seeds= 2'."),
    # the old code called the byte "U+DCE9 (a control character)" and said to quote it
    ("seeds=\udce9", "byte 0xE9 (character 7) is not UTF-8 text (a terminal in another encoding?); "
     "type the override in UTF-8."),
])
def test_a_look_alike_character_in_an_override_value_is_named_with_what_to_write(tmp_path, typed, said):
    refused(tmp_path, ["show", "smoke", typed, "--root", tmp_path],
            f"cannot parse override {typed!r}: {said}")


@pytest.mark.parametrize(("typed", "said", "fix"), [
    # a zero-width space in a key was named without a fix (a space was given one)
    ("see\u200bds=2", "U+200B (zero width space) at character 4", "; write 'seeds=2'"),
    ("\uff53eeds=2", "'\uff53' at character 1", "; write 'seeds=2'"),
    ("se\udce9ds=2", "byte 0xE9 at character 3", ""),  # it said "U+DCE9 (a control character)"
])
def test_a_look_alike_character_in_an_override_key_is_named_with_what_to_write(tmp_path, typed, said,
                                                                               fix):
    refused(tmp_path, ["show", "smoke", typed, "--root", tmp_path],
            f"cannot parse override {typed!r}: its key has {said}, but a key takes only ASCII "
            f"letters, digits, '_', '-', '.' and '/'{fix}.")


def test_an_accented_letter_in_a_value_is_still_told_to_be_quoted(tmp_path):
    # é stands for no ASCII character: quoted it is the text the user meant
    refused(tmp_path, ["show", "smoke", "output.run=caf\xe9", "--root", tmp_path],
            "cannot parse override 'output.run=caf\xe9': '\xe9' (character 15) is not allowed in "
            "an unquoted value (only ASCII letters, digits, spaces and _-+.$%*@?|/\\ are); quote "
            "it: output.run=\"caf\xe9\", typed in single quotes on the shell.")


@pytest.mark.parametrize(("key", "line", "said"), [
    # each was "se​eds is not a known key of the study config; did you mean seeds?", the key
    # printed with its invisible character, so that it read as the key suggested
    ("se\u200beds: 1", 5, "the key 'se\\u200beds' holds U+200B (zero width space), which does not "
     "print; write 'seeds'."),
    ("seeds\xa0: 1", 5, "the key 'seeds\\xa0' holds U+00A0 (no-break space), which does not print; "
     "write 'seeds'."),
    ("runner:\n  n_jo\u200bbs: 1", 6, "the key 'n_jo\\u200bbs' holds U+200B (zero width space), "
     "which does not print; write 'n_jobs'."),
    # a section's own sentences showed it as typed too ("factors.no​des is not a known factor")
    ("factors:\n  shape: [sphere]\n  no\ufeffdes: [144]", 7, "the key 'no\\ufeffdes' holds U+FEFF "
     "(zero width no-break space), which does not print; write 'nodes'."),
])
def test_a_key_holding_a_character_that_does_not_print_is_named_escaped(tmp_path, user_dir, key,
                                                                       line, said):
    path = mesh_study(user_dir, f"{key}\n")
    for command in ("show", "run"):
        refused(tmp_path, [command, path, "--root", tmp_path], f"{path}, line {line}: {said}")


@pytest.mark.parametrize(("typed", "said"), [
    # each was blamed on the study file ("campaigns/smoke.yaml, line 11: ..."), which does not
    # say cube, 7 or a tenth shape: an override's list element (factors.shape.0) was not matched
    # to the key the check names (factors.shape[0])
    ("factors.shape.0=cube", "factors.shape[0] has unknown value 'cube'; allowed values: sphere, "
     "ellipsoid, rounded_cube, pear, handle."),
    ("factors.nodes.1=7", "factors.nodes[1] = 7 is out of range; allowed: >= 12 and <= 20000 (a "
     "closed mesh needs 12 nodes, and one finer than 20,000 resolves nothing a 5 mm fingertip "
     "feels)."),
    ("factors.shape.9=pear", "factors.shape[9]: list index out of range."),
])
def test_an_override_of_one_level_is_named_as_the_override_not_the_study_file(tmp_path, typed, said):
    refused(tmp_path, ["show", "smoke", typed, "--root", tmp_path], said)
