"""Bad input, round 15: rough edges of the last rounds. A mesh unit refused without its option,
report formats separated by spaces, a study file ending in upper-case .YAML, a run named as
another but for case, a foreign file's trace rows dropped in silence, preparations lost from a run
whose PSO settings drifted. Each refusal: exit 2, one sentence naming what is wrong, where, and
what to write, nothing stored changed (``refused``)."""

from __future__ import annotations

import pytest
from cli_checks import refused

UNITS = "use one of m, cm, mm (the unit of the mesh file's coordinates)."


@pytest.mark.parametrize(("unit", "said"), [
    # "unknown unit 'inch'; use one of 'm', 'cm', 'mm'.": which of the command's values was it?
    ("inch", f"--unit 'inch' is not a length unit a mesh is read in; {UNITS}"),
    ("MM", f"--unit 'MM' is not a length unit a mesh is read in; did you mean --unit mm? {UNITS}"),
])
def test_an_unknown_mesh_unit_names_the_option_and_its_values(tmp_path, sphere, unit, said):
    refused(tmp_path, ["plan", sphere, "--mass-kg", "0.1", "--unit", unit], said)


@pytest.mark.parametrize(("args", "said"), [
    # "unknown report format 'md csv'; did you mean 'csv'?": md was asked for too
    (["--format", "md csv"], "--format 'md csv': report formats are separated by commas, not spaces; "
                             "give --format md,csv."),
    (["--format", "md csv,json"], "--format 'md csv,json': report formats are separated by commas, "
                                  "not spaces; give --format md,csv,json."),
    # "did you mean 'png' or 'svg'?" to a list of both, whether by spaces or commas
    (["--figure-format", "svg png"], "--figure-format 'svg png': one figure format is taken, not 2; "
                                     "choose one of png, svg, pdf."),
    (["--figure-format", "svg,png"], "--figure-format 'svg,png': one figure format is taken, not 2; "
                                     "choose one of png, svg, pdf."),
])
def test_report_formats_separated_by_spaces_are_told_the_commas(tmp_path, args, said):
    refused(tmp_path, ["report", "smoke", "--root", tmp_path, *args], said)
