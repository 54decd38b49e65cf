"""Bad configs, class by class: exit 2, the whole one-sentence message, nothing stored changed.

The classes a tester found accepted, hanging or answered with a traceback: a Dask address that is
no scheduler, designs too large to hold, ``runner.n_jobs=0``, null factor levels, factors missing
for the trial kind, bad ``GRASPCAMPAIGN_HOME``/``_PATH``/``_CACHE``, silent acceptances
(``pso.enabled=2``, Hydra's own keys, broken files listed as runnable, ``show`` accepting what
``run`` refuses, ``plan --material ''``), the drift message, study-file errors without their file,
name collisions, and override messages. Pattern of ``test_bad_input.py``.
"""

from __future__ import annotations

import contextlib
import hashlib
import http.server
import shutil
import signal
import socket
import threading
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from graspcampaign.campaign import studyfile
from graspcampaign.cli.main import app

runner = CliRunner()
PROJECT = Path(studyfile.project_dirs()[0]).parent
CAMPAIGNS = PROJECT / "campaigns"
SMOKE = ["shape=[sphere]", "nodes=[144]"]
HEADER = "# @package _global_\n# schema: StudyCfg\n"
BODY = "kind: mesh_features\nfactors:\n  shape: [sphere]\n  nodes: [144]\n"
RUN_NAME = "(output.run=NAME or --run NAME) or pass --allow-drift to mix them."


@contextlib.contextmanager
def _deadline(seconds: float):
    """Fail (instead of hanging or filling the memory) if the block takes longer than this."""
    def expired(signum, frame):
        raise TimeoutError(f"still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def _invoke(*args, seconds: float = 20.0):
    with _deadline(seconds):
        return runner.invoke(app, [str(a) for a in args], catch_exceptions=False)


def _snapshot(root: Path) -> dict[str, str]:
    return {p.relative_to(root).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(root.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """A results root holding one finished smoke run (so 'nothing changed' has something to keep)."""
    root = tmp_path_factory.mktemp("bad_configs") / "results"
    done = _invoke("run", "smoke", *SMOKE, "runner.backend=sequential", "--root", root)
    assert done.exit_code == 0, done.output
    return root


def _refused(results: Path, args, message: str, warnings: str = "", seconds: float = 20.0) -> None:
    before = _snapshot(results)
    result = _invoke(*args, "--root", results, seconds=seconds)
    assert result.exit_code == 2, result.output
    assert result.stderr == f"{warnings}error: {message}\n"
    assert _snapshot(results) == before


@pytest.fixture
def user_dir(tmp_path, monkeypatch):
    """A directory of the user's own study files on GRASPCAMPAIGN_PATH."""
    folder = tmp_path / "my_studies"
    folder.mkdir()
    monkeypatch.setenv("GRASPCAMPAIGN_PATH", str(folder))
    return folder


@pytest.fixture
def home(tmp_path, monkeypatch):
    """A GRASPCAMPAIGN_HOME copy of conf/ and campaigns/ that a test may break."""
    root = tmp_path / "home"
    shutil.copytree(PROJECT / "conf", root / "conf")
    shutil.copytree(CAMPAIGNS, root / "campaigns")
    monkeypatch.setenv("GRASPCAMPAIGN_HOME", str(root))
    studyfile.project_dirs.cache_clear()
    yield root
    studyfile.project_dirs.cache_clear()


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
        start = time.perf_counter()
        _refused(results, ["run", "smoke", *SMOKE, "runner=dask", f"runner.address={address}",
                           "runner.connect_timeout_s=0.5", "--run", "on_dask"],
                 f"runner.address = '{address}': no Dask scheduler answered within 0.5 s ({why}); "
                 "start one (dask scheduler) or drop runner.address to run on a local cluster.",
                 seconds=10)
        assert time.perf_counter() - start < 4.0


# -- 2. designs too large to hold ------------------------------------------------------------------
def test_seeds_beyond_any_design_are_refused_before_expanding(results):
    for command in ("show", "run"):
        _refused(results, [command, "baseline_grid", "seeds=99999999999999999999999"],
                 "seeds = 99999999999999999999999 is out of range; allowed: >= 1 and <= 1000000 (a "
                 "study holds at most 1,000,000 trials, docs/decisions.md).", seconds=3)


def test_a_design_beyond_the_trial_limit_is_refused_before_expanding(results):
    _refused(results, ["show", "smoke", "seeds=200000"],
             "study smoke has 2,000,000 trials (5 x 2 x 200000), more than the 1,000,000 a study may "
             "hold (each costs ~0.8 KB of memory before it runs, docs/decisions.md); reduce seeds, "
             "repeats or the factor levels, or split the study.", seconds=3)


# -- 3. runner.n_jobs = 0 --------------------------------------------------------------------------
def test_n_jobs_zero_is_refused_at_compose(results):
    for command in ("show", "run"):
        _refused(results, [command, "smoke", *SMOKE, "runner.n_jobs=0"],
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
        _refused(results, [command, "baseline_grid", override], NULLS[override])


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
            _refused(results, [command, "smoke", *SMOKE], f"GRASPCAMPAIGN_HOME={home} {problem}"
                                                          f"{HOME_HINT}")
        listing = _invoke("list")
        assert listing.exit_code == 2
        assert listing.stderr == f"error: GRASPCAMPAIGN_HOME={home} {problem}{HOME_HINT}\n"
    finally:
        studyfile.project_dirs.cache_clear()


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
    _refused(results, ["show", "mine"],
             f"unknown study 'mine'; available studies: {studies} (searched: {CAMPAIGNS}; "
             f"GRASPCAMPAIGN_PATH entries skipped: {entry} ({short})).",
             warnings=f"warning: GRASPCAMPAIGN_PATH entry {entry} {problem}; it is skipped.\n")


def test_a_cache_that_cannot_be_kept_is_said_once(tmp_path, monkeypatch):
    blocker = tmp_path / "cache_file"
    blocker.write_text("a file, not a directory")
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(blocker))
    listing = _invoke("list")
    assert listing.exit_code == 0, listing.output
    assert listing.stderr == (f"warning: GRASPCAMPAIGN_CACHE={blocker} is not a directory, so the "
                              "catalog cache is not kept; list and show work without it, "
                              "recomputing what they need (slower).\n")
    assert "baseline_grid" in listing.stdout


# -- 8. the drift message names what changed -------------------------------------------------------
def test_drift_names_the_first_changed_keys(results):
    _refused(results, ["run", "smoke", *SMOKE, "features.edge_dihedral_deg=31"],
             f"run {results / 'smoke' / 'default'} was started with a different resolved study "
             "config (features.edge_dihedral_deg 30.0 -> 31.0); use a new run name " + RUN_NAME)
    _refused(results, ["run", "smoke", "shape=[sphere,pear]", "nodes=[144]", "seeds=2"],
             f"run {results / 'smoke' / 'default'} was started with a different resolved study "
             'config (seeds 1 -> 2, factors.shape ["sphere"] -> ["sphere", "pear"]); use a new run '
             "name " + RUN_NAME)
