"""Run provenance: the manifest (resolved config, hashes, versions, commit, host, times)."""

from __future__ import annotations

import dataclasses
import datetime as dt
import itertools
import json
import os
import platform
import socket
import subprocess
import sys
from importlib import metadata
from pathlib import Path
from typing import Any

import graspcampaign
from graspcampaign.campaign.former_names import current_config
from graspcampaign.campaign.grid import content_hash
from graspcampaign.campaign.override import group
from graspcampaign.campaign.paths import path_problem
from graspcampaign.campaign.schema import StudyCfg
from graspcampaign.errors import DamagedRunError, UserInputError, access_denied

_PACKAGES = ("numpy", "scipy", "trimesh", "pandas", "pyarrow", "joblib", "hydra-core",
             "omegaconf", "statsmodels", "matplotlib", "dask", "distributed", "scikit-learn")
#: What never changes a trial's result: where and how trials run, and the text describing them.
_RESULT_FREE = ("runner", "output", "description")
#: What a body's preparation (``prepared/``) depends on no more than a trial's result depends on
#: :data:`_RESULT_FREE`: which trials the design forms (a preparation is keyed and seeded by its
#: body and the study seed alone) and what the report compares them with.
PREPARATION_FREE = (*_RESULT_FREE, "factors", "seeds", "repeats", "zip", "method_factors", "paper",
                    "compare_with", "extension")
#: What the hash left out before the description left it too (docs/decisions.md): runs stored
#: then carry this legacy digest, which still names their config.
_LEGACY_FREE = ("runner", "output")


def now_utc() -> str:
    """Return the current UTC time in ISO 8601."""
    return dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds")


def study_dict(study: StudyCfg) -> dict[str, Any]:
    """Return the resolved study config as plain data."""
    return dataclasses.asdict(study)


def config_hash(study: StudyCfg, manifest: dict[str, Any] | None = None) -> str:
    """Hash the parts of the resolved config that can change a trial's result.

    With the (verified) ``manifest`` of a run that stored this same config under its legacy
    digest, or under a factor's former name (``former_names.current_config``), return the run's
    digest: the run keeps one name for its config across sessions."""
    digest = config_digest(study_dict(study))
    if manifest and manifest["config_hash"] != digest and config_digest(
            current_config(manifest["config"])) == digest:
        return manifest["config_hash"]
    return digest


def config_digest(config: dict[str, Any], free: tuple[str, ...] = _RESULT_FREE) -> str:
    """:func:`config_hash` of a resolved config as plain data (a manifest's ``config``), leaving
    out the top-level keys ``free``."""
    return content_hash({k: v for k, v in config.items() if k not in free}, length=16)


def preparation_hash(config: dict[str, Any]) -> str:
    """The digest of what a body's preparation depends on in a resolved config as plain data (all
    but :data:`PREPARATION_FREE`; a factor's former name read as its current one), kept by each
    ``run`` session (``preparation_hash``)."""
    return config_digest(current_config(config), PREPARATION_FREE)


def git_state() -> dict[str, Any]:
    """Return the commit and dirty flag of the source checkout, if it is one."""
    src = Path(graspcampaign.__file__).resolve().parent
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=src, capture_output=True,
                                text=True, timeout=5, check=True).stdout.strip()
        dirty = bool(subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                                    cwd=src, capture_output=True, text=True, timeout=5,
                                    check=True).stdout.strip())
    except (OSError, subprocess.SubprocessError):
        return {"commit": None, "dirty": None}
    return {"commit": commit, "dirty": dirty}


def code_version() -> str:
    """Return the code version a run is tied to: package version plus git commit."""
    commit = git_state()["commit"]
    return f"{graspcampaign.__version__}+{commit[:12]}" if commit else graspcampaign.__version__


def package_versions() -> dict[str, str | None]:
    versions: dict[str, str | None] = {"python": sys.version.split()[0]}
    for name in _PACKAGES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = None
    return versions


def new_manifest(study: StudyCfg, run: str, n_trials: int, source: str) -> dict[str, Any]:
    """Return the manifest of a run that starts now."""
    return {
        "study": study.name,
        "run": run,
        "kind": study.kind,
        "source": source,
        "n_trials": n_trials,
        "config_hash": config_hash(study),
        "code_version": code_version(),
        "git": git_state(),
        "packages": package_versions(),
        "host": {"name": socket.gethostname(), "platform": platform.platform(),
                 "cpus": os.cpu_count()},
        "started_at": now_utc(),
        "finished_at": None,
        "sessions": [],
        "digests": True,  # every file of the run carries the digest of its values (records.py)
        "format": MANIFEST_FORMAT,
        "config": study_dict(study),
    }


def ingested(manifest: dict[str, Any]) -> bool:
    """Whether ``ingest`` stored the run (its sessions name the files they ingested): a rig's
    measurements or a virtual rig's exports, never added to by ``run``."""
    sessions = manifest.get("sessions") if isinstance(manifest.get("sessions"), list) else []
    return manifest.get("source") == "measured" or any(
        isinstance(s, dict) and "ingested" in s for s in sessions)


def one_config(manifest: dict[str, Any], config_hash: str | None = None) -> bool:
    """Whether every session of the run ran one config: the manifest's (and ``config_hash``, when
    given). A session that names no config (an ``ingest`` of an earlier version) may have run any."""
    want = manifest["config_hash"] if config_hash is None else config_hash
    return manifest["config_hash"] == want and all(
        s.get("config_hash") == want for s in manifest["sessions"])


def design_change(manifest: dict[str, Any]) -> tuple[str, str] | None:
    """How a run's design differs from its study file's default, as its manifest records it: the
    overrides as given, and its trial count ("4 of the study's 18 trials"); None for a run of the
    default design, or one stored before manifests recorded the default."""
    default = manifest.get("default_design")
    if not isinstance(default, dict) or default.get("config_hash") == manifest.get("config_hash"):
        return None
    size = default.get("n_trials")
    of = f" of the study's {size}" if isinstance(size, int) else ""
    changed = [o for o in map(str, manifest.get("overrides") or [])  # not where or how trials ran
               if group(o) not in _RESULT_FREE]
    return " ".join(changed), f"{manifest.get('n_trials')}{of} trials"


def paper_overrides(manifest: dict[str, Any]) -> list[str]:
    """The overrides of a run's ``manifest`` that replaced a value of its ``paper:`` block (the values
    its report shows as the paper's), as given."""
    return [o for o in overrides_given(manifest) or [] if group(o) == "paper"]


def overrides_given(manifest: Any) -> list[str] | None:
    """The overrides a run's ``manifest`` keeps as they were given (``overrides``,
    :func:`~graspcampaign.campaign.compose.as_given`), which a command resuming the run must give
    again; None where it keeps none (a run made by the API, or stored before manifests kept them)
    or keeps something other than a list of text."""
    given = manifest.get("overrides") if isinstance(manifest, dict) else None
    return given if isinstance(given, list) and all(isinstance(item, str) for item in given) else None


def study_given(manifest: Any, name: str) -> str:
    """The study a command resuming the run names: the absolute path of the study file the run was
    started from where it was given by path (``study_file``, :func:`~graspcampaign.campaign.compose.
    as_given`), else ``name``, the study's name (a manifest stored before it kept the file, too)."""
    given = manifest.get("study_file") if isinstance(manifest, dict) else None
    return given if isinstance(given, str) and given else name


def last_design(manifest: dict[str, Any]) -> dict[str, Any] | None:
    """The last session that names its design's trial count (``n_trials``): a ``run`` session
    since sessions record it; None for a run stored before, or only ingested."""
    sessions = manifest.get("sessions") if isinstance(manifest.get("sessions"), list) else []
    return next((s for s in reversed(sessions) if isinstance(s, dict)
                 and isinstance(s.get("n_trials"), int) and not isinstance(s["n_trials"], bool)), None)


def run_size(manifest: dict[str, Any]) -> Any:
    """The trial count of the run's design: the design of the session that last ran it (a run
    resumed under ``--allow-drift`` runs its new design), else the one it was started with."""
    last = last_design(manifest)
    return manifest.get("n_trials") if last is None else last["n_trials"]


def run_complete(manifest: dict[str, Any], n_recorded: int) -> bool:
    """Whether every trial of the run's design (:func:`run_size`) is recorded: as the session
    that last ran it counted them on ending (``recorded``; one still running or killed counted
    none), since a drifted run may also hold trials of an earlier design that its new one left
    out; for a run whose sessions name no design, its ``n_recorded`` trials are its ``n_trials``."""
    last = last_design(manifest)
    if last is None:
        return n_recorded == manifest.get("n_trials")
    return last.get("recorded") == last["n_trials"]


#: The manifest's fields every command relies on, and what each must hold.
_COUNT = "a whole number of trials"
_FIELDS: dict[str, tuple[tuple[type, ...], str]] = {
    "study": ((str,), "a name"), "run": ((str,), "a name"), "kind": ((str,), "a trial kind"),
    "source": ((str,), "a data source"), "n_trials": ((int,), _COUNT),
    "config_hash": ((str,), "a hash"), "code_version": ((str,), "a version"),
    "started_at": ((str,), "a time"), "finished_at": ((str, type(None)), "a time or null"),
    "sessions": ((list,), "a list of sessions"), "config": ((dict,), "the resolved config"),
}
_OPTIONAL = {"n_recorded": ((int,), _COUNT), "digests": ((bool,), "true or false"),
             "overrides": ((list,), "a list of overrides"), "study_file": ((str,), "a study file's path"),
             "default_design": ((dict,), "the study file's default design"),
             "format": ((int,), "a format number")}

#: The layout of a run's files this code writes and reads (the manifest's ``format``; a manifest
#: without one is format 1). Raise it when a run stored now could not be read as one stored
#: before (a file, table or column moved or changed meaning, not merely added): this code then
#: refuses a run of a later format instead of misreading it (docs/decisions.md).
MANIFEST_FORMAT = 1


def read_manifest(path: Path) -> dict[str, Any] | None:
    """Return a run's manifest, or None if the run has none.

    Raises
    ------
    DamagedRunError
        A manifest that cannot be read or is not what the tool writes (not JSON, not an object, a
        field missing or of the wrong type), in one sentence naming the file and what to do: the
        run's records cannot be checked or used without it.
    UserInputError
        A manifest this user may not open (:func:`~graspcampaign.errors.access_denied`): not
        damaged, so no advice to restore it.
    """
    if not (path.exists() or path.is_symlink()):
        return None
    why = None if path.is_file() or path.is_dir() else f"it {path_problem(path, directory=False)}"
    try:  # a byte order mark (an editor's re-save) carries no content: RFC 8259 lets a reader skip it
        text = "" if why else path.read_bytes().decode("utf-8").removeprefix("\ufeff")
    except IsADirectoryError:
        why = "it is a directory, not a file"
    except PermissionError as exc:  # not damaged: this user may not open it
        raise UserInputError(access_denied(exc)) from None
    except OSError as exc:
        why = f"it cannot be read: {exc.strerror or type(exc).__name__}"
    except UnicodeDecodeError as exc:
        why = f"not UTF-8 text: byte {exc.start} is 0x{exc.object[exc.start]:02x}"
    if why is None:
        try:
            manifest = json.loads(text) if text.strip() else None
        except json.JSONDecodeError as exc:
            why = f"not valid JSON: {exc.msg} (line {exc.lineno}, column {exc.colno})"
        else:
            why = _manifest_problem(manifest) if text.strip() else "it is empty"
    if why is not None:
        raise manifest_error(path, why)
    _check_not_newer(path.parent, manifest)
    mismatch = manifest_mismatch(path.parent, manifest)
    if mismatch:
        run_path, what = path.parent, MISMATCH.format(mismatch[0])
        raise DamagedRunError(f"run {run_path.parent.name}/{run_path.name} at {run_path} has "
                              f"{what}; {mismatch[1]}.", f"has {what}")
    return manifest


def _release(version: str) -> tuple[int, ...]:
    """The release numbers of a code version ("0.2.1+3f2a..." -> (0, 2, 1)); () if none."""
    release = version.partition("+")[0]
    numbers = []
    for part in release.split("."):
        digits = "".join(itertools.takewhile(str.isdigit, part))
        if not digits:
            break
        numbers.append(int(digits))
    return tuple(numbers)


def _check_not_newer(run_path: Path, manifest: dict[str, Any]) -> None:
    """Refuse a run stored in a later layout than this code reads (``format``), and warn, once, of
    one stored by a later release in this layout: a later release may compute or name things
    otherwise (the two versions named), but its files read as this code's. Every manifest read
    passes here, so the git commit (two git processes, :func:`code_version`) is asked for only
    to name this code in a refusal or warning: the release compared is the package's."""
    label, theirs = f"{run_path.parent.name}/{run_path.name}", manifest["code_version"]
    if manifest.get("format", 1) > MANIFEST_FORMAT:
        raise UserInputError(f"run {label} at {run_path} was stored by graspcampaign {theirs} in "
                             f"file layout {manifest['format']}, and this code ({code_version()}) "
                             f"reads layout {MANIFEST_FORMAT} at most; read it with graspcampaign "
                             f"{theirs.partition('+')[0]} or later.")
    if _release(theirs) > _release(graspcampaign.__version__):
        import warnings

        warnings.warn(f"run {label} was stored by graspcampaign {theirs}, a later release than "
                      f"this code ({code_version()}); it is read as this code reads it.",
                      stacklevel=3)


#: How a run's problem names a manifest that does not describe the run.
MISMATCH = "a manifest.json that does not match the run ({})"


def kind_facts_or_none(kind: str) -> dict[str, Any]:
    """The facts of trial kind ``kind`` (``catalog.kind_facts``: cached, nothing numerical
    imported), or {} for a kind not available here."""
    from graspcampaign.campaign.catalog import kind_facts
    from graspcampaign.campaign.kind import kind_available

    return kind_facts(kind) if kind_available(kind) else {}


def record_sources(source: str) -> set[str]:
    """The sources of the records a run stored as ``source`` may hold: its own, and in a run
    stored as measured a virtual rig's too (``ingest`` stores measured records of a virtual rig's
    protocol, or its exports, in a run of their own)."""
    return {source, "virtual"} if source == "measured" else {source}


def manifest_mismatch(run_path: Path, manifest: dict[str, Any]) -> tuple[str, str] | None:
    """``(why, advice)`` if a well-formed manifest does not describe the run at ``run_path``, else
    None: its ``study`` and ``run`` are the directory's (where the run is stored is what every
    page calls it), its ``study`` and ``kind`` its config's, its ``config_hash`` the hash of its
    config (the drift check and the records' configs rely on it), its ``source`` one its trial
    kind makes (a simulated run labelled measured would be reported as hardware data)."""
    restore = "restore the file from a backup"
    stored_as = f"{run_path.parent.name}/{run_path.name}"
    for field, truth in (("study", run_path.parent.name), ("run", run_path.name)):
        if manifest[field] != truth:
            where = {"study": f"{manifest['study']}/{run_path.name}",
                     "run": f"{run_path.parent.name}/{manifest['run']}"}[field]
            return (f"{field} is {manifest[field]!r}, but the run is stored as {stored_as}",
                    f"{restore}, or put a moved run directory back as {where}")
    config = manifest["config"]
    for field, key in (("study", "name"), ("kind", "kind")):
        if key in config and config[key] != manifest[field]:
            return f"{field} is {manifest[field]!r}, but its config says {config[key]!r}", restore
    digest = config_digest(config)
    if manifest["config_hash"] not in (digest, config_digest(config, _LEGACY_FREE)):
        return (f"config_hash is {manifest['config_hash']}, but its config hashes to {digest}",
                restore)
    made = kind_facts_or_none(manifest["kind"]).get("source")
    if made is not None and made not in record_sources(manifest["source"]):
        return (f"source is {manifest['source']!r}, but trial kind {manifest['kind']} makes {made} "
                "records", restore)
    return None


def _manifest_problem(manifest: Any) -> str | None:
    """What is wrong with a parsed manifest, or None."""
    if not isinstance(manifest, dict):
        return f"it holds a JSON {_json_type(manifest)}, not an object of the run's fields"
    for key, (types, what) in [*_FIELDS.items(), *((k, v) for k, v in _OPTIONAL.items()
                                                     if k in manifest)]:
        if key not in manifest:
            return f"it has no {key} field"
        value = manifest[key]
        if not isinstance(value, types) or (isinstance(value, bool) and bool not in types) or (
                types == (int,) and value < 0):
            shown = json.dumps(value)
            return f"{key} is {shown if len(shown) <= 40 else shown[:37] + '...'}, not {what}"
    if not all(isinstance(s, dict) for s in manifest["sessions"]):
        return "sessions holds an entry that is not an object"
    # a session is listed when its counts are written; before that (versions up to the integrity
    # checks) a run was stored with no session until its first one ended, unfinished, uncounted
    if not manifest["sessions"] and ("n_recorded" in manifest or manifest["finished_at"]):
        return ("sessions is [], but a run with n_recorded or finished_at has had at least one "
                "session")
    return None


def _json_type(value: Any) -> str:
    return {list: "list", str: "string", int: "number", float: "number", bool: "boolean",
            type(None): "null"}.get(type(value), type(value).__name__)


def manifest_error(path: Path, why: str) -> DamagedRunError:
    """The one sentence for a run whose manifest cannot be used."""
    run_path = path.parent
    return DamagedRunError(
        f"run {run_path.parent.name}/{run_path.name} at {run_path} has a damaged manifest.json "
        f"({why}); its records cannot be checked without it, so restore the file from a backup "
        "or move the run directory aside and run the study again.",
        f"has a damaged manifest.json ({why})")


def write_manifest(path: Path, manifest: dict[str, Any]) -> None:
    """Write the manifest atomically; a failed write (a full disk) leaves the file as it was and
    no temporary file behind (:class:`~graspcampaign.errors.StoreWriteError`)."""
    from graspcampaign.campaign.records import writing

    tmp = path.with_name(f".{path.name}.tmp")
    with writing(path, tmp):
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp.write_text(json.dumps(manifest, indent=2, default=str))
        os.replace(tmp, path)


def config_changes(recorded: dict[str, Any] | None, study: StudyCfg, limit: int = 3,
                   free: tuple[str, ...] = _RESULT_FREE) -> list[str]:
    """The first keys where ``study`` differs from a manifest's recorded ``config``, as
    ``'evaluator.n_cand 1000 -> 10'``, leaving out the top-level keys ``free`` (as
    :func:`config_digest`: by default those that cannot change a result, as :func:`config_hash`);
    empty when the manifest holds no config to compare."""
    if not isinstance(recorded, dict):
        return []
    now = json.loads(json.dumps(study_dict(study), default=str))  # as the manifest stores it
    changes: list[str] = []

    def walk(old: Any, new: Any, key: str) -> None:
        if len(changes) >= limit or old == new:
            return
        if isinstance(old, dict) and isinstance(new, dict):
            for sub in [*old, *(k for k in new if k not in old)]:
                if key == "" and sub in free:
                    continue
                walk(old.get(sub, "<unset>"), new.get(sub, "<unset>"), f"{key}.{sub}" if key else sub)
            return
        changes.append(f"{key} {_text(old)} -> {_text(new)}")

    walk(recorded, now, "")
    return changes


def _text(value: Any) -> str:
    text = json.dumps(value, default=str) if not isinstance(value, str) else value
    return text if len(text) <= 60 else f"{text[:57]}..."


class DriftError(UserInputError):
    """The resolved config or code changed since the run started."""


def config_drift(manifest: dict[str, Any], study: StudyCfg) -> str:
    """How ``study`` differs from the config the run started with ("" if it is that config, under
    either digest), naming what changed: ``resolved study config (seed 7 -> 8)``."""
    if manifest.get("config_hash") == config_hash(study, manifest):
        return ""
    keys = config_changes(manifest.get("config"), study)
    return "resolved study config" + (f" ({', '.join(keys)})" if keys else "")


def ingest_refusal(manifest: dict[str, Any], study: StudyCfg, label: str, path: Path) -> str:
    """What ``ingest`` says, refusing measured records of ``study`` for the run ``label`` at ``path``
    ("" if it would not): only the config counts, measured records do not depend on the code."""
    changed = config_drift(manifest, study)
    return (f"run {label} at {path} was started with a different {changed}; records of another config "
            "are stored in a run of their own, so choose another run name (--run NAME).") if changed else ""


def check_drift(manifest: dict[str, Any], study: StudyCfg, allow_drift: bool, path: Path) -> None:
    """Refuse to add ``study``'s trials to a run started with another resolved config or code
    version (unless ``allow_drift``), naming what changed."""
    if allow_drift:
        return
    changes = [changed] if (changed := config_drift(manifest, study)) else []
    if manifest.get("code_version") != code_version():
        changes.append(f"code version ({manifest.get('code_version')} -> "
                       f"{code_version()})")
    if changes:
        resume = as_started(manifest, study, path) if changed and len(changes) == 1 else ""
        raise DriftError(
            f"run {path} was started with a different {' and '.join(changes)}; {resume}use a new "
            "run name (output.run=NAME or --run NAME) or pass --allow-drift to mix them."
        )


def as_started(manifest: dict[str, Any], study: StudyCfg, path: Path) -> str:
    """``"resume it as started (COMMAND), "`` where the overrides the run was started with
    (``overrides``, as given) compose to its config today, so that command resumes it; ``""``
    otherwise (the study file itself changed, or the manifest keeps no overrides)."""
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.paths import run_command
    from graspcampaign.errors import UserInputError

    given, named = overrides_given(manifest), study_given(manifest, study.name)
    if given is None:
        return ""
    try:
        again = compose_study(named, list(given))
    except UserInputError:
        return ""
    if config_drift(manifest, again):
        return ""
    return f"resume it as started ({run_command(named, given, path.name, path.parent.parent)}), "
