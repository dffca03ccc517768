"""The contact table for multibody codes (``output.contact_table``): its columns, its values against result.json,
Kalker's linear coefficients against FASTSIM, the same table from 2 worker processes as from one, and the failed
cases listed (exit 4)."""

import csv
import dataclasses
import json
import math

import pytest

from contact.__main__ import main
from contact.scenes.cost import wheel_rail_cost
from contact.wheel_rail.contact_table import (FAILED_COLUMNS, FAILED_FILE, TABLE_COLUMNS, TABLE_FILE, table_csv,
                                              table_rows)
from contact.wheel_rail.parse import load_wheel_rail_scene
from contact.run_files import run_wheel_rail_scene
from contact.wheel_rail.scene import RunSpec
from meshes.profiles import S1002, Rail60E1
from wrlayer.errors import InputError

#: Four cases of both wheels; the last one (lateral 25 mm) pushes the right flange through the rail and fails.
SCENE = """type = "wheel_rail"
[wheel]
side = "both"
[wheelset]
roll_rad = "auto"
[material]
G_MPa = 82000.0
poisson = 0.28
[sweep]
lateral_mm = [0.0, 3.0, 6.0, 25.0]
yaw_rad = [0.0, 0.002, 0.004, 0.0]
[method]
normal = "kik_piotrowski"   # FASTSIM on KP's semi-elliptic strips is the equivalent ellipse's linear theory
[output]
contact_table = true
vtk = false
"""


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The sweep solved in this process and by 2 worker processes: {workers: (exit code, out folder)}."""
    out = {}
    for workers in (1, 2):
        folder = tmp_path_factory.mktemp(f"workers{workers}")
        scene = folder / "table.toml"
        scene.write_text(SCENE + f"[run]\nworkers = {workers}\n", encoding="utf-8")
        out[workers] = (main(["simulate", str(scene), "--out", str(folder / "out")]), folder / "out")
    return out


def _rows(path):
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def test_the_table_has_the_documented_columns_and_one_row_per_wheel_and_patch(runs):
    code, out = runs[1]
    assert code == 4
    with open(out / TABLE_FILE, encoding="utf-8") as fh:
        assert tuple(next(csv.reader(fh))) == TABLE_COLUMNS
    result = json.loads((out / "result.json").read_text())
    n = sum(w["n_patches"] for c in result["cases"] if "wheels" in c for w in c["wheels"].values())
    rows = _rows(out / TABLE_FILE)
    assert len(rows) == n >= 6 and {r["side"] for r in rows} == {"right", "left"}
    assert {r["case"] for r in rows} == {"0", "1", "2"}


def test_the_values_are_the_sweeps_result_json_values(runs):
    _, out = runs[1]
    result = json.loads((out / "result.json").read_text())
    rail, wheel = Rail60E1(), S1002()
    same = {"y_rail_mm": "y_rail_mm", "y_wheel_mm": "y_wheel_mm", "Y_track_mm": "Y_track_mm",
            "Z_track_mm": "Z_track_mm", "contact_angle_rad": "contact_angle_rad", "rolling_radius_mm":
            "wheel_radius_mm", "normal_force_N": "normal_force_N", "area_mm2": "area_mm2", "creepage_x":
            "creepage_x", "creepage_y": "creepage_y", "spin_per_mm": "spin_per_mm", "Fx_N": "Fx_N", "Fy_N": "Fy_N",
            "Mz_Nmm": "Mz_Nmm"}
    for row in _rows(out / TABLE_FILE):
        case = result["cases"][int(row["case"])]
        for key in ("lateral_mm", "yaw_rad", "roll_rad", "pitch_rate_rad_s", "vertical_load_N", "speed_mm_s"):
            assert float(row[key]) == pytest.approx(case[key], rel=1e-9, abs=1e-15)
        w = case["wheels"][row["side"]]
        p = w["patches"][int(row["patch"])]
        assert int(row["n_patches"]) == w["n_patches"]
        for column, key in same.items():
            assert float(row[column]) == pytest.approx(p[key], rel=1e-9, abs=1e-15), column
        assert float(row["z_rail_mm"]) == pytest.approx(float(rail.z(p["y_rail_mm"])), rel=1e-9, abs=1e-12)
        assert float(row["z_wheel_mm"]) == pytest.approx(float(wheel.z(p["y_wheel_mm"])), rel=1e-9, abs=1e-12)
        # the equivalent ellipse keeps the area and the length/width ratio (FASTSIM's, Kik & Piotrowski 2008)
        a, b = float(row["a_mm"]), float(row["b_mm"])
        assert math.pi * a * b == pytest.approx(p["area_mm2"], rel=1e-9)
        assert a / b == pytest.approx(p["length_mm"] / p["width_mm"], rel=1e-9)
        G = 82000.0
        assert float(row["f11_N"]) == pytest.approx(G * a * b * float(row["C11"]), rel=1e-8)
        assert float(row["f23_Nmm"]) == pytest.approx(G * (a * b) ** 1.5 * float(row["C23"]), rel=1e-8)


def test_linear_spin_coefficient_gives_fastsims_lateral_force_at_small_spin(runs):
    """Centred wheelset (case 0): no lateral creepage, a small spin; FASTSIM's Fy is the linear -f23 phi."""
    _, out = runs[1]
    row = next(r for r in _rows(out / TABLE_FILE) if r["case"] == "0" and r["side"] == "right")
    assert float(row["creepage_y"]) == 0.0 and abs(float(row["spin_per_mm"])) > 1e-5
    linear = -float(row["f23_Nmm"]) * float(row["spin_per_mm"])
    assert float(row["Fy_N"]) == pytest.approx(linear, rel=0.02)


def test_two_workers_give_the_same_table_and_results_as_one(runs):
    (code1, out1), (code2, out2) = runs[1], runs[2]
    assert code1 == code2 == 4
    assert (out2 / TABLE_FILE).read_text() == (out1 / TABLE_FILE).read_text()  # bit-identical
    assert (out2 / FAILED_FILE).read_text() == (out1 / FAILED_FILE).read_text()
    r1, r2 = (json.loads((o / "result.json").read_text()) for o in (out1, out2))
    for c1, c2 in zip(r1["cases"], r2["cases"], strict=True):
        c1.pop("time_s"), c2.pop("time_s")
        assert c1 == c2


def test_failed_cases_are_listed_beside_the_table(runs):
    _, out = runs[1]
    failed = _rows(out / FAILED_FILE)
    assert tuple(failed[0]) == FAILED_COLUMNS
    assert [(r["case"], r["lateral_mm"]) for r in failed] == [("3", "25")]
    assert failed[0]["error"] and failed[0]["wheel"] in ("right", "left", "wheelset")


def test_no_failed_list_without_failures_and_frictional_csvs_on_request(tmp_path, runs):
    scene = tmp_path / "ok.toml"
    scene.write_text(SCENE.replace("25.0]", "1.0]") + "frictional_csv = false\n", encoding="utf-8")
    out = tmp_path / "out"
    assert main(["simulate", str(scene), "--out", str(out)]) == 0
    assert (out / TABLE_FILE).is_file() and not (out / FAILED_FILE).exists()
    assert not list(out.glob("frictional_*")) and json.loads((out / "result.json").read_text())[
        "frictional_outputs"] == []
    assert sorted(p.name for p in runs[1][1].glob("frictional_*")) == ["frictional_cells.csv",
                                                                       "frictional_strips.csv"]


@pytest.mark.parametrize("text, key", [("[run]\nworkers = 0\n", "run.workers"),
                                       ("[run]\nworkers = 1.5\n", "run.workers"),
                                       ("[run]\nscheduler = \"http://host:8786\"\n", "run.scheduler"),
                                       ("[run]\nthreads = 2\n", "run.threads"),
                                       ("[output]\ncontact_table = \"yes\"\n", "output.contact_table")])
def test_bad_run_and_output_keys_name_the_key(tmp_path, text, key):
    scene = tmp_path / "bad.toml"
    scene.write_text('type = "wheel_rail"\n' + text, encoding="utf-8")
    with pytest.raises(InputError, match=f"bad.toml: {key}"):
        load_wheel_rail_scene(scene)


def test_run_defaults_to_one_process():
    assert not RunSpec().parallel and RunSpec(workers=2).parallel and RunSpec(scheduler="tcp://h:1").parallel


def test_a_dask_cluster_gives_the_same_table(runs, tmp_path):
    """The cases on a Dask cluster (the runner's scheduler mode; an in-process cluster here)."""
    distributed = pytest.importorskip("distributed")
    _, out1 = runs[1]
    scene = load_wheel_rail_scene(out1.parent / "table.toml")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cl:
        scene = dataclasses.replace(scene, run=RunSpec(scheduler=cl.scheduler_address))
        result = run_wheel_rail_scene(scene, tmp_path, plots=False, vtk=False)
    assert result.n_failed == 1
    assert table_csv(table_rows(result, scene)) == (out1 / TABLE_FILE).read_text()


def test_the_cost_estimate_shares_the_cases_among_the_workers():
    scene = load_wheel_rail_scene("scenes/wheel_rail_sweep_elastic.toml")
    one = wheel_rail_cost(scene)
    two = wheel_rail_cost(dataclasses.replace(scene, run=RunSpec(workers=2)))
    assert two.seconds == pytest.approx(one.seconds / 2) and "on 2 worker(s)" in two.describe()


def test_simulate_workers_flag_gives_the_serial_numbers(tmp_path, capsys):
    serial, parallel = tmp_path / "serial", tmp_path / "parallel"
    scene = "scenes/wheel_rail_sweep_elastic.toml"
    assert main(["simulate", scene, "--out", str(serial), "--no-vtk"]) == 0
    assert main(["simulate", scene, "--out", str(parallel), "--no-vtk", "--workers", "2"]) == 0
    rows = [[{k: v for k, v in r.items() if k != "time_s"} for r in csv.DictReader(open(d / "cases.csv"))]
            for d in (serial, parallel)]
    assert rows[0] and rows[0] == rows[1]
    assert main(["simulate", scene, "--out", str(tmp_path / "bad"), "--workers", "0"]) == 2
    assert "error: --workers: must be >= 1" in capsys.readouterr().err
