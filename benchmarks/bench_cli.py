"""Start-up of the answering commands: `list`, `show`, `status`, `--help` against the interpreter
importing the package (`python -c "import graspcampaign"`), measured in the same run.

Each command runs in a fresh process (what a user waits for), best of five after one warm-up call
that also fills the catalog cache (campaign/catalog.py); the first, cold `list` after a code change
is reported separately. Prints a Markdown table; the target is well under 1 s for each command.

    python benchmarks/bench_cli.py
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _common import print_table

ROOT = Path(__file__).resolve().parents[1]


def _env(cache: str) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + env.get("PYTHONPATH", "")
    env["GRASPCAMPAIGN_CACHE"] = cache
    env.pop("GRASPCAMPAIGN_PATH", None)
    return env


def _time(args: list[str], env: dict[str, str], cwd: str) -> float:
    start = time.perf_counter()
    done = subprocess.run(args, env=env, cwd=cwd, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if done.returncode not in (0, 2):
        raise RuntimeError(f"{' '.join(args)} failed: {done.stderr}")
    return elapsed


def _best(args, env, cwd, repeat=5) -> float:
    return min(_time(args, env, cwd) for _ in range(repeat))


def main() -> None:
    py = sys.executable
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as work:
        env = _env(cache)
        gc = [py, "-m", "graspcampaign"]
        cold_list = _time([*gc, "list"], env, work)  # empty cache: computes the catalog
        # a finished run for `status` to read
        subprocess.run([*gc, "run", "smoke", "shape=[sphere]", "nodes=[144]",
                        "runner.backend=sequential", "--root", f"{work}/results"], env=env,
                       cwd=work, check=True, capture_output=True)
        reference = _best([py, "-c", "import graspcampaign"], env, work)
        commands = {
            "--help": [*gc, "--help"],
            "list": [*gc, "list"],
            "show baseline_grid": [*gc, "show", "baseline_grid", "mu=[0.3]", "seeds=2"],
            "show test1_bench": [*gc, "show", "test1_bench"],
            "status smoke": [*gc, "status", "smoke", "--root", f"{work}/results"],
        }
        rows = []
        for label, args in commands.items():
            _time(args, env, work)  # warm-up (OS caches, catalog)
            t = _best(args, env, work)
            rows.append((f"`graspcampaign {label}`", f"{t:.2f}", f"{t / reference:.1f}"))
        rows.append(("`graspcampaign list` (cold catalog)", f"{cold_list:.2f}",
                     f"{cold_list / reference:.1f}"))
    print(f"reference: `python -c \"import graspcampaign\"` = {reference:.3f} s (best of 5)\n")
    print_table(["command", "time [s]", "x reference"], rows, ["---", "---:", "---:"])


if __name__ == "__main__":
    main()
