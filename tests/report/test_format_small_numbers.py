"""Numbers too small to write out: values below a thousandth, times with an SI prefix, p-values
(the one formatter, report/format.py)."""

from __future__ import annotations

import math

import pytest

from graspcampaign.report import format as fmt


@pytest.mark.parametrize("value, sig, expected", [
    (7.02e-5, None, "7.02e-5"),    # friction_mass's finger force printed 0.0000702 N
    (-6.06e-4, None, f"{fmt.MINUS}6.06e-4"),
    (1.2e-7, 2, "1.2e-7"),
    (0.00164, None, "0.00164"),    # from a thousandth up: written out, as a p-value is
    (0.001, 2, "0.0010"),
])
def test_a_value_below_a_thousandth_rounded_alone_prints_in_scientific_form(value, sig, expected):
    """Rounded to its own significant digits (a column's ``EACH``, or ``sig``), a value below 0.001 prints
    as p-values do: its written-out leading zeros read as measured digits. The check is Python's own
    ``e`` format, not the formatter's code."""
    text = fmt.number(value, fmt.EACH, sig=sig)
    assert text == expected
    if "e" in text:
        assert text.replace(fmt.MINUS, "-") == f"{value:.{(sig or 3) - 1}e}".replace("e-0", "e-")
    assert fmt.number(7.02e-5, 7) == "0.0000702"  # a column's fixed decimals stay written out


@pytest.mark.parametrize("seconds, sig, expected", [
    (0.99, 2, "990 ms"), (0.0016395, 3, "1.64 ms"), (0.000185, 3, "185 \u00b5s"), (6e-5, 1, "60 \u00b5s"),
    (0.0009996, 3, "1.00 ms"),     # the prefix of the value as rounded, not "1000 µs" or "1.000 ms"
    (2.5, 3, "2.50 s"), (0.0, 3, "0.00 s"),
])
def test_scaled_writes_the_si_prefix_that_fits_the_magnitude(seconds, sig, expected):
    """The surrogate's timing printed the paper's 0.99 s as 990000 µs (six digits, two printed)."""
    assert fmt.scaled(seconds, "s", sig) == expected


@pytest.mark.parametrize("p", [2.947e-62, 9.005e-16, 6.642e-64, 0.00099, 2.4e-4])
def test_small_p_values_print_in_scientific_form(p):
    text = fmt.p_value(p)
    assert "e-" in text and len(text) <= 8 and float(text) == pytest.approx(p, rel=0.06)


def test_p_values_at_or_above_a_thousandth_print_two_significant_digits():
    assert [fmt.p_value(p) for p in (0.0472, 0.5, 1.0, 0.001)] == ["0.047", "0.50", "1.0", "0.0010"]
    assert fmt.p_value(math.nan) == fmt.MISSING
