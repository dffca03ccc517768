"""Shared test fixtures. The reference material lives beside the clone in ``../shared/reference``."""

import os
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")

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
