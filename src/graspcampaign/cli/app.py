"""The ``graspcampaign`` Typer application and what every command shares: the options, the
one-sentence errors (exit 2, traceback with ``--debug``), the warnings printed once, and the checks
of ``--root`` and output paths made before any work.

The commands are in :mod:`graspcampaign.cli.main` (studies, runs, reports) and
:mod:`graspcampaign.cli.hardware` (schedule, ingest, plan).
"""

from __future__ import annotations

import logging
import math
import os
import sys
import traceback
import warnings
from pathlib import Path
from typing import Annotated

import typer
from typer.core import TyperGroup

try:  # typer >= 0.2x carries its own click
    from typer._click.exceptions import BadParameter, UsageError
except ImportError:  # pragma: no cover - older typer on click
    from click.exceptions import BadParameter, UsageError

#: what a value Typer could not convert should have been (pydantic's error type)
_WANTED = {"float_parsing": "a number", "int_parsing": "a whole number",
           "int_from_float": "a whole number", "bool_parsing": "true or false"}


def usage_sentence(exc: UsageError, command: str | None) -> str:
    """One sentence for a ``command`` line Typer cannot parse (a value of the wrong type, an
    unknown option, a missing argument), pointing to the command's help."""
    errors = getattr(exc.__cause__, "errors", lambda: [])()
    if isinstance(exc, BadParameter) and exc.param is not None and errors:
        hint = exc.param.opts[0] if exc.param.opts else exc.param.name
        what = _WANTED.get(errors[0]["type"], errors[0]["msg"].lower())
        text = f"{hint} {errors[0]['input']!r} is not {what}"
    else:
        text = exc.format_message().rstrip(".")
        text = text[:1].lower() + text[1:]
    return f"{text}; see graspcampaign {command + ' ' if command else ''}--help."


def repeated_option(command, args: list[str]) -> str | None:
    """The sentence for an option given twice in a command's ``args`` (click would keep the last
    silently), or None; a repeatable option (``--set``) and the words after ``--`` aside."""
    options = {name: param for param in command.params
               if param.param_type_name == "option" and not param.multiple
               for name in (*param.opts, *param.secondary_opts)}
    seen: dict[str, str] = {}
    words = iter(args)
    for word in words:
        if word == "--":
            return None
        name, equals, _ = word.partition("=")
        param = options.get(name)
        if param is None:
            continue
        typed = word if equals or param.is_flag else f"{word} {next(words, '')}".rstrip()
        if param.name in seen:
            return f"option {param.opts[0]} is given twice ({seen[param.name]}, then {typed}); give it once."
        seen[param.name] = typed
    return None


class _Commands(TyperGroup):
    """The commands, whose command-line errors are one sentence like every other refusal."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        for command in self.commands.values():  # typer's --help would keep a docstring's line breaks
            paragraphs = (command.help or "").split("\n\n")
            command.help = "\n\n".join(" ".join(paragraph.split()) for paragraph in paragraphs)

    def invoke(self, ctx):
        # the command's name and words, before click parses them (``_protected_args``: click 8.2)
        command, *args = [*(getattr(ctx, "_protected_args", None)
                            or getattr(ctx, "protected_args", [])), *ctx.args] or [None]
        if command in self.commands and (twice := repeated_option(self.commands[command], args)):
            fail(twice)
        try:
            return super().invoke(ctx)
        except UsageError as exc:
            if type(exc).__name__ == "NoArgsIsHelpError":  # help was shown
                raise
            fail(usage_sentence(exc, command if command in self.commands else None))


app = typer.Typer(
    cls=_Commands,
    add_completion=True,
    no_args_is_help=True,
    help="Reproducible experiment campaigns for soft-object grasp planning.",
    pretty_exceptions_enable=False,
)
state = {"debug": False}

StudyArg = Annotated[str, typer.Argument(help="Study name (see `list`) or path of a study file.",
                                         show_default=False)]
Overrides = Annotated[
    list[str] | None,
    typer.Argument(help="Hydra overrides, e.g. mu=[0.3] seeds=2 runner.n_jobs=2.", show_default=False),
]
RunOpt = Annotated[str | None, typer.Option("--run", help="Run name (default: the study's output.run).")]


def path_or_empty(value: str, option: str = "path") -> Path | str:
    """A path option's value, ``""`` kept as given (as a Path it would read as "."), so that an
    empty ``--root`` is refused instead of meaning the current directory; a leading ``~`` or
    ``~user`` is read as the shell reads it (quoted, ``--root '~/runs'`` reaches the tool as typed,
    and would make a directory named ``~``), and one whose home cannot be found is refused naming
    ``option``, as is an option's (not a file to read, ``option`` "path") beginning or ending with
    a space (:func:`spaced`). The one reading of every path option (:data:`RootOpt`,
    :func:`file_path`)."""
    from graspcampaign.campaign.paths import expand_home, shown

    if not value:
        return value
    if option != "path" and (why := spaced(value)):  # a file to read is found or not as named
        fail(f"{option} {value!r} {why}.")
    path, unknown = expand_home(value)
    if unknown:
        fail(f"{option} {shown(value)} {unknown}; give its path in full.")
    return path


def spaced(value: str) -> str | None:
    """Why a path to write or a results root ``value`` beginning or ending with a space is refused
    (after the value), or None: pasted with the space beside it, ``--root ' results'`` would make
    a folder named `` results`` beside ``results``, and `status` would not find the runs there."""
    if not value.strip(" "):
        return "is only spaces; give a path"
    if value[0] == " ":
        return (f"begins with a space, which would be part of the name; write {value.strip(' ')!r} "
                "(its full path, for a name that does begin with one)")
    if value[-1] == " ":
        return f"ends with a space, which would be part of the name; write {value.strip(' ')!r}"
    return None


def root_path(value: str) -> Path | str:
    """``--root``'s value (:func:`path_or_empty`)."""
    return path_or_empty(value, "--root")


def file_path(option: str, hint: str, example: str, makes_dirs: bool = False):
    """The parser of an option naming a file to write (``schedule --out``, ``plan --png``,
    ``reproduce --times``): :func:`path_or_empty`, and a value ending in a path separator refused
    as the directory it names, as an existing directory is (:func:`writable_stem`): as a Path the
    separator would be dropped and ``--out day1/`` would write ``day1.csv`` beside it. A value
    whose name is only a format suffix (``DIR/.csv``, :data:`FORMAT_SUFFIXES`, any case) is refused
    too: to a Path that is a hidden file's name with no suffix, so the file would be written as
    the hidden ``.csv`` (``.csv.csv`` for a stem), which a directory listing does not show.

    ``hint`` and ``example`` name the file to give instead ("a file stem such as", "schedule").
    A command that refuses a file in a missing directory (``makes_dirs`` false: a typo grows no
    tree) says the directory named does not exist and to create it, so the file suggested is one
    the command then takes."""
    separators = os.sep + (os.altsep or "")

    def parse(value: str) -> Path | str:
        if value.endswith(tuple(separators)) and value.rstrip(separators):  # "/" alone: the root
            named = f"{option} {value} ends in '{value[-1]}', so it names a directory"
            instead = f"give {hint} {Path(value) / example}."
            if makes_dirs or os.path.isdir(value):
                fail(f"{named}; {instead}")
            fail(f"{named}, and no directory {value.rstrip(separators)} exists; create one and "
                 f"{instead}")
        if Path(value).name.lower() in FORMAT_SUFFIXES:  # '.txt' is a hidden name to Path
            fail(f"{option} {value} names only a suffix, no file name (a name beginning with a dot "
                 f"is a hidden file's); give {hint} {Path(value).with_name(example)}.")
        return path_or_empty(value, option)
    return parse


def number(option: str, kind: type = float):
    """The parser of a numeric option (``plan --mass-kg``, ``report --jobs``): Typer's own reading
    of ``kind`` (pydantic's; a word it cannot read is refused by :func:`usage_sentence`), and a
    number written with an underscore refused, as an override's is (``check_overrides``): read as
    grouping digits, ``--mass-kg 0.1_5`` was 0.15; a number that is no finite number refused as
    typed (``--mass-kg 1e400`` was "inf is out of range"). The one reading of every numeric option."""
    def parse(value: str) -> float | int:
        from pydantic import TypeAdapter, ValidationError
        from pydantic_core import PydanticCustomError

        try:
            read = TypeAdapter(kind).validate_python(value)
        except ValidationError as exc:  # re-raised as is, it would be called a value error
            error = exc.errors()[0]
            raise PydanticCustomError(error["type"], error["msg"]) from None
        if isinstance(read, float) and not math.isfinite(read):  # said as typed, not as inf
            from graspcampaign.campaign.override_scan import not_finite

            fail(f"{option} {not_finite(str(value).strip()) or value}; give a finite number.")
        if "_" in str(value):
            fail(f"{option} {value} has an underscore, which is read as grouping digits, the "
                 f"number {read}; write the number without it ({read}, if that is what you meant).")
        return read
    return parse


RootOpt = Annotated[Path | None, typer.Option("--root", help="Results root (default: output.root, "
                                                             "i.e. results).",
                                              parser=root_path, metavar="path")]

# ValueErrors from the core and rig layers that mean bad input (a mesh, an ingested file).
_INPUT_ERRORS = {"MeshError", "IngestError"}


def fail(message: str, code: int = 2) -> None:
    """Print ``message`` as the command's error, long values shortened (``errors.shorten``, as
    every ``UserInputError`` is: a path of 300 characters echoed whole buried the sentence), and
    exit with ``code``."""
    from graspcampaign.errors import shorten

    typer.echo(f"error: {shorten(message)}", err=True)
    raise typer.Exit(code)


def guard(fn):
    """Turn bad-input exceptions into one sentence and exit 2 (traceback with --debug)."""
    import functools

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        from graspcampaign.errors import UserInputError, access_denied, disk_full, name_too_long

        try:
            return fn(*args, **kwargs)
        except typer.Exit:
            raise
        except KeyboardInterrupt:  # Typer exits 130 on it in silence; a command says more itself
            if state["debug"]:
                traceback.print_exc()
            typer.echo("interrupted (Ctrl-C).", err=True)
            raise typer.Exit(130) from None
        except (UserInputError, ValueError) as exc:
            if state["debug"]:
                traceback.print_exc()
            if isinstance(exc, UserInputError) or type(exc).__name__ in _INPUT_ERRORS:
                fail(str(exc))
            raise
        except OSError as exc:  # a full disk where no layer said so itself (a report's figure),
            long = name_too_long(exc) or access_denied(exc)  # a name too long to stat or open, or
            if not (disk_full(exc) or long):  # a place this user may not open (chmod 000)
                raise
            if state["debug"]:
                traceback.print_exc()
            if long:
                fail(long)
            fail(f"cannot write {exc.filename or 'a file'}: {os.strerror(exc.errno).lower()}; free "
                  "some space there and run the command again.")
    return wrapper


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Print a warning of the layers as one ``warning: ...`` line (no file, no line, no class)."""
    text = str(message)
    if text not in _shown:
        _shown.add(text)
        print(f"warning: {text}", file=sys.stderr)


_shown: set[str] = set()


@app.callback()
def _main(debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks and logs.")] = False):
    state["debug"] = debug
    _shown.clear()
    package_log = logging.getLogger("graspcampaign")
    if debug:
        logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    elif not package_log.handlers:
        package_log.addHandler(logging.NullHandler())  # warnings reach the user once, below
    warnings.showwarning = _show_warning


def _configure(cfg, root: Path | None):
    """Apply ``--root`` to a composed study (where records go never changes a result)."""
    if root is not None:
        cfg.output.root = str(root)
    return cfg


def check_root(root: Path | None, write: bool = False) -> None:
    """Refuse a bad ``--root`` (empty, a file, unwritable when ``write``) before any work."""
    if root is not None:
        from graspcampaign.campaign import paths

        paths.check_root(root, "--root", write=write)


def compose(study: str, overrides: list[str] | None, root: Path | None = None):
    from graspcampaign.campaign.compose import compose_study

    return _configure(compose_study(study, overrides or []), root)


#: Suffixes naming a file format of their own (a table, a workbook, text, a picture, a page, an
#: archive): a command refuses to write another format under a name ending so (``other_format``).
FORMAT_SUFFIXES = (".csv", ".tsv", ".txt", ".json", ".yaml", ".yml", ".parquet", ".xlsx", ".xls",
                   ".ods", ".png", ".jpg", ".jpeg", ".svg", ".pdf", ".html", ".md", ".zip", ".gz")


def other_format(out: Path, writes: tuple[str, ...]) -> bool:
    """Whether ``out``'s suffix names a format (:data:`FORMAT_SUFFIXES`, any case) other than
    those of ``writes``: the file written would not be what its name says."""
    return out.suffix.lower() in FORMAT_SUFFIXES and out.suffix.lower() not in writes


def outside_runs(out: Path, option: str) -> None:
    """Refuse an output ``out`` at or inside a run's directory, which holds that run's files only (a
    file in its records/ would have every command refuse the run as damaged)."""
    from graspcampaign.campaign.paths import run_around

    if (run := run_around(out)) is not None:
        fail(f"{option} {out} is inside the directory of run {run.parent.name}/{run.name} ({run}), "
             "which holds that run's files only; give a path outside it.")


def writable_stem(out: Path, option: str, hint: str = "a file stem such as",
                   example: str = "schedule") -> Path:
    """Check that files ``<out>.<ext>`` (or ``out``) can be written, before any work: a directory
    in its place, a file on its path or a directory that cannot be written is bad input."""
    from graspcampaign.campaign.paths import control_character, path_problem

    if out == "":  # as a Path, "" would read "." (path_or_empty)
        fail(f"{option} is empty; give {hint} {example}.")
    if (control := control_character(out, option)) is not None:
        fail(control)
    outside_runs(out, option)
    why = path_problem(out, write=True, directory=False)
    if why == "is a directory, not a file":
        fail(f"{option} {out} is a directory; give {hint} {out / example}.")
    if why is not None:
        fail(f"{option} {out}: {why}.")
    return out
