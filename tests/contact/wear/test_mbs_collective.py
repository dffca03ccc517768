"""A load collective from a multibody export: weights, the merging rule, strict reading (exit 2, one line naming
the file and the row) and a wear run that takes the shipped example export."""

import dataclasses
import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from contact.__main__ import main
from contact.scenes.sections import TangentialSpec
from contact.wear.mbs_collective import BIN_WIDTHS, MbsCollective, merge_cells, read_mbs_collective, sample_weights
from contact.wear.scene import parse_wear_scene
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.sections import WheelLoadSpec
from contact.wheel_rail.solve import solve_wheel
from contact.wheel_rail.track_geometry import WheelsetPose
from meshes.profiles import Rail60E1, S1002
from wrlayer.errors import InputError

REPO = Path(__file__).resolve().parents[3]
EXPORT = REPO / "scenes" / "wear" / "mbs_curve_export.csv"
HEADER = "time_s,lateral_mm,yaw_rad,vertical_load_left_N,vertical_load_right_N,speed_mm_s"
CREEP = "creepage_x_right,creepage_y_right,spin_right_1_per_m,creepage_x_left,creepage_y_left,spin_left_1_per_m"


def test_weights_by_distance_and_time_by_hand():
    """Samples at t = 0, 1, 3 s: midpoint intervals 0.5, 1.5, 1.0 s. By time: 0.5/3, 1.5/3, 1/3. By distance at
    speeds 10, 20, 40: 5, 30, 40 -> /75. From distances 0, 10, 30 m at the same speeds, by time: 0.5, 0.75,
    0.25 s -> /1.5."""
    t, v = np.array([0.0, 1.0, 3.0]), np.array([10.0, 20.0, 40.0])
    assert sample_weights(t, v, "time_s", "time") == pytest.approx([0.5 / 3, 1.5 / 3, 1.0 / 3])
    assert sample_weights(t, v, "time_s", "distance") == pytest.approx([5 / 75, 30 / 75, 40 / 75])
    s = np.array([0.0, 10.0, 30.0])
    assert sample_weights(s, v, "distance_m", "time") == pytest.approx([0.5 / 1.5, 0.75 / 1.5, 0.25 / 1.5])
    assert sample_weights(s, v, "distance_m", "distance") == pytest.approx([5 / 30, 15 / 30, 10 / 30])


def test_merging_rule_by_hand():
    """Lateral 0.0, 0.1 (same 0.25 mm cell), 1.0 (another): two cells, weighted means; with max_conditions = 1 the
    widths grow until one cell holds all."""
    values = {"lateral_mm": np.array([0.0, 0.1, 1.0]), "yaw_rad": np.zeros(3), "curvature_1_per_m": np.zeros(3),
              "speed_mm_s": np.array([10.0, 20.0, 30.0])}
    w = np.array([0.2, 0.6, 0.2])
    (w0, m0, n0), (w1, m1, n1) = merge_cells(values, w, 5)
    assert (w0, n0, w1, n1) == pytest.approx((0.8, 2, 0.2, 1))
    assert m0["lateral_mm"] == pytest.approx((0.2 * 0.0 + 0.6 * 0.1) / 0.8)
    assert m0["speed_mm_s"] == pytest.approx((0.2 * 10 + 0.6 * 20) / 0.8)
    assert m1["lateral_mm"] == 1.0
    ((w_all, m_all, n_all),) = merge_cells(values, w, 1)
    assert (w_all, n_all) == (pytest.approx(1.0), 3) and m_all["lateral_mm"] == pytest.approx(0.26)
    assert BIN_WIDTHS[0] == 0.25


def test_shipped_export_merges_into_at_most_max_conditions():
    """The shipped export: 301 samples; weights sum to 1; the curve part (curvature 1/600, 5 mm, 2.1 mrad, outer
    right wheel loaded 3 % more) is the heaviest condition: half the distance (15 s of 30 s at constant speed)
    plus the samples of the transition's end in its cell."""
    for n in (1, 3, 6, 20):
        conds, table = read_mbs_collective(MbsCollective(EXPORT.name, max_conditions=n), EXPORT.parent, "x",
                                           460.0)
        assert 1 <= len(conds) <= n and sum(c.weight for c in conds) == pytest.approx(1.0, abs=1e-12)
        assert table.values.shape[0] == 301
    heavy = max(conds, key=lambda c: c.weight)
    assert heavy.curvature_1_per_m == pytest.approx(1 / 600.0, rel=0.02) and heavy.lateral_mm == pytest.approx(5.0,
                                                                                                             abs=0.05)
    assert heavy.vertical_load_right_N == pytest.approx(61800.0, rel=0.01) and heavy.load_on("left") < 60000.0
    assert 0.5 <= heavy.weight < 0.6


def test_longitudinal_creepage_gives_the_pitch_rate(tmp_path):
    """omega = V (1 - xi) / r0: xi = -0.002 (traction) at V = 20000 mm/s, r0 = 460 mm."""
    f = tmp_path / "e.csv"
    f.write_text(f"{HEADER},longitudinal_creepage\n0,0,0,50000,50000,20000,-0.002\n1,0,0,50000,50000,20000,-0.002\n")
    (c,), _ = read_mbs_collective(MbsCollective(f.name), tmp_path, "e.csv", 460.0)
    assert c.pitch_rate_rad_s == pytest.approx(20000.0 * 1.002 / 460.0)


@pytest.mark.parametrize("text, match", [
    (f"{HEADER}\n0,0,0,5e4,5e4,2e4\n1,0,0,5e4,oops,2e4\n", "row 2, column vertical_load_right_N: not a number"),
    (f"{HEADER}\n0,0,0,5e4,5e4,2e4\n1,0,0,5e4,5e4\n", "row 2 has 5 fields, the header 6"),
    (f"{HEADER}\n0,0,0,5e4,5e4,2e4\n0,0,0,5e4,5e4,2e4\n", "row 2, column time_s: must increase strictly"),
    (f"{HEADER}\n0,0,0,5e4,-1,2e4\n1,0,0,5e4,5e4,2e4\n", "row 1, column vertical_load_right_N: must be > 0"),
    (f"{HEADER}\n0,0,0.3,5e4,5e4,2e4\n", r"row 1, column yaw_rad: \|yaw\| must be < 0.2"),
    (f"{HEADER},distance_m\n0,0,0,5e4,5e4,2e4,0\n", "exactly one of the columns time_s, distance_m"),
    ("time_s,lateral_mm,yaw_rad,speed_mm_s\n0,0,0,2e4\n", "missing column.s. vertical_load_left_N"),
    (f"{HEADER},lateral_m\n0,0,0,5e4,5e4,2e4,0\n", "unknown column 'lateral_m'"),
    (f"{HEADER},curvature_1_per_m\n0,0,0,5e4,5e4,2e4,0.5\n", "row 1, column curvature_1_per_m"),
    (f"{HEADER},{CREEP}\n0,0,0,5e4,5e4,2e4,0.3,0,0,-0.3,0,0\n1,0,0,5e4,5e4,2e4,0.3,2.0,0,-0.3,0,0\n",
     r"row 2, column creepage_y_right: \|creepage\| must be < 0.5 \(a fraction, not per cent\)"),
    (f"{HEADER},{CREEP}\n0,0,0,5e4,5e4,2e4,0,0,0,0,0,40\n", r"row 1, column spin_left_1_per_m: \|spin\| must be <= 5"),
    (f"{HEADER},creepage_x_right\n0,0,0,5e4,5e4,2e4,0\n", "all six or none: missing creepage_y_right"),
])
def test_bad_exports_exit_2_with_one_line_naming_file_and_row(text, match, tmp_path, wear_dict, write_scene, capsys):
    (tmp_path / "export.csv").write_text(text)
    path = write_scene(wear_dict(collective=None))
    path.write_text(path.read_text() + '\n[collective]\ncsv = "export.csv"\n')
    assert main(["wear", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("error: w.toml: collective.csv (export.csv): "), err
    assert re.search(match, err), err


@pytest.mark.parametrize("keys, match", [('weight_by = "mileage"', "weight_by: must be one of distance, time"),
                                         ("max_conditions = 0", "max_conditions"),
                                         ('lateral_mm = [1.0]', "unknown key")])
def test_bad_collective_keys(keys, match, tmp_path, wear_dict):
    shutil.copy(EXPORT, tmp_path / EXPORT.name)
    data = wear_dict()
    data["collective"] = dict(csv=EXPORT.name, **{k.split(" = ")[0]: json.loads(k.split(" = ")[1]) for k in [keys]})
    with pytest.raises(InputError, match=match):
        parse_wear_scene(data, tmp_path / "w.toml")


def test_wear_run_takes_the_shipped_export(tmp_path, wear_dict, write_scene):
    """A short run (one side, 2 merged conditions, no layers) on the shipped export completes; result.json records
    the export's file and SHA-256 and the merged conditions with their per-wheel loads and curvature."""
    shutil.copy(EXPORT, tmp_path / EXPORT.name)
    path = write_scene(wear_dict(collective=None, layers=None,
                                 wear={"distance_km": 20.0, "steps": 1, "inelastic": False}))
    path.write_text(path.read_text() + f'\n[collective]\ncsv = "{EXPORT.name}"\nmax_conditions = 2\n')
    out = tmp_path / "out"
    assert main(["wear", str(path), "--out", str(out), "--quiet", "--no-plots"]) == 0
    res = json.loads((out / "result.json").read_text())
    assert res["status"] == "complete"
    src = res["inputs"]["collective_source"]
    assert src["file"].endswith(EXPORT.name) and len(src["sha256"]) == 64
    conds = res["inputs"]["conditions"]
    assert len(conds) == 2 and sum(c["weight"] for c in conds) == pytest.approx(1.0)
    assert max(c["curvature_1_per_m"] for c in conds) > 1e-3
    assert all(c["vertical_load_right_N"] > 0 and c["vertical_load_left_N"] > 0 for c in conds)
    wear = res["steps"][0]["bodies"]
    assert all(b["wear_max_mm"] > 0 for b in wear)


def test_export_creepages_replace_the_kinematic_ones(tmp_path):
    """Per-wheel creepages of an export: merged as weighted means (equal weights here: samples 1 s apart at one
    speed), the spin converted from 1/m to 1/mm; the solver uses them at the patch instead of the kinematics and
    result.json says so; without the columns nothing changes (the kinematic creepages of the position)."""
    f = tmp_path / "e.csv"
    f.write_text(f"{HEADER},{CREEP}\n0,2,0,5e4,5e4,2e4,-0.001,0.002,-0.1,0.001,0.0,0.1\n"
                 "1,2,0,5e4,5e4,2e4,-0.003,0.004,-0.3,0.003,0.0,0.3\n")
    (c,), _ = read_mbs_collective(MbsCollective(f.name), tmp_path, "e.csv", 460.0)
    assert c.creepages_right == pytest.approx((-0.002, 0.003, -0.2e-3))
    assert c.creepages_left == pytest.approx((0.002, 0.0, 0.2e-3))
    inputs = WheelRailInputs(load=WheelLoadSpec(5e4, 2e4), tangential=TangentialSpec(0.3),
                             pose=WheelsetPose(2.0, 0.0, 0.0), creepages=c.creepages_right)
    patch = solve_wheel(Rail60E1(), S1002(), inputs).patches[0]
    assert (patch.kinematics.vx, patch.kinematics.vy, patch.kinematics.phi_per_mm) == pytest.approx(c.creepages_right)
    assert patch.Fx_N > 0 and patch.Fy_N < 0                       # Kalker: the force opposes the creepage
    kinematic = solve_wheel(Rail60E1(), S1002(), dataclasses.replace(inputs, creepages=None)).patches[0]
    assert kinematic.kinematics.vx != pytest.approx(-0.002, abs=1e-4) and kinematic.kinematics.vy == 0.0


def test_wear_run_records_export_creepages(tmp_path, wear_dict, write_scene):
    f = tmp_path / "e.csv"
    f.write_text(f"{HEADER},{CREEP}\n0,2,0,5e4,5e4,2e4,-0.001,0.002,-0.1,0.001,0.0,0.1\n"
                 "1,2,0,5e4,5e4,2e4,-0.001,0.002,-0.1,0.001,0.0,0.1\n")
    path = write_scene(wear_dict(collective=None, layers=None, wear={"distance_km": 1.0, "steps": 1,
                                                                     "inelastic": False}))
    path.write_text(path.read_text() + '\n[collective]\ncsv = "e.csv"\n')
    out = tmp_path / "out"
    assert main(["wear", str(path), "--out", str(out), "--quiet", "--no-plots"]) == 0
    res = json.loads((out / "result.json").read_text())
    assert res["inputs"]["collective_source"]["creepages"] == "export"
    assert res["inputs"]["conditions"][0]["creepages_right"] == pytest.approx([-0.001, 0.002, -0.1e-3])
    (patch,) = res["steps"][0]["conditions"][0]["patches"]
    assert (patch["creepage_x"], patch["creepage_y"], patch["spin_per_mm"]) == pytest.approx((-0.001, 0.002, -1e-4))
