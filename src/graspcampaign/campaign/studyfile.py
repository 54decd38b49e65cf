"""Where study and group files live (a first look at a YAML file before Hydra sees it,
:func:`read_yaml`, is :mod:`graspcampaign.campaign.yamlfile`'s).

Config search path (documented in the README):

- ``GRASPCAMPAIGN_HOME``: a directory holding ``conf/`` (the config groups) and ``campaigns/`` (the
  studies) that replaces the ones shipped with the package (default: the source checkout the
  package is imported from, else the copies inside the wheel);
- ``GRASPCAMPAIGN_PATH``: further directories of study files (``*.yaml``), separated by ``:`` (``;``
  on Windows), searched in order *before* ``campaigns/``, so a study of your own can keep a name of
  the tool's;
- a study argument that names a file (``./my_study.yaml``, anything ending in ``.yaml``/``.yml`` or
  holding a path separator) is that file.

Nothing here imports Hydra, numpy or the numerical layers: ``graspcampaign list`` runs on this
module alone.
"""

from __future__ import annotations

import os
import re
from functools import cache
from pathlib import Path

from graspcampaign.campaign.paths import (
    expand_home,
    input_file_problem,
    path_problem,
    read_denied,
    shown,
    unreachable,
)
from graspcampaign.campaign.yamlfile import NESTED_TOO_DEEPLY, read_yaml  # noqa: F401  (public here too)
from graspcampaign.core.words import meant
from graspcampaign.errors import ConfigError, UserInputError

_SCHEMA_LINE = re.compile(r"^#\s*schema:\s*(\w+)")
_SUFFIXES = (".yaml", ".yml")


@cache
def project_dirs() -> tuple[Path, Path]:
    """Return ``(conf_dir, campaigns_dir)``.

    ``$GRASPCAMPAIGN_HOME`` when set (non-empty): it must hold both, or the error says what it
    lacks (a home that is silently passed over would run the shipped configs instead of the
    user's). Otherwise the source checkout the package is imported from (editable installs), then
    the copies shipped inside the wheel.

    Raises
    ------
    UserInputError
        ``GRASPCAMPAIGN_HOME`` does not exist, is not a directory, or lacks ``conf/config.yaml``
        or ``campaigns/``; or no copy of them is found at all.
    """
    home = os.environ.get("GRASPCAMPAIGN_HOME", "").strip()
    if home:
        root, unknown = expand_home(home)
        problem = unknown or _home_problem(root)
        if problem:
            raise UserInputError(f"GRASPCAMPAIGN_HOME={home} {problem}; point it at a directory "
                                 "holding conf/ (with conf/config.yaml and the config groups) and "
                                 "campaigns/ (the study files), e.g. a copy of the shipped ones, "
                                 "or unset it to use those.")
        return root / "conf", root / "campaigns"
    here = Path(__file__).resolve()
    for root in (here.parents[3], here.parents[1] / "_data"):
        if (root / "conf" / "config.yaml").is_file() and (root / "campaigns").is_dir():
            return root / "conf", root / "campaigns"
    raise UserInputError("cannot find conf/config.yaml and campaigns/; set GRASPCAMPAIGN_HOME to "
                         "a directory that has both.")


def _home_problem(root: Path) -> str | None:
    """What a ``GRASPCAMPAIGN_HOME`` directory lacks, in words (None: nothing); a directory of it
    this user may not read is named."""
    if not os.path.exists(root):  # a symbolic link leading nowhere: said so
        return unreachable(root) or os.path.islink(root) and path_problem(root) or "does not exist"
    if not root.is_dir():
        return "is a file, not a directory"
    for place in ("", "conf", "campaigns"):
        if os.path.isdir(root / place) and (why := read_denied(root / place)):
            return f"has {place}/, which {why}" if place else why
    if not (root / "conf").is_dir():
        return "has no conf/ directory"
    if not (root / "conf" / "config.yaml").is_file():
        return "has no conf/config.yaml"
    if not (root / "campaigns").is_dir():
        return "has no campaigns/ directory"
    return None


def study_dirs() -> list[Path]:
    """Return the directories searched for study files: ``$GRASPCAMPAIGN_PATH``, then campaigns/.

    An entry of ``GRASPCAMPAIGN_PATH`` that is not a directory is skipped with a warning naming
    it.
    """
    extra = []
    for entry in os.environ.get("GRASPCAMPAIGN_PATH", "").split(os.pathsep):
        if not entry.strip():
            continue
        path, problem = _search_entry(entry)
        if problem:
            _warn(f"GRASPCAMPAIGN_PATH entry {entry} {problem}; it is skipped.")
            continue
        extra.append(path)
    return [*extra, project_dirs()[1]]


def _search_entry(entry: str) -> tuple[Path, str | None]:
    """A ``GRASPCAMPAIGN_PATH`` entry as the directory it names (``~`` read as a shell reads it)
    and why it is skipped (a home that cannot be found, no directory there), or None: one reading
    for the search and for the words that describe it."""
    path, unknown = expand_home(entry)
    return path, unknown or _path_problem(path)


def _path_problem(path: Path) -> str | None:
    """Why ``path`` is no directory of study files (missing, or a file: then how to run it; one
    this user may not read)."""
    if not os.path.exists(path):  # a symbolic link leading nowhere: said so
        return unreachable(path) or os.path.islink(path) and path_problem(path) or "does not exist"
    if not path.is_dir():
        hint = (" (run a study file by giving its path: graspcampaign run " + str(path) + ")"
                if path.suffix in _SUFFIXES else "")
        return f"is a file, not a directory of study files{hint}"
    return read_denied(path)


def _warn(message: str) -> None:
    """A warning the command line prints once per command as ``warning: ...``."""
    import warnings

    warnings.warn(message, stacklevel=3)


def search_path_text() -> str:
    """The study search path in words, for a message: the directories searched, in order, and
    the ``GRASPCAMPAIGN_PATH`` entries skipped with why."""
    searched, skipped = [], []
    for entry in os.environ.get("GRASPCAMPAIGN_PATH", "").split(os.pathsep):
        if entry.strip():
            problem = _search_entry(entry)[1]
            (skipped.append(f"{entry} ({problem.split(' (')[0]})") if problem
             else searched.append(entry))
    text = ", ".join([*searched, str(project_dirs()[1])])
    if skipped:
        text += f"; GRASPCAMPAIGN_PATH entries skipped: {', '.join(skipped)}"
    elif not searched:
        text += "; GRASPCAMPAIGN_PATH adds directories of your own"
    return text


def study_files() -> dict[str, Path]:
    """Return ``{study name: file}`` over the search path (the first directory holding a name wins)."""
    out: dict[str, Path] = {}
    for directory in study_dirs():
        for path in sorted(directory.iterdir()):
            if path.suffix in _SUFFIXES and path.is_file():
                out.setdefault(path.stem, path)
    return dict(sorted(out.items()))


def case_twin_study(name: str, files: dict[str, Path] | None = None) -> tuple[str, Path] | None:
    """The study on the search path (``files``, :func:`study_files`' listing, when the caller has
    it) whose name differs from ``name`` only in case (``smoke`` for ``Smoke``), and its file; else
    None. Runs are stored by their study's name (``<root>/<name>/``), and on a file system that
    ignores case the two are one directory."""
    return next(((other, path) for other, path in (study_files() if files is None else files).items()
                 if other != name and other.lower() == name.lower()), None)


def study_place(path: Path) -> str:
    """A study file as a refusal names it: ``campaigns/smoke.yaml`` for one of the tool's (or the
    config home's) studies, else its path."""
    campaigns_dir = project_dirs()[1]
    return f"{campaigns_dir.name}/{path.name}" if path.parent == campaigns_dir else str(path)


#: why two studies may not have names that differ only in case, after "names A and B"
CASE_TWINS = ("runs are stored and reported by their study's name, and on a file system that "
              "ignores case (macOS, Windows, a USB stick) the directories {0}/ and {1}/ are one")


def config_place(absolute: Path) -> str | None:
    """Why ``absolute`` is the tool's configs' place rather than a results root: a directory
    holding ``conf/config.yaml`` and ``campaigns/`` (a source checkout, a ``GRASPCAMPAIGN_HOME``),
    or one inside its ``conf/`` or ``campaigns/``; else None. Runs stored there lie among its files,
    and `report` takes each of them for a run it cannot read (a line apiece)."""
    def home(place: Path) -> bool:
        return (place / "conf" / "config.yaml").is_file() and (place / "campaigns").is_dir()

    if home(absolute):
        return (f"it holds conf/config.yaml and campaigns/, the tool's configs (a source checkout "
                f"or a GRASPCAMPAIGN_HOME), so runs stored there would lie among its files; give "
                f"a folder for the results instead, such as {absolute / 'results'}")
    inside = next((place for place in absolute.parents
                   if place.name in ("conf", "campaigns") and home(place.parent)), None)
    if inside is None and absolute.name in ("conf", "campaigns") and home(absolute.parent):
        inside = absolute
    if inside is None:
        return None
    return (f"it is {'inside ' if inside != absolute else ''}{inside}, the tool's "
            f"{'config groups' if inside.name == 'conf' else 'study files'}, so runs stored there "
            f"would lie among them; give a folder for the results instead, such as "
            f"{inside.parent / 'results'}")


def list_studies() -> list[str]:
    """Return the study names on the search path, sorted."""
    return list(study_files())


def is_path_argument(study: str) -> bool:
    """Whether a study argument names a file rather than a study."""
    return study.lower().endswith(_SUFFIXES) or "/" in study or os.sep in study


def study_and_run(study: str, root: Path | str | None = None) -> str | None:
    """Why ``study`` is refused when it is ``<study>/<run>`` (``smoke/default``, as the results
    directory spells a run) rather than a study: one sentence giving the two apart; else None.
    Its first part is a study on the search path, or (``root``) a folder of runs there."""
    parts = study.split("/")
    if (len(parts) != 2 or not all(parts) or Path(study).suffix.lower() in _SUFFIXES
            or os.path.isfile(study)):
        return None
    if parts[0] not in study_files() and not (root is not None and (Path(root) / parts[0]).is_dir()):
        return None
    return (f"study {study!r} names a study and a run, as the results directory spells them; "
            f"give the study's name and the run apart: {parts[0]} --run {parts[1]}.")


def find_study(study: str, files: dict[str, Path] | None = None) -> Path:
    """Return the file of a study given by name (on the search path: ``files``, :func:`study_files`'
    listing, when the caller has it) or by path.

    Raises
    ------
    ConfigError
        No such study or file, naming the available studies.
    """
    if not isinstance(study, str):
        raise ConfigError(f"study = {study!r} is not a study's name or file path: give it as text.")
    if is_path_argument(study):
        if (apart := study_and_run(study)) is not None:
            raise ConfigError(apart)
        path, unknown = expand_home(study)
        if unknown:
            raise ConfigError(f"study file {shown(study)} {unknown}; give its path in full.")
        if (why := input_file_problem(path)) is not None:
            raise ConfigError(f"study file {shown(study)} {why}; give a YAML file.")
        if path.suffix.lower() in _SUFFIXES and path.suffix not in _SUFFIXES:
            raise ConfigError(f"study file {shown(study)} {_MISCASED} rename it "
                              f"{path.with_suffix(path.suffix.lower()).name}.")
        if path.suffix not in _SUFFIXES:
            raise ConfigError(f"study file {shown(study)} must end in .yaml or .yml.")
        return path
    files = study_files() if files is None else files
    if study not in files:
        for directory in study_dirs():  # a mine.YAML there is not listed, nor a mine.yaml that is
            found = [p for p in directory.iterdir() if p.stem == study and p.suffix.lower() in _SUFFIXES]
            if found and found[0].suffix in _SUFFIXES:  # no file (a link leading nowhere, a folder)
                raise ConfigError(f"unknown study {study!r}: {found[0]} {input_file_problem(found[0])}"
                                  "; make it a study file (YAML) or move it aside.")
            if found:
                raise ConfigError(f"unknown study {study!r}: the file {found[0]} {_MISCASED} rename "
                                  f"it {study}{found[0].suffix.lower()}.")
        raise ConfigError(f"unknown study {study!r}; {meant(study, files)}"
                          f"available studies: {', '.join(files)} (searched: {search_path_text()}).")
    return files[study]


#: why a study file ending in .YAML (.Yml, ...) is not read: the case of a suffix matters
_MISCASED = ("is not read: a study file's name ends in .yaml or .yml in lower case, as the study "
             "search path and Hydra's look for it (the case of a file name matters on Linux);")


def schema_of(path: Path) -> str | None:
    """Return the schema a YAML file names in its header (``# schema: Name``).

    The header is the leading block of comment lines (a study's first line is Hydra's
    ``# @package _global_``); a UTF-8 byte-order mark before it is allowed.
    """
    with open(path, encoding="utf-8-sig") as fh:
        for line in fh:
            if not line.startswith("#"):
                break
            match = _SCHEMA_LINE.match(line)
            if match:
                return match.group(1)
    return None


def check_package_header(path: Path) -> None:
    """Refuse a study file without Hydra's ``# @package _global_`` in its leading comments.

    Without it Hydra would nest the whole study under a ``campaigns:`` key. A UTF-8 byte-order
    mark before it is allowed (the composition reads a copy without it).
    """
    with open(path, encoding="utf-8-sig") as fh:
        for line in fh:
            if not line.startswith("#"):
                break
            if re.match(r"#\s*@package\s+_global_\s*$", line):
                return
    raise ConfigError(f"{path} does not start with the comment line '# @package _global_', which "
                      "every study file needs (see campaigns/smoke.yaml).")


def check_group_files() -> None:
    """Parse every YAML under ``conf/``; the first invalid one raises naming its file and line."""
    conf_dir, _ = project_dirs()
    for path in sorted(conf_dir.rglob("*.yaml")):
        read_yaml(path)


def configured_output(study: str | None, key: str = "run") -> str:
    """Return where a study writes by default, read without Hydra: its ``output.run`` (``key``
    ``"run"``) or its results root, ``output.root`` (``"root"``, ``~`` not yet read as a home).

    The study file's ``output.<key>`` if it sets one, else the ``conf/output`` default's
    (``default``, ``results``); for no study, or a name not on the search path (records of a study
    of another tool version), the ``conf/output`` default's.
    """
    try:
        data = {} if study is None else read_yaml(find_study(study), study=True)
    except ConfigError:
        data = {}
    output = data.get("output")
    if isinstance(output, dict) and output.get(key):
        return str(output[key])
    default = project_dirs()[0] / "output" / "default.yaml"
    value = read_yaml(default).get(key) if default.is_file() else None
    return str(value or {"run": "default", "root": "results"}[key])


def group_options(group: str) -> tuple[str, ...]:
    """Return the options of a config group (the YAML files in ``conf/<group>/``), sorted."""
    return tuple(sorted(p.stem for p in (project_dirs()[0] / group).glob("*.yaml")))
