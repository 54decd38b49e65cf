"""Small synthetic runs for the report tests, readers of what their reports write, and the other
helpers more than one test module uses (a test module imports from here, never from another test module).

The records are built column for column as docs/records.md specifies (base columns, factors, the
kind's outputs, trace tables), written through ``RunStore`` with a manifest from
``campaign.provenance``; trial ids and scene ids come from the campaign's own design expansion.

Imported by name (``from synthetic_runs import ...``), as pytest puts this directory on the path.
"""

from __future__ import annotations

import re
import zlib
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from graspcampaign.campaign.compose import project_dirs
from graspcampaign.campaign.grid import expand
from graspcampaign.campaign.provenance import new_manifest, now_utc, write_manifest
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.schema import StudyCfg

SHAPES = ["sphere", "ellipsoid", "rounded_cube", "pear", "handle"]
PLANNERS = ["heuristic", "antipodal", "random", "centroid", "ferrari_canny"]  # the design's order
P_SUCCESS = {"heuristic": 0.7, "antipodal": 0.4, "random": 0.1, "centroid": 0.0, "no_s1": 0.7,
             "no_s2": 0.65}


def make_run(root, name: str, kind: str, factors: dict, seeds: int, paper: dict | None,
             outputs: Callable[[dict, np.random.Generator], dict], *, seed: int = 11,
             error_every: int = 0, tables: Callable[[str, dict, dict], dict] | None = None,
             prepared: list[dict] | None = None, source: str = "simulation",
             **study_kw) -> RunStore:
    """Write a run of ``name`` like the runner does: records (+ traces), then the manifest.

    ``paper`` None takes the study file's paper block (the typed values a real run carries).
    """
    if paper is None:
        paper = study_paper_block(name)
    study = StudyCfg(name=name, kind=kind, seed=seed, seeds=seeds, factors=factors, paper=paper,
                     **study_kw)
    trials = expand(study)
    rng = np.random.default_rng(seed)
    rows, traces = [], {}
    for trial in trials:
        row = {"trial_id": trial.trial_id, "study": name, "run": "r1", "kind": kind,
               "trial_index": trial.index, "scene_id": trial.scene_id, "status": "ok",
               "error_type": None, "error_message": None, "wall_time_s": 0.01,
               "worker": "pid1", "host": "test", "source": source, **trial.factors}
        if error_every and trial.index % error_every == error_every - 1:
            row.update(status="error", error_type="RuntimeError", error_message="boom")
        else:
            out = outputs(trial.factors, rng)
            row.update(out)
            if tables:
                for tname, cols in tables(trial.trial_id, trial.factors, out).items():
                    traces.setdefault(tname, []).extend(cols)
        rows.append(row)
    store = RunStore(root / name / "r1")
    half = len(rows) // 2
    store.write_shard("records", "aaaaaaaaaa", rows[:half])
    store.write_shard("records", "bbbbbbbbbb", rows[half:])
    for tname, trows in traces.items():
        store.write_shard(f"tables/{tname}", "aaaaaaaaaa", trows)
    if prepared:
        store.write_shard("prepared", "aaaaaaaaaa", prepared)
    manifest = new_manifest(study, "r1", len(trials), source)
    manifest["finished_at"] = now_utc()
    manifest["sessions"].append({"config_hash": manifest["config_hash"]})  # a finished run had one
    write_manifest(store.manifest_path, manifest)
    return store


def run_reduced(root: Path, reduced: dict[str, list[str]]) -> Path:
    """Run each study of ``reduced`` (name: its overrides) by the engine into the results root ``root``,
    sequentially and without progress lines; return ``root``."""
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.runner import run_study

    for study, overrides in reduced.items():
        run_study(compose_study(study, ["runner.backend=sequential", "runner.progress=false",
                                        f"output.root={root}", *overrides]))
    return root


def quasi_static_outputs(factors: dict, rng: np.random.Generator) -> dict:
    """One quasi_static record (docs/records.md), outcome drawn per planner."""
    planner = factors.get("planner", "heuristic")
    success = bool(rng.random() < P_SUCCESS.get(planner, 0.5))
    check = "none" if success else str(rng.choice(["residual", "torque", "slip"]))
    deltas = rng.lognormal(np.log(0.8), 0.6, 3)
    forces = rng.uniform(1, 10, 3)
    out = {
        "nodes": factors.get("nodes", 390), "n_cand": 200, "success": success,
        "failure_check": check,
        "residual_norm_n": float(rng.uniform(0, 0.45) if success else rng.uniform(0.5, 4)),
        "torque_norm_nm": float(rng.uniform(0, 0.01)),
        "slip_margin_n": float(rng.uniform(0.1, 2) if success else rng.uniform(-2, 0.5)),
        "eta": float(rng.uniform(0, 0.8)), "delta_max_mm": float(deltas.max()),
        "exceeds_1mm": bool(deltas.max() > 1.0), "iterations": int(rng.integers(5, 100)),
        "h_total": float(rng.uniform(0.15, 0.28)), "s1": 0.1, "s2": 0.1, "s3": 0.05,
        "n_c": 0, "n_e": 0, "n_sharp_vertex": 0, "n_sharp_edge": 0,
        "lambda1": 0.332, "lambda2": 0.88, "n_exp": 0.487,
        "plan_time_s": 0.01 * (1 + factors.get("nodes", 390) / 1000) + rng.uniform(0, 1e-3),
        "eval_time_s": 0.02 + rng.uniform(0, 1e-3),
    }
    for j in range(3):
        out[f"delta_{j + 1}_mm"] = float(deltas[j])
        out[f"normal_force_{j + 1}_n"] = float(forces[j])
        out[f"vertex_{j + 1}"] = int(rng.integers(0, 390))
        out[f"contact_normal_z_{j + 1}"] = float(rng.uniform(-1, 1))
    # issue 13/17 columns (docs/records.md): the gate only removes passes, torque only binds
    unbounded = success or bool(rng.random() < 0.15)
    upper = int(rng.integers(0, 3))
    law = factors.get("grip_law", "paper")
    out.update({
        "grip_law": law, "success_unbounded": unbounded, "valid_geometry": success or not unbounded,
        "success_vertical": unbounded or bool(rng.random() < 0.2),
        "success_no_torque": success or check == "torque",
        "failure_check": "geometry" if unbounded and not success else check,
        "n_upper": upper, "n_released": upper if law == "paper" else 0, "n_loaded": 3 - upper,
        "support_share_max": float(rng.uniform(0.3, 1.0)), "rho": float(rng.uniform(0.0, 1.0)),
        "epsilon_fc": float(max(0.0, rng.normal(0.02, 0.05))), "pso_at_bound": "lambda1,n",
        "grip_capped": law != "paper" and bool(rng.random() < 0.8),
        "grip_needed_n": float("nan") if law == "paper" else float(rng.choice([2.0, 40.0, np.inf])),
    })
    if planner == "ferrari_canny":
        out.update(spearman_h_epsilon=float(rng.uniform(-0.8, 0.1)),
                   spearman_h_epsilon_fc=float(rng.uniform(-0.9, 0.2)))
    return out


def report_dir(run: RunStore | Path) -> Path:
    """The report folder of a run, given its store or its folder (``<root>/<study>/<run>``)."""
    return (run.path if isinstance(run, RunStore) else run) / "report"


def read_table(run: RunStore | Path, name: str) -> pd.DataFrame:
    """The run's ``tables/<name>.csv``."""
    return pd.read_csv(report_dir(run) / "tables" / f"{name}.csv")


def ok_records(store: RunStore) -> pd.DataFrame:
    df = store.read().to_pandas()
    ok = df[df["status"] == "ok"]
    return ok.assign(success=ok["success"].astype(bool)) if "success" in ok else ok


def md_table(md: str, name: str) -> pd.DataFrame:
    """The Markdown table printed above ``tables/<name>.csv`` as text cells (minus signs as "-"; an
    escaped ``\\|`` inside a cell is its text)."""
    lines = md.split(f"(`tables/{name}.csv`)", 1)[1].strip().split("\n\n", 1)[0].splitlines()
    rows = [[c.strip().replace("\\|", "|").replace("\u2212", "-")
             for c in re.split(r"(?<!\\)\|", line.strip()[1:-1])] for line in lines]
    return pd.DataFrame(rows[2:], columns=rows[0])


def report_md(run: RunStore | Path) -> str:
    """The run's report.md."""
    return (report_dir(run) / "report.md").read_text()


def caption(store: RunStore, name: str) -> str:
    """The bold caption line above table ``name`` in report.md."""
    return next(line for line in report_md(store).splitlines() if f"(`tables/{name}.csv`)" in line)


def candidates(trial_id: str, factors: dict, out: dict) -> dict:
    """50 (H, epsilon) candidates per ferrari_canny trial (docs/records.md trace table)."""
    if factors["planner"] != "ferrari_canny":
        return {}
    rng = np.random.default_rng(zlib.crc32(trial_id.encode()))
    h = rng.uniform(0.2, 3.0, 50)
    eps = np.maximum(0.0, 0.1 - 0.04 * h + 0.03 * rng.normal(size=50))
    return {"candidates": [{"trial_id": trial_id, "candidate": i, "h_total": float(a), "epsilon_fc": float(e)}
                           for i, (a, e) in enumerate(zip(h, eps, strict=True))]}


def study_paper_block(name: str) -> dict:
    """The ``paper:`` block of the shipped study file ``name`` as YAML holds it ({} without a file)."""
    path = project_dirs()[1] / f"{name}.yaml"
    return yaml.safe_load(path.read_text())["paper"] if path.exists() else {}


def opening(run: RunStore | Path) -> str:
    """The run's "What this shows" paragraph, as report.md prints it."""
    return report_md(run).split("## What this shows\n\n", 1)[1].split("\n\n", 1)[0]


#: what a backticked name in prose may be: a decision or the page's own files, or a record column (or one
#: of its values) a reader needs to find in a table, in parentheses after the words naming it
FILES = re.compile(r"docs/decisions\.md|(tables|figures)/[\w.]+")
COLUMN = re.compile(r"[a-z][a-z0-9_]*")
#: or a command a reader types, as typed (an ingested run's "Filled by `graspcampaign ingest`")
COMMAND = re.compile(r"graspcampaign [a-z]+")


def code_for_words(text: str) -> list[str]:
    """The backticked names in ``text`` that stand for words: not a decision, the page's files or a
    command, nor a column in parentheses (an ingested run's `source = virtual` was one)."""
    bad = []
    for m in re.finditer(r"`([^`]*)`", text):
        depth = text[:m.start()].count("(") - text[:m.start()].count(")")
        if not (FILES.fullmatch(m.group(1)) or COMMAND.fullmatch(m.group(1))
                or (COLUMN.fullmatch(m.group(1)) and depth > 0)):
            bad.append(f"{m.group(0)} in {text[:80]!r}")
    return bad


#: the Test 2/3 studies of the shared results tree and their reduced fractions (conftest.py REDUCED)
HARDWARE_STUDIES = {"test2_grasp": "params.fraction=0.08", "test3_disturbance": "params.fraction=0.1"}


def both_readings(root: Path, study: str) -> pd.DataFrame:
    """Executed records of a Test 2/3 run's both belief readings, long: the trace table's outcome columns
    on the records' factors (an independent merge, not the report's own reshaping)."""
    store = RunStore(root / study / "default")
    rec, none = store.read().to_pandas(), store.read("tables/belief_none").to_pandas()
    keep = ["trial_id", "planner", "shape", "aborted", "status"]
    cf = rec[keep].merge(none.drop(columns=[c for c in keep[1:] if c in none]), on="trial_id")
    out = pd.concat([rec.assign(belief_error="paper"), cf.assign(belief_error="none")])
    return out[(out["status"] == "ok") & ~out["aborted"].astype(bool)].reset_index(drop=True)


# Table 4 of the paper (μ_s, μ_k per material family), typed from its text
TABLE4_MU = {"gel": (0.772, 0.544), "silicone_soft": (0.619, 0.440), "bio_foam": (0.684, 0.506),
             "silicone_ref": (0.509, 0.364)}


def below_arrest(dropped: pd.DataFrame) -> int:
    """How many of ``dropped`` hold a recorded SF (``sf_actual``) below their material's μ_s/μ_k."""
    return sum(sf < TABLE4_MU[m][0] / TABLE4_MU[m][1] for m, sf in zip(dropped["material"],
                                                                       dropped["sf_actual"], strict=True))


def cost_ratio_run(fastest, median, min_column=True, itself=((1.0, 1.0),)):
    """A mesh_resolution run's resolution panel: per trial on 1750 nodes, and on the 144-node reference
    mesh against itself (``itself``), the two meshes' fastest and median repeats [s] in the given ratios
    (the reference mesh's 1 ms fastest, 2 ms median); its cost_ratio table computed, as the opening
    reads it."""
    from types import SimpleNamespace

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.mesh_resolution import COST

    per_mesh = {144: itself, 1750: zip(fastest, median, strict=True)}
    rows = [{"panel": "resolution", "status": "ok", "nodes": n, "reference_nodes": 144,
             "eval_time_min_s": 1e-3 * f, "eval_time_reference_min_s": 1e-3, "eval_time_s": 2e-3 * m,
             "eval_time_reference_s": 2e-3, "cost_ratio_vs_reference": f if min_column else m}
            for n, ratios in per_mesh.items() for f, m in ratios]
    records = pd.DataFrame(rows)
    if not min_column:  # a run stored before the fastest repeat was recorded: its ratio is of medians
        records = records.drop(columns=["eval_time_min_s", "eval_time_reference_min_s"])
    run = Run(records, {}, SimpleNamespace(runtime_ratio_1750_144=1.95, runtime_ratio_target=1.5))
    run.tables["cost_ratio"] = COST.compute(run)
    return run


def _figure_items(items):
    """Every ``Figure`` of a spec's items, those wrapped in another item (test1's finalize-stage
    figures) included."""
    from graspcampaign.report.spec import Figure

    for item in items:
        if isinstance(item, Figure):
            yield item
        elif isinstance(getattr(item, "item", None), Figure):
            yield item.item


def draw_figure(run, draw, size=None):
    """The matplotlib Figure ``draw(run, fig)`` draws (a spec ``Figure``'s ``draw`` at its ``size``, or one
    panel of it on ``fig.add_subplot()``): on an Agg canvas in the report's style (``style.RC``,
    constrained layout), then drawn, as the report draws a figure."""
    import matplotlib as mpl
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from graspcampaign.report import style

    with mpl.rc_context(style.RC):
        fig = Figure(figsize=size, layout="constrained")
        FigureCanvasAgg(fig)
        draw(run, fig)
        fig.canvas.draw()
    return fig


def draw_all(root: Path, study: str) -> dict:
    """Each figure of ``study``'s run, drawn on an Agg canvas (the report's tables rendered first)."""
    from graspcampaign.campaign.paper import study_paper
    from graspcampaign.report.build import spec_for
    from graspcampaign.report.document import Document
    from graspcampaign.report.render import Run, render

    store = RunStore(root / study / "default")
    run = Run(store.read().to_pandas(), store.check(), study_paper(study), store)
    spec = spec_for(study, "")
    render(spec, run, Document("", run.source, []))
    return {item.name: draw_figure(run, item.draw, item.size) for item in _figure_items(spec.items)}


def printed_decimals(printed: str) -> int:
    """The decimals a number as the paper prints it has ("4.0": 1, "95": 0, "≈ 86": 0)."""
    return len(printed.split(".")[1]) if "." in printed else 0


def page_image_px() -> float:
    """The widest a figure's image shows on the HTML page [px]: ``main``'s max-width less its side
    padding, less ``figure``'s padding and border (report.style.CSS; ``img{max-width:100%}``)."""
    from graspcampaign.report.style import CSS

    def px(rule: str, prop: str) -> list[float]:
        body = re.search(r"(?:^|})\s*" + rule + r"\{([^}]*)\}", CSS).group(1)  # the screen rule, first
        value = re.search(r"(?:^|;)" + prop + r":([^;]*)", body).group(1)
        return [float(v.removesuffix("px")) for v in value.split() if re.fullmatch(r"[\d.]+(px)?", v)]

    main_side = px("main", "padding")[1]  # padding: top side bottom
    return (px("main", "max-width")[0] - 2 * main_side - 2 * px("figure", "padding")[0]
            - 2 * px("figure", "border")[0])


def half_an_em(text) -> float:
    """Half an em of ``text``'s font in display pixels: the least gap between two neighbouring labels
    (a word space is 0.32 em in DejaVu Sans; labels closer than that read as one phrase)."""
    return 0.5 * text.get_fontsize() * text.figure.dpi / 72


#: the studies the ``fresh_reports`` fixture (conftest.py) reports again (test_report_reads_only.py)
FRESH_STUDIES = ("surrogate", "test1_bench")
FORMATS = ["md", "csv", "json", "html"]  # the formats the sim_root fixture writes (conftest.py)
