"""No test module imports another test module: what several share lives in a helper module of its
directory (``synthetic_runs.py``, ``cli_checks.py``, ...) or, for a fixture, in its ``conftest.py``.

A fixture imported from another test module is a second copy of it (a session fixture is then built
once per module that holds it: tests/cli/test_damaged_round3.py built the runs of test_lost_parts.py
again), and a helper kept in a test module ties the two modules' edits together.
"""

from __future__ import annotations

import ast
from pathlib import Path

TESTS = Path(__file__).parent


def imported_test_modules(source: str) -> list[str]:
    """The test modules (``test_*``) that ``source`` imports, at any depth of its code."""
    names = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.append(node.module)
    return [name for name in names if name.split(".")[-1].startswith("test_")]


def test_no_test_module_imports_another():
    found = {str(path.relative_to(TESTS)): names for path in sorted(TESTS.rglob("*.py"))
             if (names := imported_test_modules(path.read_text()))}
    assert found == {}


def test_the_check_finds_each_form_of_import():
    source = ("import test_a\nimport test_b as b\nfrom test_c import x\n"
              "def f():\n    from test_d import y\n"
              "import synthetic_runs\nfrom cli_checks import invoke\n"
              "from graspcampaign.core import test_kind\n")
    assert imported_test_modules(source) == ["test_a", "test_b", "test_c", "test_d"]
