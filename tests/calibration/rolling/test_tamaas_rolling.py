"""The Tamaas rolling reference (``benchmarks/tamaas_rolling.py``) on a tiny periodic cell: a pressure below first
yield rolled across the half-space leaves no groove, one above it leaves a groove of the order of the static dent
that grows little in the second pass (shakedown at 1.7 p_y). Skipped when Tamaas is not importable."""

import pytest

from benchmarks.tamaas_rolling import RollingCase, roll, static_dent

pytest.importorskip("tamaas")

TINY = dict(dx_a=0.5, step_a=0.5, passes=2)


def test_elastic_level_leaves_no_groove():
    res = roll(RollingCase("tiny_elastic", 0.9, **TINY))
    assert max(abs(g) for g in res["groove_mm"]) < 1e-9
    assert res["max_cum_plastic"][-1] == 0.0


def test_plastic_level_leaves_a_groove_near_the_static_dent():
    case = RollingCase("tiny_plastic", 1.7, **TINY)
    dent = static_dent(case)["dent_mm"]
    res = roll(case)
    g1, g2 = res["groove_mm"]
    assert dent > 1e-3
    assert 0.6 * dent < g1 < 1.1 * dent
    assert g1 < g2 < 1.1 * g1
