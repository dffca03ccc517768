"""The console summary of ``simulate-all`` (fits 100 columns, one short table per scene kind) and the full table in
table.md / table.csv."""

import csv
import io
from pathlib import Path
from types import SimpleNamespace as Record

from contact.scenes.result_table import (SHOWN_PASSES, SUMMARY_WIDTH, results_table, scene_summary, summary_text,
                                        wheel_rail_rows)
from contact.scenes.run_result import relative_key


def contact_result(p_max, passes=1, reference=None):
    one = {"length_mm": 10.0, "width_mm": 5.0, "area_mm2": 40.0, "delta_mm": 0.08, "Fx_N": -1234.0,
           "Fy_N": 0.0, "p_max_MPa": p_max, "WT_max_N_per_mm": 1.0, "PT_max_W_per_mm2": 0.5, "u0_mm": 0.01,
           "up0_mm": 0.0}
    return Record(passes=[Record(**dict(one, up0_mm=0.001 * k), index=k + 1) for k in range(passes)],
                  inputs={"reference": reference or {}}, shakedown_pass=passes if passes > 1 else None)


def wheel_rail_result(normal="kik_piotrowski"):
    patch = {"normal_force_N": 12_345.0, "p_max_MPa": 1500.0}
    wheels = {"right": Record(patches=[Record(**patch), Record(**dict(patch, normal_force_N=2000.0))], Y_over_Q=-1.25),
              "left": Record(patches=[Record(**dict(patch, p_max_MPa=600.0))], Y_over_Q=0.3)}
    return Record(type="wheel_rail", inputs={"method": {"normal": normal}}, n_failed=1,
                  cases=[Record(wheels=wheels, error=None),
                         Record(wheels=None, error="table does not cover the contact location")])


def results():
    return {"hertz_check": contact_result(1659.0, reference={"source": "Hertz", "p_max_MPa": 1818.5}),
            "paper_shakedown": contact_result(1194.0, passes=20,
                                              reference={"source": "paper Table 1", "passes": 19.0,
                                                         "p_max_MPa": 1190.0}),
            "a_scene_with_a_very_long_file_name_indeed": contact_result(900.0),
            "sweep": wheel_rail_result(), "sweep_exact": wheel_rail_result("exact")}


def test_summary_fits_the_terminal_and_points_to_the_full_table():
    out = Path("out") / "simulate"
    lines = summary_text(results(), out).splitlines()
    assert max(len(line) for line in lines) <= SUMMARY_WIDTH == 100
    assert lines[-3:] == [f"  {out / 'table.md'}", f"  {out / 'table.csv'}", f"  {out / '<scene>' / 'result.json'}"]
    # one row per scene, its reference indented below it
    row = next(k for k, line in enumerate(lines) if line.startswith("paper_shakedown "))
    assert lines[row].split()[1:2] == ["20"] and "1194" in lines[row].split()
    assert lines[row + 1].startswith("  paper Table 1") and "1190" in lines[row + 1].split()
    assert any(line.startswith("a_scene_with_a_very_long_fi…") for line in lines)
    # wheel-rail scenes: their own table, largest absolute values, failed cases counted
    sweep = next(line for line in lines if line.startswith("sweep "))
    assert sweep.split() == ["sweep", "kik_piotrowski", "2", "1", "3", "12.3", "1500", "1.25"]
    assert next(line for line in lines if line.startswith("sweep_exact")).split()[1] == "exact"


def test_full_table_keeps_every_column_and_adds_the_wheel_rail_rows():
    md, text = results_table(results())
    rows = list(csv.reader(io.StringIO(text)))
    assert rows[0] == ["quantity", "unit", "hertz_check", "hertz_check: Hertz", "paper_shakedown (pass 1)",
                       "paper_shakedown (pass 20)", "paper_shakedown: paper Table 1",
                       "a_scene_with_a_very_long_file_name_indeed"]
    assert all("sweep" not in cell for cell in rows[0])                  # the CSV holds the Table 1 rows only
    assert md.splitlines()[0] == "| " + " | ".join(rows[0]) + " |"
    assert "| sweep | kik_piotrowski | 2 | 1 | 3 | 12.3 | 1500 | 1.25 |" in md
    assert wheel_rail_rows({"x": contact_result(1.0)}) == []


def test_scene_summary_gives_each_pass_key_numbers_within_100_columns():
    lines = scene_summary("paper_shakedown", contact_result(1194.0, passes=20))
    assert lines[0] == "paper_shakedown: 20 passes, shakedown at pass 20"
    assert lines[1].split() == ["pass", "p_max", "MPa", "length", "mm", "width", "mm", "delta", "mm", "F_x", "kN",
                                "F_y", "kN", "u_p(0)", "mm"]
    rows = [line.split() for line in lines[2:]]
    assert len(rows) == SHOWN_PASSES and [r[0] for r in rows] == ["1", "2", "3", "…", "19", "20"]
    assert rows[0] == ["1", "1194", "10.00", "5.00", "0.080000", "-1.23", "0.00", "0.0000"]
    assert rows[-1][-1] == "0.0190"                                  # the residual u_p(0) of pass 20, mm
    one = scene_summary("hertz_check", contact_result(1659.0))
    assert one[0] == "hertz_check: 1 pass" and len(one) == 3
    sweep = scene_summary("a_sweep_with_a_very_long_file_name_indeed", wheel_rail_result())
    assert sweep[0] == "a_sweep_with_a_very_long_fi…: 2 cases, 1 failed; largest over the cases:"
    assert sweep[2].split()[1:] == ["kik_piotrowski", "2", "1", "3", "12.3", "1500", "1.25"]
    for name, result in results().items():                            # indented as simulate-all prints them
        assert max(len("  " + line) for line in scene_summary(name, result)) <= SUMMARY_WIDTH


def test_relative_deviation_keys_name_a_fraction():
    assert [relative_key(k) for k in ("length_mm", "area_mm2", "delta_mm", "Fx_N", "p_max_MPa", "WT_max_N_per_mm",
                                      "PT_max_W_per_mm2", "u0_mm", "passes")] == [
        "length_rel", "area_rel", "delta_rel", "Fx_rel", "p_max_rel", "WT_max_rel", "PT_max_rel", "u0_rel",
        "passes_rel"]


def test_wear_summary_names_each_step_largest_wear_within_100_columns():
    from contact.scenes.result_table import wear_summary

    def body(wear_mm, y_mm):
        return Record(stats=Record(wear_max_mm=wear_mm, wear_max_y_mm=y_mm))

    steps = [Record(index=k + 1, start_km=5000.0 * k, end_km=5000.0 * (k + 1), conicity=Record(delta_r_mm=0.1234),
                    bodies={("right", "rail"): body(0.002 * (k + 1), -12.345),
                            ("right", "wheel"): body(0.001, 30.0)}) for k in range(12)]
    lines = wear_summary("s1002_60e1.toml", steps, Path("out") / "wear" / "result.json")
    assert lines[0] == f"s1002_60e1.toml: 12 steps, 60000 km -> {Path('out/wear/result.json')}, steps.csv, profiles/"
    assert lines[-1] == ("  step 12: 55000..60000 km, max wear 24.00 µm (right rail at y = -12.35 mm), "
                         "dr = 0.1234 mm")
    assert len(lines) == 13 and max(len(line) for line in lines) <= SUMMARY_WIDTH
