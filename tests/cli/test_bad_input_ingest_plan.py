"""Bad input on the paths least tried: runner options that would be ignored, measured-record files
given twice or far beyond any schedule, and decimal commas. Each is refused in one sentence with
exit 2 and nothing stored changed (``refused``)."""

from __future__ import annotations

import pytest
from cli_checks import SMOKE, refused


@pytest.mark.parametrize("backend", ["loky", "sequential"])
def test_a_dask_address_without_the_dask_backend_is_refused(results, backend):
    # the old code ran the trials on this machine and never said the address went unused
    for command in ("show", "run"):
        refused(results, [command, "smoke", *SMOKE, f"runner.backend={backend}",
                          "runner.address=tcp://127.0.0.1:8786", "--run", "elsewhere", "--root",
                          results],
                f"runner.address = 'tcp://127.0.0.1:8786' names a Dask scheduler, but "
                f"runner.backend = {backend} runs the trials on this machine and would ignore it: "
                "add runner.backend=dask, or drop runner.address.")
