"""Typed ``paper:`` blocks of the hardware protocols, Tests 1-3 (paper §7-§9).

See :mod:`graspcampaign.campaign.paper` for the rules. Field names follow the study files;
``*_pct`` in percent, ranges as closed ``(low, high)`` tuples; each number is typed with its kind
of quantity (:mod:`graspcampaign.campaign.paper_bounds`), which bounds it.
"""

from __future__ import annotations

from dataclasses import dataclass

from graspcampaign.campaign.paper import keyed
from graspcampaign.campaign.paper_bounds import (
    R2,
    AngleDeg,
    Count,
    Fraction,
    Friction,
    NonNegative,
    NonNegativeRange,
    Pct,
    PctError,
    PctErrorRange,
    PctOfWeight,
    PctRange,
    PointsDiff,
    Positive,
    PositiveRange,
    PValue,
    Score,
    Signed,
)

# --------------------------------------------------------------------------------------------
# Test 1 (§7, Tables 4-5, Figs. 23-26)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Table4Row:
    """One material family of Table 4 (E mean ± SD over 12 specimens, the rest means)."""

    modulus_kpa: Positive
    modulus_sd_kpa: NonNegative
    exponent_n: Positive
    k_n_per_mm_n: Positive
    f05_n: Positive
    c_n_s_per_m: Positive
    mu_s: Friction
    mu_k: Friction
    k_t_n_per_mm: Positive
    rho: Fraction
    tau_s: Positive


@dataclass(frozen=True)
class Table5Row:
    """One parameter of Table 5: simulation (Table 3) and experiment mean ± SD, CV."""

    simulation: Positive
    mean: Positive
    sd: NonNegative
    cv_pct: PctError


@dataclass(frozen=True)
class RmseSummary:
    """Mean, median and largest RMSE [% of peak]."""

    mean: PctError
    median: PctError
    max: PctError


@dataclass(frozen=True)
class NormalTransfer:
    """Normal-force transfer error per split [%] (Fig. 26c)."""

    train: PctError
    unseen_specimen: PctError
    unseen_speed: PctError


@dataclass(frozen=True)
class TransferPaper:
    """§7.6, Fig. 26c: transfer errors [%]."""

    normal_force: NormalTransfer
    friction_max: PctError
    relaxation: PctError
    flat_to_curved: PctError


@dataclass(frozen=True)
class Test1Paper:
    """§7: bench calibration."""

    tables: str
    events_commanded: Count
    events_completed: Count
    events_aborted: Count
    normal_fits: Count
    normal_fits_accepted: Count
    oblique_events: Count
    cycle_measurements: Count
    retained_trace_events: Count
    retained_trace_samples: Count
    n_exp_mean: Positive
    n_exp_sd: NonNegative
    n_exp_family_range: PositiveRange
    n_exp_simulation: Positive
    rmse_pct: PctError
    rmse_pct_accepted: PctError
    rmse_pct_all: PctError
    flagged_rmse_pct_range: PctErrorRange
    loop_area_median_mj: NonNegative
    loading_work_median_mj: NonNegative
    unloading_work_median_mj: NonNegative
    oblique_margin_n: dict[str, Signed] = keyed("press_angle")
    oblique_classification_match_pct: Pct
    mu_s_environment: dict[str, Friction] = keyed("environment")
    stick_slip_transition_mm_per_s: Positive
    k_t_range_n_per_mm: PositiveRange
    relaxation_ratio_fig25a: Fraction
    k_ratio_target: Positive
    permanent_set_mm: NonNegativeRange
    stabilises_after_cycles: Count
    table4: dict[str, Table4Row] = keyed("material")
    table5: dict[str, Table5Row] = keyed("parameter")
    pso_runs_logged: Count
    pso_runs_converged: Count
    pso_n_run_median: Positive
    pso_transfer_rmse_pct: RmseSummary
    pso_diverged_transfer_rmse_pct: PctErrorRange
    transfer_pct: TransferPaper


# --------------------------------------------------------------------------------------------
# Test 2 (§8, Tables 6-7, Figs. 28-31)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Table6Row:
    """Proposed planner on one shape (Table 6)."""

    n: Count
    success_pct: Pct
    natural_pct: Pct
    force_err_pct: PctError
    deformation_err_pct: PctError


@dataclass(frozen=True)
class Table7Row:
    """Executed trials of one planner (Table 7)."""

    n: Count
    success_pct: Pct
    stable_pct: Pct
    slip_pct: Pct
    drop_pct: Pct
    damage_pct: Pct


@dataclass(frozen=True)
class ClassifierPaper:
    """Scores of a pre-execution flag against measured success."""

    accuracy: Score
    precision: Score
    recall: Score
    f1: Score | None = None


@dataclass(frozen=True)
class GroupCProposed:
    """§8.1: the flag on the proposed planner's group C trials: how many it certifies (and their share),
    how many of those are not successes, its precision, and its certified share outside group C."""

    section: str
    trials: Count
    certified: Count
    certified_failed: Count
    precision: Score
    certified_pct: Pct
    certified_elsewhere_pct: Pct


@dataclass(frozen=True)
class GroupCPooled:
    """§8.4: the pooled flag's precision inside group C and over every other trial."""

    section: str
    precision: Score
    precision_elsewhere: Score


@dataclass(frozen=True)
class GroupCPaper:
    """The flag's precision inside group C as §8.1 (proposed planner) and §8.4 (pooled) print it."""

    proposed: GroupCProposed
    pooled: GroupCPooled


@dataclass(frozen=True)
class McNemarPaper:
    """A printed McNemar test: chi2 (continuity-corrected), pairs won and lost, odds ratio."""

    chi2: NonNegative
    won: Count
    lost: Count
    odds_ratio: NonNegative | None = None


@dataclass(frozen=True)
class Test2Paper:
    """§8: grasp validation."""

    tables: str
    commanded: Count
    executed: Count
    aborted: Count
    proposed_trials: Count
    proposed_success_pct: Pct
    proposed_success_wilson_pct: PctRange
    proposed_success_bootstrap_pct: PctRange
    validation_success_pct: Pct
    group_c_pct: Pct
    group_e_success_pct_range: PctRange
    proposed_stable_pct: Pct
    proposed_marginal_pct: Pct
    proposed_drop_damage_contact_pct_max: Pct
    centroid_success_pct: Pct
    no_pso_success_pct: Pct
    force_balance_success_pct: Pct
    random_success_pct: Pct
    parity_slope: Signed
    parity_r2: R2
    force_err_median_pct: PctError
    deformation_err_median_pct: PctError
    contact_point_err_median_mm: NonNegative
    hold_force_per_finger_n: PositiveRange
    hold_slip_max_mm: NonNegative
    lift_height_mm: Positive
    fig28_reference_pct: Pct
    classifier: ClassifierPaper
    classifier_proposed: ClassifierPaper
    classifier_baselines_precision: Score
    classifier_group_c: GroupCPaper
    proposed_certified: Count
    proposed_certified_failed: Count
    successes_labelled_unstable: Count
    measured_successes: Count
    mcnemar_centroid: McNemarPaper
    chi2_planner_success: NonNegative
    force_err_planner_median_pct_range: PctErrorRange
    force_err_kruskal_p: PValue
    slip_friction_kruskal_h: NonNegative
    table6: dict[str, Table6Row] = keyed("shape")
    table7: dict[str, Table7Row] = keyed("planner")
    success_by_material_pct: dict[str, Pct] = keyed("material")
    matched_pct: dict[str, Pct] = keyed("planner")


# --------------------------------------------------------------------------------------------
# Test 3 (§9, Tables 8-9, Figs. 33-36)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Table8Row:
    """One disturbance block of Table 8 (proposed planner, natural friction)."""

    disturbance: str
    n: Count
    success_pct: Pct
    pred_err_pct: PctError
    headline: Positive | None = None
    headline_unit: str | None = None


@dataclass(frozen=True)
class Table9Row:
    """One planner of Table 9 (all trials)."""

    n: Count
    success_pct: Pct
    wilson_pct: PctRange
    stable_pct: Pct
    drop_pct: Pct
    damage_pct: Pct
    lat_threshold_n: Positive
    threshold_err_pct: PctError


@dataclass(frozen=True)
class CoatingLevel:
    """One coating of the friction probes (§9.2)."""

    threshold_n: Positive
    success_pct: Pct


@dataclass(frozen=True)
class SurvivalPaper:
    """§9.5, Fig. 36b: the lateral-threshold survival curve."""

    above_3n_pct: Pct
    half_at_n: Positive
    above_5n_pct: Pct
    centroid_failed_by_n: Positive


@dataclass(frozen=True)
class LogisticPaper:
    """§9.5: logistic regression of failure (n and coefficients)."""

    n: Count
    load: Signed
    mass: Signed
    mu: Signed
    proposed: Signed


@dataclass(frozen=True)
class Test3Paper:
    """§9: disturbance rejection."""

    tables: str
    commanded: Count
    executed: Count
    aborted: Count
    proposed_trials: Count
    proposed_success_pct: Pct
    proposed_success_wilson_pct: PctRange
    proposed_success_bootstrap_pct: PctRange
    natural_success_pct: Pct
    no_pso_success_pct: Pct
    centroid_success_pct: Pct
    force_balance_success_pct: Pct
    random_success_pct: Pct
    lateral_threshold_median_n: Positive
    direction_threshold_range_n: PositiveRange
    coating: dict[str, CoatingLevel] = keyed("coating")
    down_payload_median_pct_w: PctOfWeight
    vertical_levels_pct: dict[str, Pct] = keyed("vertical_load")
    yaw_torque_median_nm: Positive
    yaw_torque_with_probes_nm: Positive
    yaw_rotation_median_deg: AngleDeg
    blocks_pct: dict[str, Pct] = keyed("block")
    lateral_threshold_median_error_pct: PctError
    lateral_threshold_trials: Count
    geometric_baseline_error_pct: PctError
    threshold_err_centroid_pct: PctError
    threshold_err_force_balance_pct: PctError
    threshold_ols_slope: Signed
    threshold_ols_r2: R2
    bland_altman_bias_n: Signed
    bland_altman_loa_half_width_n: NonNegative
    threshold_err_over_50pct: Count
    torque_threshold_err_pct: PctError
    block_parity_r2: dict[str, R2] = keyed("block")
    first_finger_accuracy_pct: Pct
    impulse_retained_pct: dict[str, Pct] = keyed("impulse_load")
    impulse_drop_pct: dict[str, Pct] = keyed("impulse_load")
    impulse_residual_slip_mm: NonNegative
    sinusoid_slip_mm_range: NonNegativeRange
    sinusoid_pct: Pct
    matched_proposed_pct: Pct
    matched_baseline_success_pct_range: PctRange
    matched_difference_centroid_pp: PointsDiff
    mcnemar_centroid: McNemarPaper
    margin_over_random_pp: PointsDiff
    survival: SurvivalPaper
    retention_classifier: ClassifierPaper
    retention_certified: Count
    retention_certified_failed: Count
    logistic: LogisticPaper
    chi2_planner_retention: NonNegative
    drop_pct: Pct
    damage_pct: Pct
    table8: dict[str, Table8Row] = keyed("block")
    table9: dict[str, Table9Row] = keyed("planner")
