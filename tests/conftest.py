"""Shared test fixtures. The reference material lives beside the clone in ``../shared/reference``."""

import os
from pathlib import Path

from wrlayer.runner import THREAD_VARIABLES

# One BLAS/MKL/OpenMP thread per pytest-xdist worker process (`make test` runs two on two cores; more threads only
# compete for them), set before numpy and MKL load and read these variables.
if os.environ.get("PYTEST_XDIST_WORKER"):
    for _variable in THREAD_VARIABLES:
        os.environ.setdefault(_variable, "1")

import matplotlib  # noqa: E402 - after the thread variables
import pytest  # noqa: E402

matplotlib.use("Agg")
os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")
# no progress lines in the captured stderr of the tests (tests/wrlayer/test_progress.py sets its own mode)
os.environ.setdefault("WRLAYER_PROGRESS", "0")

REPO = Path(__file__).resolve().parents[1]


def find_reference_dir() -> Path:
    """``$WRLAYER_REFERENCE`` or ``<repo>/../shared/reference``."""
    env = os.environ.get("WRLAYER_REFERENCE")
    return Path(env) if env else REPO.parent / "shared" / "reference"


@pytest.fixture(scope="session")
def reference_dir() -> Path:
    ref = find_reference_dir()
    if not (ref / "profiles").is_dir():
        pytest.fail(f"reference material not found at {ref} (set WRLAYER_REFERENCE)")
    return ref


def pytest_collection_modifyitems(config, items):
    """The slow tests first (the sort keeps the collection order within each group): on the two workers of
    ``make test`` a long test collected late kept one worker busy after the other had run out of tests."""
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)
