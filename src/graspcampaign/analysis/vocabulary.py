"""One vocabulary (order, label, colour) for every study, so a level reads and looks the same in every
table and figure. Orders are the paper's (Table 7 / Fig. 18 planners, Fig. 14 shapes, Table 4
materials), labels its words; the proposed planner is the report's main blue. A colour means one
thing: no two vocabularies (nor ``OTHER_COLOURS``) share one (docs/decisions.md, *One colour, one
meaning*)."""

from __future__ import annotations

from collections.abc import Iterable
from typing import NamedTuple


class Term(NamedTuple):
    """One entry of a vocabulary: its record value, display label and colour (none: a label only)."""

    key: str
    label: str
    colour: str = ""


def _terms(*rows: tuple[str, ...]) -> dict[str, Term]:
    return {row[0]: Term(*row) for row in rows}


#: The proposed planner (paper: "proposed", full H(G)).
PROPOSED = "heuristic"

PLANNERS = _terms(  # the heuristic's single-term ablations next to it, as in Fig. 16
    ("heuristic", "proposed H(G)", "#1f5aa6"),
    ("no_s1", "\u2212S1", "#4c78b5"), ("no_s2", "\u2212S2", "#5f8bc2"),
    ("no_s3", "\u2212S3", "#739ecf"), ("no_pc", "\u2212Pc", "#87b0db"),
    ("no_pe", "\u2212Pe", "#9bc2e6"), ("antipodal", "antipodal", "#e08a1e"),
    ("centroid", "centroid", "#8c8c8c"), ("no_pso", "no PSO", "#6a8fc7"),
    ("force_balance", "force balance", "#7b4ea3"), ("random", "random", "#c9a227"),
    ("ferrari_canny", "Ferrari\u2013Canny \u03b5", "#b5403a"), ("reference", "reference search", "#2e7d32"),
)
SHAPES = _terms(
    ("sphere", "sphere", "#1b9e77"), ("ellipsoid", "ellipsoid", "#e7298a"),
    ("rounded_cube", "rounded cube", "#66a61e"), ("pear", "pear", "#a6761d"),
    ("handle", "concave handle", "#17becf"),
)
MATERIALS = _terms(
    ("gel", "gel", "#01665e"), ("silicone_soft", "silicone, soft", "#9c27b0"),
    ("bio_foam", "bio foam", "#8c510a"), ("silicone_ref", "silicone, ref.", "#f781bf"),
)
GRIP_LAWS = _terms(  # issue 13 item 3; paper = Algorithm 2 as published (Sec. 6.5, 12)
    ("paper", "Algorithm 2 (paper)", "#283593"), ("slip", "slip-margin grip", "#ad1457"),
    ("oracle", "oracle equal grip", "#00897b"),
)
MODEL_PRESETS = _terms(  # conf/model
    ("table2", "Tables 2\u20133 constants", "#004d40"),
    ("firm", "firm preset (Shore 30A/50A, Hertz)", "#bf360c"),
    ("nominal", "nominal Hertz (uncalibrated)", "#9e9d24"),
)
INTEGRATORS = _terms(  # gravity_settle's factor (Sec. 12)
    ("rk4", "RK4 (explicit, the paper's)", "#311b92"), ("implicit", "implicit midpoint", "#ff8f00"),
)
OUTCOMES = _terms(
    ("stable", "stable", "#1b5e20"), ("success", "marginal success", "#81c784"),
    ("partial", "partial", "#ffb74d"), ("failure_slip", "slip", "#e57373"),
    ("failure_drop", "drop", "#c62828"), ("failure_damage", "damage", "#6d4c41"),
    ("failure_contact_loss", "contact loss", "#37474f"),
)
DYNAMIC_STATUSES = _terms(  # how a dynamic grasp ended (core.grasp_phases.STATUSES)
    ("stable", "held (stable)"), ("not_settled", "not settled by t_max"),
    ("penetration_limit", "penetration limit"), ("dropped", "dropped"),
)
LP_MU0_REASONS = _terms(  # why the friction-cone LP at mu = 0 fails (docs/records.md, lp_mu0_reason)
    ("feasible", "nothing (feasible)"), ("force_balance", "force balance"),
    ("torque_balance", "torque balance"),
)
BELIEF_MODELS = _terms(  # what a planner knows (rig/belief.py; decisions.md, Planner beliefs ...)
    ("calibrated", "Test 1 calibration"), ("nominal_law", "nominal Hertzian law"),
    ("nominal_geometry", "nominal Hertzian law, planar grasp"), ("actual", "actual quantities"),
)
BLOCKS = _terms(
    ("A", "lateral pull", "#c2185b"), ("B", "vertical load", "#00838f"),
    ("C", "yaw torque", "#8d6e63"), ("D", "impulse", "#e64a19"), ("E", "sinusoid", "#7cb342"),
)
PARAMETERS = _terms(
    ("lambda1", "\u03bb1"), ("lambda2", "\u03bb2"), ("n", "n"), ("n_exp", "n"), ("b", "b"), ("k", "k"),
    ("c", "c"),
)
ENVIRONMENTS = _terms(  # Test 1's environmental groups in the paper's words (Sec. 7.1)
    ("cool_dry", "cool/dry"), ("normal_lab", "normal-lab"), ("warm_humid", "warm/humid"),
)
SURROGATE_MODELS = _terms(  # Appendix A's models, and the brief PSO call they are timed against
    ("pso_call", "brief PSO call", "#4a148c"), ("mlp", "MLP 64-32", "#006064"),
    ("random_forest", "random forest", "#827717"),
)
SURROGATE_VARIABLES = _terms(  # Appendix A's labels, regression targets and features (record ids)
    ("success", "configured check (validity gate)"), ("success_unbounded", "Algorithm 1 as published"),
    ("success_vertical", "|R_z| reading"), ("abs_residual_z_n", "|R_z| [N]"),
    ("log10_residual_norm_n", "log10 \u2016R\u2016 [log10 N]"),
    ("log10_delta_max_mm", "log10 \u03b4max [log10 mm]"), ("mass_kg", "mass [kg]"), ("mu", "\u03bc"),
    ("lambda1", "\u03bb1"), ("lambda2", "\u03bb2"), ("msd_b", "MSD damping b"),
)
STUDY_PANELS = _terms(  # sensitivity (Fig. 19) and mesh_resolution (Fig. 20) panels
    ("mu_mass", "(a) \u03bc \u00d7 m"), ("lambda", "(b) \u03bb1 \u00d7 \u03bb2"), ("n_b", "(c) n \u00d7 b"),
    ("resolution", "mesh resolution"), ("budget", "candidate budget N_cand"),
    ("n_max", "doubled N_max re-run"),
)
FINGERS = _terms(  # Paul Tol's muted scheme (colour-blind safe): indigo, wine, purple
    ("finger1", "finger 1", "#332288"), ("finger2", "finger 2", "#882255"),
    ("finger3", "finger 3", "#aa4499"),
)
# Levels and counts the hardware protocols fix (rig/ builds its sheets from these) and the words a paper
# block keys them by (Test 1 §7.3; Test 2 §8.1 groups' trials; Test 3 §9.2 coatings, block B, block D)
OBLIQUE_ANGLES_DEG = (0.0, 15.0, 30.0, 45.0)
TEST2_GROUP_TRIALS = {"A": 120, "B": 240, "C": 144, "D": 105, "E": 120, "M": 90}
COATINGS = _terms(("high", "high"), ("medium", "medium"), ("low", "low"))
VERTICAL_LOADS_W = (("down", 0.25), ("down", 0.5), ("down", 0.75), ("up", 0.5), ("up", 1.0))
IMPULSE_LOADS_W = (0.8, 1.0, 1.2, 1.4, 1.8)

#: Record column -> its vocabulary.
VOCABULARIES: dict[str, dict[str, Term]] = {
    "planner": PLANNERS, "shape": SHAPES, "material": MATERIALS, "grip_law": GRIP_LAWS,
    "model_preset": MODEL_PRESETS, "integrator": INTEGRATORS, "outcome": OUTCOMES,
    "block": BLOCKS, "parameter": PARAMETERS, "panel": STUDY_PANELS,
    "dynamic_status": DYNAMIC_STATUSES, "environment": ENVIRONMENTS, "model": SURROGATE_MODELS,
    "variable": SURROGATE_VARIABLES, "lp_mu0_reason": LP_MU0_REASONS, "belief_model": BELIEF_MODELS,
    # a McNemar table's compared planner; a table's scope of trials (a planner, or "all", "baselines" ...
    # that print as they are)
    "compared": PLANNERS, "scope": PLANNERS,
    # a paper block's keys only: no record column holds these
    "finger": FINGERS, "coating": COATINGS,
    "press_angle": _terms(*((f"{a:g}", f"{a:g}°") for a in OBLIQUE_ANGLES_DEG)),
    "vertical_load": _terms(*((f"{way}_{w}", f"{way} {w:g} W") for way, w in VERTICAL_LOADS_W)),
    "impulse_load": _terms(*((str(w), f"{w:g} W") for w in IMPULSE_LOADS_W)),
}
#: Header of a factor column outside the vocabularies (its unit in brackets).
FACTOR_LABELS = {"mu": "μ", "mass_kg": "mass [kg]", "nodes": "nodes", "weight_scale":
                 "weight scale", "n_cand": "N_cand", "friction_level": "friction"}
#: Unit suffixes of record columns ``<words>_<unit>`` (docs/records.md) and how headers print them.
UNITS = {"pct": "%", "mm": "mm", "m": "m", "n": "N", "nm": "N·m", "s": "s", "ms": "ms",
         "kg": "kg", "j": "J", "mj": "mJ", "deg": "°", "rad": "rad", "kpa": "kPa"}
#: Colours of levels outside every vocabulary (friction levels, node counts), in level order: a green
#: ramp, dark to light, as such levels are ordered.
OTHER_COLOURS = ("#00441b", "#006d2c", "#238b45", "#41ae76", "#66c2a4", "#99d8c9")


def label(column: str, value: object) -> str:
    """Return the display label of ``value`` in ``column`` (the value itself if unknown)."""
    term = VOCABULARIES.get(column, {}).get(str(value))
    return term.label if term else str(value)


def things(column: str) -> str:
    """Return ``column`` without its unit suffix (``lat_threshold_n`` -> ``lat_threshold``): the
    things a count ``n_<things>`` of it counts."""
    words, _, suffix = column.rpartition("_")
    return words if words and suffix in UNITS else column


def colour(column: str, value: object, index: int = 0) -> str:
    """Return the colour of ``value`` in ``column``; unknown values cycle ``OTHER_COLOURS``."""
    term = VOCABULARIES.get(column, {}).get(str(value))
    return term.colour if term and term.colour else OTHER_COLOURS[index % len(OTHER_COLOURS)]


def ordered(column: str, values: Iterable, first: Iterable = ()) -> list:
    """Return the distinct ``values`` in display order: the levels of ``first`` (a study's design order)
    that the vocabulary lacks (a column without one, a table's ``all`` scope), the vocabulary's, then
    by text: a planner is listed in the vocabulary's order whatever a study's design order."""
    import pandas as pd  # here: composing a study reads VOCABULARIES, and `show` needs no pandas

    if isinstance(values, pd.Series):  # a column of ~10^5 records: each distinct value once
        values = values.unique()
    values = list(dict.fromkeys(v for v in values if not pd.isna(v)))
    vocabulary, rank = VOCABULARIES.get(column, {}), {}
    for v in [*(v for v in first if v not in vocabulary), *vocabulary]:
        rank.setdefault(v, len(rank))
    return sorted(values, key=lambda v: (rank.get(v, rank.get(str(v), len(rank))), str(v)))


def data_source(sources: Iterable, declared: str | None) -> str:
    """The data source a run is reported as (SPEC §4), from the ``source`` values its records hold
    and the source its manifest declares: ``virtual`` as soon as one record says so, else the
    declared source (``simulation`` if none). Pure Python, so ``status`` answers without pandas."""
    return "virtual" if "virtual" in set(sources) else str(declared or "simulation")
