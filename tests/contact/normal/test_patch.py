"""A strip patch refuses what it cannot carry: one InputError per kind of bad array."""

import numpy as np
import pytest

from contact.normal.patch import Patch
from wrlayer.errors import InputError

Y, XL, PK = np.array([-0.5, 0.0, 0.5]), np.array([2.0, 3.0, 2.0]), np.array([500.0, 900.0, 500.0])


@pytest.mark.parametrize("y, xl, pk, message", [
    (Y, XL, np.array([500.0, np.nan, 500.0]), "NaN or infinite"),
    (Y, np.array([2.0, np.inf, 2.0]), PK, "NaN or infinite"),
    (np.array([-0.5, -np.inf, 0.5]), XL, PK, "NaN or infinite"),
    (Y, np.array([2.0, 0.0, 2.0]), PK, "x_lead_mm > 0"),
    (Y, XL, np.array([500.0, -1.0, 500.0]), "p_peak_MPa >= 0"),
    (np.array([-0.5, 0.5, 0.5]), XL, PK, "must increase"),
    (Y[:2], XL, PK, "one length"),
])
def test_bad_strips_are_refused(y, xl, pk, message):
    with pytest.raises(InputError, match=message):
        Patch(0.5, y, xl, pk)


def test_a_good_patch_keeps_its_arrays_as_floats():
    p = Patch(0.5, [-1, 0, 1], [2, 3, 2], [0, 900, 0])
    assert p.y_mm.dtype == float and p.normal_force_N() == pytest.approx(0.5 * np.pi * 900 * 3 * 0.5)
