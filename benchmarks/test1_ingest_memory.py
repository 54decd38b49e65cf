"""Peak memory and wall time of ``graspcampaign ingest test1_bench`` on one waveform CSV of part of
the full Test 1 schedule (every 40th and every 10th of the 19,168 events of ``test1_schedule``,
seed 701 as campaigns/test1_bench.yaml), written as ``benchmarks/test1_file_size.py`` writes the
whole (the virtual bench's waveforms in the waveform sheet's columns, the channels as the sensors
resolve them), each ingest in a process of its own, and extrapolated in a line through the two
to the whole schedule's 32.8 M samples (``test1_file_size.py``). Peak memory is the process's
maximum resident set (``resource.getrusage``), its imports included.

Sets the figures of docs/decisions.md, "A Test 1 waveform file is read from the file".

Run: ``python benchmarks/test1_ingest_memory.py`` (some 3 minutes and 250 MB of disk).
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

from graspcampaign.rig.test1 import test1_schedule
from graspcampaign.rig.test1_bench import _waves_frame, run_events

CAMPAIGN_SAMPLES = 32.8e6  # benchmarks/test1_file_size.py: every event of the full schedule
CHUNK = 500

_INGEST = """
import resource, runpy, sys, time
start = time.perf_counter()
sys.argv = ["graspcampaign", "ingest", "test1_bench", sys.argv[1], "--root", sys.argv[2]]
try:
    runpy.run_module("graspcampaign", run_name="__main__")
except SystemExit as stop:
    assert not stop.code, stop.code
print(time.perf_counter() - start, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024)
"""

def write(stride: int, path: Path) -> int:
    """Write every ``stride``-th event's waveforms to ``path``; return its number of samples."""
    rows = test1_schedule(701).to_dict("records")[::stride]
    samples = 0
    with path.open("w", newline="") as out:
        for i in range(0, len(rows), CHUNK):
            frame = _waves_frame(run_events(rows[i:i + CHUNK], 701, keep_waveforms=True, fit=False)[2])
            frame.to_csv(out, index=False, header=i == 0)
            samples += len(frame)
    return samples


def main() -> None:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for stride in (40, 10):
            path = Path(tmp) / f"waves_{stride}.csv"
            samples = write(stride, path)
            start = time.perf_counter()
            root = Path(tmp) / f"root{stride}"
            done = subprocess.run([sys.executable, "-c", _INGEST, str(path), str(root)],
                                  capture_output=True, text=True, check=True)
            seconds, peak = (float(v) for v in done.stdout.split()[-2:])
            rows.append((stride, samples, path.stat().st_size, peak, time.perf_counter() - start, seconds))
    print("| events | samples | file (MiB) | peak RSS (GiB) | wall time (s), process | of it, the ingest |")
    print("|---|---:|---:|---:|---:|---:|")
    for stride, samples, size, peak, wall, seconds in rows:
        print(f"| every {stride}th | {samples:,} | {size / 2**20:.0f} | {peak / 2**30:.2f} | {wall:.1f} | "
              f"{seconds:.1f} |")
    (_, n0, _, p0, w0, _), (_, n1, _, p1, w1, _) = rows
    slope, per = (p1 - p0) / (n1 - n0), (w1 - w0) / (n1 - n0)
    print(f"\nper sample: {slope:.0f} bytes, {per * 1e6:.1f} us; the whole schedule (32.8 M samples): "
          f"{(p1 + slope * (CAMPAIGN_SAMPLES - n1)) / 2**30:.1f} GiB, "
          f"{(w1 + per * (CAMPAIGN_SAMPLES - n1)) / 60:.1f} min")


if __name__ == "__main__":
    main()
