"""Typed ``paper:`` blocks of the hardware protocols, Tests 1-3 (paper §7-§9).

See :mod:`graspcampaign.campaign.paper` for the rules. Field names follow the study files;
``*_pct`` in percent, ranges as closed ``(low, high)`` tuples.
"""

from __future__ import annotations

from dataclasses import dataclass

from graspcampaign.campaign.paper import Range, keyed

# --------------------------------------------------------------------------------------------
# Test 1 (§7, Tables 4-5, Figs. 23-26)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Table4Row:
    """One material family of Table 4 (E mean ± SD over 12 specimens, the rest means)."""

    modulus_kpa: float
    modulus_sd_kpa: float
    exponent_n: float
    k_n_per_mm_n: float
    f05_n: float
    c_n_s_per_m: float
    mu_s: float
    mu_k: float
    k_t_n_per_mm: float
    rho: float
    tau_s: float


@dataclass(frozen=True)
class Table5Row:
    """One parameter of Table 5: simulation (Table 3) and experiment mean ± SD, CV."""

    simulation: float
    mean: float
    sd: float
    cv_pct: float


@dataclass(frozen=True)
class RmseSummary:
    """Mean, median and largest RMSE [% of peak]."""

    mean: float
    median: float
    max: float


@dataclass(frozen=True)
class NormalTransfer:
    """Normal-force transfer error per split [%] (Fig. 26c)."""

    train: float
    unseen_specimen: float
    unseen_speed: float


@dataclass(frozen=True)
class TransferPaper:
    """§7.6, Fig. 26c: transfer errors [%]."""

    normal_force: NormalTransfer
    friction_max: float
    relaxation: float
    flat_to_curved: float


@dataclass(frozen=True)
class Test1Paper:
    """§7: bench calibration."""

    tables: str
    events_commanded: int
    events_completed: int
    events_aborted: int
    normal_fits: int
    normal_fits_accepted: int
    oblique_events: int
    cycle_measurements: int
    retained_trace_events: int
    retained_trace_samples: int
    n_exp_mean: float
    n_exp_sd: float
    n_exp_family_range: Range
    n_exp_simulation: float
    rmse_pct: float
    rmse_pct_accepted: float
    rmse_pct_all: float
    flagged_rmse_pct_range: Range
    loop_area_median_mj: float
    loading_work_median_mj: float
    unloading_work_median_mj: float
    oblique_margin_n: dict[str, float] = keyed("press_angle")
    oblique_classification_match_pct: float
    mu_s_environment: dict[str, float] = keyed("environment")
    stick_slip_transition_mm_per_s: float
    k_t_range_n_per_mm: Range
    relaxation_ratio_fig25a: float
    k_ratio_target: float
    permanent_set_mm: Range
    stabilises_after_cycles: int
    table4: dict[str, Table4Row] = keyed("material")
    table5: dict[str, Table5Row] = keyed("parameter")
    pso_runs_logged: int
    pso_runs_converged: int
    pso_n_run_median: float
    pso_transfer_rmse_pct: RmseSummary
    pso_diverged_transfer_rmse_pct: Range
    transfer_pct: TransferPaper


# --------------------------------------------------------------------------------------------
# Test 2 (§8, Tables 6-7, Figs. 28-31)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Table6Row:
    """Proposed planner on one shape (Table 6)."""

    n: int
    success_pct: float
    natural_pct: float
    force_err_pct: float
    deformation_err_pct: float


@dataclass(frozen=True)
class Table7Row:
    """Executed trials of one planner (Table 7)."""

    n: int
    success_pct: float
    stable_pct: float
    slip_pct: float
    drop_pct: float
    damage_pct: float


@dataclass(frozen=True)
class ClassifierPaper:
    """Scores of a pre-execution flag against measured success."""

    accuracy: float
    precision: float
    recall: float
    f1: float | None = None


@dataclass(frozen=True)
class GroupCProposed:
    """§8.1: the flag on the proposed planner's group C trials: how many it certifies (and their share),
    how many of those are not successes, its precision, and its certified share outside group C."""

    section: str
    trials: int
    certified: int
    certified_failed: int
    precision: float
    certified_pct: float
    certified_elsewhere_pct: float


@dataclass(frozen=True)
class GroupCPooled:
    """§8.4: the pooled flag's precision inside group C and over every other trial."""

    section: str
    precision: float
    precision_elsewhere: float


@dataclass(frozen=True)
class GroupCPaper:
    """The flag's precision inside group C as §8.1 (proposed planner) and §8.4 (pooled) print it."""

    proposed: GroupCProposed
    pooled: GroupCPooled


@dataclass(frozen=True)
class McNemarPaper:
    """A printed McNemar test: chi2 (continuity-corrected), pairs won and lost, odds ratio."""

    chi2: float
    won: int
    lost: int
    odds_ratio: float | None = None


@dataclass(frozen=True)
class Test2Paper:
    """§8: grasp validation."""

    tables: str
    commanded: int
    executed: int
    aborted: int
    proposed_trials: int
    proposed_success_pct: float
    proposed_success_wilson_pct: Range
    proposed_success_bootstrap_pct: Range
    validation_success_pct: float
    group_c_pct: float
    group_e_success_pct_range: Range
    proposed_stable_pct: float
    proposed_marginal_pct: float
    proposed_drop_damage_contact_pct_max: float
    centroid_success_pct: float
    no_pso_success_pct: float
    force_balance_success_pct: float
    random_success_pct: float
    parity_slope: float
    parity_r2: float
    force_err_median_pct: float
    deformation_err_median_pct: float
    contact_point_err_median_mm: float
    hold_force_per_finger_n: Range
    hold_slip_max_mm: float
    lift_height_mm: float
    fig28_reference_pct: float
    classifier: ClassifierPaper
    classifier_proposed: ClassifierPaper
    classifier_baselines_precision: float
    classifier_group_c: GroupCPaper
    proposed_certified: int
    proposed_certified_failed: int
    successes_labelled_unstable: int
    measured_successes: int
    mcnemar_centroid: McNemarPaper
    chi2_planner_success: float
    force_err_planner_median_pct_range: Range
    force_err_kruskal_p: float
    slip_friction_kruskal_h: float
    table6: dict[str, Table6Row] = keyed("shape")
    table7: dict[str, Table7Row] = keyed("planner")
    success_by_material_pct: dict[str, float] = keyed("material")
    matched_pct: dict[str, float] = keyed("planner")


# --------------------------------------------------------------------------------------------
# Test 3 (§9, Tables 8-9, Figs. 33-36)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Table8Row:
    """One disturbance block of Table 8 (proposed planner, natural friction)."""

    disturbance: str
    n: int
    success_pct: float
    pred_err_pct: float
    headline: float | None = None
    headline_unit: str | None = None


@dataclass(frozen=True)
class Table9Row:
    """One planner of Table 9 (all trials)."""

    n: int
    success_pct: float
    wilson_pct: Range
    stable_pct: float
    drop_pct: float
    damage_pct: float
    lat_threshold_n: float
    threshold_err_pct: float


@dataclass(frozen=True)
class CoatingLevel:
    """One coating of the friction probes (§9.2)."""

    threshold_n: float
    success_pct: float


@dataclass(frozen=True)
class SurvivalPaper:
    """§9.5, Fig. 36b: the lateral-threshold survival curve."""

    above_3n_pct: float
    half_at_n: float
    above_5n_pct: float
    centroid_failed_by_n: float


@dataclass(frozen=True)
class LogisticPaper:
    """§9.5: logistic regression of failure (n and coefficients)."""

    n: int
    load: float
    mass: float
    mu: float
    proposed: float


@dataclass(frozen=True)
class Test3Paper:
    """§9: disturbance rejection."""

    tables: str
    commanded: int
    executed: int
    aborted: int
    proposed_trials: int
    proposed_success_pct: float
    proposed_success_wilson_pct: Range
    proposed_success_bootstrap_pct: Range
    natural_success_pct: float
    no_pso_success_pct: float
    centroid_success_pct: float
    force_balance_success_pct: float
    random_success_pct: float
    lateral_threshold_median_n: float
    direction_threshold_range_n: Range
    coating: dict[str, CoatingLevel] = keyed("coating")
    down_payload_median_pct_w: float
    vertical_levels_pct: dict[str, float] = keyed("vertical_load")
    yaw_torque_median_nm: float
    yaw_torque_with_probes_nm: float
    yaw_rotation_median_deg: float
    blocks_pct: dict[str, float] = keyed("block")
    lateral_threshold_median_error_pct: float
    lateral_threshold_trials: int
    geometric_baseline_error_pct: float
    threshold_err_centroid_pct: float
    threshold_err_force_balance_pct: float
    threshold_ols_slope: float
    threshold_ols_r2: float
    bland_altman_bias_n: float
    bland_altman_loa_half_width_n: float
    threshold_err_over_50pct: float
    torque_threshold_err_pct: float
    block_parity_r2: dict[str, float] = keyed("block")
    first_finger_accuracy_pct: float
    impulse_retained_pct: dict[str, float] = keyed("impulse_load")
    impulse_drop_pct: dict[str, float] = keyed("impulse_load")
    impulse_residual_slip_mm: float
    sinusoid_slip_mm_range: Range
    sinusoid_pct: float
    matched_proposed_pct: float
    matched_baseline_success_pct_range: Range
    matched_difference_centroid_pp: float
    mcnemar_centroid: McNemarPaper
    margin_over_random_pp: float
    survival: SurvivalPaper
    retention_classifier: ClassifierPaper
    retention_certified: int
    retention_certified_failed: int
    logistic: LogisticPaper
    chi2_planner_retention: float
    drop_pct: float
    damage_pct: float
    table8: dict[str, Table8Row] = keyed("block")
    table9: dict[str, Table9Row] = keyed("planner")
