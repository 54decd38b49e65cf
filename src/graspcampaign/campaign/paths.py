"""Where commands read and write: the results root, a run's directory and output files, checked
before any work.

A bad place (an empty name, a file where a directory belongs, a directory, named pipe, device or
socket where a file belongs, a read-only file system) is one sentence naming the option and why,
given before anything runs or is written. Standard library only: ``show`` and ``status`` answer
without the numerical layers.
"""

from __future__ import annotations

import errno
import os
import re
import shlex
import stat
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from graspcampaign.core.words import PERMISSION_DENIED
from graspcampaign.errors import ConfigError, UserInputError, blocked, cannot_write, too_long


def path_problem(path: Path, *, write: bool = False, directory: bool = True) -> str | None:
    """Say why ``path`` cannot serve as a directory (or, ``directory=False``, a file) to read or
    ``write``, without leaving anything behind or waiting; None if it can.

    The nearest existing one of ``path`` and its parents (a symlink exists, dangling or not)
    decides: a file where a directory must be ("/x: is a file, not a directory", "/x: /x/a is a
    file ..."), a directory, named pipe, device or socket where a file must be, or (``write``) a
    place this process cannot write: probed by creating and removing a temporary file in the
    directory the file would be created in (or opening the existing regular file to append,
    never to create), because permission bits do not tell (root passes them, yet cannot create a
    file in ``/proc``). A path too long for the system (:func:`~graspcampaign.errors.too_long`)
    is refused first: no check of it or its parents would say so.
    """
    if (long := too_long(path)) is not None:
        return long
    for i, where in enumerate([path, *path.parents]):
        if not os.path.lexists(where):
            continue
        if i == 0 and not directory:
            if where.is_dir():
                return "is a directory, not a file"
            if not write and not where.exists():  # a symlink leading nowhere: not "no such file"
                return _dangling(where)
            if where.exists() and not where.is_file():
                return f"is {_special(where.stat().st_mode)}, not a regular file"
        elif not where.is_dir():
            if where.is_file():
                what = "is a file, not a directory"
            elif not where.exists():  # a symlink leading nowhere or in a loop
                what = _dangling(where)
            else:
                what = f"is {_special(where.stat().st_mode)}, not a directory"
            return what if i == 0 else f"{where} {what}"
        return write_denied(where) if write else None
    return None


def _first_control(path: str | os.PathLike) -> str | None:
    """The first control character (Unicode category Cc: a line break, a tab) of ``path``, or None."""
    import unicodedata

    return next((c for c in os.fspath(path) if unicodedata.category(c) == "Cc"), None)


def shown(path: str | os.PathLike) -> str:
    """``path`` as a message shows it: as given, or quoted with its control characters escaped
    (``'/x/no\\nsuch.yaml'``) when it holds one (a line break, a tab), so that the sentence stays
    on one line. The one way every message names a path a user gave."""
    text = os.fspath(path)
    return text if _first_control(text) is None else repr(text)


def control_character(path: str | os.PathLike, option: str) -> str | None:
    """The sentence refusing a results root or an output path that holds a control character (a
    line break, a tab), or None. Such a name is legal, but no one types it on purpose (a path
    pasted across two lines): it would make a directory or file whose name every listing and
    message splits. The path is shown quoted, with the character escaped, as an override is."""
    if (char := _first_control(path)) is None:
        return None
    return (f"{option} {shown(path)}: U+{ord(char):04X} (a control character) is not "
            "allowed in a path given here; remove it.")


def input_file_problem(path: Path) -> str | None:
    """Why ``path``, given as a file to read, is not one, in the words after the path; None for a
    regular file (or a symbolic link to one).

    The one check of every file a command reads (a study file, measured records, a mesh), so that
    each names a bad one alike: a directory ("is a directory, not a file"), a named pipe, device,
    socket or symbolic link leading nowhere (:func:`path_problem`'s words: it exists, so "does not
    exist" would mislead), a file, or a directory on its way, this user may not open (a probe:
    root passes permission bits), or nothing there ("does not exist"). The caller adds what to
    give.
    """
    if os.path.lexists(path):  # a regular file: None; anything else: why not
        return path_problem(path, directory=False) or read_denied(path)
    return unreachable(path) or "does not exist"


def read_denied(path: Path) -> str | None:
    """Why this user may not read the file ``path``, or list the directory ``path`` and open
    what it holds, in the words after the path; None if it may. A probe, not the permission bits
    (root passes them)."""
    try:
        if os.path.isdir(path):
            with os.scandir(path):
                pass
            os.stat(os.path.join(path, os.curdir))
        else:
            os.close(os.open(path, os.O_RDONLY | os.O_NONBLOCK))
    except PermissionError:
        return f"cannot be read by this user: {PERMISSION_DENIED}"
    return None


def unreachable(path: Path) -> str | None:
    """Why this user cannot reach ``path``: a directory on its way it may not search
    (:func:`~graspcampaign.errors.blocked`), in the words after the path; or None."""
    if (parent := blocked(path)) == os.fspath(path):
        return None
    return f"cannot be reached by this user ({parent} cannot be searched): {PERMISSION_DENIED}"


def _dangling(link: Path) -> str:
    """What a symbolic link that leads to no file is: one in a loop, or one to a missing target."""
    try:
        os.stat(link)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            return "is a symbolic link in a loop (it leads back to itself)"
    return f"is a symbolic link to {os.readlink(link)}, which does not exist"


def _special(mode: int) -> str:
    """What a file that is neither a directory nor a regular file is."""
    return ("a named pipe (FIFO)" if stat.S_ISFIFO(mode) else "a socket" if stat.S_ISSOCK(mode)
            else "a character device" if stat.S_ISCHR(mode) else "a block device"
            if stat.S_ISBLK(mode) else "a special file")


def write_denied(where: Path) -> str | None:
    """Why this process cannot write into (or over) ``where``, or None: a probe, not a guess. An
    existing regular file is opened to append (without creating it, without waiting); anything
    else is probed in the directory its file would be created in (a dangling symlink's target's)."""
    try:
        if where.is_file():
            os.close(os.open(where, os.O_WRONLY | os.O_APPEND | os.O_NONBLOCK))
        else:
            parent = where if where.is_dir() else Path(os.path.realpath(where)).parent
            handle, probe = tempfile.mkstemp(prefix=".graspcampaign-probe-", dir=parent)
            os.close(handle)
            os.unlink(probe)
    except OSError as exc:
        return cannot_write(exc)
    return None


def check_root(root: str | Path, key: str = "--root", *, write: bool = False) -> Path:
    """Return the results root ``root`` after checking it can hold (``write``: receive) runs.

    Checked before any work, so that a bad root is one sentence naming it and nothing is written.

    Raises
    ------
    UserInputError
        An empty root (it would mean the current directory), a file in its place or on its path,
        a run's directory or a place inside one (a run written there would land among its
        records), a study's directory, or (``write``) a directory that cannot be written.
    """
    if not isinstance(root, (str, os.PathLike)):
        raise UserInputError(f"{key} = {root!r} is not a path: give the results directory as text "
                             "or a Path.")
    if not str(root).strip():
        raise UserInputError(f"{key} is empty; give the results directory (for example "
                             "results): an empty root would mean the current directory.")
    if (control := control_character(root, key)) is not None:
        raise UserInputError(control)
    why = path_problem(Path(root), write=write) or _not_a_results_root(Path(root))
    if why is not None:
        raise UserInputError(f"{key} {root}: {why}.")
    return Path(root)


def _not_a_results_root(root: Path) -> str | None:
    """Why ``root`` is a run's (a directory holding ``manifest.json``) or a study's place rather
    than a results root, with the root that holds it; None if it is neither."""
    absolute = Path(os.path.abspath(root))
    if (where := run_around(absolute)) is not None:
        run = f"run {where.parent.name}/{where.name}"
        what = f"the directory of {run}" if where == absolute else f"inside {run} ({where})"
        return f"it is {what}; give the results root that holds it ({where.parent.parent})"
    from graspcampaign.campaign.studyfile import config_place  # lazy: it imports paths at its top

    if (why := config_place(absolute)) is not None:
        return why
    try:
        folders = [entry for entry in os.scandir(absolute) if entry.is_dir()]
    except OSError:
        return None
    if any(os.path.lexists(Path(entry.path) / "manifest.json") for entry in folders):
        return (f"it holds the runs of study {absolute.name}; give the results root that holds "
                f"it ({absolute.parent})")
    return None


def run_around(path: Path) -> Path | None:
    """The run directory (one holding ``manifest.json``) that ``path`` is or lies inside, or None."""
    absolute = Path(os.path.abspath(path))
    return next((where for where in [absolute, *absolute.parents]
                 if os.path.lexists(where / "manifest.json")), None)


def expand_home(path: str | os.PathLike) -> tuple[Path, str | None]:
    """``path`` with a leading ``~`` or ``~user`` read as that home directory, as a shell reads it
    (an environment variable set in a file, or a quoted argument, reaches the tool with it), and
    None; or ``path`` as given and why it cannot be read so (no such user, no HOME), in words."""
    try:
        return Path(path).expanduser(), None
    except RuntimeError:  # pathlib's "Could not determine home directory."
        return Path(path), f"starts with {Path(path).parts[0]}, a home directory that cannot be found"


def config_root(root: str) -> str:
    """A composed study's ``output.root`` with a leading ``~`` read as the home directory, as the
    ``--root`` option reads it (:func:`expand_home`): ``output.root=~/runs`` (quoted, or in a
    study file) made a directory named ``~``. Anything else is returned as written.

    Raises
    ------
    ConfigError
        A home directory that cannot be found, naming ``output.root``.
    """
    if not isinstance(root, str) or not root.startswith("~"):
        return root
    path, unknown = expand_home(root)
    if unknown:
        raise ConfigError(f"output.root = {root} {unknown}; give its path in full.",
                          key="output.root")
    return str(path)


def how_to_make(root: Path | str, study: str, run: str | None = None,
                overrides: Sequence[str] = (), then: str = "first") -> str:
    """The end of a "no such run" message: the command that makes run ``run`` of ``study`` (default:
    its configured run) under ``root``, with the options it needs (a hardware protocol's ``measured``
    run: ``ingest``) and the ``overrides`` a run already started was given (without them `run`
    refuses it as started with another config), followed by ``then`` ("first", or "again to finish
    it" for a run started): one sentence, which no caller cuts to add its own end. For a run named
    as one there but for case, which `run` and `ingest` refuse (:func:`check_case_twin`), it says
    that instead of a command that would be refused."""
    from graspcampaign.campaign.studyfile import configured_output

    if run is not None and (twin := case_twin(Path(root) / study / run)) is not None:
        return (f"a run named {run} cannot be made beside {twin.name} (on a file system that "
                "ignores case the two are one directory).")  # `run` and `ingest` refuse it
    if run == "measured" and _ingests(study):  # `ingest`'s run: a rig's files make it
        rooted = root_options(root, study)
        command = " ".join(["graspcampaign ingest", shlex.quote(study), "FILE…", *map(shlex.quote, rooted)])
        return f"store the rig's measured records with `{command}` {then}."
    named = None if run in (None, configured_output(study, "run")) else run
    return f"run `{run_command(study, overrides, named, root)}` {then}."


def run_command(study: str, overrides: Sequence[str] = (), run: str | None = None,
                root: Path | str | None = None) -> str:
    """The ``graspcampaign run`` command, quoted for a shell (:func:`shlex.join`), that makes or
    resumes run ``run`` of ``study`` (None: no ``--run``, its configured run) under ``root`` (None:
    no ``--root``): the study, the ``overrides`` the run was given, as given (without them `run`
    refuses the run as started with another config), then ``--run`` and ``--root``
    (:func:`root_options`). The one builder of every `run` command a message suggests: a
    damaged run's advice, a missing run's, a Ctrl-C's. An override setting ``output.root`` keeps
    ``--root`` even for the default root, which would otherwise yield to it."""
    rooted = [] if root is None else root_options(root, study)
    if root is not None and not rooted and any(
            item.lstrip("+~").partition("=")[0] == "output.root" for item in overrides):
        rooted = ["--root", str(root)]
    named = [] if run is None else ["--run", run]
    return shlex.join(["graspcampaign", "run", study, *overrides, *named, *rooted])


def near_run(root: Path | str, study: str, run: str) -> str:
    """For a "no run at PATH" message: ``did you mean --run NAME? `` naming the stored run of
    ``study`` under ``root`` nearest ``run`` (a misspelt --run; :func:`~graspcampaign.core.words.meant`),
    or ``""``; the command that makes ``run`` follows it."""
    from graspcampaign.core.words import meant

    try:
        runs = [e.name for e in os.scandir(Path(root) / study)
                if os.path.isfile(os.path.join(e.path, "manifest.json"))]
    except OSError:
        return ""
    return meant(run, runs, "--run {}")


def case_twin(path: Path) -> Path | None:
    """The entry beside ``path`` whose name differs from ``path``'s only in case, when ``path`` is
    not there itself (by the directory's listing); else None."""
    try:
        names = [entry.name for entry in os.scandir(path.parent)]
    except OSError:  # no directory of the study yet: no run of it either
        return None
    twins = [name for name in names if name.lower() == path.name.lower()]
    return None if not twins or path.name in names else path.parent / twins[0]


def check_case_twin(path: Path, label: str) -> None:
    """Refuse the run at ``path`` (``label``: ``study/run``) when its directory is not there and
    one whose name differs from it only in case is (``smoke/Default`` beside ``smoke/default``):
    :func:`case_twin_problem`'s sentence."""
    if (problem := case_twin_problem(path, label)) is not None:
        raise UserInputError(problem)


def case_twin_problem(path: Path, label: str) -> str | None:
    """Why `run` and `ingest` refuse the run at ``path`` (``label``: ``study/run``), one sentence,
    when its directory is not there and one whose name differs from it only in case is; else None.
    `show` prints it as a note, and a "no run" message gives it in place of the command that would
    make the run (which would be refused).

    On a file system that ignores case (macOS's and Windows' by default, the FAT and exFAT of USB
    sticks) the two are one directory: a copy of the results there would merge the runs, and a run
    made there would add its trials to the other's. Read from the study directory's listing, which
    spells each name as it was made, so the answer is the same on either kind of file system."""
    if (twin := case_twin(path)) is None:
        return None
    add = (f"to add to that run, give --run {twin.name}; for a new one, "
           if os.path.lexists(twin / "manifest.json") else "")
    return (f"run {label} at {path}: its name differs only in case from {twin}, which is there "
            "already, and on a file system that ignores case (macOS, Windows, a USB stick) the two "
            f"are one directory; {add}give a run name that differs in more than case.")


#: The file a run or ingest holds its run by (``runner.run_lock``), in the run's directory.
LOCK_FILE = ".lock"


def held_by_a_run(run_dir: Path) -> bool:
    """Whether another process holds the run at ``run_dir`` (its lock, ``runner.run_lock``) now: a
    ``run`` or ``ingest`` is recording it. Probed with a shared lock let go at once, nothing made
    or written; no lock file, or a file system without locks, says no."""
    import fcntl

    try:
        handle = os.open(run_dir / LOCK_FILE, os.O_RDONLY | os.O_NONBLOCK)  # a named pipe: no wait
    except OSError:
        return False
    try:
        fcntl.flock(handle, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    except OSError:  # no locks here (NFS mounted with nolock): run_lock warned who ran it
        return False
    finally:
        os.close(handle)  # the shared lock goes with it
    return False


#: How long a run waits for a lock held shared, by :func:`held_by_a_run` probing it for an
#: instant (a `status` or `report` at the same moment), before it takes the run as held.
_PROBE_GRACE_S = 0.2


def lock_exclusive(handle: int) -> None:
    """Take the exclusive lock of a run's lock file (``runner.run_lock``) without waiting for
    another run, but over a probe's instant: a `status` or `report` asking :func:`held_by_a_run`
    holds the file shared for microseconds, and a run starting then was refused as "being run by
    another process". Retried for :data:`_PROBE_GRACE_S`; a run holding it raises
    ``BlockingIOError`` all the same."""
    import fcntl
    import time

    deadline = time.monotonic() + _PROBE_GRACE_S
    while True:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return
        except BlockingIOError:
            if time.monotonic() >= deadline:
                raise
            time.sleep(0.005)


def root_options(root: Path | str, study: str | None = None) -> list[str]:
    """The ``--root`` option a suggested command of ``study`` needs to reach ``root`` (none for
    the root it writes to by default, its ``output.root``: :func:`stored_root`); for
    :func:`shlex.join`, so that a root with a space stays one argument."""
    return [] if Path(root) == stored_root([] if study is None else [study]) else ["--root", str(root)]


def stored_root(studies: Sequence[str]) -> Path:
    """The results root the named studies are stored under when no ``--root`` is given: their
    ``output.root`` as their study files set it (read without Hydra; else ``conf/output``'s,
    ``results``), ``~`` read as the home directory (:func:`config_root`), as `run` stores them.

    Raises
    ------
    UserInputError
        Studies stored under different roots (one report writes one root's index), or a root in
        the home directory of no user.
    """
    from graspcampaign.campaign.studyfile import configured_output

    roots = ({study: configured_output(study, "root") for study in studies}
             or {"": configured_output(None, "root")})
    if len(set(roots.values())) > 1:
        raise UserInputError("the studies named are stored under different results roots (their "
                             f"output.root: {', '.join(f'{s} under {r}' for s, r in roots.items())}), "
                             "and one report writes one root's index; report them one root at a "
                             "time, with --root.")
    return Path(config_root(next(iter(roots.values()))))


def _ingests(study: str) -> bool:
    """Whether a study on the search path is a hardware protocol, whose measured records
    ``ingest`` stores (a study known only by its records is not)."""
    from graspcampaign.campaign.kind import get_kind
    from graspcampaign.campaign.studyfile import find_study, read_yaml

    try:
        kind = read_yaml(find_study(study), study=True).get("kind")
        return get_kind(str(kind)).ingest is not None
    except UserInputError:  # unknown, broken or not runnable: not a protocol to ingest into
        return False


def write_file(path: Path, data: str | bytes) -> None:
    """Write ``data`` (text as UTF-8) as ``path`` through a hidden temporary file beside it, so
    that a write stopped midway (Ctrl-C, a full disk) leaves ``path`` as it was, never half written,
    and no temporary file behind. The file written over keeps its permissions, and a symbolic link
    its place (the file it points to is written), as a write in place kept them; the temporary
    file is this process's own, so two processes writing one file never replace each other's."""
    if path.is_dir():  # os.replace would say only "Is a directory"
        raise UserInputError(f"{path} is a directory where this command writes a file; move it "
                             "aside and run the command again.")
    target = Path(os.path.realpath(path)) if path.is_symlink() else path
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode)
    except OSError:  # none yet: the umask's, as for any new file
        mode = None
    tmp = target.with_name(f".{target.name}.{os.getpid()}.tmp")
    try:
        tmp.write_bytes(data.encode("utf-8") if isinstance(data, str) else data)
        if mode is not None:
            os.chmod(tmp, mode)
        os.replace(tmp, target)
    except OSError as exc:  # named by the file it was for, not the temporary one
        raise OSError(exc.errno, exc.strerror, str(path)) from None
    finally:
        tmp.unlink(missing_ok=True)


#: A study or run name: one path component of ASCII letters, digits, '.', '_' and '-'.
_RUN_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}")


def usable_name(text: str) -> bool:
    """Whether ``text`` may name a study or a run (:func:`check_name`)."""
    return bool(_RUN_NAME.fullmatch(text))


def check_name(value: Any, key: str) -> str:
    """Check a study or run name: one path component, so results stay under the results root.

    Raises
    ------
    ConfigError
        Naming ``key`` and the allowed characters.
    """
    if not isinstance(value, str):  # a notebook's run=3 was stored as a number, then refused
        raise ConfigError(f"{key} = {value!r} is not a name: give it as text (a str).", key=key)
    text = value
    if not usable_name(text):
        raise ConfigError(f"{key} = {text!r} is not allowed; use ASCII letters (a-z, A-Z), digits, "
                          "'.', '_' and '-' (starting with a letter or digit, at most 100), so the "
                          "run stays inside the results directory.", key=key)
    return text


def run_dir(root: str | Path, study: str, run: str, key: str = "--run") -> Path:
    """Return ``<root>/<study>/<run>`` after checking both names stay one path component each."""
    return Path(root) / check_name(study, "study name") / check_name(run, key)


def run_path(study: Any, run: str | None = None) -> Path:
    """Return a composed study's ``<output.root>/<study>/<run>`` (``run`` None: ``output.run``).

    Raises
    ------
    ConfigError
        A run name that is not one plain path component (``../elsewhere``): runs stay inside the
        results root; an empty name is refused, never taken for the default run.
    """
    if run is not None:
        return run_dir(study.output.root, study.name, run)
    return run_dir(study.output.root, study.name, study.output.run, "output.run")
