"""The fast-mode targets of benchmarks.bench_tangential_a22 (no sweep run: the verdict on given deviations)."""

from benchmarks.bench_tangential_a22 import FAST_SPEEDUP, FAST_TOLERANCE, targets_met


def _worst(p_max=0.01, area=0.01, fn=0.001, fx=0.01, fy=0.01) -> dict:
    return {"p_max_MPa": (p_max, 14, "right"), "area_mm2": (area, 14, "right"), "normal_force_N": (fn, 2, "left"),
            "Fx_N": (fx, 1, "right"), "Fy_N": (fy, 2, "right")}


def test_every_target_met():
    assert targets_met(_worst(), None, FAST_SPEEDUP) == "speed yes, forces yes, p_max and area yes"


def test_a_force_or_the_speed_outside_is_reported():
    assert targets_met(_worst(fy=-1.01 * FAST_TOLERANCE), None, 0.99 * FAST_SPEEDUP) == \
        "speed no, forces no, p_max and area yes"


def test_the_patch_judged_against_the_fine_strips_when_the_exact_mode_is_off():
    off = _worst(area=-0.08)
    assert targets_met(off, None, 4.0).endswith("p_max and area no")
    assert targets_met(off, _worst(area=-0.017), 4.0).endswith("p_max and area against 0.025 mm strips only")
    assert targets_met(off, _worst(p_max=0.06), 4.0).endswith("p_max and area no")


def test_the_tangential_clock_adds_the_solves_cpu_time_and_puts_the_solver_back(monkeypatch):
    from benchmarks.bench_tangential_a22 import tangential_clock
    from contact.wheel_rail import balance

    def busy(n):
        return sum(i * i for i in range(n))

    monkeypatch.setattr(balance, "solve_regions", busy)
    with tangential_clock() as spent:
        assert balance.solve_regions is not busy
        assert balance.solve_regions(200000) == busy(200000)
    assert spent[0] > 0 and balance.solve_regions is busy
