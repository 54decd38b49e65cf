"""Public statistics API for notebooks: ``from graspcampaign import stats``.

Re-exports the statistics of the analysis layer (:mod:`graspcampaign.analysis.rates`,
:mod:`~graspcampaign.analysis.association`, :mod:`~graspcampaign.analysis.agreement`). Every
function validates its inputs first (:mod:`graspcampaign.analysis.checks`, one sentence naming
the argument) and hands the computation to scipy.stats / statsmodels; results are small frozen
dataclasses. Display formatting lives in :mod:`graspcampaign.report.format`.
"""

from graspcampaign.analysis.agreement import (
    LIMITS_OF_AGREEMENT_Z,
    BlandAltmanResult,
    ClassifierMetrics,
    ParityResult,
    SurvivalCurve,
    bland_altman,
    classifier_metrics,
    coefficient_of_variation,
    median_abs_pct_error,
    parity_fit,
    survival_curve,
)
from graspcampaign.analysis.association import (
    Chi2Result,
    KruskalResult,
    LogisticResult,
    RatesTest,
    chi2_contingency_test,
    equal_rates_test,
    kruskal_wallis,
    logistic_regression,
)
from graspcampaign.analysis.rates import (
    BOOTSTRAP_RESAMPLES,
    CONFIDENCE_LEVEL,
    BootstrapInterval,
    McNemarResult,
    ProportionInterval,
    SampleSizeResult,
    cluster_bootstrap_interval,
    discordant_pairs,
    mcnemar,
    power_two_proportions,
    wilson_interval,
)

__all__ = [
    "BOOTSTRAP_RESAMPLES",
    "CONFIDENCE_LEVEL",
    "LIMITS_OF_AGREEMENT_Z",
    "BlandAltmanResult",
    "BootstrapInterval",
    "Chi2Result",
    "ClassifierMetrics",
    "KruskalResult",
    "LogisticResult",
    "RatesTest",
    "McNemarResult",
    "ParityResult",
    "ProportionInterval",
    "SampleSizeResult",
    "SurvivalCurve",
    "bland_altman",
    "chi2_contingency_test",
    "equal_rates_test",
    "classifier_metrics",
    "cluster_bootstrap_interval",
    "coefficient_of_variation",
    "discordant_pairs",
    "kruskal_wallis",
    "logistic_regression",
    "mcnemar",
    "median_abs_pct_error",
    "parity_fit",
    "power_two_proportions",
    "survival_curve",
    "wilson_interval",
]
