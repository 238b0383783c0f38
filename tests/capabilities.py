"""What a test needs from the machine (plots, MPI): a test whose need is not met is skipped,
saying why, unless VIMPACT_REQUIRE names the capability (a comma-separated list, e.g.
"plots,mpi"): then it fails. The test command sets it for what its installer provides, so a
missing package or a broken build of the plotting package cannot pass as a skip there."""
import os

import pytest


def required(capability):
    """Whether VIMPACT_REQUIRE names the capability."""
    return capability in {c.strip() for c in os.environ.get("VIMPACT_REQUIRE", "").split(",")}


def need(capability, available, why):
    """Skip (or fail, where required) the calling test unless `available`."""
    if available:
        return
    if required(capability):
        pytest.fail(f"{why}; VIMPACT_REQUIRE names {capability}", pytrace=False)
    pytest.skip(why)
