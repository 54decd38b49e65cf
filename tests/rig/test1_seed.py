"""The seed and the per-specimen key the Test 1 tests share (tests/rig/conftest.py runs the
virtual bench with this seed; the tests draw their schedules with it).

Imported by name (``from test1_seed import ...``), as pytest puts this directory on the path.
"""

SEED = 7
KEY = ["material", "specimen", "environment"]
