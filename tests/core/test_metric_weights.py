"""Each weight of Eq. 6 (and of the hardware form of §8.1) scales its own term and no other.

The closed-form tests of test_metric.py use unit weights, where a weight applied to the wrong term
goes unseen; here one weight at a time is non-zero and the total must be that term alone.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from graspcampaign.core.metric import HeuristicTerms, HeuristicWeights

TERMS = ("s1", "s2", "s3", "n_c", "n_e")
WEIGHTS = ("w1", "w2", "w3", "p_c", "p_e")
unit_values = arrays(np.float64, 4, elements=st.floats(0.0, 1.0))


def _terms(s1, s2, s3, n_c, n_e):
    return HeuristicTerms(s1=s1, s2=s2, s3=s3, s2_angle=s2, s2_side=s2, n_c=n_c, n_e=n_e,
                          pc_mag=n_c / 2, pe_mag=n_e / 2)


@settings(deadline=None)  # values checked, not time: a loaded machine stalls an example
@given(unit_values, unit_values, unit_values, st.integers(0, 3), st.integers(0, 3),
       st.floats(0.1, 10.0))
def test_one_weight_alone_gives_its_own_term(s1, s2, s3, n_c, n_e, weight):
    terms = _terms(s1, s2, s3, np.full(4, n_c), np.full(4, n_e))
    for term, name in zip(TERMS, WEIGHTS, strict=True):
        alone = HeuristicWeights(**{w: (weight if w == name else 0.0) for w in WEIGHTS})
        np.testing.assert_allclose(terms.total(alone), weight * getattr(terms, term), err_msg=name)


@settings(deadline=None)  # values checked, not time: a loaded machine stalls an example
@given(unit_values, unit_values, unit_values, unit_values, unit_values, st.floats(0.1, 10.0))
def test_one_hardware_weight_alone_scores_its_own_term(s1, s2, s3, pc_mag, pe_mag, weight):
    """§8.1: H~ = sum_i w_i (1 - S_i) - P_c - P_e with P_c = p_c pc_mag and P_e = p_e pe_mag; the two
    magnitudes are drawn apart, so a penalty weight read against the other magnitude is seen."""
    terms = replace(_terms(s1, s2, s3, np.zeros(4), np.zeros(4)), pc_mag=pc_mag, pe_mag=pe_mag + 1.5)
    own = {"w1": 1.0 - s1, "w2": 1.0 - s2, "w3": 1.0 - s3, "p_c": -terms.pc_mag, "p_e": -terms.pe_mag}
    for name in WEIGHTS:
        alone = HeuristicWeights(**{w: (weight if w == name else 0.0) for w in WEIGHTS})
        np.testing.assert_allclose(terms.score_hardware(alone), weight * own[name], err_msg=name)
