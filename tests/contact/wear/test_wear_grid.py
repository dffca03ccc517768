"""Arc-length grid: conservative deposit, smoothing, update along the normal, refusal of a folding profile."""

import numpy as np
import pytest

from contact.wear.profile_grid import ArcGrid
from meshes.profiles import S1002, Rail60E1
from wrlayer.errors import InputError


@pytest.mark.parametrize("profile", [Rail60E1(), S1002()])
def test_deposit_is_conservative(profile):
    g = ArcGrid.of(profile, 0.2)
    rng = np.random.default_rng(1)
    y = np.sort(rng.uniform(-10.0, 10.0, 57))
    d = rng.uniform(0.0, 1e-3, y.size)
    node = g.deposit(y, d, 0.1)
    assert g.area_mm2(node) == pytest.approx(np.sum(d * 0.1), rel=1e-12)
    smooth = g.smooth(node, 1.5)
    assert g.area_mm2(smooth) == pytest.approx(g.area_mm2(node), rel=1e-6)
    assert smooth.max() < node.max()


def test_deposit_outside_profile_is_refused():
    g = ArcGrid.of(Rail60E1(), 0.2)
    with pytest.raises(InputError, match="outside the profile"):
        g.deposit(np.array([500.0]), np.array([1e-3]), 0.1)


def test_update_moves_along_the_normal():
    prof = Rail60E1()
    g = ArcGrid.of(prof, 0.2)
    depth = 0.05 * np.exp(-((g.y_mm - 3.0) / 4.0) ** 2)
    new = g.updated(depth, "worn", "test")
    pts = new.points
    dist, _ = prof.signed_distance(pts)
    assert np.allclose(np.abs(dist), depth, atol=2e-5)
    assert np.all(new.z(g.y_mm[50:-50]) <= prof.z(g.y_mm[50:-50]) + 1e-12)  # rail material removed: surface lower


def test_folding_profile_is_refused_naming_the_step():
    g = ArcGrid.of(S1002(), 0.2)
    depth = np.zeros_like(g.y_mm)
    steep = int(np.argmax(np.abs(g.normal[:, 0])))  # where the normal is most horizontal (flange)
    depth[steep] = 5.0
    with pytest.raises(InputError, match="step 7.*non-monotone"):
        g.updated(depth, "worn", "step 7: right wheel profile")
