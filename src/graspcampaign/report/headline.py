"""The Table 1 headline page: every headline success rate across studies, with testbed and n."""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from graspcampaign.analysis.records import rate_table
from graspcampaign.analysis.vocabulary import PROPOSED, TEST2_GROUP_TRIALS, label
from graspcampaign.campaign.paper import check_paper, study_paper
from graspcampaign.campaign.paths import write_file
from graspcampaign.campaign.provenance import design_change
from graspcampaign.campaign.records import RunStore
from graspcampaign.core.words import counted
from graspcampaign.errors import ConfigError, DamagedRunError, UserInputError, access_denied
from graspcampaign.report import format as fmt
from graspcampaign.report.document import Col, Document, Table, Text
from graspcampaign.report.render import reason
from graspcampaign.report.spec import verdicts
from graspcampaign.report.style import SOURCE_SHORT


def _baseline(planner: str) -> bool:
    """A baseline of the proposed planner (not the planner itself, not an ablation variant)."""
    return planner != PROPOSED and (planner == "no_pso" or not str(planner).startswith("no_"))


@dataclass(frozen=True)
class Headline:
    """One row of the paper's Table 1 and how to compute it from a run's records."""

    study: str
    label: str
    section: str
    paper: Callable[[Any], float]
    n_paper: Callable[[Any], int] | None = None
    baselines: Callable[[Any], dict[str, float]] | None = None
    subset: tuple[str, frozenset] | None = None  # (record column, accepted values)


def _rates(p: Any) -> dict[str, float]:
    return {k: v for k, v in p.success_pct.items() if _baseline(k)}


def _table_rates(table: dict) -> dict[str, float]:
    return {k: row.success_pct for k, row in table.items() if k != PROPOSED}


#: Table 1's "Grasp validation, nominal": the validation groups (§8.2), whose n is their trials in §8.1.
VALIDATION = ("group", frozenset({"A", "B", "D"}))
#: The paper's rates of the quasi-static studies are Algorithm 2's (grip law ``paper``).
ALGORITHM_2 = ("grip_law", frozenset({"paper"}))
TABLE1: tuple[Headline, ...] = (
    Headline("ablation", "Heuristic ablation", "Sec. 6.3", lambda p: p.success_pct[PROPOSED],
             lambda p: p.trials_per_variant, _rates, ALGORITHM_2),
    Headline("baseline_grid", "Baseline grid", "Sec. 6.5", lambda p: p.success_pct[PROPOSED],
             lambda p: p.trials_per_planner, _rates, ALGORITHM_2),
    Headline("test2_grasp", "Grasp validation, nominal", "Sec. 8.2", lambda p: p.validation_success_pct,
             lambda p: sum(TEST2_GROUP_TRIALS[g] for g in VALIDATION[1]), subset=VALIDATION),
    Headline("test2_grasp", "Grasp validation, all", "Sec. 8.5", lambda p: p.proposed_success_pct,
             lambda p: p.proposed_trials, lambda p: _table_rates(p.table7)),
    Headline("test3_disturbance", "Disturbance, natural μ", "Sec. 9.2", lambda p: p.natural_success_pct,
             lambda p: sum(r.n for r in p.table8.values()),  # Table 8's five blocks: Table 1's 740
             subset=("friction_level", frozenset({"natural"}))),
    Headline("test3_disturbance", "Disturbance, all", "Sec. 9.5", lambda p: p.proposed_success_pct,
             lambda p: p.proposed_trials, lambda p: _table_rates(p.table9)),
)
REDUCED_MARK = "†"
REDUCED_NOTE = (f"{REDUCED_MARK} A reduced or modified run: its design is not the study file's "
                "default, so its rate is not the paper-scale result (its report names the overrides).")
FACTOR_NOUNS = {"shape": "shapes", "mass_kg": "masses", "mu": "frictions", "nodes": "meshes"}
COLUMNS = [
    Col("headline", "headline (proposed planner)"), Col("testbed", "testbed (ours)"),
    Col("run", "run", link="report"), Col("paper", "paper %"), Col("n_paper", "paper n", 0),
    Col("rate_pct", "ours % (Wilson 95%)", 1, low="wilson_low_pct", high="wilson_high_pct", why="why"),
    Col("n", "n"), Col("n_error", "errors"), Col("n_aborted", "aborted"),
    Col("difference", "difference [pp]", 1, signed=True),
    Col("paper_baselines", "baselines: paper"), Col("ours_baselines", "baselines: ours"),
    Col("verdict", "verdict"), Col("section", "section"),
]
ROW = ["headline", "section", "study", "run", "source", "testbed", "paper_pct", "paper", "n_paper",
       "paper_baselines", "n", "n_error", "n_aborted", "rate_pct", "wilson_low_pct",
       "wilson_high_pct", "ours_baselines", "why", "report"]
INTRO = ("Each row is the proposed planner's success rate over executed trials (errored trials "
         "and aborted hardware attempts are excluded from the denominator and counted in "
         "*errors* and *aborted*), with its Wilson 95% interval, beside the paper's Table 1. As "
         "in the paper, rows are **not** comparable with each other: each has its own testbed, "
         "object set, baselines and trial count.")
VIRTUAL_NOTE = " Rows from the virtual rig are synthetic data, not hardware results."


def _ranked(rates: dict[str, float]) -> str:
    return ", ".join(f"{label('planner', k)} {fmt.number(v, 1)}%"
                     for k, v in sorted(rates.items(), key=lambda kv: -kv[1])) or fmt.MISSING


def _unset(column: str, config: dict) -> Any:
    """The level of a record that does not name ``column``: a quasi-static trial is judged by the
    evaluator's grip law (Algorithm 2 unless configured; a factor names it in every record)."""
    return (config.get("evaluator") or {}).get("grip_law", "paper") if column == "grip_law" else None


def _row(h: Headline, paper: Any, **extra) -> dict:
    row = {"headline": h.label, "section": h.section, "study": h.study, "n": 0, "n_error": 0,
           "n_aborted": 0, "paper_baselines": fmt.MISSING, "ours_baselines": fmt.MISSING, "why": ""}
    if paper is not None:
        row.update(paper_pct=h.paper(paper), paper=fmt.paper_text(h.paper(paper), 1),  # as printed: ≈ 86
                   n_paper=h.n_paper(paper) if h.n_paper else None,
                   paper_baselines=_ranked(h.baselines(paper)) if h.baselines else fmt.MISSING)
    return {**row, **extra}


def _read_run(study: str, store: RunStore) -> tuple[dict, Any, pd.DataFrame, str] | None:
    """The run's manifest, typed paper values, records (the columns every Table 1 row of ``study``
    reads) and data source; None for an empty directory, not a run."""
    manifest = store.check(["records"])  # duplicate, foreign or missing records: not read
    if manifest is None:
        return None
    config = manifest.get("config") or {}
    try:
        paper = check_paper(study, config.get("paper"))
    except ConfigError:
        paper = study_paper(study)
    subsets = [h.subset[0] for h in TABLE1 if h.study == study and h.subset]
    records, source = store.read_records(manifest, ["status", "planner", "success", "aborted", *subsets])
    return manifest, paper, records.to_pandas(), source


def _read_once(memo: dict, study: str, path: Path) -> tuple | None:
    """:func:`_read_run` of the run at ``path``, read once for every Table 1 row it serves (Test 2's and
    Test 3's two): its result, or its error raised again for each row."""
    if (study, path) not in memo:
        try:
            memo[study, path] = _read_run(study, RunStore(path))
        except Exception as exc:  # noqa: BLE001 - each row that reads the run names it (headline_rows)
            memo[study, path] = exc
    if isinstance(memo[study, path], Exception):
        raise memo[study, path]
    return memo[study, path]


def _run_row(h: Headline, store: RunStore, root: Path, read: tuple | None) -> dict | None:
    """The row of ``h`` over the run ``read`` (:func:`_read_run` of ``store``; None: no run)."""
    if read is None:
        return None
    manifest, paper, records, source = read
    config = manifest.get("config") or {}
    column, levels = h.subset or (None, frozenset())
    design = " × ".join([f"{len(v)} {FACTOR_NOUNS.get(k, k + ' levels')}" for k, v in (
        config.get("factors") or {}).items() if k not in ("planner", "variant", column) and len(v) > 1]
        + ([f"{config['seeds']} seeds"] if int(config.get("seeds", 1)) > 1 else [])) + (
        f"; {column.replace('_', ' ')} {', '.join(label(column, v) for v in sorted(levels))} only"
        if column and len((config.get("factors") or {}).get(column, ())) > 1 else "")
    change, page = design_change(manifest), store.path / "report" / "report.html"
    common = {"run": manifest.get("run"), "source": source,
              "testbed": SOURCE_SHORT.get(source, source) + (f": {design}" if design else "")
              + (f" {REDUCED_MARK} (reduced run: {change[1]})" if change else ""),
              "report": page.relative_to(root).as_posix()  # linked once written, as the index
              if page.exists() or page.with_suffix(".md").exists() else None}
    if column and (unset := _unset(column, config)) is not None:
        records = records.assign(**{column: records[column].fillna(unset) if column in records else unset})
    if column and column not in records:
        return _row(h, paper, why=f"the records lack the `{column}` column this "
                                  "sub-population needs", **common)
    records = records[records[column].isin(levels)] if column else records
    if "planner" not in records or not records["planner"].eq(PROPOSED).any():
        return _row(h, paper, why="no trial of the proposed planner" + (
            f" with {column} = {', '.join(sorted(levels))}" if column else ""), **common)
    rates = rate_table(records, ["planner"]).set_index("planner")
    mine, others = rates.loc[PROPOSED], rates[(rates["n"] > 0) & rates.index.map(_baseline).to_numpy(bool)]
    return _row(h, paper, **{k: mine[k] for k in ("n", "n_error", "n_aborted", "rate_pct",
                                                  "wilson_low_pct", "wilson_high_pct")},
                why=mine["rate_why"], ours_baselines=_ranked(others["rate_pct"].to_dict()), **common)


def folders(path: Path, strict: bool = False, files: bool = False) -> list[Path]:
    """The directories in ``path`` (``files``: and its files but hidden ones), sorted; an entry
    that cannot be read (as under /proc) is none, a ``path`` that cannot be listed has none
    (``strict``: raises the OSError)."""
    try:
        names = os.listdir(path)
    except OSError:
        if strict:
            raise
        return []
    return sorted(path / name for name in names if os.path.isdir(path / name)
                  or files and not name.startswith(".") and os.path.isfile(path / name))


def unlistable(path: Path) -> str | None:
    """Why this user may not list the folder ``path`` (a study's, chmod 000: its runs cannot be
    found, so a walk would skip them unsaid), in :func:`~graspcampaign.errors.access_denied`'s
    sentence; None if it can be listed or is no folder."""
    try:
        os.listdir(path)
    except PermissionError as exc:
        return access_denied(exc)
    except OSError:  # no folder, or gone: nothing to name
        pass
    return None


def runs_of(study_dir: Path) -> list[Path]:
    """The runs in a study's folder: each directory holding a run (its manifest, or stored files
    a missing manifest leaves), and each file in place of one (a run that cannot be read: the
    pages that summarised it must not silently drop it)."""
    return [path for path in folders(study_dir, files=True) if not os.path.isdir(path)
            or any(os.path.exists(path / p) for p in ("manifest.json", "records"))]


def headline_rows(root: Path | str, unreadable: list[tuple[str, str]] | None = None,
                  ) -> pd.DataFrame:
    """Return the headline table over every run under ``root`` (one row per entry and run); a run
    that cannot be read gets a row saying so and is added to ``unreadable``."""
    root, rows, read = Path(root), [], {}
    for h in TABLE1:
        study_dir = root / h.study
        runs = runs_of(study_dir)
        rows += [] if runs else [_row(h, study_paper(h.study), why="no records yet")]
        for r in runs:
            try:
                row = _run_row(h, RunStore(r), root, _read_once(read, h.study, r))
                rows += [] if row is None else [row]
            except Exception as exc:  # noqa: BLE001 - a broken run is named, not fatal
                if unreadable is not None and isinstance(exc, UserInputError):
                    label = r.relative_to(root).as_posix()
                    unreadable += [] if label in dict(unreadable) else [(label, reason(exc))]
                # what is wrong, not where: the page is the same wherever the root lies
                what = f"it {exc.what}" if isinstance(exc, DamagedRunError) else reason(exc)
                rows.append(_row(h, study_paper(h.study), run=r.name,
                                 why=f"the run cannot be read: {what}"))
    return verdicts(pd.DataFrame(rows, columns=ROW).astype({"n_paper": "Int64"}), "rate_pct",
                    "paper_pct", "wilson_low_pct", "wilson_high_pct", unit="%")


def write_headline(root: Path, pages: list[str], frame: pd.DataFrame) -> None:
    """Write ``headline.csv`` and, for each of ``pages`` (md, html), ``headline.<page>`` of
    ``frame``, the :func:`headline_rows` of ``root``: a run is linked from a page only if its
    report has a page of that format."""
    write_file(root / "headline.csv", frame.to_csv(index=False))
    reduced = frame["testbed"].astype(str).str.contains(REDUCED_MARK).any()
    virtual = frame["source"].eq("virtual").any()
    differ, judged = fmt.differing(frame)
    # of the rows compared: a row without records or without a paper value is not a difference
    why = (f" {differ} of {counted(judged, 'compared row')} "
           f"{'differs' if differ == 1 else 'differ'} from the paper (the paper's value outside our 95% "
           "interval); each run's report, linked in *run*, opens with where and why." if differ else "")
    for page in pages:
        linked = frame.assign(report=[r if isinstance(r, str) and (root / r).with_suffix(f".{page}").is_file()
                                      else None for r in frame["report"]])
        doc = Document("Headline success rates (paper Table 1)", "", [], [
            Text(INTRO + (VIRTUAL_NOTE if virtual else "") + why),
            Table("headline", "Table 1, ours beside the paper", linked, COLUMNS, csv="headline.csv"),
            *([Text(REDUCED_NOTE, "note")] if reduced else [])
        ])
        write_file(root / f"headline.{page}", doc.html() if page == "html" else doc.markdown())
