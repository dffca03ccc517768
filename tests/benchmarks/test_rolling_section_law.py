"""The tables' rolling-law nodes fitted on the refined section runs: reading the runs, the fit (mean of the
node's positions, levels x = p0 / p_2 resampled to the tables' grid), the stored nodes not fitted kept, the
long-patch node written into both tables, and the check against the other position's law."""

import json

import numpy as np
import pytest

from benchmarks import rolling_section_law as sl
from benchmarks.bench_rolling_section_gap import SectionGapRow
from benchmarks.rolling_section_cases import LEVELS, POSITIONS, TRACTIONS
from benchmarks.rolling_section_refined import cases_of
from calibration.rolling.law_fit import PassFit
from wrlayer.layer_table import LayerTable

RAIL = "scenes/tables/rail_60E1_default.json"
LABELS = {p[0]: p[3] for p in POSITIONS}


def truth(c, level):
    """A known shakedown law's parameters at (c, level): rho, A, q, B = 0 (the node has no ratcheting)."""
    return PassFit(1.0 + 0.4 * c + 0.1 * (level - 1.0), 0.05 + 0.1 * c, 0.3 + 0.1 * level, 0.0, 0.0)


def runs(names=("crown", "corner"), offset=0.02, p_2_over_py=1.0):
    """Refined runs of ``names`` with the known law's ratios, one position ``offset`` above, the other below."""
    out = []
    for k, name in enumerate(names):
        for c in TRACTIONS:
            for lv in LEVELS:
                g = truth(c, lv).factors(5) * (1.0 + (offset if k == 0 else -offset))
                out.append(sl.SectionRun(name, c, lv, lv / p_2_over_py, tuple(g)))
    return out


def test_the_node_is_the_mean_of_the_two_positions_on_the_tables_levels():
    law, fits = sl.fit_node(runs(), ("crown", "corner"))
    assert law.p0_over_p2 == list(LEVELS) and law.traction_coefficient == list(TRACTIONS)
    for c in TRACTIONS:
        for lv in LEVELS:
            np.testing.assert_allclose(law.factor(np.arange(1, 6), lv, c), truth(c, lv).factors(5), rtol=2e-3)
    assert len(fits) == len(LEVELS) * len(TRACTIONS)
    assert "crown and corner" in law.source and "h = a/4" in law.source


def test_the_levels_are_p0_over_the_tables_p_2_resampled_to_the_grid():
    shifted, _ = sl.fit_node(runs(p_2_over_py=0.98), ("crown", "corner"))  # x = level / 0.98
    direct, _ = sl.fit_node(runs(), ("crown", "corner"))
    x = 1.3 / 0.98
    np.testing.assert_allclose(shifted.factor(np.arange(1, 6), x, 0.2), direct.factor(np.arange(1, 6), 1.3, 0.2),
                               rtol=5e-3)
    assert shifted.p0_over_p2 == list(LEVELS)


def test_an_incomplete_level_is_refused():
    with pytest.raises(KeyError, match="incomplete"):
        sl.fit_node(runs()[1:], ("crown", "corner"))


def test_the_table_keeps_the_nodes_not_fitted():
    node, _ = sl.fit_node(runs(), ("crown", "corner"))
    stored = LayerTable.read(sl.ROOT / RAIL).rolling_law
    law = sl.with_nodes(RAIL, {0: node})
    assert law.aspect_ratio == stored.aspect_ratio
    assert law.node(0).first_pass_ratio == node.first_pass_ratio and law.node(0).source == node.source
    for k in range(1, len(stored.aspect_ratio)):
        assert law.node(k) == stored.node(k)


def test_the_field_side_gives_the_long_patch_node_of_both_tables():
    fitted = sl.fitted_nodes(runs() + runs(("field",), offset=0.0))
    assert set(fitted) == {sl.RAIL_TABLE, sl.WHEEL_TABLE}  # the wheel's round node: no tread or flange runs
    assert set(fitted[sl.RAIL_TABLE]) == {0, 1} and set(fitted[sl.WHEEL_TABLE]) == {1}
    assert fitted[sl.WHEEL_TABLE][1] is fitted[sl.RAIL_TABLE][1] and "field" in fitted[sl.RAIL_TABLE][1].source
    law = sl.with_nodes(sl.WHEEL_TABLE, fitted[sl.WHEEL_TABLE])
    stored = LayerTable.read(sl.ROOT / sl.WHEEL_TABLE).rolling_law
    assert law.node(0) == stored.node(0) and law.node(2) == stored.node(2)
    np.testing.assert_allclose(law.factor(np.arange(1, 6), 1.5, 0.2, law.aspect_ratio[1]),
                               truth(0.2, 1.5).factors(5), rtol=2e-3)


def test_each_position_is_checked_against_the_other_positions_law():
    text = sl.law_markdown(runs(offset=0.02))  # each 2 % off the mean, 4 % off the other
    assert "in 20 of 20 cases; fitted to the other position of a two-position node alone, in 20 of 20" in text
    text = sl.law_markdown(runs(offset=0.03))  # 6 % off the other position
    assert "in 20 of 20 cases; fitted to the other position of a two-position node alone, in 0 of 20" in text
    assert sl.law_markdown(runs()[1:]) == ""  # no complete node
    text = sl.law_markdown(runs(offset=0.03) + runs(("field",), offset=0.0))  # one position: nothing held out
    assert "in 30 of 30 cases; fitted to the other position of a two-position node alone, in 0 of 20" in text
    assert text.count("| — |") == 10


def test_the_refined_runs_are_read_with_x_over_the_tables_p_2(tmp_path):
    rows = [SectionGapRow(LABELS["crown"], 0.2, 1.3 + 1e-12, 800.0, 790.0, 0.01, 0.009, (1, 1, 1), (1, 1, 1), (1, 1, 1),
                          (1, 1, 1))]
    case = cases_of(rows, "crown")[0]
    grooves = [0.0105, 0.0112, 0.0116, 0.0118, 0.0120]
    (tmp_path / case.key).mkdir()
    (tmp_path / case.key / "rolling.json").write_text(json.dumps(
        {"levels": [{"p0_MPa": case.p0_MPa, "static_dent_mm": 0.01, "groove_mm": grooves}]}))
    (run,) = sl.section_runs(rows, tmp_path)
    assert (run.name, run.c, run.level) == ("crown", 0.2, 1.3)  # the level as the grid has it
    assert run.x == pytest.approx(1.3 * 800.0 / 790.0)
    np.testing.assert_allclose(run.ratios, np.array(grooves) / 0.01)
    assert run.dent_over_r == pytest.approx(0.01 / 0.009)  # the run's static dent over the table's r
    np.testing.assert_allclose(run.required(), np.array(grooves) / 0.009)
    (tmp_path / case.key / "rolling.json").write_text(json.dumps(
        {"levels": [{"p0_MPa": case.p0_MPa, "static_dent_mm": 0.01, "groove_mm": grooves[:2]}]}))
    assert sl.section_runs(rows, tmp_path) == []  # an incomplete run is left out


def test_the_spread_is_what_the_two_positions_need_at_the_same_x():
    def flange_dent_over_r(f):  # equal groove over static dent; the flange's dent f times the table's r
        return [sl.SectionRun(r.name, r.c, r.level, r.x, r.ratios, f if r.name == "flange" else 1.0)
                for r in runs(("tread", "flange"), offset=0.0)]

    text = sl.spread_markdown(flange_dent_over_r(1.12))
    assert "In 10 of 10 cases the two positions need G_n further apart than 1.105" in text
    assert "| tread and flange | 0.2 | 1.3 | 1.300 | 1.120, 1.120, 1.120 |" in text
    assert "In 0 of 10 cases" in sl.spread_markdown(flange_dent_over_r(1.08))
    assert sl.spread_markdown(runs(("field",), offset=0.0)) == ""  # one position: nothing to spread


def test_a_need_linear_in_x_is_compared_at_the_nodes_x():
    def need(x):
        return 2.0 - 0.5 * x  # the same need at every x for both positions, passes 1-5 alike

    shifted = [sl.SectionRun(name, c, lv, lv + dx, (need(lv + dx),) * 5)
               for name, dx in (("tread", 0.01), ("flange", -0.01)) for c in TRACTIONS for lv in LEVELS]
    text = sl.spread_markdown(shifted)
    assert "In 0 of 10 cases" in text and "| 1.000, 1.000, 1.000 |" in text
    assert "| 1.006, 1.006, 1.006 |" not in text  # not the raw ratio at unequal x
