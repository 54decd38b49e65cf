"""The numerical core never imports the campaign, rig, report or CLI layers or their libraries."""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import graspcampaign

CORE = Path(graspcampaign.__file__).parent / "core"
# The standard library plus the numerical libraries; graspcampaign only through core itself.
ALLOWED_ROOTS = set(sys.stdlib_module_names) | {"numpy", "scipy", "trimesh", "numba", "graspcampaign"}


def _imports(path: Path):
    tree = ast.parse(path.read_text(), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative import: stays inside core
                yield "graspcampaign.core" + (f".{node.module}" if node.module else "")
            else:
                yield node.module


def test_core_imports_only_numerics():
    offenders = []
    files = sorted(CORE.rglob("*.py"))
    assert files, "core/ has no modules"
    for path in files:
        for name in _imports(path):
            root = name.split(".")[0]
            if root not in ALLOWED_ROOTS:
                offenders.append(f"{path.name}: {name}")
            elif root == "graspcampaign":
                parts = name.split(".")
                if len(parts) > 1 and parts[1] != "core":
                    offenders.append(f"{path.name}: {name}")
    assert not offenders, "core imports outside the numerical core: " + ", ".join(offenders)


def test_the_walker_sees_forbidden_imports(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("import pandas\nfrom graspcampaign.campaign import runner\nfrom . import mesh\n")
    assert list(_imports(bad)) == ["pandas", "graspcampaign.campaign", "graspcampaign.core"]
