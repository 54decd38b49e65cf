"""The MuJoCo peer benchmark (benchmarks/bench_mujoco.py, benchmarks/_mujoco_sphere.py).

Every test but the first needs the optional ``bench`` extra (MuJoCo) and is skipped without it.
The map of our constants onto MuJoCo is checked against MuJoCo's own arithmetic (its constraint
rows, its simulation to rest), not against a copy of our formulas.
"""

from __future__ import annotations

import dataclasses
import runpy
import sys
from pathlib import Path

import numpy as np
import pytest

from graspcampaign.core.mesh import make_object

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


@pytest.fixture(scope="module")
def bench():
    """Import the benchmark modules from benchmarks/ (a script folder, not a package)."""
    sys.path.insert(0, str(BENCHMARKS))
    try:
        import _mujoco_sphere
        import bench_mujoco
    finally:
        sys.path.remove(str(BENCHMARKS))
    return bench_mujoco, _mujoco_sphere


@pytest.fixture(scope="module")
def grasp(bench):
    pytest.importorskip("mujoco")
    return bench[0].our_grasp()


def test_without_mujoco_the_benchmark_prints_one_line(monkeypatch, capsys):
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    monkeypatch.setitem(sys.modules, "mujoco", None)  # makes `import mujoco` raise ImportError
    names = ("_mujoco_sphere", "bench_mujoco")
    saved = {name: sys.modules.pop(name, None) for name in names}
    try:
        runpy.run_path(str(BENCHMARKS / "bench_mujoco.py"), run_name="__main__")
    finally:  # leave no module imported without MuJoCo behind
        for name, module in saved.items():
            sys.modules.pop(name, None)
            if module is not None:
                sys.modules[name] = module
    assert capsys.readouterr().out == (
        "bench_mujoco: skipped, MuJoCo is not installed (pip install -e '.[bench]')\n")


@pytest.mark.parametrize("variant", ["edge", "membrane"])
def test_model_is_our_sphere_with_our_nodes_edges_and_mass(bench, grasp, variant):
    _, sphere = bench
    mesh, setup, _ = grasp
    model, data = sphere.build_mujoco(mesh, setup.msd_params, setup.contact, 0.3, variant)
    mujoco = sphere.mujoco
    mujoco.mj_forward(model, data)
    assert model.nflex == 1 and model.flex_vertnum[0] == len(mesh.vertices) == 356
    node_bodies = model.flex_vertbodyid
    assert model.body_mass[node_bodies].sum() == pytest.approx(setup.msd_params.mass, rel=1e-12)
    np.testing.assert_allclose(model.body_mass[node_bodies], setup.body.node_mass, rtol=1e-12)
    np.testing.assert_allclose(data.flexvert_xpos, mesh.vertices, atol=1e-12)
    edges = {tuple(sorted(e)) for e in model.flex_edge.tolist()}
    assert edges == {tuple(e) for e in setup.body.edges.tolist()}
    assert model.nv == 3 * 356  # three slide joints per node, nothing else moves
    np.testing.assert_allclose(model.dof_damping, setup.msd_params.b)
    # The inverse weight the solref map assumes is the one MuJoCo's compiler computed.
    weight = sphere.point_inverse_weight(setup.msd_params, 356)
    np.testing.assert_allclose(model.body_invweight0[node_bodies, 0], weight, rtol=1e-9)
    if variant == "edge":
        np.testing.assert_allclose(model.flexedge_invweight0, weight, rtol=1e-9)


def test_edge_rows_are_our_springs_and_dampers_at_rest(bench, grasp):
    _, sphere = bench
    mesh, setup, _ = grasp
    model, data = sphere.build_mujoco(mesh, setup.msd_params, setup.contact, 0.3, "edge")
    spring, damper, omega = sphere.edge_rows_at_rest(model, data)
    assert spring == pytest.approx(setup.msd_params.k, rel=1e-9)
    assert damper == pytest.approx(setup.msd_params.c, rel=1e-9)
    assert int(np.sum(data.efc_type == sphere.mujoco.mjtConstraint.mjCNSTR_EQUALITY)) == 1062
    assert omega > 0.0


def test_mujoco_edge_shell_squeezes_like_ours(bench, grasp):
    """Static consequence of the map: two antipodal nodes pushed together by 0.1 mN close the
    same distance in MuJoCo (simulated to rest, soft constraints) as in our linearised body
    (26.25 N/m; MuJoCo gave 26.20 when this was written, the rest of the gap is the shell's
    nonlinearity at a finite load)."""
    _, sphere = bench
    mesh, setup, _ = grasp
    pair = sphere.squeeze_pair(np.asarray(mesh.vertices))
    ours = sphere.ours_squeeze_stiffness(mesh, setup.msd_params, pair)
    theirs = sphere.mujoco_squeeze_stiffness(mesh, setup.msd_params, setup.contact, "edge", pair)
    assert theirs == pytest.approx(ours, rel=0.01)


@pytest.mark.parametrize("variant", ["edge", "membrane"])
def test_fingertips_touch_the_sphere_within_the_window(bench, grasp, variant):
    """The three fingertips, held at the 0.5 mm seed of our grasp, touch the MuJoCo sphere and
    push it (positive normal forces) at every step of the 20.75 ms window."""
    _, sphere = bench
    mesh, setup, initial = grasp
    model, data = sphere.build_mujoco(mesh, setup.msd_params, setup.contact, 0.3, variant)
    n_steps = int(round(100 * setup.dt / model.opt.timestep))
    grips = np.tile(initial.grip, (n_steps, 1))
    paths = sphere.mocap_paths(setup, grips, setup.dt, model.opt.timestep * np.arange(n_steps))
    trace = sphere.trace_mujoco(model, data, paths)
    assert trace.touching.any(axis=0).all()
    assert trace.touching[0].all()
    assert np.all(trace.normal_forces[trace.touching] > 0.0)
    # The first step sees the seed depth exactly: the flex radius offset is compensated.
    np.testing.assert_allclose(trace.depths[0], setup.grasp.seed_depth, atol=1e-6)


def test_soft_constraint_edges_move_a_mode_at_the_capped_frequency(bench, grasp):
    """The dynamic difference the benchmark prints: with R = r I, a mode of our (undamped) network
    at w oscillates in MuJoCo at w / sqrt(1 + w^2 / w_c^2), w_c^2 = K imp (from a_c = A (A+R)^-1
    a_ref + R (A+R)^-1 a_u). Checked on a mid-spectrum mode of a 62-node sphere (fast); on the
    356-node sphere the same run gave 141.4 rad/s against 141.5 predicted for the lowest mode
    (153 rad/s in ours) and 363.9 against 363.9 for a 1374 rad/s mode."""
    _, sphere = bench
    _, setup, _ = grasp
    mujoco = sphere.mujoco
    mesh = make_object("sphere", 62)
    params = dataclasses.replace(setup.msd_params, b=0.0, c=0.0)
    stiffness, _ = sphere.our_rest_stiffness(mesh, params)
    eigenvalues, modes = np.linalg.eigh(stiffness * (62 / params.mass))
    elastic = np.flatnonzero(eigenvalues > 1e-6 * eigenvalues[-1])
    which = elastic[len(elastic) // 2]
    omega, mode = np.sqrt(eigenvalues[which]), modes[:, which]
    model, data = sphere.build_mujoco(mesh, params, setup.contact, 0.0, "edge", timestep=2.5e-4)
    _, _, omega_c = sphere.edge_rows_at_rest(model, data)
    mujoco.mj_resetData(model, data)
    data.mocap_pos[:] = 1.0  # fingertips away
    data.qpos[:] = 1e-5 * mode / np.abs(mode).max()
    projection = np.empty(400)
    for k in range(400):  # 0.1 s, several periods
        mujoco.mj_step(model, data)
        projection[k] = data.qpos @ mode
    crossings = np.flatnonzero(np.diff(np.sign(projection)) != 0)
    measured = np.pi / (np.mean(np.diff(crossings)) * model.opt.timestep)
    assert measured == pytest.approx(omega / np.sqrt(1.0 + (omega / omega_c) ** 2), rel=0.01)
    assert measured < 0.5 * omega  # far from our network's own frequency
