"""The layers import one way: ``cli -> campaign, rig, report -> analysis -> core``.

Rules (STYLE.md "Layout and the direction of imports", issue 14):

* core imports only the standard library, numpy, scipy, trimesh, numba, and core itself;
* analysis imports only core and itself (besides the libraries it is built on);
* rig and report never import each other;
* report never imports a campaign trial kind, the runner, or rig; it reads runs through
  ``campaign.records`` / ``campaign.provenance`` and the typed paper values of ``campaign.paper``,
  and checks a results root with ``campaign.paths``;
* nothing but cli (and ``python -m``'s ``__main__``) imports cli;
* a name one module takes from another module of the package is public: no module imports an
  underscore name of another, or reads one as an attribute of an imported module.

The checker walks every module's ``import`` statements (top level and inside functions, relative
imports resolved) with :mod:`ast`; the last tests run it on a synthetic package that breaks each
rule, so the rules are known to bite.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

import graspcampaign

PACKAGE = Path(graspcampaign.__file__).parent
STDLIB = set(sys.stdlib_module_names)
CORE_LIBRARIES = {"numpy", "scipy", "trimesh", "numba"}
ANALYSIS_LIBRARIES = CORE_LIBRARIES | {"pandas", "statsmodels"}
REPORT_CAMPAIGN = ("campaign.records", "campaign.provenance", "campaign.paper",
                   "campaign.paper_hardware", "campaign.paths")


def imports(path: Path) -> list[str]:
    """Return the absolute module names ``path`` imports (relative ones resolved)."""
    return [name for name, _ in bound_imports(path)]


def bound_imports(path: Path) -> list[tuple[str, str]]:
    """Return (absolute name imported, local name bound) per import of ``path``: ``import a.b``
    imports ``a.b`` and binds ``a``; a star import binds ``*``."""
    tree = ast.parse(path.read_text(), filename=str(path))
    here = module_name(path).split(".")
    package = here if path.name == "__init__.py" else here[:-1]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(alias.name, alias.asname or alias.name.split(".")[0])
                    for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = ".".join(package[: len(package) - node.level + 1]) if node.level else ""
            module = ".".join(filter(None, [base, node.module]))
            out += [(module if alias.name == "*" else f"{module}.{alias.name}",
                     alias.asname or alias.name) for alias in node.names]
    return out


ROOTS: dict[Path, str] = {}


def module_name(path: Path) -> str:
    for root, name in ROOTS.items():
        if root in path.parents:
            rel = path.relative_to(root).with_suffix("")
            parts = [name, *rel.parts]
            return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
    raise AssertionError(f"{path} is outside every registered package root")


def layer_of(module: str) -> str:
    """Return the layer a ``graspcampaign.*`` module belongs to ("top" for the package files)."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in {
        "core", "analysis", "campaign", "rig", "report", "cli"} else "top"


def violations(package_dir: Path, package: str = "graspcampaign") -> list[str]:
    """Return one line per import that breaks a layer rule, for every module of the package."""
    ROOTS[package_dir] = package
    out = []
    for path in sorted(package_dir.rglob("*.py")):
        me = module_name(path)
        mine = layer_of(me)
        for name in imports(path):
            root = name.split(".")[0]
            ours = root == package
            target = layer_of(package + name[len(root):]) if ours else None
            full = package + name[len(root):] if ours else name
            bad = None
            if mine == "core":
                if not ours and root not in STDLIB | CORE_LIBRARIES:
                    bad = "core imports only the standard library and numerics"
                elif ours and target != "core":
                    bad = "core imports nothing above it"
            elif mine == "analysis":
                if not ours and root not in STDLIB | ANALYSIS_LIBRARIES:
                    bad = "analysis imports no plotting, config or storage library"
                elif ours and target not in ("core", "analysis"):
                    bad = "analysis imports core only"
            elif mine == "rig" and target == "report":
                bad = "rig never imports report"
            elif mine == "report":
                if target == "rig":
                    bad = "report never imports rig"
                elif target == "campaign" and not any(
                        full == f"{package}.{m}" or full.startswith(f"{package}.{m}.")
                        for m in REPORT_CAMPAIGN):
                    bad = "report reads runs through campaign.records/provenance/paper/paths only"
            if target == "cli" and mine != "cli" and me != f"{package}.__main__":
                bad = "only cli imports cli"
            if bad:
                out.append(f"{me} imports {full}: {bad}")
    return out


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def private_uses(package_dir: Path, package: str = "graspcampaign") -> list[str]:
    """Return one line per underscore name a module takes from another module of the package:
    imported by name, or read as an attribute of an imported module (``bench._qlv``)."""
    ROOTS[package_dir] = package
    modules = {module_name(path) for path in package_dir.rglob("*.py")}
    out = []
    for path in sorted(package_dir.rglob("*.py")):
        me = module_name(path)
        bound = {local: name for name, local in bound_imports(path)}
        taken = set(imports(path))
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            if isinstance(node, ast.Attribute) and _private(node.attr):
                chain = [node.attr]
                while isinstance(node := node.value, ast.Attribute):
                    chain.insert(0, node.attr)
                if isinstance(node, ast.Name) and node.id in bound:
                    target = bound[node.id]
                    # ``import a.b`` binds ``a``: the chain is then spelled out from ``a``
                    head = node.id if target.split(".")[0] == node.id else target
                    taken.add(".".join([head, *chain]))
        for name in sorted(taken):
            owner, _, attr = name.rpartition(".")
            if _private(attr) and owner in modules and owner != me:
                out.append(f"{me} takes {name}: a name shared between modules is public")
    return out


def test_the_package_keeps_every_layer_rule():
    assert violations(PACKAGE) == []


def test_no_module_takes_a_private_name_of_another():
    assert private_uses(PACKAGE) == []


def test_every_layer_is_walked():
    ROOTS[PACKAGE] = "graspcampaign"
    layers = {layer_of(module_name(p)) for p in PACKAGE.rglob("*.py")}
    assert {"core", "analysis", "campaign", "rig", "report", "cli"} <= layers


def _tree(tmp_path: Path, files: dict[str, str]) -> Path:
    pkg = tmp_path / "fakepkg"
    for rel, text in {**{f"{layer}/__init__.py": "" for layer in (
            "core", "analysis", "campaign", "campaign/kinds", "rig", "report", "cli")},
            "__init__.py": "", **files}.items():
        (pkg / rel).parent.mkdir(parents=True, exist_ok=True)
        (pkg / rel).write_text(text)
    return pkg


@pytest.mark.parametrize(("path", "source", "rule"), [
    ("core/mesh.py", "import pandas\n", "core imports only the standard library"),
    ("core/mesh.py", "from ..analysis import rates\n", "core imports nothing above it"),
    ("core/mesh.py", "def f():\n    from fakepkg.report import build\n",
     "core imports nothing above it"),
    ("analysis/rates.py", "import matplotlib.pyplot\n", "analysis imports no plotting"),
    ("analysis/rates.py", "from fakepkg.campaign.records import RunStore\n",
     "analysis imports core only"),
    ("analysis/rates.py", "from fakepkg import rig\n", "analysis imports core only"),
    ("rig/virtual.py", "from fakepkg.report import format\n", "rig never imports report"),
    ("report/build.py", "from fakepkg.rig.analysis import x\n", "report never imports rig"),
    ("report/spec.py", "from ..rig import test1\n", "report never imports rig"),
    ("report/build.py", "from fakepkg.campaign.kinds.hardware import export\n",
     "report reads runs through campaign.records"),
    ("report/build.py", "import fakepkg.campaign.runner\n",
     "report reads runs through campaign.records"),
    ("campaign/runner.py", "from fakepkg.cli import main\n", "only cli imports cli"),
])
def test_the_checker_catches_each_broken_rule(tmp_path, path, source, rule):
    pkg = _tree(tmp_path, {path: source})
    found = violations(pkg, "fakepkg")
    assert len(found) == 1 and rule in found[0], found


def test_the_checker_passes_allowed_imports(tmp_path):
    pkg = _tree(tmp_path, {
        "core/mesh.py": "import numpy\nfrom . import feature\nimport logging\n",
        "core/feature.py": "import trimesh\n",
        "analysis/rates.py": "import pandas\nfrom fakepkg.core import mesh\nfrom . import records\n",
        "analysis/records.py": "from scipy import stats\n",
        "report/build.py": "from fakepkg.campaign.records import RunStore\n"
                           "from fakepkg.campaign.paper import check_paper\n"
                           "from fakepkg.analysis import rates\nimport matplotlib\n",
        "rig/plan.py": "from fakepkg.analysis import rates\nfrom fakepkg.core import mesh\n",
        "cli/main.py": "from fakepkg.report import build\nfrom fakepkg.rig import plan\n",
    })
    assert violations(pkg, "fakepkg") == []


@pytest.mark.parametrize(("source", "name"), [
    ("from fakepkg.core.feature import _helper\n", "_helper"),
    ("from .feature import helper, _helper\n", "_helper"),
    ("def f():\n    from ..core.feature import _helper\n", "_helper"),
    ("from fakepkg.core import feature\nx = feature._helper(1)\n", "_helper"),
    ("from . import feature as f\nx = f._TABLE['a']\n", "_TABLE"),
    ("import fakepkg.core.feature\nx = fakepkg.core.feature._helper\n", "_helper"),
])
def test_the_checker_catches_a_private_name_taken_from_another_module(tmp_path, source, name):
    pkg = _tree(tmp_path, {"core/feature.py": "", "core/mesh.py": source})
    assert private_uses(pkg, "fakepkg") == [
        f"fakepkg.core.mesh takes fakepkg.core.feature.{name}: a name shared between modules "
        "is public"]


def test_the_checker_passes_public_names_and_private_attributes(tmp_path):
    pkg = _tree(tmp_path, {
        "core/feature.py": "class Table:\n    _cache = {}\n\ndef _own():\n    return _own\n",
        "core/mesh.py": "from fakepkg.core import feature\nfrom .feature import Table\n"
                        "import numpy as np\nx = feature.Table._cache, Table._cache\n"
                        "y = feature.__name__, np._NoValue\n",
    })
    assert private_uses(pkg, "fakepkg") == []


def store_privates(package_dir: Path, package: str = "graspcampaign") -> list[str]:
    """Return one line per private attribute of the run store (``campaign.records.RunStore``) read
    outside its module, as ``<object>._name``: what another module needs of the store is public."""
    from graspcampaign.campaign.records import RunStore

    ROOTS[package_dir] = package
    private = {name for name in vars(RunStore) if _private(name)}
    out = []
    for path in sorted(package_dir.rglob("*.py")):
        if path == package_dir / "campaign" / "records.py":
            continue
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            if (isinstance(node, ast.Attribute) and node.attr in private
                    and not (isinstance(node.value, ast.Name) and node.value.id == "self")):
                out.append(f"{module_name(path)}:{node.lineno} reads RunStore.{node.attr}")
    return out


def test_no_module_reads_a_private_of_the_run_store():
    """campaign.parts, integrity and repair read the store's _listing, _verified, _dir, _parts,
    _drop_rows and _keep_rows."""
    assert store_privates(PACKAGE) == []


def test_the_store_checker_catches_a_private_read_outside_the_store(tmp_path):
    pkg = _tree(tmp_path, {"campaign/records.py": "", "campaign/parts.py":
                           "def f(store):\n    return store._live('records'), store.path\n"})
    assert store_privates(pkg, "fakepkg") == ["fakepkg.campaign.parts:2 reads RunStore._live"]
