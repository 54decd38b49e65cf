"""Bad configs, class by class: exit 2, the whole one-sentence message, nothing stored changed.

The classes a tester found accepted, hanging or answered with a traceback: a Dask address that is
no scheduler, designs too large to hold, ``runner.n_jobs=0``, null factor levels, factors missing
for the trial kind, bad ``GRASPCAMPAIGN_HOME``/``_PATH``/``_CACHE``, silent acceptances
(``pso.enabled=2``, Hydra's own keys, broken files listed as runnable, ``show`` accepting what
``run`` refuses, ``plan --material ''``), the drift message, study-file errors without their file,
name collisions (override messages: ``test_bad_overrides.py``). Pattern of ``test_bad_input.py``.
"""

from __future__ import annotations

import contextlib
import http.server
import shlex
import shutil
import socket
import threading
from pathlib import Path

import pytest
from cli_checks import HEADER, invoke, refused

from graspcampaign.campaign import studyfile
from graspcampaign.campaign.kind import KINDS

PROJECT = Path(studyfile.project_dirs()[0]).parent
CAMPAIGNS = PROJECT / "campaigns"
SMOKE = ["shape=[sphere]", "nodes=[144]"]
BODY = "kind: mesh_features\nfactors:\n  shape: [sphere]\n  nodes: [144]\n"
RUN_NAME = "(output.run=NAME or --run NAME) or pass --allow-drift to mix them."


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """A results root holding one finished smoke run (so 'nothing changed' has something to keep)."""
    root = tmp_path_factory.mktemp("bad_configs") / "results"
    done = invoke("run", "smoke", *SMOKE, "runner.backend=sequential", "--root", root)
    assert done.exit_code == 0, done.output
    return root


# -- 1. a Dask address that accepts connections but is no scheduler -------------------------------
@contextlib.contextmanager
def _silent_server():
    """Accepts every connection and never sends a byte."""
    server = socket.create_server(("127.0.0.1", 0))
    held = []

    def accept():
        with contextlib.suppress(OSError):
            while True:
                held.append(server.accept()[0])

    threading.Thread(target=accept, daemon=True).start()
    try:
        yield server.getsockname()[1]
    finally:
        server.close()
        for conn in held:
            conn.close()


@contextlib.contextmanager
def _http_server(eager: bool):
    """An HTTP server: Python's (it waits for a request line), or one answering at once."""
    if not eager:
        quiet = type("Quiet", (http.server.BaseHTTPRequestHandler,),
                     {"log_message": lambda self, *args: None})
        server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), quiet)
        threading.Thread(target=server.serve_forever, daemon=True).start()
        try:
            yield server.server_address[1]
        finally:
            server.shutdown()
            server.server_close()
        return
    listener = socket.create_server(("127.0.0.1", 0))

    def answer():
        with contextlib.suppress(OSError):
            while True:
                conn = listener.accept()[0]
                conn.sendall(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n")
                conn.close()

    threading.Thread(target=answer, daemon=True).start()
    try:
        yield listener.getsockname()[1]
    finally:
        listener.close()


DASK = {"silent": (_silent_server, "it accepted the connection but did not answer Dask's handshake"),
        "http": (lambda: _http_server(eager=False),
                 "it accepted the connection but did not answer Dask's handshake"),
        "http_eager": (lambda: _http_server(eager=True), "it answered, but not in Dask's protocol")}


@pytest.mark.parametrize("server", sorted(DASK))
def test_a_dask_address_that_is_no_scheduler_is_refused_within_its_timeout(results, server):
    pytest.importorskip("distributed")
    serve, why = DASK[server]
    with serve() as port:
        address = f"tcp://127.0.0.1:{port}"
        # the deadline is the bound: the old code hung for good (or asked for 3 EiB); a loaded
        # machine may take seconds to refuse, so no tighter wall-clock assert
        refused(results, ["run", "smoke", *SMOKE, "runner=dask", f"runner.address={address}",
                          "runner.connect_timeout_s=0.5", "--run", "on_dask", "--root", results],
                f"runner.address = '{address}': no Dask scheduler answered within 0.5 s ({why}); "
                "start one (dask scheduler) or drop runner.address to run on a local cluster.",
                seconds=20)


# -- 2. designs too large to hold ------------------------------------------------------------------
def test_seeds_beyond_any_design_are_refused_before_expanding(results):
    for command in ("show", "run"):
        refused(results, [command, "baseline_grid", "seeds=99999999999999999999999", "--root", results],
                "seeds = 99999999999999999999999 is out of range; allowed: >= 1 and <= 1000000 (a "
                "study holds at most 1,000,000 trials, docs/decisions.md).", seconds=15)


def test_a_design_beyond_the_trial_limit_is_refused_before_expanding(results):
    refused(results, ["show", "smoke", "seeds=200000", "--root", results],
            "study smoke has 2,000,000 trials (5 x 2 x 200000), more than the 1,000,000 a study may "
            "hold (each costs ~0.8 KB of memory before it runs, docs/decisions.md); reduce seeds, "
            "repeats or the factor levels, or split the study.", seconds=15)


# -- 3. runner.n_jobs = 0 --------------------------------------------------------------------------
def test_n_jobs_zero_is_refused_at_compose(results):
    for command in ("show", "run"):
        refused(results, [command, "smoke", *SMOKE, "runner.n_jobs=0", "--root", results],
                "runner.n_jobs = 0 is out of range; allowed: != 0 (joblib's n_jobs: a number of "
                "worker processes, or -1 for every core, -2 for every core but one).")


# -- 4. null factor levels -------------------------------------------------------------------------
NULLS = {"mu=null": "factors.mu[0] must be of type float, got null; give the factor's levels, e.g. "
                    "mu: [0.3, 0.5].",
         "mu=[0.3,null]": "factors.mu[1] must be of type float, got null; give the factor's levels, "
                          "e.g. mu: [0.3, 0.5].",
         "mass_kg=null": "factors.mass_kg[0] must be of type float, got null; give the factor's "
                         "levels, e.g. mass_kg: [0.2, 0.4]."}


@pytest.mark.parametrize("override", sorted(NULLS))
def test_a_null_factor_level_is_refused(results, override):
    for command in ("show", "run") if override == "mu=null" else ("show",):
        refused(results, [command, "baseline_grid", override, "--root", results], NULLS[override])


# -- 5. factors the trial kind needs ---------------------------------------------------------------
def test_a_study_file_without_its_kinds_factors_is_named_with_its_line(results, user_dir):
    path = user_dir / "mine.yaml"
    path.write_text(HEADER + "name: mine\nkind: quasi_static\nfactors:\n  shape: [sphere]\n")
    refused(results, ["show", "mine", "--root", results],
            f"{path}, line 5: trial kind 'quasi_static' needs the factors mass_kg, mu and planner "
            "on every trial, which this study does not set (its factors: shape); give each a list "
            "of levels under factors, e.g. mass_kg: [0.2, 0.4].")


def test_factors_missing_for_the_trial_kind_are_named(results):
    for command in ("show", "run"):
        refused(results, [command, "baseline_grid", "~factors.mu", "--root", results],
                "trial kind 'quasi_static' needs the factor mu on every trial, which this study "
                "does not set (its factors: shape, mass_kg, planner); give each a list of levels "
                "under factors, e.g. mu: [0.3, 0.5].")
        refused(results, [command, "smoke", "kind=quasi_static", "--root", results],
                "trial kind 'quasi_static' needs the factors mass_kg, mu and planner on every "
                "trial, which this study does not set (its factors: shape, nodes); give each a "
                "list of levels under factors, e.g. mass_kg: [0.2, 0.4].")


# -- 6. the environment variables ------------------------------------------------------------------
HOME_HINT = ("; point it at a directory holding conf/ (with conf/config.yaml and the config groups) "
             "and campaigns/ (the study files), e.g. a copy of the shipped ones, or unset it to use "
             "those.")


@pytest.mark.parametrize("case", ["missing", "file", "empty", "no_conf", "no_campaigns"])
def test_a_bad_graspcampaign_home_is_named(results, tmp_path, monkeypatch, case):
    home = tmp_path / "home"
    problem = {"missing": "does not exist", "file": "is a file, not a directory",
               "empty": "has no conf/ directory", "no_conf": "has no conf/ directory",
               "no_campaigns": "has no campaigns/ directory"}[case]
    if case == "file":
        home.write_text("not a directory")
    elif case != "missing":
        home.mkdir()
        if case == "no_campaigns":
            shutil.copytree(PROJECT / "conf", home / "conf")
        if case == "no_conf":
            shutil.copytree(CAMPAIGNS, home / "campaigns")
    monkeypatch.setenv("GRASPCAMPAIGN_HOME", str(home))
    studyfile.project_dirs.cache_clear()
    try:
        for command in ("show", "run") if case == "missing" else ("show",):
            refused(results, [command, "smoke", *SMOKE, "--root", results],
                    f"GRASPCAMPAIGN_HOME={home} {problem}{HOME_HINT}")
        listing = invoke("list")
        assert listing.exit_code == 2
        assert listing.stderr == f"error: GRASPCAMPAIGN_HOME={home} {problem}{HOME_HINT}\n"
    finally:
        studyfile.project_dirs.cache_clear()


def test_an_empty_group_file_of_graspcampaign_home_is_named(results, home):
    table2 = home / "conf" / "model" / "table2.yaml"
    table2.write_text("")
    refused(results, ["show", "smoke", *SMOKE, "--root", results],
            f"{table2} is empty; a file of config group model sets keys of model "
            "(lambda1, lambda2, n_exp, fingertip_radius_m, e_finger_pa, e_object_pa, nu_finger, "
            "nu_object, damping_law, alpha_hc_s_per_m).")
    # `list` says it once, not once per study, and lists every study as broken
    listing = invoke("list")
    message = f"{table2} is empty; a file of config group model sets keys of model"
    assert listing.stderr.count(message) == 1, listing.stderr
    assert listing.stderr.startswith(f"warning: every study is broken: {message}")
    assert listing.stdout.count("broken") == len(studyfile.study_files())


@pytest.mark.parametrize("case", ["missing", "file", "study_file"])
def test_a_bad_graspcampaign_path_entry_is_warned_about(results, tmp_path, monkeypatch, case):
    entry = {"missing": tmp_path / "nowhere", "file": tmp_path / "notes.txt",
             "study_file": tmp_path / "mine.yaml"}[case]
    if case != "missing":
        entry.write_text(HEADER + "name: mine\n" + BODY)
    monkeypatch.setenv("GRASPCAMPAIGN_PATH", str(entry))
    problem = {"missing": "does not exist",
               "file": "is a file, not a directory of study files",
               "study_file": f"is a file, not a directory of study files (run a study file by "
                             f"giving its path: graspcampaign run {entry})"}[case]
    studies = ", ".join(p.stem for p in sorted(CAMPAIGNS.glob("*.yaml")))
    short = problem.split(" (")[0]
    refused(results, ["show", "mine", "--root", results],
            f"unknown study 'mine'; available studies: {studies} (searched: {CAMPAIGNS}; "
            f"GRASPCAMPAIGN_PATH entries skipped: {entry} ({short})).",
            warnings=f"warning: GRASPCAMPAIGN_PATH entry {entry} {problem}; it is skipped.\n")


def test_a_cache_that_cannot_be_kept_is_said_once(tmp_path, monkeypatch):
    blocker = tmp_path / "cache_file"
    blocker.write_text("a file, not a directory")
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(blocker))
    listing = invoke("list")
    assert listing.exit_code == 0, listing.output
    assert listing.stderr == (f"warning: GRASPCAMPAIGN_CACHE={blocker} is not a directory, so the "
                              "catalog cache is not kept; list and show work without it, "
                              "recomputing what they need (slower).\n")
    assert "baseline_grid" in listing.stdout


# -- 7. silent acceptances -------------------------------------------------------------------------
SILENT = {
    "pso.enabled=2": "pso.enabled must be true or false, got 2 (override 'pso.enabled=2').",
    "hydra.run.dir=/tmp": "override 'hydra.run.dir=/tmp' sets hydra.run.dir, a key of Hydra's own "
                          "runtime; this tool uses Hydra to compose studies and runs them itself, "
                          "so hydra keys have no effect: leave it out.",
    "+hydra.x=1": "override '+hydra.x=1' sets hydra.x, a key of Hydra's own runtime; this tool uses "
                  "Hydra to compose studies and runs them itself, so hydra keys have no effect: "
                  "leave it out.",
}


@pytest.mark.parametrize("override", sorted(SILENT))
def test_overrides_once_accepted_silently_are_refused(results, override):
    for command in ("show", "run") if override == "pso.enabled=2" else ("show",):
        refused(results, [command, "smoke", *SMOKE, override, "--root", results], SILENT[override])


def test_list_says_which_study_files_are_broken(user_dir):
    (user_dir / "bad_model.yaml").write_text(HEADER + "name: bad_model\n" + BODY + "model: nosuch\n")
    (user_dir / "bad_eval.yaml").write_text(HEADER + "name: bad_eval\n" + BODY
                                            + "evaluator:\n  n_cand: -3\n")
    (user_dir / "fine.yaml").write_text(HEADER + "name: fine\n" + BODY)
    result = invoke("list")
    assert result.exit_code == 0, result.output
    assert result.stderr == (
        f"warning: study bad_eval is broken: {user_dir / 'bad_eval.yaml'}, line 9: "
        "evaluator.n_cand = -3 is out of range; allowed: >= 1.\n"
        f"warning: study bad_model is broken: {user_dir / 'bad_model.yaml'}, line 8: model must be "
        "a mapping of its keys (lambda1, lambda2, n_exp, fingertip_radius_m, "
        "e_finger_pa, e_object_pa, nu_finger, nu_object, damping_law, alpha_hc_s_per_m), got "
        "'nosuch' (str); a preset of conf/model/ (firm, nominal, table2) is chosen on the command "
        "line, e.g. model=firm.\n")
    rows = {line.split("│")[1].strip(): line.split("│")[4].strip()
            for line in result.stdout.splitlines() if line.count("│") > 4}
    assert (rows["bad_model"], rows["bad_eval"], rows["fine"]) == ("broken", "broken", "yes")
    names = invoke("list", "--names").stdout.split()
    assert "fine" in names and "bad_model" not in names and "bad_eval" not in names


def test_list_says_when_it_cannot_check_a_study(results, user_dir):
    path = user_dir / "mine.yaml"
    path.write_text(HEADER + "name: mine\n" + BODY + "seeds: ${nosuch}\n")
    listing = invoke("list")
    assert listing.exit_code == 0 and listing.stderr == ""
    row = next(line for line in listing.stdout.splitlines() if line.startswith("│ mine "))
    assert row.split("│")[4].strip() == "yes (not checked)"  # only composing resolves ${...}
    refused(results, ["show", "mine", "--root", results],
            f"{path}, line 8: seeds refers to ${{nosuch}}, which is not a key of the study config.")


SHOW_LIKE_RUN = {
    # the registry's kinds, so a kind added to KINDS needs no edit here
    "kind: teleport": ("kind: teleport\nfactors:\n  shape: [sphere]\n", 4,
                       f"trial kind 'teleport' is unknown; known kinds: {', '.join(sorted(KINDS))}."),
    "params: {bogus: 1}": (BODY + "params:\n  bogus: 1\n", 9,
                           "params.bogus is not a parameter of trial kind 'mesh_features', which "
                           "takes none."),
    "params of a kind that has some": (BODY.replace("mesh_features", "quasi_static").replace(
        "nodes: [144]", "mass_kg: [0.2]\n  mu: [0.3]\n  planner: [heuristic]") + "params:\n  bogus: 1\n",
        11, "params.bogus is not a known key of params; known keys: nodes, stream_study, "
            "candidate_sample."),
}


@pytest.mark.parametrize("case", sorted(SHOW_LIKE_RUN))
def test_show_refuses_what_run_refuses(results, user_dir, case):
    body, line, message = SHOW_LIKE_RUN[case]
    path = user_dir / "mine.yaml"
    path.write_text(HEADER + "name: mine\n" + body)
    for command in ("show", "run"):
        refused(results, [command, "mine", "--root", results], f"{path}, line {line}: {message}")


def test_plan_refuses_an_empty_material(tmp_path):
    mesh = tmp_path / "object.stl"
    mesh.write_text("solid nothing\nendsolid nothing\n")
    result = invoke("plan", mesh, "--mass-kg", "0.3", "--material", "")
    assert result.exit_code == 2, result.output
    assert result.stderr == ("error: --material '' is not a Table 4 material family; use one of "
                             "gel, silicone_soft, bio_foam, silicone_ref.\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["object.stl"]  # no picture either


# -- 8. the drift message names what changed -------------------------------------------------------
def test_drift_names_the_first_changed_keys(results):
    resume = shlex.join(["graspcampaign", "run", "smoke", *SMOKE, "runner.backend=sequential",
                         "--run", "default", "--root", str(results)])
    refused(results, ["run", "smoke", *SMOKE, "features.edge_dihedral_deg=31", "--root", results],
            f"run {results / 'smoke' / 'default'} was started with a different resolved study "
            f"config (features.edge_dihedral_deg 30.0 -> 31.0); resume it as started ({resume}), use "
            "a new run name " + RUN_NAME)
    refused(results, ["run", "smoke", "shape=[sphere,pear]", "nodes=[144]", "seeds=2", "--root", results],
            f"run {results / 'smoke' / 'default'} was started with a different resolved study "
            f'config (seeds 1 -> 2, factors.shape ["sphere"] -> ["sphere", "pear"]); resume it as '
            f"started ({resume}), use a new run name " + RUN_NAME)


# -- 9. study-file errors name the file, the line, the key and what it takes -----------------------
STUDY_FILES = {
    "factors_a_list": ("kind: mesh_features\nfactors: [shape, nodes]\n", 5,
                       "factors must be a mapping of factor names to lists of levels (e.g. shape: "
                       "[sphere, pear]), got ['shape', 'nodes'] (list)."),
    "level_not_a_list": ("kind: mesh_features\nfactors:\n  shape: sphere\n  nodes: [144]\n", 6,
                         "factors.shape must be a list of levels, e.g. shape: [sphere, pear], got "
                         "'sphere' (str)."),
    "model_a_name": (BODY + "model: nosuch\n", 8,
                     "model must be a mapping of its keys (lambda1, lambda2, n_exp, "
                     "fingertip_radius_m, e_finger_pa, e_object_pa, nu_finger, nu_object, "
                     "damping_law, alpha_hc_s_per_m), got 'nosuch' (str); a preset of conf/model/ "
                     "(firm, nominal, table2) is chosen on the command line, e.g. model=firm."),
    "evaluator_out_of_range": (BODY + "evaluator:\n  n_cand: -3\n", 9,
                               "evaluator.n_cand = -3 is out of range; allowed: >= 1."),
    "seeds_interpolation": (BODY + "seeds: ${nosuch}\n", 8,
                            "seeds refers to ${nosuch}, which is not a key of the study config."),
    "extension_maybe": (BODY + "extension: maybe\n", 8, "extension must be true or false, got "
                                                        "'maybe' (str)."),
}


@pytest.mark.parametrize("case", sorted(STUDY_FILES))
@pytest.mark.parametrize("how", ["name", "path"])
def test_a_study_file_error_names_the_file_line_and_key(results, user_dir, case, how):
    body, line, message = STUDY_FILES[case]
    path = user_dir / "mine.yaml"
    path.write_text(HEADER + "name: mine\n" + body)
    for command in ("show", "run") if how == "name" else ("show",):
        refused(results, [command, "mine" if how == "name" else path, "--root", results],
                f"{path}, line {line}: {message}")


HOME_FILES = {
    "lambda1: -3": ("lambda1: 0.332", "lambda1: -3", 4,
                    "model.lambda1 = -3.0 is out of range; allowed: > 0 and <= 15 (the "
                    "identification scale factors stay within 10x their PSO bounds)."),
    "bogus: 1": ("nu_object: 0.45\n", "nu_object: 0.45\nbogus: 1\n", 12,
                 "model.bogus is not a known key of model; known keys: lambda1, lambda2, "
                 "n_exp, fingertip_radius_m, e_finger_pa, e_object_pa, nu_finger, nu_object, "
                 "damping_law, alpha_hc_s_per_m."),
}


@pytest.mark.parametrize("case", sorted(HOME_FILES))
def test_a_group_file_error_names_the_file_and_line(results, home, case):
    old, new, line, message = HOME_FILES[case]
    table2 = home / "conf" / "model" / "table2.yaml"
    table2.write_text(table2.read_text().replace(old, new))
    for command in ("show", "run"):
        refused(results, [command, "smoke", *SMOKE, "--root", results], f"{table2}, line {line}: {message}")


# -- 10. names: a study that hides a tool study, a renamed study, a file named otherwise -----------
def test_a_study_hiding_a_tool_study_needs_its_paper_block(results, user_dir):
    path = user_dir / "baseline_grid.yaml"
    # of baseline_grid's kind (one of another kind is refused for its kind first: round 14)
    path.write_text(HEADER + "name: baseline_grid\nkind: quasi_static\nfactors: {shape: [sphere], "
                    "mass_kg: [0.4], mu: [0.3], planner: [heuristic]}\n")
    for command in ("show", "run"):
        refused(results, [command, "baseline_grid", "--root", results],
                f"{path}: paper.figure is missing (a required key): this file takes "
                "the name of the tool's study baseline_grid (campaigns/baseline_grid.yaml), which "
                "it hides, so its runs are reported as that study and its paper block must hold "
                "that study's values; copy the paper block of campaigns/baseline_grid.yaml, or "
                "give your study a name of its own.")


def test_a_renamed_study_keeps_comparing_with_its_paper_values(results):
    result = invoke("show", "baseline_grid", "name=my_grid", "--root", results)
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("study: my_grid\n")
    assert f"run: {results / 'my_grid' / 'default'} (0 of 3375 recorded)" in result.stdout
    from graspcampaign.campaign.compose import compose_study

    assert compose_study("baseline_grid", ["name=my_grid"]).compare_with == "baseline_grid"


def test_a_study_file_named_otherwise_than_its_name_is_refused(results, user_dir):
    path = user_dir / "named_file.yaml"
    path.write_text(HEADER + "name: other_name\n" + BODY)
    for command in ("show", "run"):
        refused(results, [command, "named_file", "--root", results],
                f"{path}, line 3: name: other_name is not the file's name named_file; a study is "
                "listed, run and reported by its file name (status and report look for "
                "named_file), so write name: named_file or rename the file to other_name.yaml.")


def test_a_study_file_with_a_byte_order_mark_is_read(results, user_dir):
    (user_dir / "mine.yaml").write_bytes(b"\xef\xbb\xbf" + (HEADER + "name: mine\n" + BODY).encode())
    shown = invoke("show", "mine", "--root", results)
    assert shown.exit_code == 0, shown.output
    assert "axes: shape 1 x nodes 1 x seeds 1 = 1 trial" in shown.stdout
    listing = invoke("list")
    assert listing.stderr == ""
