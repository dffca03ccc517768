"""The tables' rolling laws fitted on the refined section runs: reading the runs, the fit (levels x = p0 / p_2
resampled to the tables' grid), one round node per position at its convexity, the long-patch node in both tables,
the stored very long node kept, and the held-out position checked between the nodes."""

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


def node_runs(offsets: dict[str, float]):
    """Refined runs of the positions ``offsets`` with the known law's ratios, each ``offsets[name]`` above it."""
    out = []
    for name, off in offsets.items():
        out += runs((name,), offset=off)
    return out


#: Each node position's ratio over the known law: the wheel's two round positions apart by 12 %.
OFFSETS = {"crown": 0.0, "corner": 0.02, "tread": -0.04, "flange": 0.08, "field": 0.1}


def test_each_table_law_has_its_positions_at_their_convexity_and_keeps_the_very_long_node():
    laws = sl.table_laws(sl.complete_nodes(node_runs(OFFSETS)))
    assert set(laws) == {sl.RAIL_TABLE, sl.WHEEL_TABLE}
    n = np.arange(1, 6)
    for table_rel, law in laws.items():
        stored = LayerTable.read(sl.ROOT / table_rel).rolling_law
        assert len(law.aspect_ratio) == 4 and sorted(set(law.aspect_ratio)) == sorted(set(stored.aspect_ratio))
        assert law.node(3) == stored.node(len(stored.aspect_ratio) - 1) and law.convexity[3] == 0.0
        names = ("crown", "corner") if table_rel == sl.RAIL_TABLE else ("flange", "tread")  # by convexity
        for k, name in enumerate(names + ("field",)):
            s = sl.position_convexity(name)
            assert law.convexity[k] == pytest.approx(s)
            np.testing.assert_allclose(law.factor(n, 1.5, 0.2, law.aspect_ratio[k], s),
                                       truth(0.2, 1.5).factors(5) * (1 + OFFSETS[name]), rtol=3e-3)
    s_tread, s_flange = sl.position_convexity("tread"), sl.position_convexity("flange")
    assert s_flange < sl.position_convexity("inner") < s_tread < 0.0 < sl.position_convexity("crown")
    mid = laws[sl.WHEEL_TABLE].factor(n, 1.5, 0.2, laws[sl.WHEEL_TABLE].aspect_ratio[0], 0.5 * (s_tread + s_flange))
    np.testing.assert_allclose(mid, truth(0.2, 1.5).factors(5) * 1.02, rtol=3e-3)   # halfway: linear in s
    assert sl.table_laws(sl.complete_nodes(runs(("crown",)))) == {}  # a table with a node missing: not written


def test_the_held_out_position_is_checked_against_its_tables_law():
    def inner(offset):  # the inner tread's ratios, ``offset`` over the known law (the tables' law there: -0.3 %)
        return [sl.SectionRun("inner", r.c, r.level, r.x, r.ratios) for r in runs(("tread",), offset=offset)]

    text = sl.law_markdown(node_runs(OFFSETS) + inner(0.0))
    assert "in 50 of 50 cases at their nodes' positions and in 10 of 10 at the positions held out" in text
    assert text.count("| inner | held out |") == 10
    text = sl.law_markdown(node_runs(OFFSETS) + inner(-0.06))  # 6 % below the law between the nodes
    assert "in 0 of 10 at the positions held out" in text
    assert sl.law_markdown(runs(("crown",))) == ""  # no table complete


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


def test_the_shipped_laws_are_the_fit_of_the_committed_runs():
    """The shipped tables' rolling laws are what ``--write-tables`` writes from the runs kept in benchmarks/data."""
    from benchmarks.bench_rolling_section_gap import collect

    data = sl.ROOT / "benchmarks" / "data"
    runs_ = sl.section_runs(collect(data / "rolling_section_gap", False), data / "rolling_section_refined")
    laws = sl.table_laws(sl.complete_nodes(runs_))
    assert set(laws) == {sl.RAIL_TABLE, sl.WHEEL_TABLE}
    for table_rel, law in laws.items():
        assert law == LayerTable.read(sl.ROOT / table_rel).rolling_law
