"""Test 1 virtual bench benchmark: generate and fit all 19,168 events (target < 120 s, 2 cores).

Every figure is measured in this same run:
- wall time to generate every attempt's waveform (no fits), the reference;
- wall time to generate *and* fit every completed event, and its ratio to the reference
  (the cost of the per-event fits);
- both with ``n_jobs`` workers (default 2; ``python benchmarks/bench_test1.py 1`` for one).
It then prints the campaign figures of §7 beside the paper's. These are virtual-bench
numbers (source = "virtual"), never hardware results.

Run: ``python benchmarks/bench_test1.py [n_jobs]``.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

from graspcampaign.rig import test1 as T

SEED = 701  # campaigns/test1_bench.yaml


def main(n_jobs: int = 2) -> None:
    schedule = T.test1_schedule(SEED)
    t0 = time.perf_counter()
    gen = T.run_virtual_bench(schedule, SEED, n_jobs=n_jobs, keep_waveforms=False, fit=False)
    t_gen = time.perf_counter() - t0
    t0 = time.perf_counter()
    res = T.run_virtual_bench(schedule, SEED, n_jobs=n_jobs, keep_waveforms=False)
    t_all = time.perf_counter() - t0
    n_samples = int(gen.attempts["n_samples"].sum())

    print(f"## Test 1 virtual bench ({len(schedule)} planned events, n_jobs={n_jobs}, "
          f"{os.cpu_count()} CPUs)\n")
    print("| stage | wall time (s) | ratio to generation | target |")
    print("|---|---:|---:|---|")
    print(f"| generate {len(gen.attempts)} attempts ({n_samples / 1e6:.1f} M samples) "
          f"| {t_gen:.1f} | 1.00 | reference |")
    print(f"| generate + fit {len(res.fits)} completed events | {t_all:.1f} | "
          f"{t_all / t_gen:.2f} | < 120 s {'(met)' if t_all < 120 else '(MISSED)'} |")

    f = res.fits
    att = res.attempts["status"].value_counts()
    nf = f[f["block"] == "normal"]
    acc = nf[nf["accepted"]]
    ob = T.oblique_summary(f)
    margin = ob.groupby("angle_deg")["margin_n"].mean()
    cy = T.cyclic_summary(f)
    print("\n| quantity (virtual bench) | ours | paper |")
    print("|---|---:|---:|")
    print(f"| commanded attempts | {len(res.attempts)} | 19229 |")
    print(f"| completed / aborted | {att.get('completed', 0)} / {att.get('aborted', 0)} "
          "| 19168 / 61 |")
    print(f"| normal fits accepted | {len(acc)} / {len(nf)} | 4888 / 5040 |")
    print(f"| n (accepted), mean ± SD | {acc['exponent_n'].mean():.3f} ± "
          f"{acc['exponent_n'].std():.3f} | 0.46 ± 0.07 |")
    print(f"| normal RMSE mean, accepted / all (%) | {acc['rmse_pct'].mean():.2f} / "
          f"{nf['rmse_pct'].mean():.2f} | 2.66 / 2.73 |")
    print(f"| median loop area (mJ) | {nf['loop_area_mj'].median():.3f} | 0.082 |")
    print(f"| C per event, median (N s/m) | {nf['c_n_s_per_m'].median():.3f} "
          f"(median SE {nf['c_se_n_s_per_m'].median():.2f}) | 0.055-0.062 |")
    print(f"| oblique margin 0/15/30/45 deg (N) | "
          f"{' / '.join(f'{margin.get(a, np.nan):.2f}' for a in (0, 15, 30, 45))} "
          "| 0.45 / - / 0.05 / -0.16 |")
    print(f"| Coulomb class = margin sign | {ob['classification_matches_margin'].mean():.1%} "
          "| 100% of 1728 |")
    print(f"| lowest K/K1 after 200 cycles | {cy.groupby('specimen_id')['k_ratio'].last().min():.3f}"
          " | > 0.85 |")
    t4 = T.table4(f, res.truths)
    cols = [c for c in t4.columns if c != "material"]
    print("\n| material | " + " | ".join(cols) + " |")
    print("|---|" + "---:|" * len(cols))
    for _, row in t4.iterrows():
        print(f"| {row['material']} | " + " | ".join(f"{row[c]:.3f}" for c in cols) + " |")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 2)
