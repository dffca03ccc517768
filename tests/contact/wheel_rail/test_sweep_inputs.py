"""Per-case sweep inputs (lists per key or a CSV the scene names), the shipped Manchester A-2.2 scene, cases.csv."""

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from contact.__main__ import main
from contact.wheel_rail.parse import parse_wheel_rail_scene
from contact.run_files import run_wheel_rail_scene
from wrlayer.errors import InputError

SCENES = Path(__file__).resolve().parents[3] / "scenes"


def _run(data, scene_path, out_dir, plots=False):
    return run_wheel_rail_scene(parse_wheel_rail_scene(data, scene_path), out_dir, plots).to_dict()


def _scene(**sections):
    data = {"type": "wheel_rail", "wheel": {"side": "right"}}
    data.update(sections)
    return data


def test_every_pose_and_kinematic_input_can_vary_per_case(tmp_path):
    sweep = {"lateral_mm": [0.0, 2.0], "yaw_rad": [0.0, 0.004], "roll_rad": [0.0, 1e-4],
             "pitch_rate_rad_s": [4.30, 4.40], "vertical_load_N": [8000.0, 12000.0], "speed_mm_s": [1900.0, 2100.0]}
    result = _run(_scene(sweep=sweep), tmp_path / "s.toml", tmp_path, plots=False)
    for k, case in enumerate(result["cases"]):
        for key, values in sweep.items():
            assert case[key] == pytest.approx(values[k])
        w = case["wheels"]["right"]
        assert w["vertical_force_N"] == pytest.approx(sweep["vertical_load_N"][k], rel=1e-6)
    # the pitch rate enters the creepage: vx ~ 1 - omega r / V
    p0 = result["cases"][0]["wheels"]["right"]["patches"][0]
    assert p0["creepage_x"] == pytest.approx(1.0 - 4.30 * abs(p0["Z_track_mm"] - 0.0 + 460.0) / 1900.0, abs=2e-3)
    rows = list(csv.DictReader((tmp_path / "cases.csv").open()))
    assert [float(r["vertical_load_N"]) for r in rows] == [8000.0, 12000.0]


def test_sweep_csv_with_contact_signs(tmp_path):
    (tmp_path / "cases.csv").write_text("# a comment\ncase,lateral_mm,yaw_rad,roll_rad,pitch_rate_rad_s,extra\n"
                                        "1,0.0,0.0,0.0,-4.35,7\n2,1.0,0.0024,-5.0e-05,-4.3466,7\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"unknown column 'extra'.*list it in sweep.ignore_columns"):
        parse_wheel_rail_scene(_scene(sweep={"csv": "cases.csv", "convention": "contact"}), tmp_path / "s.toml")
    parsed = parse_wheel_rail_scene(_scene(sweep={"csv": "cases.csv", "convention": "contact",
                                                  "ignore_columns": ["extra"]}), tmp_path / "s.toml")
    cases = parsed.cases
    assert [c.lateral_mm for c in cases] == [0.0, 1.0]
    assert cases[1].roll_rad == pytest.approx(5.0e-05) and cases[1].pitch_rate_rad_s == pytest.approx(4.3466)
    assert parsed.sweep.csv.ignored_columns == ("case", "extra")


@pytest.mark.parametrize("text, sweep, match", [
    ("lateral_mm\nabc\n", {}, r"s.toml: sweep.csv \(c.csv\): row 1, column lateral_mm: not a number"),
    ("a,b\n1,2\n", {"ignore_columns": ["a", "b"]}, r"sweep.csv \(c.csv\): no column named like"),
    ("\ufefflateral_mm\n3\n", {"mode": "bad"}, r"sweep.mode"),  # a byte-order mark does not hide the column
    ("lateral_mm,lateral_mm\n1,2\n", {}, r"column 'lateral_mm' appears twice"),
    ("lateral_mm,pitch_rate_rad_s\n0,-4.35\n", {}, r"row 1: pitch rate -4.35 rad/s in the 'wrlayer' convention "
     r"turns the wheel backwards; check sweep.convention"),
    ("lateral_mm\n" + "1" * 300 + "\n", {}, r"a field of 300 characters"),
    ("lateral_mm\n1\n", {"lateral_mm": [1.0]}, r"sweep.lateral_mm: give the per-case values either in the CSV"),
    ("lateral_mm\n1\n", {"convention": "simpack"}, r"sweep.convention: must be one of"),
    ("lateral_mm,vertical_load_N\n1,-5\n", {}, r"sweep.vertical_load_N: must be > 0"),
])
def test_bad_sweep_csv_names_the_key(tmp_path, text, sweep, match):
    (tmp_path / "c.csv").write_text(text, encoding="utf-8")
    with pytest.raises(InputError, match=match):
        parse_wheel_rail_scene(_scene(sweep={"csv": "c.csv", **sweep}), tmp_path / "s.toml")


def test_bad_method_keys_are_named(tmp_path):
    with pytest.raises(InputError, match=r"s.toml: method.contact_point: must be one of"):
        parse_wheel_rail_scene(_scene(method={"contact_point": "centre"}), tmp_path / "s.toml")
    with pytest.raises(InputError, match=r"s.toml: method.normal: must be one of"):
        parse_wheel_rail_scene(_scene(method={"normal": "hertz"}), tmp_path / "s.toml")
    with pytest.raises(InputError, match=r"s.toml: method.balance: must be one of"):
        parse_wheel_rail_scene(_scene(method={"balance": "vertical"}), tmp_path / "s.toml")


def test_shipped_manchester_a22_scene(tmp_path, reference_dir, monkeypatch):
    monkeypatch.setenv("WRLAYER_REFERENCE", str(reference_dir))
    out = tmp_path / "out"
    assert main(["simulate", str(SCENES / "manchester_a22.toml"), "--out", str(out)]) == 0
    result = json.loads((out / "result.json").read_text())
    assert len(result["cases"]) == 21 and result["n_failed"] == 0
    assert result["inputs"]["rail_profile"].startswith("MBench_UIC60")
    inputs = list(csv.DictReader(line for line in (reference_dir / "mbench_a22_inputs.csv").open()
                                 if not line.startswith("#")))
    for case, row in zip(result["cases"], inputs):
        assert case["pitch_rate_rad_s"] == pytest.approx(-float(row["pitch_rate_rad_s"]))   # CONTACT's sign
        assert case["roll_rad"] == pytest.approx(-float(row["roll_rad"]))
        assert case["yaw_rad"] == pytest.approx(float(row["yaw_rad"]))
        for side in ("right", "left"):
            w = case["wheels"][side]
            assert abs(w["vertical_force_N"] - 10000.0) / 10000.0 < 1e-6
            assert w["approach_mm"] > 0
            for p in w["patches"]:   # every patch's normal approach follows the wheel's vertical approach
                gamma = p["first_contact"]["contact_angle_rad"]
                assert p["delta_mm"] == pytest.approx(w["approach_mm"] * np.cos(gamma) - p["normal_gap_mm"],
                                                      rel=1e-6, abs=1e-9)
            assert sum(p["load_share"] for p in w["patches"]) == pytest.approx(1.0)
            assert all(p["contact_point"] == "weighted_centre" for p in w["patches"])
    # lateral 5 mm: on the benchmark's profile files the gauge corner carries load together with the tread
    two = result["cases"][10]["wheels"]["right"]["patches"]
    assert len(two) == 2 and min(p["load_share"] for p in two) > 0.05
    rows = list(csv.DictReader((out / "cases.csv").open()))
    assert len(rows) == sum(len(w["patches"]) for c in result["cases"] for w in c["wheels"].values())
    assert np.isfinite([float(r["Fx_N"]) for r in rows]).all()


def test_no_progress_bar_in_logs_and_failed_cases_in_the_csv(tmp_path, capsys):
    data = _scene(sweep={"lateral_mm": [0.0, 25.0]})
    result = _run(data, tmp_path / "s.toml", tmp_path, plots=False)
    err = capsys.readouterr().err
    assert "\x1b" not in err and "case/s" not in err            # stderr is not a terminal here: no bar
    rows = list(csv.DictReader((tmp_path / "cases.csv").open()))
    assert result["n_failed"] == 1
    assert rows[0]["error"] == "" and "flange through the rail" in rows[1]["error"]
    assert float(rows[0]["normal_force_N"]) > 0 and rows[1]["normal_force_N"] == ""


def test_roll_from_the_csv_conflicts_with_auto_roll(tmp_path):
    (tmp_path / "c.csv").write_text("lateral_mm,roll_rad\n0.0,0.0\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"s.toml: sweep.roll_rad: cannot sweep the roll angle when"):
        parse_wheel_rail_scene(_scene(wheelset={"roll_rad": "auto"}, sweep={"csv": "c.csv"}), tmp_path / "s.toml")


def test_exact_solver_keys_are_validated(tmp_path):
    with pytest.raises(InputError, match=r"s.toml: method.exact_cells: must be an integer in \[8, 1024\]"):
        parse_wheel_rail_scene(_scene(method={"normal": "exact", "exact_cells": 3}), tmp_path / "s.toml")
    with pytest.raises(InputError, match=r"s.toml: method.layer_mode: must be one of"):
        parse_wheel_rail_scene(_scene(method={"normal": "exact", "layer_mode": "sliding"}), tmp_path / "s.toml")


def test_cases_csv_gives_both_reference_points(tmp_path):
    result = _run(_scene(method={"contact_point": "weighted_centre"}), tmp_path / "s.toml", tmp_path,
                                  plots=False)
    row = next(csv.DictReader((tmp_path / "cases.csv").open()))
    p = result["cases"][0]["wheels"]["right"]["patches"][0]
    assert float(row["y_rail_mm"]) == pytest.approx(p["weighted_centre"]["y_rail_mm"])
    assert float(row["y_rail_weighted_centre_mm"]) == pytest.approx(p["weighted_centre"]["y_rail_mm"])
    assert float(row["y_rail_first_contact_mm"]) == pytest.approx(p["first_contact"]["y_rail_mm"])
    assert row["contact_point"] == "weighted_centre"


def test_profile_file_plausibility_and_its_switch(tmp_path):
    """An upside-down rail file is refused naming the scene key and the switch; accept_unusual_profile reads it."""
    import numpy as np

    from meshes.profiles import get_profile
    from meshes.profiles.io import write_text

    y, z = get_profile("60E1").sample(0.5)
    write_text(tmp_path / "flipped.csv", np.column_stack([y, -np.asarray(z)]))
    scene = _scene()
    scene["profiles"] = {"rail": "flipped.csv"}
    with pytest.raises(InputError, match=r"s.toml: profiles.rail: .*upside down.*accept_unusual_profile"):
        parse_wheel_rail_scene(scene, tmp_path / "s.toml")
    scene["profiles"]["accept_unusual_profile"] = True
    parsed = parse_wheel_rail_scene(scene, tmp_path / "s.toml")
    assert parsed.profiles.accept_unusual_profile and parsed.rail_profile.name == "flipped"


def test_missing_reference_file_names_where_it_was_looked_for(tmp_path, monkeypatch):
    monkeypatch.setenv("WRLAYER_REFERENCE", str(tmp_path / "ref"))
    scene = _scene(sweep={"csv": "reference:none.csv"})
    with pytest.raises(InputError, match=r"sweep.csv: 'reference:none.csv': not found in the reference folder "
                                         r"\$WRLAYER_REFERENCE = "):
        parse_wheel_rail_scene(scene, tmp_path / "s.toml")
