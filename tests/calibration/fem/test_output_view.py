"""The 3D field pictures' view (calibration.fem.output.view_frame): seen from outside the loaded surface, whose
outward normal is the picture's up direction, for the rail (normal +z), the wheel (normal -z) and a flange
(normal nearly horizontal) alike."""

import numpy as np
import pytest

from calibration.fem.output import view_frame

CENTRE = np.array([0.0, 3.0, -1.0])


def test_rail_crown_view_is_the_former_fixed_view():
    f = view_frame(CENTRE, (0.0, 0.0, 1.0), 4.0, 2.0)
    np.testing.assert_allclose(f.camera, CENTRE + [-12.0, -8.0, 6.4])
    np.testing.assert_allclose(f.focal, CENTRE + [0.0, 0.0, -1.2])
    np.testing.assert_allclose(f.up, [0.0, 0.0, 1.0])
    np.testing.assert_allclose(f.label, CENTRE + [0.0, 2.4, -3.2])
    np.testing.assert_allclose(f.bar[0], CENTRE + [0.0, -3.6, 0.2])
    np.testing.assert_allclose(f.bar[1] - f.bar[0], [0.0, 2.0, 0.0])


@pytest.mark.parametrize("normal", [(0.0, 0.0, -1.0), (0.0, 0.97, 0.243), (0.0, -0.6, -0.8), (0.0, 0.0, 2.0)])
def test_view_from_outside_with_the_surface_up(normal):
    n = np.asarray(normal) / np.linalg.norm(normal)
    h, bar = 4.0, 2.0
    f = view_frame(CENTRE, normal, h, bar)
    assert (f.camera - CENTRE) @ n == pytest.approx(1.6 * h)  # outside the body
    assert (f.camera - CENTRE)[0] == pytest.approx(-3 * h)  # from the -x side: the symmetry plane x = 0 is seen
    np.testing.assert_allclose(f.up, n)
    assert (f.label - CENTRE) @ n == pytest.approx(-0.8 * h)  # the label lies inside the body
    d = f.bar[1] - f.bar[0]
    assert np.linalg.norm(d) == pytest.approx(bar)
    assert abs(d @ n) < 1e-12 and abs(d[0]) < 1e-12  # on the surface plane, across the rolling direction
