"""Store runs as the code before the description left the config hash did (docs/decisions.md, "A
study's description is not part of its config hash"): shared by test_legacy_hash.py (ingest, status)
and test_runner.py (run).

Imported by name (``from legacy_hashing import ...``), as pytest puts this directory on the path.
"""

from __future__ import annotations

from contextlib import contextmanager

import pytest

from graspcampaign.campaign import provenance
from graspcampaign.campaign.grid import content_hash


def old_digest(config, *_):
    """provenance.config_digest as commit 073427b had it: the description inside the hash."""
    return content_hash({k: v for k, v in config.items() if k not in ("runner", "output")}, length=16)


@contextmanager
def old_hashing():
    """Store runs as the code before the description left the hash stored them."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(provenance, "config_digest", old_digest)
        patch.setattr(provenance, "config_hash", lambda s, *_: old_digest(provenance.study_dict(s)))
        yield
