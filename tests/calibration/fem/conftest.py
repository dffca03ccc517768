"""Shared small meshes for the FEM tests (graded blocks and a quarter annulus, see calibration.fem.verification_meshes)."""

import pytest

from calibration.fem.verification_meshes import hertz_block


@pytest.fixture(scope="session")
def block_2d():
    """Half plane-strain block y >= 0, z <= 0 (P2), fine spacing 0.1 mm up to 1.2 mm, 200 mm wide and deep."""
    return hertz_block(0.1, 1.2, 200.0, order=2, dim=2)


@pytest.fixture(scope="session")
def block_2d_coarse():
    """Coarser plane-strain block for the nonlinear path tests."""
    return hertz_block(0.2, 1.2, 30.0, order=2, dim=2)
