"""Helpers of the table audit (``audit_tables.py``): read a run's records and report tables, compare
cells, and the verdict rule as ``report/format.py`` states it in words. pandas/scipy/statsmodels only:
nothing here imports graspcampaign."""

from __future__ import annotations

import glob
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import yaml
from statsmodels.stats.proportion import proportion_confint

ROOT = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results")
CAMPAIGNS = Path(__file__).resolve().parents[1] / "campaigns"
SUMMARY: list[tuple] = []  # (study, table, cells checked, mismatches)
RADIUS_MM = 5.0  # Table 2's fingertip radius
PSO_PARAMS = ["lambda1", "lambda2", "n_exp", "b", "k", "c"]


def records(study: str) -> pd.DataFrame:
    """Every record of the study's ``default`` run (records/*.parquet), in file order."""
    files = sorted(glob.glob(str(ROOT / study / "default" / "records" / "*.parquet")))
    return pd.concat([pd.read_parquet(f) for f in files], ignore_index=True)


def aux(study: str, where: str, name: str) -> pd.DataFrame:
    """A table of the run besides its records: ``tables/<name>``, ``summary/<name>``, ``prepared``."""
    return pd.read_parquet(ROOT / study / "default" / where / name)


def belief_none(study: str) -> pd.DataFrame | None:
    """The run's ``tables/belief_none`` counterfactual of Tests 2-3 (None: the run stored none)."""
    try:
        return aux(study, "tables", "belief_none")
    except FileNotFoundError:
        return None


def table(study: str, name: str) -> pd.DataFrame:
    """The report's CSV ``name`` (an empty cell is missing)."""
    return pd.read_csv(ROOT / study / "default" / "report" / "tables" / f"{name}.csv", keep_default_na=False,
                       na_values=[""])


def paper(study: str) -> dict:
    return yaml.safe_load((CAMPAIGNS / f"{study}.yaml").read_text())["paper"]


def wilson(k: int, n: int) -> tuple[float, float]:
    return proportion_confint(k, n, alpha=0.05, method="wilson") if n else (math.nan, math.nan)


def same(a, b, rtol=1e-9) -> bool:
    a, b = (None if x == "" else x for x in (a, b))
    a_na = a is None or (isinstance(a, float) and math.isnan(a)) or a is pd.NA
    b_na = b is None or (isinstance(b, float) and math.isnan(b)) or b is pd.NA
    if a_na or b_na:
        return a_na and b_na
    if isinstance(a, (bool, np.bool_)) or isinstance(b, (bool, np.bool_)):
        return str(a).lower() == str(b).lower() or (a in (0, 1) and bool(a) == bool(b))
    try:
        return math.isclose(float(a), float(b), rel_tol=rtol, abs_tol=1e-12)
    except (TypeError, ValueError):
        return str(a) == str(b)


def compare(study: str, name: str, expected: pd.DataFrame, keys: list[str], columns: list[str] | None = None,
            rtol=1e-9) -> None:
    """Every cell of ``expected`` (rows keyed by ``keys``) against the report's CSV ``name``."""
    got = table(study, name)
    columns = columns or [c for c in expected.columns if c not in keys]
    checked, bad = 0, []
    if len(got) != len(expected):
        bad.append(f"rows: report {len(got)}, expected {len(expected)}")
    got_k = got.set_index(keys) if keys else got
    exp_k = expected.set_index(keys) if keys else expected
    for idx, row in exp_k.iterrows():
        if idx not in got_k.index:
            bad.append(f"row {idx} missing")
            continue
        g = got_k.loc[idx]
        g = g.iloc[0] if isinstance(g, pd.DataFrame) else g
        for c in columns:
            checked += 1
            if c not in g.index:
                bad.append(f"{idx}/{c}: column missing")
            elif not same(g[c], row[c], rtol):
                bad.append(f"{idx}/{c}: report {g[c]!r}, expected {row[c]!r}")
    if {"verdict", "differs"} <= set(got.columns):  # the verdict's words say what `differs` says
        for _, r in got.iterrows():
            checked += 1
            d, words = r["differs"], str(r["verdict"])
            want = words.startswith("differs") if d is True or d == "True" or d == 1.0 else \
                not words.startswith("differs") and "differs" not in words.split(":")[0]
            if not want:
                bad.append(f"verdict words {words!r} beside differs = {d!r}")
    SUMMARY.append((study, name, checked, len(bad)))
    print(f"{study} / {name}: {checked} cells checked, {len(bad)} mismatches")
    for b in bad[:25]:
        print("   ", b)


def judge(ours, ref, digits, low=None, high=None):
    """Whether ours differs from the paper's value: the rule as format.verdict states it in words (a
    range: ours, or ours rounded, inside it; a point: the nearest end of our 95% CI, or ours, at least
    one unit of the last printed digit away)."""
    if ref is None or ours is None or (isinstance(ours, float) and math.isnan(ours)):
        return None
    if isinstance(ref, (list, tuple)):
        lo = -math.inf if ref[0] is None else ref[0]
        hi = math.inf if ref[1] is None else ref[1]
        return not (lo <= ours <= hi or lo <= round(ours, digits) <= hi)
    if isinstance(ref, bool):
        return bool(ours) != ref
    nearest = ours
    if low is not None and high is not None and not (math.isnan(low) or math.isnan(high)):
        if low <= ref <= high:
            return False
        nearest = min(max(ref, low), high)
    return abs(nearest - ref) >= 10.0 ** -digits


def sig3_decimals(value: float) -> int:
    """Decimals giving ``value`` three significant digits (Tables 3 and 5 as printed)."""
    return max(0, 2 - math.floor(math.log10(abs(value))))


def sig3_text(value: float) -> str:
    """``value`` at three significant digits, a trailing zero kept (4.8996 -> "4.90", 17342 -> "17300")."""
    d = 2 - math.floor(math.log10(abs(value)))
    return f"{round(value, d):.{max(d, 0)}f}"


def opening(study: str) -> str:
    """The report's opening paragraph (the first after 'What this shows')."""
    text = (ROOT / study / "default" / "report" / "report.md").read_text()
    return text.split("## What this shows", 1)[1].strip().split("\n\n", 1)[0]


def check_opening(study: str, parts: list[str]) -> None:
    """Each expected phrase (a number in its words) is in the opening paragraph."""
    text = opening(study)
    bad = [p for p in parts if p not in text]
    SUMMARY.append((study, "opening", len(parts), len(bad)))
    print(f"{study} / opening: {len(parts)} phrases checked, {len(bad)} mismatches")
    for b in bad:
        print(f"    not in the opening: {b!r}\n    opening: {text[:600]!r}")
