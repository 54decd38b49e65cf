"""The Table 1 headline page: every headline success rate across studies, with testbed and n.

Written as ``<root>/headline.md`` (and ``headline.csv``) by ``build_reports``. One row per Table 1
entry and run: the proposed planner's success over executed trials with its Wilson interval, the
strongest baseline of the same run, the paper's values, and the difference in words. As in the
paper's Table 1 the rows are *not* comparable with each other (different object sets, baselines
and trial counts); the testbed column says which is which, and virtual-rig rows say plainly that
they are synthetic. Studies without records are listed with the paper's value from their study
file, so the page always shows what is still missing.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import pandas as pd

from graspcampaign import stats
from graspcampaign.campaign.provenance import read_manifest
from graspcampaign.campaign.records import RunStore
from graspcampaign.report import format as fmt
from graspcampaign.report import table as tbl

PROPOSED_NAMES = ("heuristic", "proposed")
SOURCE_SHORT = {"simulation": "simulation", "virtual": "VIRTUAL RIG (synthetic, not hardware)",
                "measured": "hardware (measured)"}


@dataclass(frozen=True)
class Headline:
    """One row of the paper's Table 1 and how to compute it from a run's records."""

    study: str
    label: str
    section: str
    paper_key: str | None = None  # key of config.paper; None: success_pct[proposed]
    paper_n_key: str | None = None
    subset: tuple[str, frozenset] | None = None  # (column, accepted values) for a sub-population
    is_baseline: Callable[[str], bool] = lambda planner: True


def _not_ablation(planner: str) -> bool:
    return not str(planner).startswith("no_") or planner == "no_pso"


# Paper Table 1, in its order. The Test 2/3 sub-populations use the record columns ``group``
# (validation groups A, B, D) and ``friction_level`` ("natural"); rows whose column is missing say
# so instead of guessing.
TABLE1: tuple[Headline, ...] = (
    Headline("ablation", "Heuristic ablation", "Sec. 6.3", paper_n_key="trials_per_variant",
             is_baseline=_not_ablation),
    Headline("baseline_grid", "Baseline grid", "Sec. 6.5", paper_n_key="trials_per_planner"),
    Headline("test2_grasp", "Grasp validation, nominal", "Sec. 8.2",
             paper_key="validation_success_pct", subset=("group", frozenset({"A", "B", "D"}))),
    Headline("test2_grasp", "Grasp validation, all", "Sec. 8.5", paper_key="proposed_success_pct",
             paper_n_key="proposed_trials"),
    Headline("test3_disturbance", "Disturbance, natural μ", "Sec. 9.2",
             paper_key="natural_success_pct", subset=("friction_level", frozenset({"natural"}))),
    Headline("test3_disturbance", "Disturbance, all", "Sec. 9.5", paper_key="proposed_success_pct",
             paper_n_key="proposed_trials"),
)
FACTOR_NOUNS = {"shape": "shapes", "mass_kg": "masses", "mu": "frictions", "nodes": "meshes"}
COLUMNS = ["headline", "section", "study", "run", "source", "testbed", "paper_pct", "paper_n",
           "ours_pct", "wilson_low_pct", "wilson_high_pct", "n", "n_error", "n_aborted",
           "difference_pp",
           "paper_baseline", "ours_baseline", "verdict", "report"]


@cache
def campaign_paper(study: str) -> dict:
    """Return the ``paper:`` block of ``campaigns/<study>.yaml`` ({} if there is none)."""
    import dataclasses

    from graspcampaign.campaign.paper import study_paper

    paper = study_paper(study)
    return dataclasses.asdict(paper) if paper is not None else {}


def _paper_values(h: Headline, paper: dict, proposed: str) -> tuple[float | None, str, int | None]:
    """Return the paper's rate [%], its strongest baseline as text, and its n."""
    rates = dict(paper.get("success_pct") or {})
    rates.update({k[: -len("_success_pct")]: v for k, v in paper.items()
                  if k.endswith("_success_pct") and k not in ("proposed_success_pct",
                                                              "validation_success_pct",
                                                              "natural_success_pct")})
    value = paper.get(h.paper_key) if h.paper_key else rates.get(proposed)
    if h.subset is None:
        baselines = {k: v for k, v in rates.items() if k not in PROPOSED_NAMES and h.is_baseline(k)}
        text = ", ".join(f"{k} {v:g}%" for k, v in sorted(baselines.items(), key=lambda kv: -kv[1])) \
            if baselines else "—"
    else:
        text = "—"
    n = paper.get(h.paper_n_key) if h.paper_n_key else None
    return (None if value is None else float(value)), text, n


def _design(manifest: dict, records: pd.DataFrame) -> str:
    config = manifest.get("config") or {}
    factors = config.get("factors") or {}
    parts = [f"{len(v)} {FACTOR_NOUNS.get(k, k + ' levels')}" for k, v in factors.items()
             if k not in ("planner", "variant") and len(v) > 1]
    if int(config.get("seeds", 1)) > 1:
        parts.append(f"{config['seeds']} seeds")
    return " × ".join(parts)


def headline_rows(root: Path | str) -> pd.DataFrame:
    """Return the headline table over every run under ``root`` (one row per entry and run)."""
    root = Path(root)
    rows = []
    for h in TABLE1:
        study_dir = root / h.study
        runs = sorted(p for p in study_dir.iterdir() if (p / "manifest.json").exists()) \
            if study_dir.is_dir() else []
        if not runs:
            value, baseline, n = _paper_values(h, campaign_paper(h.study), PROPOSED_NAMES[0])
            rows.append(_missing(h, value, baseline, n, "no records yet"))
            continue
        for run_dir in runs:
            rows.append(_row(h, RunStore(run_dir), root))
    return pd.DataFrame(rows, columns=COLUMNS)


def _missing(h: Headline, value, baseline, n, why: str, **extra) -> dict:
    row = dict.fromkeys(COLUMNS)
    row.update(headline=h.label, section=h.section, study=h.study, paper_pct=value,
               paper_n=n, paper_baseline=baseline, verdict=why, n=0, n_error=0, n_aborted=0,
               ours_pct=math.nan, wilson_low_pct=math.nan, wilson_high_pct=math.nan,
               difference_pp=math.nan)
    row.update(extra)
    return row


def _row(h: Headline, store: RunStore, root: Path) -> dict:
    manifest = read_manifest(store.manifest_path) or {}
    paper = (manifest.get("config") or {}).get("paper") or {}
    wanted = ["status", "planner", "success", "aborted", *([h.subset[0]] if h.subset else [])]
    records = store.read("records", columns=wanted).to_pandas()
    report = store.path / "report" / "report.md"
    common = {"run": manifest.get("run"), "source": manifest.get("source"),
              "testbed": f"{SOURCE_SHORT.get(manifest.get('source'), manifest.get('source'))}"
                         f"{': ' + d if (d := _design(manifest, records)) else ''}",
              "report": report.relative_to(root).as_posix() if report.exists() else None}
    planners = set(records["planner"].dropna()) if "planner" in records else set()
    proposed = next((p for p in PROPOSED_NAMES if p in planners), None)
    value, baseline, n_paper = _paper_values(h, paper, proposed or PROPOSED_NAMES[0])
    if "success" not in records or proposed is None:
        return _missing(h, value, baseline, n_paper, "records carry no planner/success columns "
                        "for this headline", **common)
    if h.subset is not None:
        column, accepted = h.subset
        if column not in records:
            return _missing(h, value, baseline, n_paper, f"records lack the `{column}` column this "
                            "sub-population needs", **common)
        records = records[records[column].isin(accepted)]
    mine = records[records["planner"] == proposed]
    ok = tbl.executed(mine)
    n, k = len(ok), int(ok["success"].sum()) if len(ok) else 0
    row = _missing(h, value, baseline, n_paper, "no executed trial", **common)
    row["n_error"] = int((mine["status"] == "error").sum())
    row["n_aborted"] = int(mine["aborted"].astype("boolean").fillna(False).sum()) \
        if "aborted" in mine else 0
    if n:
        w = stats.wilson_interval(k, n)
        row.update(ours_pct=100 * w.estimate, wilson_low_pct=100 * w.low,
                   wilson_high_pct=100 * w.high, n=n,
                   difference_pp=tbl.difference_pp(w.estimate, value),
                   verdict=tbl.verdict(value, w.estimate, w.low, w.high))
    if h.subset is None:
        row["ours_baseline"] = _ours_baseline(records, proposed, h)
    return row


def _ours_baseline(records: pd.DataFrame, proposed: str, h: Headline) -> str:
    ok = tbl.executed(records)
    ok = ok[(ok["planner"] != proposed) & ok["planner"].map(h.is_baseline)]
    if not len(ok):
        return "—"
    rates = ok.groupby("planner")["success"].mean().sort_values(ascending=False)
    return ", ".join(f"{p} {tbl.format_number(r, 1, percent=True)}%" for p, r in rates.items())


def _given(value) -> bool:
    return value is not None and not (isinstance(value, float) and math.isnan(value))


def headline_markdown(rows: pd.DataFrame) -> str:
    """Return the headline page as Markdown."""
    from graspcampaign.report.document import _md_table

    display = pd.DataFrame({
        "headline (proposed planner)": rows["headline"],
        "testbed (ours)": rows["testbed"].fillna("—"),
        "run": rows["run"].fillna("—"),
        "paper %": [tbl.format_number(v) + (f" (n = {int(n)})" if _given(n) else "")
                    if _given(v) else "—" for v, n in zip(rows["paper_pct"], rows["paper_n"],
                                                         strict=True)],
        "ours % (Wilson 95%)": ["—" if not n else fmt.estimate(e, lo, hi, 1) for e, lo, hi, n in rows[
                ["ours_pct", "wilson_low_pct", "wilson_high_pct", "n"]].itertuples(index=False)],
        "n": rows["n"], "errors": rows["n_error"], "aborted": rows["n_aborted"],
        "difference": [tbl.format_signed(v) for v in rows["difference_pp"]],
        "strongest baselines: paper": rows["paper_baseline"].fillna("—"),
        "ours": rows["ours_baseline"].fillna("—"),
        "verdict": rows["verdict"], "section": rows["section"],
        "report": [f"[report]({r})" if _given(r) else "—" for r in rows["report"]],
    })
    return "\n".join([
        "# Headline success rates (paper Table 1)", "",
        "Each row is the proposed planner's success rate over executed trials (errored trials "
        "and aborted hardware attempts are excluded from the denominator and counted in *errors* "
        "and *aborted*), with its Wilson 95% interval, "
        "beside the paper's Table 1. As in the paper, rows are **not** comparable with each other: "
        "each has its own testbed, object set, baselines and trial count. Rows from the virtual "
        "rig are synthetic data, not hardware results.", "",
        _md_table(display), ""])


def write_headline(root: Path | str) -> Path:
    """Write ``<root>/headline.md`` and ``<root>/headline.csv``; return the Markdown path."""
    root = Path(root)
    rows = headline_rows(root)
    rows.to_csv(root / "headline.csv", index=False)
    path = root / "headline.md"
    path.write_text(headline_markdown(rows))
    return path
