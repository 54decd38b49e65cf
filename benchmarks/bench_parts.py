"""The cost of a run's account of its other parts (campaign.parts) at scale.

A run of 20,000 cheap trials, each storing 3 trace rows and using the preparation of one of 10
bodies (a kind written here), run in 40 tasks of 500 trials, then timed in fresh processes (no
file remembered as verified, as a new `status` or `report` finds them):
- reading the run's records (``RunStore.read``: every records file verified in full), the
  reference;
- the check ``status`` makes (``check_run(store, ["records"])``: records in full, the other parts
  by their footers);
- the check ``report`` makes (``check_run(store)``: every file in full, the accounts compared);
- compacting the run (``RunStore.compact_all`` at the end of the run).

Each is timed in wall-clock and CPU time (the least of 7); the CPU time is the figure to compare
on a machine shared with other work. The size of the records, of their footer and of the account
in it (and whether pyarrow's stored Arrow schema holds it again) is printed with them.

Run it from any checkout (``python benchmarks/bench_parts.py [N]``, with ``PYTHONPATH=<checkout>/src``):
a checkout before the account was kept (7570051) times the same run without it, one before the
account was stored row by row (4781cab) its earlier form.
"""

from __future__ import annotations

import base64
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pyarrow.parquet as pq

from graspcampaign.campaign.kind import TrialKind, register_kind
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.schema import OutputCfg, RunnerCfg, StudyCfg


def _prepare(study, params, body, rng):
    return {"scale": float(rng.random())}


def _trial(inp, rng):
    value = float(rng.random())
    return {"value": value, "__tables__": {"trace": {"step": [0, 1, 2],
                                                     "value_m": [value, 2 * value, 3 * value]}}}


KIND = TrialKind(name="bench_parts", run=_trial, seconds_per_trial=0.0001,
                 body_key=lambda f: {"mu": f["mu"]}, prepare=_prepare)


def _timed(code: str, path: Path, setup: str = "", repeat: int = 7) -> tuple[float, float]:
    """The least of ``repeat`` times of ``code`` (given ``store``, after ``setup``) in a fresh
    process each: wall-clock and CPU time (the process's own: on a machine shared with other work
    the wall-clock time varies twofold, the CPU time by a few per cent)."""
    script = (f"import time\nfrom graspcampaign.campaign.records import RunStore\n"
              f"from graspcampaign.campaign.integrity import check_run\n"
              f"store = RunStore({str(path)!r})\n{setup}\n"
              "t0, c0 = time.perf_counter(), time.process_time()\n"
              f"{code}\nprint(time.perf_counter() - t0, time.process_time() - c0)")
    times = [tuple(map(float, subprocess.run([sys.executable, "-c", script], check=True, text=True,
                                             capture_output=True).stdout.split()))
             for _ in range(repeat)]
    return min(t[0] for t in times), min(t[1] for t in times)


def _both(wall_cpu: tuple[float, float]) -> str:
    return f"{wall_cpu[0]:.3f} s (CPU {wall_cpu[1]:.3f} s)"


def main(n: int = 20_000) -> None:
    from graspcampaign.campaign.runner import run_study

    register_kind(KIND)
    with tempfile.TemporaryDirectory() as tmp:
        study = StudyCfg(name="bench", kind="bench_parts", seeds=n // 10,
                         factors={"mu": [round(0.1 * i, 1) for i in range(1, 11)]},
                         runner=RunnerCfg(backend="sequential", n_jobs=1, progress=False,
                                          batch_size=n // 40),
                         output=OutputCfg(root=tmp, run="r"))
        compacting = []
        original = RunStore.compact_all

        def timed_compaction(self):
            t0, c0 = time.perf_counter(), time.process_time()
            original(self)
            compacting.append((time.perf_counter() - t0, time.process_time() - c0))

        RunStore.compact_all = timed_compaction
        t0 = time.perf_counter()
        run_study(study)
        ran = time.perf_counter() - t0
        path = Path(tmp) / "bench" / "r"
        # the manifest names the kind: the checks in a fresh process need it registered there
        meta = json.loads((path / "manifest.json").read_text())
        register = ("import sys; sys.path.insert(0, " + repr(str(Path(__file__).parent)) + ")\n"
                    "from bench_parts import KIND\nfrom graspcampaign.campaign.kind import "
                    "register_kind\nregister_kind(KIND)\n")
        read = _timed(register + "store.read()", path)
        status = _timed(register + "check_run(store, ['records'])", path)
        report = _timed(register + "check_run(store)", path)
        try:  # the same checks with the accounts' check left out: its cost alone
            from graspcampaign.campaign import parts  # noqa: F401 - there or not
        except ImportError:
            alone = None
        else:
            off = "import graspcampaign.campaign.parts as p\np.part_problems = lambda *a, **k: []\n"
            alone = [_timed(f"check_run(store{arg})", path, register + off)
                     for arg in (", ['records']", "")]
        size = sum(p.stat().st_size for p in (path / "records").glob("*.parquet"))
        (records,) = (path / "records").glob("*.parquet")
        footer = pq.read_metadata(records)
        held = footer.metadata.get(b"graspcampaign.parts", b"")
        twice = held in base64.b64decode(footer.metadata[b"ARROW:schema"]) if held else False
        print(f"{meta['n_recorded']} trials recorded in {ran:.1f} s (records {size / 1e6:.2f} MB; "
              f"its footer {footer.serialized_size / 1e3:.1f} kB, the account "
              f"{len(held) / 1e3:.1f} kB{', again in the Arrow schema' if twice else ''})")
        print(f"compaction (compact_all at the run's end): {_both(compacting[-1])}")
        print(f"read the records (fresh process): {_both(read)}")
        print(f"status check (records in full, the other parts by footers): {_both(status)} "
              f"({status[1] / read[1]:.2f}x reading, CPU)")
        print(f"report check (every file in full): {_both(report)} "
              f"({report[1] / read[1]:.2f}x reading, CPU)")
        if alone:
            print(f"the same checks without the accounts' check: status {_both(alone[0])}, "
                  f"report {_both(alone[1])}: the accounts' check costs "
                  f"{(status[1] - alone[0][1]) / read[1]:.2f}x and "
                  f"{(report[1] - alone[1][1]) / read[1]:.2f}x reading the records (CPU)")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20_000)
