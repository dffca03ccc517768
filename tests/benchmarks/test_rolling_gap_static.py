"""The static-dent mesh study of the gap: the extrapolation, the static dent of a tiny block (the cases' own load
path), the mesh correction of a gap row and the half-space layer's fit."""

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from benchmarks import rolling_gap as gap
from benchmarks.rolling_gap_cases import GapCase, GapCaseResult, GapPosition, run_case
from benchmarks.rolling_gap_static import (MAX_ORDER, Extrapolation, StaticPoint, common_pressure_dents,
                                            converged_dents, corrected_groove,
                                            corrected_rows, extrapolate, load_points, observed_order, point_path,
                                            ratio_checks, static_point, within_target)
from calibration.rolling.layer_prediction import StaticCurve
from test_rolling_gap_cases import MESH, MIXED, TRACK

H = np.array([1 / 2, 1 / 3, 1 / 4, 1 / 5])


@pytest.mark.parametrize("p", [1.0, 1.5, 2.0])
def test_richardson_recovers_limit_and_order(p):
    f = 0.05 - 0.02 * H ** p
    ext = extrapolate(H[::-1], f[::-1])                 # any order of the meshes
    assert ext.method == "richardson"
    assert ext.order == pytest.approx(p, rel=1e-6)
    assert ext.value == pytest.approx(0.05, rel=1e-9)


def test_non_monotone_or_out_of_range_sequences_give_the_finest():
    wiggle = extrapolate(H[:3], [1.0, 1.2, 1.1])
    assert (wiggle.value, wiggle.method) == (1.1, "finest") and math.isnan(wiggle.order)
    fast = 1.0 - 0.5 * H[:3] ** (MAX_ORDER + 1.5)       # converged faster than the asymptotic range allows
    ext = extrapolate(H[:3], fast)
    assert ext.method == "finest" and ext.value == fast[-1]
    two = extrapolate(H[:2], [1.0, 1.1])
    assert (two.value, two.method) == (1.1, "finest")
    assert math.isnan(observed_order(H[:3], np.array([1.0, 1.0, 1.1])))


def test_corrected_groove_keeps_the_ratio():
    np.testing.assert_allclose(corrected_groove([0.9, 1.0], 1.0, 1.2), [1.08, 1.2])


def row(position="rail crown", static=1.0):
    return gap.GapRow(position, "rail", 0.0, 1.7, 1350.0, static, 1.1, [1, 2], [0.95, 1.0], [1.1, 2.2], [1.1, 1.1],
                      [1.05, 1.1], [0.95 * static, 1.0 * static], 10, f"{position}_c0_p1.7")


def test_corrected_rows_scale_fem_and_block_not_the_layer():
    conv = {("rail crown", 1.7): Extrapolation(1.2, 2.0, "richardson")}
    (out,) = corrected_rows([row(), row("rail gauge corner")], conv)   # no converged dent: left out
    assert out.static_dent_mm == 1.2
    np.testing.assert_allclose(out.fem_mm, [1.14, 1.2])
    np.testing.assert_allclose(out.law_on_block_mm, [1.14, 1.2])
    assert out.rolling_mm == row().rolling_mm and out.layer_static_mm == row().layer_static_mm
    assert out.error("rolling_mm") == pytest.approx(max(1.0 - 1.05 / 1.14, 1.0 - 1.1 / 1.2))


def test_static_point_is_the_cases_static_dent_and_round_trips(tmp_path):
    pos = GapPosition("tiny", "", 0.0, 1.3, 1.0, MIXED)
    pt = static_point(pos, MESH.elements_per_semi_axis, (1.3, 2.1), TRACK, MESH)
    case = run_case(GapCase(pos, 2.1, 0.0, 1, MESH.elements_per_semi_axis), tmp_path, track=TRACK, mesh=MESH)
    assert pt.dent_at(2.1) == pytest.approx(case.static_dent_mm, rel=1e-9)
    assert pt.top_p_MPa == pytest.approx(case.static_p_MPa) and pt.p_y_MPa == pytest.approx(case.p_y_MPa)
    assert 0 < pt.dent_at(1.3) < pt.dent_at(2.1)
    path = point_path(tmp_path / "st", pt.position, pt.elements_per_semi_axis)
    path.parent.mkdir()
    path.write_text(json.dumps(pt.to_dict()))
    (back,) = load_points(tmp_path / "st")
    assert back == pt
    ext = converged_dents([back])[("tiny", 2.1)]
    assert ext.method == "finest" and ext.value == pt.dent_at(2.1)


def _halfspace_case(level: float, p_y: float, u_pl_of, n: int = 22) -> GapCaseResult:
    p = np.linspace(0.0, level * p_y, n)
    u = u_pl_of(p / p_y)
    return GapCaseResult(f"hs_{level}", "half-space", "", 0.0, 1.0, 1.0, 0.0, level, p_y, float(u[-1]), p.tolist(),
                         u.tolist())


def test_halfspace_layer_uses_the_given_reference_with_the_default_fit():
    p_y = 800.0
    case = _halfspace_case(2.1, p_y, lambda x: 1e-5 * np.maximum(x - 1.0, 0.0) ** 2)
    p, u_pl = np.array(case.static_p_MPa), np.array(case.static_u_pl_mm)
    own = gap.layer_static_residuals([case])
    same = gap.layer_static_residuals([case], gap.HalfspaceStatic(StaticCurve(p, u_pl, 1e-5), p_y, (2.1,),
                                                                  (case.static_dent_mm,)))
    double = gap.layer_static_residuals([case], gap.HalfspaceStatic(StaticCurve(p, 2.0 * u_pl, 2e-5), p_y, (2.1,),
                                                                    (2.0 * case.static_dent_mm,)))
    assert own == same and own[("half-space", 2.1)] > 0
    assert double[("half-space", 2.1)] == pytest.approx(2.0 * own[("half-space", 2.1)], rel=1e-3)
    assert gap.LAYER_FIT.mode == "operating_range"


def test_halfspace_layer_sees_every_levels_peak_near_first_yield():
    """The highest level's steps of p_y / 10 miss the curved onset of u_pl; the 1.15 level's own static curve ends
    on its peak, and the layer fitted to all cases' points gives that level's dent (elastic unloading: the dent is
    u_pl at the peak) within the calibration's error (3 % of max(dent, dent(1.5 p_y) / 3))."""
    p_y = 800.0
    u_pl_of = lambda x: 1e-3 * np.maximum(x - 1.0, 0.0) ** 1.8  # noqa: E731
    cases = [_halfspace_case(lv, p_y, u_pl_of, n) for lv, n in ((1.15, 13), (1.5, 16), (2.1, 22))]
    ref = gap.HalfspaceStatic.of_cases(cases)
    assert ref.levels == (1.15, 1.5, 2.1) and ref.dents_mm == pytest.approx(u_pl_of(np.array(ref.levels)))
    assert np.isclose(ref.curve.p_MPa, 1.15 * p_y).any() and np.isclose(ref.curve.p_MPa, 2.1 * p_y).any()
    r = gap.layer_static_residuals(cases)
    for lv in ref.levels:
        assert abs(r[("half-space", lv)] - u_pl_of(lv)) <= 0.03 * max(u_pl_of(lv), u_pl_of(1.5) / 3)


def test_ratio_checks_pair_cases_and_count_the_target():
    def res(key, static, grooves, dofs):
        return GapCaseResult(key, "rail crown", "", 0.0, 1.0, 1.0, 0.0, 1.7, 800.0, static, [0.0], [0.0],
                             groove_mm=grooves, n_dofs=dofs)

    coarse = [res("rail_crown_c0_p1.7", 1.0, [0.9, 0.95, 0.97], 100)]
    fine = [res("rail_crown_c0_p1.7_h4", 2.0, [1.86, 1.9], 800), replace(coarse[0], position="other")]
    (chk,) = ratio_checks(coarse, fine)
    assert (chk.key, chk.coarse_dofs, chk.fine_dofs, chk.passes) == ("rail_crown_c0_p1.7", 100, 800, [1, 2])
    np.testing.assert_allclose(chk.change(), [0.93 / 0.9 - 1.0, 0.0], atol=1e-12)
    assert chk.fine_groove_mm == [1.86, 1.9]
    rows = [replace(row(), rolling_mm=[1.0, 1.05]), row()]   # worst 5.3 %, 10.5 %
    assert within_target(rows) == [rows[0]]


def test_common_pressure_dents_read_every_curve_at_one_pressure():
    def point(n, p_y, k):   # u_pl = k (p / 800 - 1) above 800 MPa on every mesh, loaded to 2.1 p_y
        p = np.linspace(0.0, 2.1 * p_y, 43)
        u = k * np.maximum(p / 800.0 - 1.0, 0.0)
        return StaticPoint("x", n, 0, p_y, [1.3, 2.1], [0.0, 0.0], p.tolist(), u.tolist())

    pts = [point(2.0, 790.0, 1.0 - 0.2 / 4), point(3.0, 800.0, 1.0 - 0.2 / 9), point(4.0, 795.0, 1.0 - 0.2 / 16)]
    ext = common_pressure_dents(pts)[("x", 2.1)]
    assert ext.method == "richardson" and ext.order == pytest.approx(2.0, rel=1e-6)
    assert ext.value == pytest.approx(1.0 / (1.0 - 0.2 / 16), rel=1e-9)   # the limit over the finest mesh


def test_own_block_line_reports_the_halfspace_worst_case_only():
    from dataclasses import replace

    from benchmarks.rolling_gap import own_block_line

    hs = replace(row("half-space"), group="half-space", key="half-space_c0.2_p2.1", rolling_mm=[0.9, 1.0])
    line = own_block_line([row(), hs, replace(hs, key="half-space_c0_p1.3", rolling_mm=[0.95, 1.0])])
    assert "within 5.3 %" in line and "all 2 cases" in line and "half-space_c0.2_p2.1" in line
    assert own_block_line([row()]) == ""
