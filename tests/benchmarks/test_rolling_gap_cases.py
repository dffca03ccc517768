"""One tiny 3D gap case: the rolling FEM of an elliptic patch with mixed hardening and traction, its case file
(read back instead of recomputed), the law fitted to it and the gap row against the layer."""

import json

import numpy as np
import pytest

import benchmarks.rolling_gap as gap
import benchmarks.rolling_gap_cases as gap_cases
from calibration.rolling.config import RollingMaterial, TrackMeshSettings, TrackSettings
from benchmarks.rolling_gap_cases import GapCase, GapCaseResult, GapPosition, run_case
from calibration.rolling.law_fit import fit_passes
from wrlayer.rolling_law import RollingLaw

TRACK = TrackSettings(length_factor=1.0, step_factor=0.5, n_passes=2, ramp_steps=1)
MESH = TrackMeshSettings(elements_per_semi_axis=1.5, order=1, size_factor=3.0, fine_depth_factor=1.0,
                         fine_width_factor=1.0)
MIXED = RollingMaterial(H_iso_MPa=10000.0, H_kin_MPa=10000.0)


def flat(rho):
    """A rolling law with first-pass ratio ``rho`` everywhere and no increment per pass."""
    return RollingLaw(list(gap.LEVELS), list(gap.TRACTIONS), [[rho] * 5] * 2, [[0.0] * 5] * 2,
                      [[0.0] * 5] * 2, [[0.0] * 5] * 2, f"rho {rho}")


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    out = tmp_path_factory.mktemp("gap")
    case = GapCase(GapPosition("tiny", "", 0.0, 1.3, 1.0, MIXED), 2.1, 0.2, n_passes=2)
    return case, out, run_case(case, out, track=TRACK, mesh=MESH)


def test_tiny_case_rolls_and_is_written(tiny):
    case, out, res = tiny
    assert res.failed == "" and len(res.groove_mm) == 2 and res.n_dofs < 3000
    assert 0.5 < res.groove_mm[0] / res.static_dent_mm < 1.5       # a groove of the static dent's order
    assert res.groove_mm[1] >= res.groove_mm[0] > 0
    assert res.static_p_MPa[-1] == pytest.approx(2.1 * res.p_y_MPa)
    data = json.loads((out / f"{case.key}.json").read_text())
    assert GapCaseResult.from_dict(data) == res


def test_a_present_case_is_read_not_recomputed(tiny, monkeypatch):
    case, out, res = tiny
    monkeypatch.setattr(gap_cases, "build_model", lambda *a: pytest.fail("recomputed"))
    assert run_case(case, out, track=TRACK, mesh=MESH) == res


def test_law_fitted_to_the_case_reproduces_it(tiny):
    _, _, res = tiny
    fit = fit_passes(res.groove_mm, res.static_dent_mm)
    np.testing.assert_allclose(fit.factors(2) * res.static_dent_mm, res.groove_mm, rtol=1e-9)


def synthetic(position, a_mm, level, truth, static_mm):
    return GapCaseResult(f"{position}_c0_p{level}", position, "scenes/tables/rail_60E1_default.json", 0.0, a_mm,
                         0.75 * a_mm, 0.0, level, 790.0, static_mm, [0.0], [0.0],
                         groove_mm=(truth.factors(10) * static_mm).tolist())


def test_gap_rows_fit_the_group_law_and_stand_ins_scale():
    from calibration.rolling.law_fit import PassFit
    from wrlayer.layer_table import LayerTable

    truth = {1.15: PassFit(1.04, 0.05, 0.22, 0.0, 0.0), 1.3: PassFit(0.97, 0.04, 0.3, 0.0, 0.0),
             1.5: PassFit(0.94, 0.04, 0.3, 0.0001, 0.0), 1.7: PassFit(0.95, 0.03, 0.3, 0.0, 0.0),
             2.1: PassFit(0.9, 0.08, 0.5, 0.02, 0.0)}
    assert sorted(truth) == list(gap_cases.LEVELS)  # the law is fitted only when every level is present
    results = [synthetic("rail crown", 7.161, lv, f, 0.02 * lv) for lv, f in truth.items()]
    both = gap.with_stand_ins(results)
    tread = [r for r in both if r.position == "wheel tread"]
    assert len(tread) == len(truth) and "stand-in" in tread[0].key
    k = tread[0].a_mm / 7.161
    assert tread[0].groove_mm == pytest.approx([k * g for g in results[0].groove_mm])
    rows, laws = gap.gap_rows(results)
    assert set(laws) == {"rail"} and laws["rail"].traction_coefficient == [0.0]
    ch = LayerTable.read(gap_cases.ROOT / "scenes/tables/rail_60E1_default.json").characteristic_at(0.0)
    for row in rows:
        assert row.error("law_on_block_mm") < 2e-3
        r = float(ch.unloading_residual(row.p0_over_py * ch.elastic_limit_MPa))
        assert row.layer_static_mm == pytest.approx(r)
        assert row.relaxed_mm == pytest.approx([r * n for n in row.passes])
        assert row.rolling_mm == pytest.approx(r * truth[row.p0_over_py].factors(10)[np.array(row.passes) - 1],
                                               rel=2e-3)


def test_tables_get_their_round_law_and_the_long_patch_laws_as_shape_nodes():
    long_laws = {"long patch": flat(1.2), "very long patch": flat(1.1)}
    ratios = [gap.group_aspect_ratio(g) for g in ("rail", "long patch", "very long patch")]
    assert 1.3 < ratios[0] < 1.4 and 3.7 < ratios[1] < 3.9 and 10.0 < ratios[2] < 10.3   # crown, corner; 25; 30
    law = gap.shaped_law("rail", {"rail": flat(1.0), **long_laws})
    assert law.aspect_ratio == pytest.approx(ratios)
    assert float(law.factor(1, 1.5, 0.2, 1.0)) == pytest.approx(1.0)   # a round patch: the round law
    assert float(law.factor(1, 1.5, 0.2, ratios[1])) == pytest.approx(1.2)
    assert float(law.factor(1, 1.5, 0.2, 20.0)) == pytest.approx(1.1)  # clamped to the longest patch's
    stored = gap.shaped_law("wheel", long_laws)                       # no wheel cases: the table's own law
    shipped = gap.LayerTable.read(gap.ROOT / gap.GROUPS["wheel"][1]).rolling_law
    assert float(stored.factor(1, 1.5, 0.2, 1.0)) == pytest.approx(float(shipped.factor(1, 1.5, 0.2, 1.0, 0.0)))
    assert float(stored.factor(1, 1.5, 0.2, 1.0)) != pytest.approx(float(shipped.factor(1, 1.5, 0.2, 1.0, -0.1)))
    with pytest.raises(KeyError):
        gap.shaped_law("rail", {"rail": flat(1.0), "long patch": flat(1.2)})


def test_shape_check_compares_the_shaped_law_at_the_cases_patch_shape():
    laws = {"rail": flat(1.0), "wheel": flat(1.0), "long patch": flat(1.2), "very long patch": flat(1.2)}
    mid = float(np.sqrt(gap.group_aspect_ratio("rail") * gap.group_aspect_ratio("long patch")))
    case = GapCaseResult("k", "shape", gap.GROUPS["rail"][1], 0.0, mid, 1.0, 0.2, 1.5, 800.0, 0.01, [0.0], [0.0],
                         groove_mm=[0.011, 0.011])                    # FEM g/dent 1.1: the law halfway in log(a/b)
    md = gap.shape_check_markdown([case], laws)
    assert "| 1.000, 1.000 | 0.909, 0.909 |" in md[2]
    assert md[-1].startswith("Worst |law / FEM - 1|: 0.0 % with the patch-shape nodes, 9.1 %")


def test_the_blocks_write_only_the_very_long_node(monkeypatch):
    written = {}
    monkeypatch.setattr(gap, "write_law", lambda table_rel, law: written.setdefault(table_rel, law))
    very_long = flat(1.3)
    gap.write_block_nodes({"very long patch": very_long, "long patch": flat(9.0), "rail": flat(9.0)})
    assert set(written) == {t for _, t in gap.GROUPS.values() if t}
    for table_rel, law in written.items():
        stored = gap.LayerTable.read(gap.ROOT / table_rel).rolling_law
        assert law.aspect_ratio == stored.aspect_ratio and law.convexity == stored.convexity
        last = len(law.aspect_ratio) - 1
        assert all(law.node(k) == stored.node(k) for k in range(last))  # the sections' nodes kept
        assert law.node(last).first_pass_ratio == very_long.first_pass_ratio
