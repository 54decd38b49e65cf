"""Bad input, round 8: a quoted comma in a long override, an old or encrypted Excel workbook given
to ingest, a negative ``runner.n_jobs`` beyond the machine's cores, an unfinished source run of
dynamic_check, two new runs of one run started at once, and the odd roots, options and files of
round 8's table (the final report of branch bad8).
Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

from cli_checks import refused


def test_a_comma_inside_a_quoted_string_separates_no_values(results):
    """A quoted level holding 2,500 commas was refused as "2,500 comma-separated values, more than
    an override can hold"; Hydra reads it as one string, in linear time, so its own check speaks."""
    text = ",".join(["a"] * 2500)
    refused(results, ["show", "smoke", f"shape=['{text}']", "--root", results],
            f"factors.shape[0] has unknown value '{text[:60]}... ({len(text)} characters)'; "
            "allowed values: sphere, ellipsoid, rounded_cube, pear, handle.", seconds=10)
