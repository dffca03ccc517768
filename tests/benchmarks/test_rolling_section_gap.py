"""The section gap's bookkeeping: the layer's groove from a table (Masing residual times the rolling law) against a
rolling.json, and the configurations it runs (parsed by the rolling reader)."""

import pytest

from benchmarks import bench_rolling_section_gap as sg
from benchmarks import rolling_section_cases as cases
from wrlayer.layer_table import LayerTable


def test_every_configuration_is_a_valid_section_run():
    for _, table, y_mm, _ in cases.POSITIONS:
        for c in cases.TRACTIONS:
            cfg = cases.section_config(table, y_mm, c)
            assert cfg.contact.body == "section" and cfg.contact.y_mm == y_mm
            assert cfg.track.n_passes == cases.N_PASSES and tuple(cfg.contact.levels) == cases.LEVELS


def test_layer_groove_is_the_tables_residual_times_its_law():
    name, table_rel, y_mm, label = cases.POSITIONS[0]
    table = LayerTable.read(sg.ROOT / table_rel)
    ch = table.characteristic_at(y_mm)
    run = {"p_y_MPa": 800.0, "levels": [
        {"p0_over_py": 1.7, "static_dent_mm": 0.02, "groove_mm": [0.019, 0.020, 0.0203, 0.0204, 0.0205]},
        {"p0_over_py": 2.1, "static_dent_mm": 0.03, "groove_mm": [0.03]}]}  # too few passes: left out
    rows = sg.rows_of(run, table_rel, y_mm, label, 0.2)
    assert len(rows) == 1
    r = float(ch.unloading_residual(1.7 * 800.0))  # at the FEM's peak pressure, 1.7 x its own p_y
    geo = next(p["geometry"] for p in table.positions if p["y_mm"] == y_mm)
    aspect = geo["a_mm"] / geo["b_mm"]             # the law at the position's patch shape and convexity
    convexity = 0.5 * geo["b_mm"] * geo["k_y_per_mm"]
    row = rows[0]
    assert row.table_residual_mm == pytest.approx(r)
    assert row.fem_mm == (0.019, 0.020, 0.0205)
    for n, law in zip(cases.COMPARED, row.law_mm):
        assert law == pytest.approx(r * float(table.rolling_law.factor(n, 1.7 * 800.0 / ch.elastic_limit_MPa, 0.2,
                                                                       aspect, convexity)))
    assert row.relaxed_mm == pytest.approx(tuple(n * r for n in cases.COMPARED))
    text = sg.table_markdown(rows)
    assert f"| {label} | 0.2 | 1.7 |" in text and "of 1 cases" in text
