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

Run it from any checkout (``python benchmarks/bench_parts.py [N]``): a checkout before the account
was kept (7570051) times the same run without it.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

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


def _timed(code: str, path: Path, setup: str = "", repeat: int = 7) -> float:
    """The least of ``repeat`` times of ``code`` (given ``store``, after ``setup``) in a fresh
    process each."""
    script = (f"import time\nfrom graspcampaign.campaign.records import RunStore\n"
              f"from graspcampaign.campaign.integrity import check_run\n"
              f"store = RunStore({str(path)!r})\n{setup}\nt0 = time.perf_counter()\n{code}\n"
              "print(time.perf_counter() - t0)")
    return min(float(subprocess.run([sys.executable, "-c", script], check=True, text=True,
                                    capture_output=True).stdout) for _ in range(repeat))


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
            t0 = time.perf_counter()
            original(self)
            compacting.append(time.perf_counter() - t0)

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
        print(f"{meta['n_recorded']} trials recorded in {ran:.1f} s (records {size / 1e6:.2f} MB)")
        print(f"compaction (compact_all at the run's end): {compacting[-1]:.3f} s")
        print(f"read the records (fresh process): {read:.3f} s")
        print(f"status check (records in full, the other parts by footers): {status:.3f} s "
              f"({status / read:.2f}x reading)")
        print(f"report check (every file in full): {report:.3f} s ({report / read:.2f}x reading)")
        if alone:
            print(f"the same checks without the accounts' check: status {alone[0]:.3f} s, "
                  f"report {alone[1]:.3f} s: the accounts' check costs "
                  f"{(status - alone[0]) / read:.2f}x and {(report - alone[1]) / read:.2f}x "
                  "reading the records")

if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20_000)
