"""Exceptions that mean "bad usage or bad input" (exit code 2 on the command line)."""

from __future__ import annotations

import codecs
import errno
import os
import re

#: A value longer than this is shown by its start and its length (a 100,000-character override
#: echoed in full buries the sentence; longer than any path or key list a message names:
#: docs/decisions.md, "Long values in messages").
LONG_VALUE = 200
#: a long quoted value: its quotes are no apostrophe ("the run's", "trials'"), which a word
#: character stands beside
_LONG_QUOTED = re.compile(rf"(?<!\w)'([^'\n]{{{LONG_VALUE + 1},}})'(?!\w)")
#: a long unquoted word, the punctuation after it (the colon after a path) kept outside the cut
_LONG_WORD = re.compile(rf"([^\s']{{{LONG_VALUE + 1},}}?)([:;,.]?)(?=[\s']|$)")


def shorten(message: str) -> str:
    """Return ``message`` with every quoted value or word longer than :data:`LONG_VALUE`
    characters cut to its first 60 and its length: ``'xxxx... (100000 characters)'``."""
    def cut(text: str) -> str:
        return f"{text[:60]}... ({len(text)} characters)"

    message = _LONG_QUOTED.sub(lambda m: f"'{cut(m.group(1))}'", message)
    return _LONG_WORD.sub(lambda m: cut(m.group(1)) + m.group(2), message)


def disk_full(exc: BaseException) -> bool:
    """Whether ``exc`` is a write that found no space (a full disk, or a quota reached): the one
    failure whose advice is "free some space there and run the command again"."""
    return isinstance(exc, OSError) and exc.errno in (errno.ENOSPC, errno.EDQUOT)


#: Bytes of one file or directory name (NAME_MAX: Linux's ext4, xfs, btrfs and tmpfs, macOS's
#: APFS) and of a whole path (PATH_MAX in Linux's limits.h, its terminating NUL included).
NAME_MAX, PATH_MAX = 255, 4096


def too_long(path: str | os.PathLike) -> str | None:
    """Why the system would refuse ``path`` as too long (one name in it over :data:`NAME_MAX`
    bytes, or the whole over :data:`PATH_MAX`), in the words after the path; None if it is not.
    Checked before any work: ``os.path.exists`` answers False for such a path, so without it a
    command ran and then failed at its first write."""
    raw = os.fsencode(path)
    size = max((len(name) for name in raw.split(b"/")), default=0)
    if size > NAME_MAX:
        return (f"a name in it is {size} bytes long, more than the {NAME_MAX} a file system takes "
                "for one file or directory name; give a shorter one")
    if len(raw) >= PATH_MAX:
        return (f"it is {len(raw)} bytes long, more than the {PATH_MAX - 1} a path may have; "
                "give a shorter one")
    return None


def name_too_long(exc: BaseException) -> str | None:
    """The sentence for a path the system refused as too long (``ENAMETOOLONG``), naming it
    shortened (:func:`shorten`) and why (:func:`too_long`); None for any other exception."""
    if not (isinstance(exc, OSError) and exc.errno == errno.ENAMETOOLONG):
        return None
    path = os.fsdecode(exc.filename or "")
    return f"{shorten(path)}: {too_long(path) or 'it is too long for the system; give a shorter one'}."


def access_denied(exc: BaseException) -> str | None:
    """The sentence for a file or directory whose permissions keep this process out
    (``EACCES``: chmod 000, another user's private folder), naming the place to open up (the
    directory on its way that cannot be searched, if one: :func:`blocked`); None for any other
    exception. Said as what it is: the file is not damaged and nothing was changed."""
    if not (isinstance(exc, OSError) and exc.errno == errno.EACCES):
        return None
    from graspcampaign.core.words import PERMISSION_DENIED

    where = blocked(exc.filename) if exc.filename else "a file or directory"
    return f"{where}: {PERMISSION_DENIED}."


def cannot_write(exc: OSError) -> str:
    """What a write that failed with ``exc`` says after the place: :data:`~graspcampaign.core.words.
    PERMISSION_DENIED` for one this user may not write in, else ``cannot write there (<reason>)``
    (a read-only file system, a full disk)."""
    from graspcampaign.core.words import PERMISSION_DENIED

    if exc.errno == errno.EACCES:
        return f"cannot be written by this user: {PERMISSION_DENIED}"
    return f"cannot write there ({exc.strerror or type(exc).__name__})"


def blocked(path: str | os.PathLike) -> str:
    """``path``, or the first directory on its way this process may not search (a ``stat`` of
    what is in it is refused), which is then the place whose permissions to change."""
    path = os.fsdecode(path)
    for parent in reversed(_parents(path)):  # from the top down
        try:
            os.stat(os.path.join(parent, os.curdir))
        except PermissionError:
            return parent
        except OSError:
            break
    return path


def _parents(path: str) -> list[str]:
    """The directories above ``path``, nearest first (``a/b/c``: ``a/b``, ``a``)."""
    out, parent = [], os.path.dirname(path)
    while parent and parent not in out:
        out.append(parent)
        parent = os.path.dirname(parent)
    return out


def utf8_text(data: bytes) -> tuple[str | None, str]:
    """The bytes of a text file (a study file, a CSV of measured records) decoded once as UTF-8, a
    byte-order mark dropped, and ``""``; or None and why they are not UTF-8 text, in the words
    after the file's name.

    UTF-16 (a spreadsheet's "Unicode text" export) is named as such (:func:`core.text.utf16`,
    which a text mesh asks too): a CSV read as UTF-8 was cells and lines of nothing ("1 cells
    where the header has 22 columns"). Otherwise the line and the first byte that no UTF-8
    character holds.
    """
    from graspcampaign.core.text import utf16

    if utf16(data):
        return None, ": the file is UTF-16 text, not UTF-8"
    try:
        return data.decode("utf-8-sig"), ""
    except UnicodeDecodeError as exc:  # its start counts from after a byte-order mark
        return None, _not_utf8(data, exc.start + len(codecs.BOM_UTF8) * data.startswith(codecs.BOM_UTF8))


def _not_utf8(data: bytes, at: int, lines: int = 0) -> str:
    """The words after a file's name for the byte ``data[at]`` that no UTF-8 character holds, ``lines``
    newlines before ``data``."""
    line = lines + data[:at].count(b"\n") + 1
    return f", line {line}: the file is not UTF-8 text (byte 0x{data[at]:02x})"


#: The bytes :func:`utf8_file` decodes at a time (16 MiB).
UTF8_BLOCK = 1 << 24


def utf8_file(path: str | os.PathLike) -> str | None:
    """Why the file ``path`` is not UTF-8 text, in :func:`utf8_text`'s words, or None when it is:
    decoded block by block and the text dropped, never held whole (a Test 1 waveform file of the
    full schedule is 1.7 GiB; its text and the bytes beside it took three times that), nor to say
    why it is not UTF-8: the line is the newlines counted in the blocks before the bad byte."""
    from graspcampaign.core.text import UTF16_HEAD, utf16

    with open(path, "rb") as handle:
        block = handle.read(UTF16_HEAD)
        if utf16(block):
            return utf8_text(block)[1]
        # "utf-8", not "utf-8-sig": a byte-order mark is a character; the bytes count from the file's start
        decoder, lines = codecs.getincrementaldecoder("utf-8")(), 0
        while True:
            pending = decoder.getstate()[0]  # a character's first bytes, cut at the last block's end
            try:
                decoder.decode(block, final=not block)
            except UnicodeDecodeError as exc:  # its start counts in the pending bytes, then the block
                return _not_utf8(pending + block, exc.start, lines)
            if not block:
                return None
            lines += block.count(b"\n")  # the pending bytes are no newline (each is 0x80 or above)
            block = handle.read(UTF8_BLOCK)


class UserInputError(Exception):
    """Bad usage or bad input: a config, an override, a file or a command-line value.

    The message is one sentence naming what is wrong and where (long values shortened,
    :func:`shorten`). The command line prints it and exits with code 2; nothing already stored is
    changed.
    """

    def __init__(self, message: str = "", *args):
        super().__init__(shorten(str(message)), *args)


class ConfigError(UserInputError):
    """A study or group config is malformed: unknown key, wrong type or out-of-range value.

    Attributes
    ----------
    key : str or None
        The dotted key the sentence is about (``factors.mu[1]``, ``model.lambda1``), if one: the
        composition names the file and line it came from.
    """

    def __init__(self, message: str = "", key: str | None = None):
        super().__init__(message)
        self.key = key


class StudyNotRunnableError(UserInputError):
    """The study's trial kind is not implemented yet, so the study cannot run."""


class DamagedRunError(UserInputError):
    """A stored file of a run fails full verification (a damaged page, footer or checksum).

    Reading a run never changes it: the report and the status refuse such a run, naming it and
    the file; resuming the run quarantines the file and runs its trials again.

    Attributes
    ----------
    what : str
        What is wrong, without the run's path or the advice ("has a duplicate file ..."), for a
        page that names the run itself.
    """

    def __init__(self, message: str, what: str | None = None):
        super().__init__(message)
        self.what = what or message


class MissingSourceRunError(UserInputError):
    """A study whose design is read from another study's records, before that run exists.

    Attributes
    ----------
    source : str
        The ``study`` (or ``study --run name``) to run first.
    """

    def __init__(self, message: str, source: str):
        super().__init__(message)
        self.source = source


class StoreWriteError(UserInputError):
    """A file of the results store could not be written (a full disk, a failing device): the
    temporary file is removed and nothing stored before is changed."""
