"""The fast-normal benchmark's tangential tables (units: % of mu N)."""

from benchmarks.bench_fast_normal import CREEPAGES, creepage_table


def _row(method, creepage, kind, fx, fy, mz):
    return {"method": method, "creepage": creepage, "kind": kind, "patch": "p", "layer": False,
            "Fx": fx, "Fy": fy, "Mz": mz}


def test_creepage_table_gives_the_worst_error_its_class_and_the_target():
    rows = [_row("a", "combined", "hertz", 1.0, -6.0, 0.5), _row("a", "combined", "quartic", -2.0, 1.0, 0.1),
            _row("a", "vx alone", "hertz", 0.1, 0.2, 0.3),
            {**_row("a", "vx alone", "quartic", 0, 0, 0), "failed": "ConvergenceError: x"}]
    lines = creepage_table(rows).splitlines()
    assert lines[2] == "| a | combined | -2.00 (quartic) | -6.00 (hertz) | +0.50 (hertz) | no |"
    assert lines[3] == "| a | vx alone | +0.10 (hertz) | +0.20 (hertz) | +0.30 (hertz) | yes |"
    assert next(iter(CREEPAGES)) == "combined"  # the per-class table and the times use the combined creepage
