"""The between-levels check (benchmarks.bench_layer_between): the element against an FEM result at equal p0."""

from types import SimpleNamespace

import numpy as np
import pytest

from benchmarks.bench_layer_between import TABLES, compare, markdown
from wrlayer.layer_table import LayerTable


def _fem_like_the_element(scale: float = 1.0):
    ch = LayerTable.read(TABLES["rail"]).characteristic_at(0.0)
    p2 = ch.elastic_limit_MPa
    p = p2 * np.linspace(0.0, 3.0, 61)
    u_pl = ch.displacement(p) - p * ch.u_mm[1] / ch.p_MPa[1]
    peaks = p2 * np.array([1.15, 1.4, 2.2])
    return SimpleNamespace(p_MPa=p.tolist(), u_pl_mm=(scale * u_pl).tolist(), unload_peaks_MPa=peaks.tolist(),
                           residual_fem_mm=(scale * ch.unloading_residual(peaks)).tolist(), first_yield_MPa=p2,
                           seconds=1.0)


def test_the_element_against_itself_is_exact_and_a_larger_fem_shows():
    row = compare("rail", 0.0, _fem_like_the_element())
    assert row.levels == pytest.approx([1.15, 1.4, 2.2]) and row.worst() < 1e-3  # the FEM curve read between points
    off = compare("rail", 0.0, _fem_like_the_element(1.1))
    assert off.residual_error[-1] == pytest.approx(1 / 1.1 - 1, rel=1e-6)
    assert "0 of 1 positions" in markdown([off]) and "1 of 1 positions" in markdown([row])
    # relative to the FEM value itself: the element is 1/1.1 of it at every peak
    assert row.worst_relative() < 1e-3 and off.worst_relative() == pytest.approx(1 - 1 / 1.1, rel=1e-6)
