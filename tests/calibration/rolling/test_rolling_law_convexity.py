"""The rolling law's convexity nodes: linear in the surface convexity b / (2 R) among the nodes of one a/b (clamped),
then log(a/b) between the groups; stored in format version 5 (older versions read as before); read by the passes at
the pass's lateral semi-axis b and the layer's lateral curvature (the table's, at the element)."""

import json

import numpy as np
import pytest

from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.passes.passes import PassesOptions, run_passes
from contact.passes.rolling_memory import RollingMemory, patch_semi_axes
from contact.scenes.layers import LayerSources, build_layer_pair
from contact.scenes.paper_example import paper_characteristic, paper_layers, paper_problem
from wrlayer.characteristic import Characteristic
from wrlayer.errors import InputError
from wrlayer.layer_table import FORMAT_VERSION_CONVEXITY_LAW, LayerTable
from wrlayer.rolling_law import RollingLaw

CH = Characteristic(np.array([0.0, 0.001, 0.004, 0.012]), np.array([0.0, 800.0, 1300.0, 1800.0]), "test")


def law(rho=0.9, a=0.0, q=0.3):
    return RollingLaw([1.3, 2.1], [0.0, 0.2], [[rho] * 2] * 2, [[a] * 2] * 2, [[q] * 2] * 2, [[0.0] * 2] * 2,
                      f"rho {rho}")


#: Two round nodes (concave flange root, flat tread) and one long node.
SHAPED = RollingLaw.by_shape([(1.34, -0.10, law(1.2)), (1.34, -0.01, law(1.0)), (3.83, 0.01, law(1.5))])


def test_round_nodes_are_linear_in_convexity_and_clamped():
    s = np.array([-0.3, -0.10, -0.055, -0.01, 0.2])
    np.testing.assert_allclose(SHAPED.factor(1, 1.7, 0.1, 1.34, s), [1.2, 1.2, 1.1, 1.0, 1.0], rtol=1e-12)
    mid = float(np.sqrt(1.34 * 3.83))                       # halfway in log(a/b) from the round group at s
    assert float(SHAPED.factor(1, 1.7, 0.1, mid, -0.055)) == pytest.approx(0.5 * (1.1 + 1.5), rel=1e-12)
    assert float(SHAPED.factor(1, 1.7, 0.1, 10.0, -0.2)) == pytest.approx(1.5)   # one node: convexity unused
    with pytest.raises(InputError, match="b/\\(2R\\) is needed"):
        SHAPED.factor(1, 1.7, 0.1, 1.34)


def test_nodes_json_and_validation():
    assert RollingLaw.from_dict(json.loads(json.dumps(SHAPED.to_dict()))) == SHAPED
    assert SHAPED.node(1) == law(1.0)                        # a node's own law, source included
    assert "convexity" not in RollingLaw.by_aspect([(1.34, law()), (3.83, law(1.5))]).to_dict()
    bad = SHAPED.to_dict()
    bad["convexity"] = [-0.01, -0.10, 0.01]                  # not increasing within a/b = 1.34
    with pytest.raises(InputError, match="convexity.*increasing"):
        RollingLaw.from_dict(bad)
    with pytest.raises(InputError, match="aspect_ratio.*increasing"):   # equal a/b only with convexity nodes
        RollingLaw.from_dict({k: v for k, v in bad.items() if k != "convexity"})
    with pytest.raises(InputError, match="convexity"):
        RollingLaw.from_dict(dict(SHAPED.to_dict(), convexity=[0.0, 0.1]))
    with pytest.raises(InputError, match="every patch-shape node"):
        RollingLaw.by_shape([(1.34, None, law()), (3.83, 0.0, law(1.5))])


def table(rolling_law, curvatures=(0.02, -0.01)):
    pos = [{"y_mm": y, "characteristic": CH.to_dict(), "geometry": {"a_mm": 6.0, "b_mm": 4.0, "k_y_per_mm": k}}
           for y, k in zip((-1.0, 1.0), curvatures)]
    return LayerTable({"body": "wheel", "profile": "p"}, pos, source="t", rolling_law=rolling_law)


def test_table_format_and_lateral_curvature():
    data = json.loads(table(SHAPED).to_json())
    assert data["format_version"] == FORMAT_VERSION_CONVEXITY_LAW
    assert LayerTable.from_dict(data, "t.json").rolling_law == SHAPED
    with pytest.raises(InputError, match="needs format_version 5"):
        LayerTable.from_dict(dict(data, format_version=4), "old.json")
    assert json.loads(table(law()).to_json())["format_version"] == 3   # a law without nodes: as before
    t = table(SHAPED)
    assert [t.lateral_curvature_at(y) for y in (-2.0, 0.0, 1.0)] == pytest.approx([0.02, 0.005, -0.01])
    np.testing.assert_allclose(t.lateral_curvature_at(np.array([-2.0, 0.0, 1.0])), [0.02, 0.005, -0.01])
    no_k = LayerTable({"body": "wheel", "profile": "p"}, [{"y_mm": 0.0, "characteristic": CH.to_dict()}])
    assert no_k.lateral_curvature_at(0.0) == 0.0


def test_layers_from_a_table_carry_its_curvature_for_a_convexity_law():
    strips = np.array([-0.5, 0.0, 0.5])
    pair = build_layer_pair(LayerSources(wheel=table(SHAPED)), strips, lambda body: strips, None, "layers")
    np.testing.assert_allclose(pair.wheel.lateral_curvature_per_mm, [0.0125, 0.005, -0.0025])
    plain = build_layer_pair(LayerSources(wheel=table(law())), strips, lambda body: strips, None, "layers")
    assert not np.any(plain.wheel.lateral_curvature_per_mm)


def test_memory_reads_the_law_at_the_patch_half_width_times_the_curvature():
    layer = PrandtlLayer.uniform(CH, np.array([0.0, 1.0]), rolling_law=SHAPED)
    layer.lateral_curvature_per_mm = np.array([-0.05, -0.05])   # R = -20 mm (concave)
    mem = RollingMemory(layer, 0.1)
    virgin = layer.relaxed()
    p = np.array([1500.0, 1500.0])
    virgin.load_to(p)
    r = virgin.unload()
    added = mem.advance(p, r, np.array([1.34, 1.34]), np.array([1.8, 0.4]))   # b/(2R) = -0.045, -0.01
    np.testing.assert_allclose(added, r * np.array([1.0 + 0.2 * 0.035 / 0.09, 1.0]), rtol=1e-12)


def test_passes_give_the_memory_the_regions_half_width():
    prob = paper_problem()
    base = paper_layers(prob).combined
    from contact.normal.method import solve_normal_with

    sol = solve_normal_with(prob, paper_layers(prob))
    main = max(sol.regions, key=lambda r: r.p0_MPa)
    a, b = patch_semi_axes(sol, prob.grid_mm)
    aspect, half = float(a[main.reference] / b[main.reference]), float(b[main.reference])
    k = -0.05 / half                                           # the surface convexity b k / 2 = -0.025
    lw = RollingLaw.by_shape([(aspect, -0.05, law(0.6)), (aspect, 0.0, law(1.0))])
    curved = PrandtlLayer.uniform(paper_characteristic(), base.y_mm, rolling_law=lw)
    curved.lateral_curvature_per_mm = np.full(base.y_mm.size, k)
    relaxed, _ = run_passes(prob, paper_layers(prob), PassesOptions(max_passes=1, memory="relaxed"))
    rolling, _ = run_passes(prob, LayerPair(combined=curved), PassesOptions(max_passes=1))
    assert rolling[0].up0_mm == pytest.approx(0.8 * relaxed[0].up0_mm, rel=1e-9)   # halfway between the nodes
