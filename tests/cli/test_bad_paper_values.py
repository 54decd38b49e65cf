"""A paper value outside the bound of its kind of quantity (campaign/paper_bounds.py) is refused
when the study is composed: one sentence naming the override or the file, the key, the value as
given and the allowed range; exit 2; nothing stored changed (``cli_checks.refused``). Each was
taken before, as a new run, and printed as "the paper's value"."""

from __future__ import annotations

import pytest
from cli_checks import refused

PCT = "is out of range; allowed: >= 0 and <= 100 (a percentage)."
SCORE = ("is out of range; allowed: >= 0 and <= 1 (a classifier's accuracy, precision, recall, F1 or "
         "AUC, from 0 to 1).")
POSITIVE = ("is out of range; allowed: > 0 (a time, force, torque, length, mass, stiffness, ratio or "
            "identified model coefficient, all positive).")


@pytest.mark.parametrize(("study", "override", "said"), [
    ("surrogate", "paper.class_balance_pct=250", f"paper.class_balance_pct = 250 {PCT}"),
    ("surrogate", "paper.auc.mlp=2", f"paper.auc.mlp = 2 {SCORE}"),
    ("surrogate", "paper.accuracy_pct=[91,89]",
     "paper.accuracy_pct = [91, 89] runs high to low; write a range low end first: [89, 91]."),
    ("surrogate", "paper.accuracy_pct=[89,100.5]", f"paper.accuracy_pct[1] = 100.5 {PCT}"),
    ("surrogate", "paper.pso_call_time_s=0", f"paper.pso_call_time_s = 0 {POSITIVE}"),
    ("surrogate", "paper.n_scenarios=-1", "paper.n_scenarios = -1 is out of range; allowed: >= 0 (a count)."),
    ("ablation", "paper.success_pct.heuristic=-0.5", f"paper.success_pct.heuristic = -0.5 {PCT}"),
    ("test3_disturbance", "paper.table9.random.wilson_pct=[10.9,125.5]",
     f"paper.table9.random.wilson_pct[1] = 125.5 {PCT}"),
    ("test2_grasp", "paper.classifier.precision=1.2", f"paper.classifier.precision = 1.2 {SCORE}"),
    ("test2_grasp", "paper.force_err_kruskal_p=1.5",
     "paper.force_err_kruskal_p = 1.5 is out of range; allowed: >= 0 and <= 1 (a p-value)."),
    ("test1_bench", "paper.table4.gel.mu_s=-0.1",
     "paper.table4.gel.mu_s = -0.1 is out of range; allowed: >= 0 and <= 3 (a friction coefficient: "
     "dry friction of soft materials stays below 3)."),
    ("pso_repeatability", "paper.cv_pct.n=-19",
     "paper.cv_pct.n = -19 is out of range; allowed: >= 0 (an error or a coefficient of variation in "
     "percent, which may exceed 100)."),
])
def test_a_paper_value_out_of_its_range_is_refused_naming_it(tmp_path, study, override, said):
    refused(tmp_path, ["run", study, override, "--root", tmp_path],
            f"campaigns/{study}.yaml with override {override}: {said}")


def test_a_percentage_error_above_100_is_a_paper_value():
    """A CV or an error in percent may exceed 100 (the paper's centroid threshold error is 73.8 %):
    not a percentage's bound."""
    from graspcampaign.campaign.compose import compose_study

    assert compose_study("test3_disturbance", ["paper.threshold_err_centroid_pct=173.8"]).paper[
        "threshold_err_centroid_pct"] == 173.8


def test_a_study_file_with_a_value_out_of_range_is_refused_naming_the_file(home, tmp_path):
    path = home / "campaigns" / "surrogate.yaml"
    text = path.read_text()
    assert "  class_balance_pct: 8.7" in text
    path.write_text(text.replace("  class_balance_pct: 8.7", "  class_balance_pct: 870"))
    refused(tmp_path, ["run", "surrogate", "--root", tmp_path],
            f"campaigns/surrogate.yaml: paper.class_balance_pct = 870 {PCT}")
