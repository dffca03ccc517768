"""The layer's prediction pass after pass equals the Prandtl layer of contact.layer under both memory rules of
contact.passes ("relaxed": a virgin element each pass, the residual moved into the profile; "state kept")."""

import numpy as np
import pytest

from calibration.rolling.layer_prediction import StaticCurve, layer_grooves
from wrlayer.characteristic import Characteristic
from contact.layer.prandtl_layer import PrandtlLayer

CH = Characteristic(np.array([0.0, 0.001, 0.004, 0.012]), np.array([0.0, 800.0, 1300.0, 1800.0]), "test")


def layer_passes(p0, n, keep_state):
    layer = PrandtlLayer.uniform(CH, np.array([0.0]))
    total, grooves = 0.0, []
    for _ in range(n):
        before = layer.u_mm.copy()
        layer.load_to(np.array([p0]))
        residual = layer.unload()
        total += float((residual - before)[0])
        grooves.append(total)
        if not keep_state:
            layer = layer.relaxed()
    return grooves


@pytest.mark.parametrize("p0", [1000.0, 1500.0, 1750.0])
def test_unloading_residual_is_the_prandtl_element(p0):
    assert float(CH.unloading_residual(p0)) == pytest.approx(layer_passes(p0, 1, True)[0], rel=1e-9, abs=1e-12)


def test_layer_grooves_follow_both_memory_rules():
    p = np.linspace(0.0, 1800.0, 37)
    curve = StaticCurve(p, CH.displacement(p) - p / CH.initial_stiffness, float(CH.unloading_residual(1800.0)))
    (lg,) = layer_grooves(curve, 800.0, [1500.0], 4, 3)
    assert lg.relaxed == pytest.approx(layer_passes(1500.0, 4, False), rel=0.05)
    assert lg.state_kept == pytest.approx(layer_passes(1500.0, 4, True), rel=0.05)
    assert lg.state_kept[-1] == lg.state_kept[0] and lg.relaxed[-1] == pytest.approx(4 * lg.relaxed[0])
