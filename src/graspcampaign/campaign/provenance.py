"""Run provenance: the manifest (resolved config, hashes, versions, commit, host, times)."""

from __future__ import annotations

import dataclasses
import datetime as dt
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
from graspcampaign.campaign.grid import content_hash
from graspcampaign.campaign.schema import StudyCfg

_PACKAGES = ("numpy", "scipy", "trimesh", "pandas", "pyarrow", "joblib", "hydra-core",
             "omegaconf", "statsmodels", "matplotlib", "dask", "distributed", "scikit-learn")
_RESULT_FREE = ("runner", "output")  # where and how trials run never changes their results


def now_utc() -> str:
    """Return the current UTC time in ISO 8601."""
    return dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds")


def study_dict(study: StudyCfg) -> dict[str, Any]:
    """Return the resolved study config as plain data."""
    return dataclasses.asdict(study)


def config_hash(study: StudyCfg) -> str:
    """Hash the parts of the resolved config that can change a trial's result."""
    data = {k: v for k, v in study_dict(study).items() if k not in _RESULT_FREE}
    return content_hash(data, length=16)


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
        "config": study_dict(study),
    }


def read_manifest(path: Path) -> dict[str, Any] | None:
    if not path.exists():
        return None
    return json.loads(path.read_text())


def write_manifest(path: Path, manifest: dict[str, Any]) -> None:
    """Write the manifest atomically."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(json.dumps(manifest, indent=2, default=str))
    os.replace(tmp, path)


def config_changes(recorded: dict[str, Any] | None, study: StudyCfg, limit: int = 3) -> list[str]:
    """The first keys where ``study`` differs from a manifest's recorded ``config``, as
    ``'evaluator.n_cand 1000 -> 10'`` (only the parts that can change a result, as
    :func:`config_hash`); empty when the manifest holds no config to compare."""
    if not isinstance(recorded, dict):
        return []
    now = json.loads(json.dumps(study_dict(study), default=str))  # as the manifest stores it
    changes: list[str] = []

    def walk(old: Any, new: Any, key: str) -> None:
        if len(changes) >= limit or old == new:
            return
        if isinstance(old, dict) and isinstance(new, dict):
            for sub in [*old, *(k for k in new if k not in old)]:
                if key == "" and sub in _RESULT_FREE:
                    continue
                walk(old.get(sub, "<unset>"), new.get(sub, "<unset>"), f"{key}.{sub}" if key else sub)
            return
        changes.append(f"{key} {_text(old)} -> {_text(new)}")

    walk(recorded, now, "")
    return changes


def _text(value: Any) -> str:
    text = json.dumps(value, default=str) if not isinstance(value, str) else value
    return text if len(text) <= 60 else f"{text[:57]}..."
