"""Helpers shared by the benchmark scripts (run as ``python benchmarks/bench_<x>.py``, so this
module is importable as ``_common`` from the script's own folder)."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Sequence


def best_of(fn: Callable[[], object], repeat: int = 3) -> float:
    """Return the shortest wall time of ``repeat`` calls of ``fn`` [s]."""
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def print_table(header: Sequence[str], rows: Iterable[Sequence[str]],
                align: Sequence[str] | None = None) -> None:
    """Print a Markdown table; ``align`` holds one of ``---``, ``---:`` per column."""
    print("| " + " | ".join(header) + " |")
    print("|" + "|".join(align or ["---"] * len(header)) + "|")
    for row in rows:
        print("| " + " | ".join(row) + " |")
