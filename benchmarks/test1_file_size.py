"""The largest Test 1 waveform file the protocol makes: every event of the full schedule (§7.1, the
19,168 events of ``test1_schedule``) on the virtual bench at its commanded ``daq_hz``, its samples
written as a CSV in the waveform sheet's columns (``schedule test1_bench --template``), the way
``graspcampaign ingest test1_bench`` reads one. The bench's channels are quantised as the sensors
resolve them (1 um, 1 mN); a rig that writes every float64 digit makes longer rows, so the CSV is
also measured with each channel at its full ``repr`` (time and channels as float64 text).

Sets ``rig.test1_ingest.MAX_WAVEFORM_BYTES`` (docs/decisions.md, "A Test 1 waveform file is at most
...").

Run: ``python benchmarks/test1_file_size.py``.
"""

from __future__ import annotations

import time

import numpy as np

from graspcampaign.rig.test1 import test1_schedule
from graspcampaign.rig.test1_bench import _waves_frame, run_events

CHUNK = 500


def main() -> None:
    start = time.perf_counter()
    rows = test1_schedule(0).to_dict("records")
    samples, quantised, full, largest = 0, 0, 0, (0, "")
    for i in range(0, len(rows), CHUNK):
        waves = run_events(rows[i:i + CHUNK], 0, keep_waveforms=True, fit=False)[2]
        frame = _waves_frame(waves)
        samples += len(frame)
        quantised += len(frame.to_csv(index=False).encode())
        noisy = frame.assign(**{c: frame[c] + np.random.default_rng(i).uniform(-1e-7, 1e-7, len(frame))
                                for c in frame.columns[1:6]})  # every digit of a float64 written
        full += len(noisy.to_csv(index=False).encode())
        big = max(waves, key=lambda w: w["time_s"].size)
        largest = max(largest, (big["time_s"].size, big["event_id"]))
    print(f"events: {len(rows)}, samples: {samples} ({samples / len(rows):.0f} an event; the most in one "
          f"event: {largest[0]}, {largest[1]})")
    print(f"CSV, quantised channels: {quantised / 2**20:.0f} MiB ({quantised / samples:.1f} bytes a sample)")
    print(f"CSV, float64 channels:   {full / 2**20:.0f} MiB ({full / samples:.1f} bytes a sample)")
    print(f"({time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
