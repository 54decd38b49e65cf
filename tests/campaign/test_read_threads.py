"""A stored file is read by the calling thread only: arrow's worker threads never call the Python
file object the tool opened. A threaded read left Python buffers of that file to arrow's workers,
which released them after the interpreter had begun to exit: `graspcampaign status` then aborted
about one time in seven ("terminate called without an active exception", exit 134)."""

from __future__ import annotations

import io
import threading

from graspcampaign.campaign import verify
from graspcampaign.campaign.records import RunStore


def test_every_read_of_a_record_file_is_made_by_the_calling_thread(tmp_path, past_the_tick,
                                                                    monkeypatch):
    store = RunStore(tmp_path / "results" / "unit" / "r1")
    path = store.write_shard("records", "a", [
        {"trial_id": f"a{i}", **{f"x{c}": 0.5 * i + c for c in range(8)}} for i in range(50)])
    readers = set()

    class Watched(io.BufferedReader):
        def read(self, *args):
            readers.add(threading.get_ident())
            return super().read(*args)

        def readinto(self, buffer):
            readers.add(threading.get_ident())
            return super().readinto(buffer)

    monkeypatch.setattr(verify, "open", lambda name, mode: Watched(io.FileIO(name, mode)),
                        raising=False)
    verify.read_file(path)  # the first read: every column, checksums verified
    table, _ = verify.read_file(path, ["trial_id", *(f"x{c}" for c in range(8))])  # a known file
    assert table.num_rows == 50 and table.column("x7").to_pylist()[1] == 7.5
    assert readers == {threading.get_ident()}
