"""Tests for the planners (Algorithm 1, §6.3, §6.5, SPEC §2.8)."""

import itertools
from dataclasses import replace

import numpy as np
import pytest
import trimesh
from scipy.stats import chisquare

from graspcampaign.core.baseline import _all_triples_chunks
from graspcampaign.core.contact import NOMINAL_CONTACT, ContactParams
from graspcampaign.core.feature import sharp_features
from graspcampaign.core.mesh import SHAPES, make_object
from graspcampaign.core.metric import heuristic_terms
from graspcampaign.core.planner import (
    ABLATIONS,
    PLANNERS,
    identification_contacts,
    plan_context,
    sample_triples,
    vertex_sampling_weights,
)

IDENTIFIED = ContactParams(lambda1=1.5, lambda2=0.5, n=1.0)


@pytest.fixture(scope="module")
def meshes():
    return {shape: make_object(shape, 144) for shape in SHAPES}


def context(mesh, **kwargs):
    kwargs.setdefault("mass", 0.4)
    kwargs.setdefault("mu", 0.3)
    kwargs.setdefault("contact", IDENTIFIED)
    kwargs.setdefault("n_cand", 300)
    return plan_context(mesh, sharp_features(mesh), **kwargs)


@pytest.fixture(scope="module")
def sphere_ctx(meshes):
    return context(meshes["sphere"], reference_budget=2000, exhaustive_limit=0)


def test_registry_holds_every_planner():
    assert set(PLANNERS) == {
        "heuristic",
        "no_pso",
        "random",
        "antipodal",
        "centroid",
        "ferrari_canny",
        "force_balance",
        "no_s1",
        "no_s2",
        "no_s3",
        "no_pc",
        "no_pe",
        "reference",
    }
    assert set(ABLATIONS) == {"no_s1", "no_s2", "no_s3", "no_pc", "no_pe"}


@pytest.mark.parametrize("name", sorted(PLANNERS))
def test_planner_result_is_self_consistent(sphere_ctx, name):
    ctx = sphere_ctx
    result = PLANNERS[name](ctx, np.random.default_rng(11))
    assert result.planner == name
    assert result.vertex_ids.shape == (3,) and len(set(result.vertex_ids.tolist())) == 3
    assert result.points.shape == (3, 3) and result.normals.shape == (3, 3)
    np.testing.assert_allclose(np.linalg.norm(result.normals, axis=1), 1.0)
    terms = heuristic_terms(ctx.heuristic, result.vertex_ids[None])
    assert result.h_total == pytest.approx(terms.total(ctx.weights)[0])
    assert (result.s1, result.s2, result.s3) == pytest.approx((terms.s1[0], terms.s2[0], terms.s3[0]))
    assert result.equilibrium.success.shape == (1,)
    assert result.contact == (NOMINAL_CONTACT if name == "no_pso" else IDENTIFIED)
    assert result.believed_success == bool(result.equilibrium.success[0])
    if name != "centroid":
        np.testing.assert_array_equal(result.points, ctx.vertices[result.vertex_ids])
        np.testing.assert_array_equal(result.normals, ctx.normals[result.vertex_ids])


def test_heuristic_is_argmin_of_its_own_candidates(sphere_ctx):
    ctx = sphere_ctx
    result = PLANNERS["heuristic"](ctx, np.random.default_rng(5))
    triples = sample_triples(ctx.sampling_weights, ctx.n_cand, np.random.default_rng(5))
    scores = heuristic_terms(ctx.heuristic, triples).total(ctx.weights)
    np.testing.assert_array_equal(result.vertex_ids, triples[np.argmin(scores)])
    assert result.h_planner == pytest.approx(scores.min()) and result.n_scored == ctx.n_cand
    # The same draw gives the identification contact set and the no-PSO triple.
    ids, points, normals = identification_contacts(ctx, np.random.default_rng(5))
    np.testing.assert_array_equal(ids, result.vertex_ids)
    no_pso = PLANNERS["no_pso"](ctx, np.random.default_rng(5))
    np.testing.assert_array_equal(no_pso.vertex_ids, result.vertex_ids)


@pytest.mark.parametrize("name", sorted(ABLATIONS) + ["force_balance"])
def test_ablation_minimises_the_reduced_heuristic(sphere_ctx, name):
    ctx = sphere_ctx
    result = PLANNERS[name](ctx, np.random.default_rng(8))
    if name == "force_balance":
        weights = replace(ctx.weights, w2=0.0, w3=0.0, p_c=0.0, p_e=0.0)
    else:
        weights = replace(ctx.weights, **{ABLATIONS[name]: 0.0})
    triples = sample_triples(ctx.sampling_weights, ctx.n_cand, np.random.default_rng(8))
    assert result.h_planner == pytest.approx(heuristic_terms(ctx.heuristic, triples).total(weights).min())
    if name == "force_balance":
        assert result.h_planner == pytest.approx(result.s1)


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_centroid_contacts_are_horizontal_and_stay_at_seed(meshes, shape):
    mesh = meshes[shape]
    for mu in (0.1, 0.3, 0.5):
        ctx = context(mesh, mu=mu, mass=0.2)
        result = PLANNERS["centroid"](ctx, np.random.default_rng(3))
        # Exact points in the horizontal plane through the centroid, on the surface
        # (distance by trimesh's closest point on each triangle).
        np.testing.assert_allclose(result.points[:, 2], ctx.centroid[2], atol=1e-12)
        triangles = mesh.triangles
        distances = [
            np.min(
                np.linalg.norm(
                    trimesh.triangles.closest_point(triangles, np.repeat(p[None], len(triangles), 0)) - p,
                    axis=1,
                )
            )
            for p in result.points
        ]
        assert max(distances) < 1e-9
        azimuths = np.arctan2(*(result.points - ctx.centroid)[:, [1, 0]].T)
        gaps = np.diff(np.sort(np.degrees(azimuths)))
        np.testing.assert_allclose(gaps, 120.0, atol=1e-9)
        assert np.all(result.normals[:, 2] == 0.0)
        # §6.5: g_k = 0, delta never leaves its seed, and the grasp fails at every mu.
        np.testing.assert_array_equal(result.equilibrium.depths, ctx.evaluator.seed_depth)
        assert not result.equilibrium.success[0]
        assert not result.equilibrium.residual_ok[0] and not result.equilibrium.slip_ok[0]


def test_antipodal_pair_is_diametric_on_sphere_with_perpendicular_third(sphere_ctx):
    ctx = sphere_ctx
    result = PLANNERS["antipodal"](ctx, np.random.default_rng(2))
    p_i, p_j, p_k = result.points
    axis = (p_j - p_i) / np.linalg.norm(p_j - p_i)
    assert np.linalg.norm(p_i + p_j) < 0.2 * 0.05  # near-diametric pair on the 5 cm sphere
    assert np.dot(result.normals[0], axis) < -0.95 and np.dot(result.normals[1], axis) > 0.95
    offset = p_k - 0.5 * (p_i + p_j)
    assert abs(np.dot(offset, axis)) / np.linalg.norm(offset) < 0.25


@pytest.mark.filterwarnings("ignore::graspcampaign.core.feature.CoarseMeshWarning")
def test_reference_exhaustive_equals_brute_force_argmin():
    mesh = make_object("sphere", 20)
    ctx = context(mesh)
    result = PLANNERS["reference"](ctx, np.random.default_rng(0))
    everything = np.array(list(itertools.combinations(range(20), 3)))
    scores = heuristic_terms(ctx.heuristic, everything).total(ctx.weights)
    assert result.exhaustive and result.n_scored == len(everything) == 1140
    assert result.h_planner == pytest.approx(scores.min())
    heuristic = PLANNERS["heuristic"](ctx, np.random.default_rng(0))
    assert heuristic.h_total >= result.h_total


def test_all_triples_chunks_enumerate_each_combination_once():
    chunks = list(_all_triples_chunks(13, chunk=17))
    assert len(chunks) > 1
    got = np.concatenate(chunks)
    expected = np.array(list(itertools.combinations(range(13), 3)))
    np.testing.assert_array_equal(got, expected)


def test_vertex_weights_are_barycentric_areas(meshes):
    mesh = meshes["pear"]
    faces = mesh.vertex_faces  # trimesh adjacency, padded with -1
    areas = np.where(faces >= 0, mesh.area_faces[faces], 0.0).sum(axis=1) / 3.0
    np.testing.assert_allclose(vertex_sampling_weights(mesh), areas / mesh.area, rtol=1e-12)


def test_sample_triples_are_distinct_and_follow_the_weights():
    rng = np.random.default_rng(9)
    weights = rng.uniform(0.5, 1.5, 200)
    weights /= weights.sum()
    triples = sample_triples(weights, 100_000, np.random.default_rng(10))
    assert np.all(triples[:, 0] != triples[:, 1]) and np.all(triples[:, 1] != triples[:, 2])
    assert np.all(triples[:, 0] != triples[:, 2])
    counts = np.bincount(triples[:, 0], minlength=200)
    assert chisquare(counts, weights * counts.sum()).pvalue > 1e-4
    with pytest.raises(ValueError, match=r"need at least 3 vertices"):
        sample_triples(np.array([0.5, 0.5]), 1, rng)


def test_plan_context_validates_budget(meshes):
    with pytest.raises(ValueError, match=r"n_cand must be a positive int"):
        context(meshes["sphere"], n_cand=0)


def test_ferrari_canny_scores_the_heuristics_candidates(sphere_ctx):
    # Same generator state -> the same N_cand triples: ferrari_canny picks their epsilon argmax,
    # the heuristic their H argmin, and each result carries the other's measure of its triple.
    from graspcampaign.core.candidate import candidate_epsilon

    fc = PLANNERS["ferrari_canny"](sphere_ctx, np.random.default_rng(11))
    heuristic = PLANNERS["heuristic"](sphere_ctx, np.random.default_rng(11))
    triples = sample_triples(sphere_ctx.sampling_weights, sphere_ctx.n_cand, np.random.default_rng(11))
    epsilon = candidate_epsilon(sphere_ctx, triples)
    assert fc.n_scored == heuristic.n_scored == sphere_ctx.n_cand
    np.testing.assert_array_equal(fc.candidates.epsilon, epsilon)
    assert fc.epsilon_fc == pytest.approx(epsilon.max(), rel=1e-12)
    assert sorted(fc.vertex_ids) == sorted(triples[int(np.argmax(epsilon))])
    h = heuristic_terms(sphere_ctx.heuristic, triples).total(sphere_ctx.weights)
    np.testing.assert_allclose(fc.candidates.h_total, h)
    assert heuristic.epsilon_fc == pytest.approx(epsilon[int(np.argmin(h))], rel=1e-9, abs=1e-15)


@pytest.mark.parametrize("shape", ["sphere", "ellipsoid", "rounded_cube"])
def test_ferrari_canny_beats_random_on_force_closure(meshes, shape):
    # Force closure = epsilon > 0. The epsilon argmax of 300 candidates is in force closure
    # whenever any candidate is; a single random triple only at the base rate.
    ctx = context(meshes[shape])
    fc = [PLANNERS["ferrari_canny"](ctx, np.random.default_rng(s)).epsilon_fc for s in range(15)]
    rand = [PLANNERS["random"](ctx, np.random.default_rng(s)).epsilon_fc for s in range(15)]
    assert np.mean(np.array(fc) > 0) == 1.0
    assert np.mean(np.array(rand) > 0) < 0.8
    assert np.all(np.array(fc) >= np.array(rand))
