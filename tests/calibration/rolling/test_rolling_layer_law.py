"""The rolling law: its fit to a groove series, its storage in a layer table (format 3; versions 1-2 still read)
and the passes' "rolling" memory rule that uses it."""

import json

import numpy as np
import pytest

from calibration.rolling.law_fit import PassFit, fit_passes, rolling_law
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.passes.passes import PassesOptions, run_passes
from contact.passes.rolling_memory import RollingMemory
from contact.scenes.paper_example import paper_characteristic, paper_layers, paper_problem
from wrlayer.characteristic import Characteristic
from wrlayer.errors import InputError
from wrlayer.layer_table import LayerTable
from wrlayer.rolling_law import RollingLaw

CH = Characteristic(np.array([0.0, 0.001, 0.004, 0.012]), np.array([0.0, 800.0, 1300.0, 1800.0]), "test")


def law(rho=0.9, a=0.04, q=0.3, b=0.0):
    return RollingLaw([1.3, 1.7, 2.1], [0.0, 0.2], [[rho] * 3, [rho + 0.05] * 3], [[a] * 3, [a] * 3],
                      [[q] * 3, [q] * 3], [[b] * 3, [b + 0.01] * 3], "test")


@pytest.mark.parametrize("params", [(0.95, 0.04, 0.3, 0.0), (0.9, 0.15, 0.6, 0.0), (0.85, 0.1, 0.4, 0.05)])
def test_fit_recovers_shakedown_and_ratcheting(params):
    truth = PassFit(*params, 0.0)
    static = 0.02
    fit = fit_passes(truth.factors(10) * static, static)
    assert fit.first_pass_ratio == pytest.approx(params[0], rel=1e-12)
    np.testing.assert_allclose(fit.factors(10), truth.factors(10), rtol=2e-3)
    assert fit.max_relative_error < 2e-3
    assert (fit.ratchet_increment > 0.01) == (params[3] > 0)


def test_without_ratcheting_a_slowly_decaying_tail_stays_shakedown():
    # increments falling by 0.23, then 0.35 per pass (the a/4 sections): with B the tail reads as ratcheting
    g = np.cumsum([1.05, 0.0716, 0.0164, 0.0058, 0.0021])
    free, shakedown = fit_passes(g, 1.0), fit_passes(g, 1.0, ratcheting=False)
    assert free.ratchet_increment > 1e-3 and shakedown.ratchet_increment == 0.0
    assert shakedown.max_relative_error < 2e-3
    assert shakedown.factors(60)[-1] < g[-1] * 1.002 < free.factors(60)[-1] / 1.05


def test_a_falling_groove_is_not_represented():
    fit = fit_passes([1.0, 0.9, 0.8], 1.0)
    assert fit.shakedown_increment == 0.0 and fit.ratchet_increment == 0.0
    assert fit.max_relative_error == pytest.approx(0.25)


def test_law_interpolates_clamps_and_follows_equivalent_passes():
    lw = law()
    assert lw.factor(1, 1.0, 0.1) == pytest.approx(0.925)            # clamped level, mid traction
    assert lw.factor(1, 3.0, -0.5) == pytest.approx(0.95)             # clamped level and |c|
    g = lw.factor(np.arange(1, 11), 1.7, 0.2)
    u = 0.0
    for n in range(10):                                                # constant peak: exactly r G_n
        u = lw.next_residual(u, 2.0, 1.7, 0.2)
        assert float(u) == pytest.approx(2.0 * g[n], rel=1e-9)
    assert float(lw.next_residual(10.0, 2.0, 1.7, 0.0)) == 10.0        # beyond the shakedown groove: no increment
    assert float(lw.next_residual(0.5, 2.0, 1.7, 0.0)) == pytest.approx(1.8)   # a higher peak: its first pass


def test_shaped_law_is_linear_in_log_aspect_clamped_and_exact_at_its_nodes():
    round_, long_ = law(rho=0.9), law(rho=1.2, a=0.1, q=0.5, b=0.01)
    lw = RollingLaw.by_aspect([(1.34, round_), (3.83, long_)])
    for r, node in ((1.0, round_), (1.34, round_), (3.83, long_), (13.6, long_)):   # at the nodes and clamped
        np.testing.assert_allclose(lw.factor(np.arange(1, 6), 1.7, 0.2, r), node.factor(np.arange(1, 6), 1.7, 0.2),
                                   rtol=1e-12)
    mid = float(np.sqrt(1.34 * 3.83))                                   # halfway in log(a/b)
    assert lw.parameters(1.7, 0.0, mid)[0] == pytest.approx(0.5 * (0.9 + 1.2), rel=1e-12)
    per_point = lw.next_residual(np.zeros(2), np.array([2.0, 2.0]), 1.7, 0.2, np.array([1.34, 3.83]))
    np.testing.assert_allclose(per_point, [2.0 * float(round_.factor(1, 1.7, 0.2)),
                                           2.0 * float(long_.factor(1, 1.7, 0.2))], rtol=1e-12)
    with pytest.raises(InputError, match="a/b is needed"):
        lw.factor(1, 1.7, 0.2)
    assert RollingLaw.from_dict(json.loads(json.dumps(lw.to_dict()))) == lw
    assert lw.node(1) == long_ and round_.node(0) is round_               # a node's own law, source included
    assert RollingLaw.by_aspect([(1.34, lw.node(0)), (3.83, lw.node(1))]) == lw
    assert "aspect_ratio" not in round_.to_dict()                      # a single-shape law writes as before
    with pytest.raises(InputError, match="one grid of levels"):
        RollingLaw.by_aspect([(1.0, round_), (2.0, RollingLaw([1.3, 2.1], [0.0], [[1.0] * 2], [[0.0] * 2],
                                                              [[0.0] * 2], [[0.0] * 2]))])
    bad = lw.to_dict()
    bad["aspect_ratio"] = [3.83, 1.34]
    with pytest.raises(InputError, match="aspect_ratio.*increasing"):
        RollingLaw.from_dict(bad)


def test_table_round_trip_and_old_versions(tmp_path):
    pos = [{"y_mm": y, "characteristic": CH.to_dict()} for y in (-1.0, 1.0)]
    t = LayerTable({"body": "rail", "profile": "p"}, pos, source="t", rolling_law=law())
    data = json.loads(t.to_json())
    assert data["format_version"] == 3 and data["rolling_law"]["shakedown_decay"][1] == [0.3] * 3
    back = LayerTable.from_dict(data, "t.json")
    assert back.rolling_law == t.rolling_law
    data.pop("rolling_law")
    for version in (1, 2, 3):                                          # older tables: no law
        assert LayerTable.from_dict(dict(data, format_version=version), "old.json").rolling_law is None
    assert json.loads(LayerTable.from_dict(data, "old").to_json())["format_version"] == 2
    with pytest.raises(InputError, match="needs format_version 3"):
        LayerTable.from_dict(dict(data, format_version=2, rolling_law=law().to_dict()), "x.json")
    bad = law().to_dict()
    bad["shakedown_decay"] = [[1.0] * 3, [0.3] * 3]
    with pytest.raises(InputError, match=r"rolling_law.*shakedown_decay\[0\]"):
        LayerTable.from_dict(dict(data, format_version=3, rolling_law=bad), "x.json")


def test_rolling_memory_is_the_law_on_the_static_residual():
    layer = PrandtlLayer.uniform(CH, np.array([0.0, 1.0]), rolling_law=law())
    mem = RollingMemory(layer, 0.0)
    p = np.array([1500.0, 0.0])                                        # the second point is not loaded
    total = np.zeros(2)
    for n in range(1, 6):
        virgin = layer.relaxed()
        virgin.load_to(p)
        total += mem.advance(p, virgin.unload())
        r = virgin.u_mm[0]
        assert total[0] == pytest.approx(r * float(law().factor(n, 1500.0 / 800.0, 0.0)), rel=1e-9)
    assert total[1] == 0.0


def with_law(pair: LayerPair, lw) -> LayerPair:
    return LayerPair(combined=PrandtlLayer.uniform(paper_characteristic(), pair.combined.y_mm, rolling_law=lw))


def test_passes_use_the_law_and_fall_back_to_relaxed_without_one():
    prob = paper_problem()
    opts = PassesOptions(max_passes=4)
    relaxed, _ = run_passes(prob, paper_layers(prob), PassesOptions(max_passes=4, memory="relaxed"))
    fallback, _ = run_passes(prob, paper_layers(prob), opts)           # no law: the paper's model, same numbers
    assert [r.up0_mm for r in fallback] == [r.up0_mm for r in relaxed]
    rolling, _ = run_passes(prob, with_law(paper_layers(prob), law(rho=0.8, a=0.05, q=0.5)), opts)
    assert rolling[0].p_max_MPa == relaxed[0].p_max_MPa                # the same virgin first pass
    assert rolling[0].up0_mm == pytest.approx(0.8 * relaxed[0].up0_mm, rel=1e-9)
    # the dent lowers the next peak: its static residual times any number of passes stays below the first groove
    assert rolling[1].p_max_MPa < rolling[0].p_max_MPa and rolling[1].up0_mm == 0.0 < relaxed[1].up0_mm
    assert rolling[-1].p_max_MPa > relaxed[-1].p_max_MPa               # a shallower dent: a higher pressure
    explicit, _ = run_passes(prob, with_law(paper_layers(prob), law()), PassesOptions(max_passes=4, memory="relaxed"))
    assert [r.up0_mm for r in explicit] == [r.up0_mm for r in relaxed]
    with pytest.raises(InputError, match="memory"):
        PassesOptions(memory="virgin")


def test_patch_aspect_is_the_regions_half_length_over_half_width():
    from types import SimpleNamespace

    from contact.passes.rolling_memory import patch_aspect_ratios

    regions = [SimpleNamespace(strips=np.array([1, 2, 3, 4]), x_lead_mm=np.array([1.0, 3.0, 3.0, 1.0])),
               SimpleNamespace(strips=np.array([7, 8]), x_lead_mm=np.array([0.5, 0.5]))]
    out = patch_aspect_ratios(SimpleNamespace(p_peak_MPa=np.zeros(10), regions=regions), 0.5)
    np.testing.assert_allclose(out, [1, 3, 3, 3, 3, 1, 1, 1, 1, 1])


def test_passes_read_the_shaped_law_at_the_pass_patch_shape():
    from contact.normal.method import solve_normal_with
    from contact.passes.rolling_memory import patch_aspect_ratios

    prob = paper_problem()
    sol = solve_normal_with(prob, paper_layers(prob))
    main = max(sol.regions, key=lambda r: r.p0_MPa)
    r = float(patch_aspect_ratios(sol, prob.grid_mm)[main.reference])
    assert 0.1 < r < 50.0
    shaped = RollingLaw.by_aspect([(r / 2, law(rho=0.6, a=0.0)), (2 * r, law(rho=1.0, a=0.0))])
    opts = PassesOptions(max_passes=1)
    relaxed, _ = run_passes(prob, paper_layers(prob), PassesOptions(max_passes=1, memory="relaxed"))
    rolling, _ = run_passes(prob, with_law(paper_layers(prob), shaped), opts)
    assert rolling[0].up0_mm == pytest.approx(0.8 * relaxed[0].up0_mm, rel=1e-9)   # halfway in log(a/b)


def test_rolling_json_carries_the_law_fitted_to_its_passes():
    from calibration.rolling.layer_prediction import LayerGroove
    from calibration.rolling.run import LevelResult, RollingResult

    truth = {1.3: PassFit(0.97, 0.04, 0.3, 0.0, 0.0), 2.1: PassFit(0.9, 0.2, 0.5, 0.08, 0.0)}
    levels = [LevelResult(x, 800.0 * x, 0.01 * x, groove_mm=(f.factors(4) * 0.01 * x).tolist(),
                          layer_groove_mm=LayerGroove([0.011 * x * n for n in range(1, 5)], [0.011 * x] * 4))
              for x, f in truth.items()]
    res = RollingResult(2, {}, 800.0, 1, 1, levels).with_rolling_law(0.0)
    lw = RollingLaw.from_dict(res.rolling_law)
    assert lw.p0_over_p2 == [1.3, 2.1] and lw.traction_coefficient == [0.0]
    for lv, f in zip(res.levels, truth.values()):
        np.testing.assert_allclose(lv.layer_groove_mm.rolling, 0.011 * lv.p0_over_py * f.factors(4), rtol=5e-3)
    assert res.to_dict()["levels"][1]["layer_groove_mm"]["rolling"] == res.levels[1].layer_groove_mm.rolling
