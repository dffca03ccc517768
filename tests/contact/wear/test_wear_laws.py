"""Wear laws: the published regimes, and the FASTSIM cell quantities they use (power balance, hand sums)."""

import numpy as np
import pytest

from contact.normal.patch import Patch
from contact.tangential.fastsim import Creepage, solve_tangential
from contact.wear.laws import ArchardMap, UsfdTable, WearLaw, cell_work, wear_of
from wrlayer.errors import InputError


def test_usfd_r8t_regimes():
    t = UsfdTable()
    x = np.array([0.0, 5.0, 10.39, 10.4, 50.0, 77.2, 100.0])
    expected = [0.0, 26.5, 5.3 * 10.39, 55.0, 55.0, 55.0, 61.9 * 100.0 - 4778.7]
    assert np.allclose(t.rate(x), expected, rtol=1e-12)


def test_archard_map_regimes():
    m = ArchardMap(hardness_MPa=2000.0)
    k = m.coefficient(np.array([100.0, 100.0, 100.0, 100.0, 1700.0]), np.array([0.1, 0.2, 0.5, 1.0, 0.5]))
    assert np.allclose(k, [5.5e-4, 5.5e-4, 35e-4, 5.5e-4, 350e-4])


def test_bad_law_and_coefficients():
    with pytest.raises(InputError, match="wear.law"):
        WearLaw("linear")
    with pytest.raises(InputError, match="hardness_MPa"):
        ArchardMap(hardness_MPa=-1.0)
    with pytest.raises(InputError, match="t1 < t2"):
        UsfdTable(t1=80.0, t2=77.2)


def _patch():
    y = np.arange(-2.0, 2.0001, 0.1)
    xl = 6.0 * np.sqrt(np.clip(1 - (y / 2.1) ** 2, 0.01, None))
    return Patch(0.1, y, xl, 900.0 * xl / xl.max())


def test_cell_work_balances_creep_force_power():
    """Dissipated work per rolled length = -(Fx vx + Fy vy + Mz phi) (FASTSIM's power balance, O(dx^2))."""
    patch = _patch()
    cr = Creepage(0.002, 0.001, 0.0)
    t = solve_tangential(patch, cr, 82000.0, 0.28, 0.3, 2000.0, nx=60)
    work, slip, tga = cell_work(t)
    area = t.dx_mm[:, None] * patch.grid_mm
    dissipated = float(np.sum(tga * area))  # N: work per rolled mm
    assert dissipated == pytest.approx(-(t.Fx_N * cr.vx + t.Fy_N * cr.vy), rel=0.01)
    assert np.all(slip >= 0) and np.all(work >= 0)


@pytest.mark.parametrize("law", ["archard", "usfd"])
def test_strip_depth_is_the_cell_sum(law):
    patch = _patch()
    t = solve_tangential(patch, Creepage(0.003, 0.0, 0.0), 82000.0, 0.28, 0.3, 2000.0, nx=30)
    wl = WearLaw(law)
    cw = wear_of(t, wl)
    _work, slip, tga = cell_work(t)
    if law == "archard":
        k = np.where(t.slip_velocity_mm_s * 1e-3 <= 0.2, 5.5e-4, 35e-4)
        hand = (k * t.pn_MPa * slip / 2550.0).sum(axis=1)
    else:
        hand = (UsfdTable().rate(tga) * t.dx_mm[:, None] * 1e-3 / 7850.0).sum(axis=1)
    assert np.allclose(cw.strip_depth_mm["wheel"], hand, rtol=1e-12, atol=0)
    assert cw.strip_depth_mm["wheel"].max() > 0


def test_archard_in_full_slip_is_proportional_to_frictional_work():
    """Full slip: traction = mu p, so k p s / H = k/(mu H) x (frictional work per area); per strip to ~1 %."""
    patch = _patch()
    mu, H, k = 0.3, 2000.0, 5.5e-4
    t = solve_tangential(patch, Creepage(0.05, 0.0, 0.0), 82000.0, 0.28, mu, 2000.0, nx=60)
    assert t.slip.mean() > 0.9
    law = WearLaw("archard", archard={"wheel": ArchardMap(hardness_MPa=H, k_low_speed=k, k_mid_speed=k,
                                                          k_high_speed=k, seizure_pressure_ratio=10.0),
                                      "rail": ArchardMap()})
    depth = wear_of(t, law).strip_depth_mm["wheel"]
    assert np.allclose(depth, k / (mu * H) * t.WT_N_per_mm, rtol=0.02)


def test_coefficient_sources_follow_the_values():
    """The provenance text recorded in result.json: the default map/table name their (secondary) source, changed
    map values or a scene table say so; the hardness alone does not change the map's source."""
    assert "Jendel 2002" in ArchardMap().source and "not checked" in ArchardMap().source
    assert ArchardMap(hardness_MPa=3000.0).source == ArchardMap().source
    assert ArchardMap(k_mid_speed=30e-4).source == "scene values"
    assert ArchardMap(v_high_m_s=1.0).source == "scene values"
    assert "R8T" in UsfdTable().source
    assert UsfdTable(name="custom rail").source == "scene table"
    assert UsfdTable(t2=70.0).source == "scene table"


def test_scene_records_the_rail_table_source(make_scene):
    default = make_scene(wear={"law": "usfd"}).law.usfd
    assert default["rail"].name == "R8T" and default["rail"].source == UsfdTable().source
    table = {"t1": 5.0, "t2": 50.0, "mild_slope": 1.0, "severe_rate": 5.0, "cat_slope": 2.0, "cat_offset": 95.0}
    custom = make_scene(wear={"law": "usfd", "usfd": {"rail": table}}).law.usfd
    assert custom["rail"].source == "scene table" and custom["wheel"].source == UsfdTable().source
    assert make_scene(wear={"archard": {"rail": {"k_seizure": 0.03}}}).law.archard["rail"].source == "scene values"
