"""An override of a whole config group (``model=firm``) refused before Hydra reads it where Hydra
would answer in its own words, or with a key of its own: the group added (``+model=firm``: "Multiple
values for model. To override a value use 'override model: firm'."), given null (``model=null``:
"Config group override must be a string or a list. Got NoneType."), or its option chosen by a key
of the study (``model=${seed}``: "_dummy_ refers to ${seed}", Hydra resolving it in a config of its
own). Called by :func:`graspcampaign.campaign.override.check_overrides` for each override; and the
sentence for an option a group does not have (:func:`missing_option_sentence`).
"""

from __future__ import annotations

import re
from typing import Any

from graspcampaign.campaign.studycheck import GROUPS
from graspcampaign.campaign.studyfile import group_options
from graspcampaign.core.words import meant

#: ``${seed}``, ``${runner.backend}``: a reference to a key, not a resolver's call (``${oc.env:X}``)
_KEY_REFERENCE = re.compile(r"\$\{\s*([\w.]+)\s*\}")


def problem(item: str, prefix: str, key: str, value: str, read: Any) -> str | None:
    """Why the override ``item`` (split as ``prefix``, ``key``, ``value``; ``read``: Hydra's
    reading of its value) of config group ``key`` is refused, one sentence; None for any other
    override, and for one choosing an option (an unknown option is named after composition)."""
    if key not in GROUPS or "~" in prefix:  # ~model: check_overrides' own sentence
        return None
    if "+" not in prefix and read is not None and not _KEY_REFERENCE.search(value):
        return None  # model=firm: its group's folder is not listed for an override it takes
    choose = f"choose one of its options ({key}=OPTION; options: {', '.join(group_options(key))})"
    if "+" in prefix:
        return (f"override {item!r} adds the config group {key}, which every study has already "
                f"(conf/config.yaml chooses its option); {choose} without the {prefix!r}: "
                f"{key}={value.strip()}.")
    if read is None:
        return f"override {item!r} gives the config group {key} null, which is no option; {choose}."
    if reference := _KEY_REFERENCE.search(value):
        return (f"override {item!r} chooses the option of config group {key} by "
                f"${{{reference[1]}}}, a key of the study, but a group's option is chosen before the "
                f"study is composed; {choose}.")
    return None


def missing_option_sentence(group: str, option: str) -> str:
    """``model=nosuch``: name the group's options (the files of ``conf/<group>/``)."""
    from graspcampaign.campaign.studyfile import project_dirs

    named = (f"{group}={option} is a list, and a study composes one option" if option[:1] == "["
             else f"{group}={option} is not an option" if option else f"{group}= names no option")
    options = ", ".join(group_options(group))
    if not options:
        groups = sorted(p.name for p in project_dirs()[0].iterdir() if p.is_dir())
        return f"{group} is not a config group; config groups: {', '.join(groups)}."
    near = meant(option, options.split(", "), f"{group}={{}}") if option[:1] != "[" else ""
    return f"{named} of config group {group}; {near}available options: {options}."
