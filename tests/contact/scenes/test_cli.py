"""``python -m contact simulate`` / ``simulate-all``: result JSON contents, pictures, Table 1, per-body calibration
tables, atomic output. Most runs are in-process (fast); one goes through the real command line."""

import csv
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from contact.__main__ import main
from wrlayer.characteristic import Characteristic
from wrlayer.layer_table import FORMAT, FORMAT_VERSION, LayerTable
from contact.scenes.scene import load_scene

SCENES = Path(__file__).resolve().parents[3] / "scenes"
BAD = Path(__file__).resolve().parents[2] / "inputs" / "bad_scenes"
PASS_KEYS = ("length_mm", "width_mm", "area_mm2", "delta_mm", "p_max_MPa", "Fx_N", "Fy_N", "WT_max_N_per_mm",
             "PT_max_W_per_mm2", "u0_mm", "up0_mm", "elastic")


def run(scene: Path, out: Path, *extra) -> dict:
    assert main(["simulate", str(scene), "--out", str(out), *extra]) == 0
    return json.loads((out / "result.json").read_text())


@pytest.fixture(scope="module")
def paper(tmp_path_factory):
    """The three paper scenes, run once for the module."""
    base = tmp_path_factory.mktemp("paper")
    return {name: run(SCENES / f"paper_{name}.toml", base / name) for name in ("no_layer", "with_layer", "shakedown")}


def test_result_has_the_documented_fields(paper):
    for result in paper.values():
        assert {"inputs", "code_version", "units", "passes", "shakedown_pass", "solver"} <= set(result)
        assert result["code_version"] and "WT_max_N_per_mm" in result["units"]
        assert len(result["inputs"]["content_sha256"]) == 64
        assert result["inputs"]["scene_file"].endswith(".toml")
        for p in result["passes"]:
            assert set(PASS_KEYS) <= set(p)
            assert p["normal_force_N"] == pytest.approx(100e3, rel=1e-8)
            assert p["Fx_N"] == pytest.approx(sum(q["Fx_N"] for q in p["patches"]))
            assert abs(np.hypot(p["Fx_N"], p["Fy_N"])) <= 0.3 * 100e3 * (1 + 1e-9)  # Coulomb bound mu N
            assert p["WT_max_N_per_mm"] > 0 and p["PT_max_W_per_mm2"] > 0


def test_layer_trends_of_table_1(paper):
    """The paper's trends: the layer enlarges the patch, lowers p_max, increases delta; shakedown enlarges the area
    further and brings p_max down to the elastic limit p_2."""
    no, layer, sd = (paper[k]["passes"] for k in ("no_layer", "with_layer", "shakedown"))
    assert layer[0]["area_mm2"] > no[0]["area_mm2"] and layer[0]["delta_mm"] > no[0]["delta_mm"]
    assert layer[0]["p_max_MPa"] < no[0]["p_max_MPa"]
    assert sd[-1]["area_mm2"] > sd[0]["area_mm2"] and sd[-1]["p_max_MPa"] < sd[0]["p_max_MPa"]
    assert sd[-1]["p_max_MPa"] == pytest.approx(1190.0, rel=0.01)
    dev = paper["shakedown"]["reference_deviation"]
    assert dev["p_max_rel"] == pytest.approx((sd[-1]["p_max_MPa"] - 1190.0) / 1190.0)
    assert dev["passes_rel"] == pytest.approx((len(sd) - 19) / 19)
    assert np.all(np.diff([p["area_mm2"] for p in sd]) > 0)
    for key in ("length_mm", "width_mm", "area_mm2", "delta_mm", "p_max_MPa", "u0_mm", "up0_mm"):
        assert sd[0][key] == pytest.approx(layer[0][key], rel=1e-12)  # pass 1 of both scenes is the same


def test_layer_numbers_follow_the_characteristic(paper):
    """u0 lies on the characteristic at p_0, up0 is eq. (8) (virgin element, p_0 <= 2 p_2), passes agree."""
    ch = Characteristic.from_dict(paper["with_layer"]["inputs"]["layers"]["combined"])
    first = paper["with_layer"]["passes"][0]
    assert not first["elastic"]
    assert first["u0_mm"] == pytest.approx(float(ch.displacement(first["p_max_MPa"])), rel=1e-9)
    assert first["up0_mm"] == pytest.approx(float(ch.residual_displacement(first["p_max_MPa"])), rel=1e-9)
    assert paper["with_layer"]["shakedown_pass"] is None  # one pass, not elastic
    assert paper["no_layer"]["shakedown_pass"] is None and paper["no_layer"]["passes"][0]["u0_mm"] == 0.0
    sd = paper["shakedown"]
    assert sd["shakedown_pass"] == len(sd["passes"]) < load_scene(SCENES / "paper_shakedown.toml").passes.max
    assert sd["passes"][-1]["up_max_mm"] <= 1e-4 and sd["passes"][-2]["up_max_mm"] > 1e-4
    grid = sd["strip_grid"]
    after = np.array(grid["separation_after_mm"]) - np.array(grid["separation_before_mm"])
    np.testing.assert_allclose(after - after.min(), np.array(grid["residual_mm"]["combined"]) - min(
        grid["residual_mm"]["combined"]), atol=1e-12)  # the dents are what changed the separation


def test_no_creepage_means_no_tangential_solution(tmp_path):
    result = run(SCENES / "hertz_check.toml", tmp_path / "hertz")
    p = result["passes"][0]
    assert (p["Fx_N"], p["Fy_N"], p["WT_max_N_per_mm"], p["PT_max_W_per_mm2"]) == (0.0, 0.0, None, None)
    assert result["method"]["tangential"] is None and result["method"]["layer"] is None
    assert result["shakedown_pass"] is None and p["elastic"]


def test_two_patches(tmp_path):
    result = run(SCENES / "two_patches.toml", tmp_path / "two")
    p = result["passes"][0]
    assert p["n_patches"] == 2
    a, b = p["patches"]
    assert a["y_max_mm"] < b["y_min_mm"]
    assert a["normal_force_N"] + b["normal_force_N"] == pytest.approx(60e3, rel=1e-8)
    assert p["area_mm2"] == pytest.approx(a["area_mm2"] + b["area_mm2"])
    assert p["Fy_N"] == pytest.approx(a["Fy_N"] + b["Fy_N"])


def test_json_flag_prints_the_result_and_plots_are_written(tmp_path, capsys):
    out = tmp_path / "hardening"
    result = run(SCENES / "paper_hardening.toml", out, "--json", "--plots")
    printed = json.loads(capsys.readouterr().out)
    assert printed == result
    names = set(result["pictures"])
    n = len(result["passes"])
    assert names == {"patch_pass1.png", f"patch_pass{n}.png", "separation.png", "shakedown.png"}
    for name in names:
        data = (out / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000
    frictional = {"frictional_strips.csv", "frictional_cells.csv"}  # wear-ready outputs (with creepage)
    assert set(result["frictional_outputs"]) == frictional
    assert sorted(p.name for p in out.iterdir()) == sorted(names | {"result.json", "vtk"} | frictional)
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary folders left
    # strain hardening: the state is kept, so the passes stop adding residual quickly, below p_max of pass 1
    assert 1 < result["shakedown_pass"] == n <= 5 and not result["passes"][0]["shakedown"]
    assert result["passes"][-1]["p_max_MPa"] < result["passes"][0]["p_max_MPa"]


def test_rerun_without_plots_removes_the_old_pictures(tmp_path):
    out = tmp_path / "out"
    first = run(SCENES / "hertz_check.toml", out, "--plots")
    assert set(first["pictures"]) == {"patch_pass1.png", "separation.png"}
    (out / "notes.txt").write_text("user file")
    second = run(SCENES / "hertz_check.toml", out)
    assert "pictures" not in second
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt", "result.json", "vtk"]


def test_rerun_without_tangential_problem_removes_the_old_frictional_csvs(tmp_path):
    out = tmp_path / "out"
    first = run(SCENES / "paper_with_layer.toml", out)
    assert first["frictional_outputs"] == ["frictional_strips.csv", "frictional_cells.csv"]
    assert (out / "frictional_cells.csv").is_file()
    second = run(SCENES / "hertz_check.toml", out)  # no creepage: no frictional CSVs of its own
    assert second["frictional_outputs"] == []
    assert sorted(p.name for p in out.iterdir()) == ["result.json", "vtk"]


def test_failed_run_leaves_the_previous_output_untouched(tmp_path):
    out = tmp_path / "out"
    run(SCENES / "hertz_check.toml", out)
    before = (out / "result.json").read_bytes()
    assert main(["simulate", str(BAD / "negative_friction.toml"), "--out", str(out), "--plots"]) == 2
    assert (out / "result.json").read_bytes() == before
    assert sorted(p.name for p in out.iterdir()) == ["result.json", "vtk"]


def test_simulate_all_table_and_failures(tmp_path, capsys):
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    for name in ("hertz_check", "paper_shakedown"):
        shutil.copy(SCENES / f"{name}.toml", scenes)
    shutil.copy(BAD / "separation_not_function.toml", scenes / "broken.toml")
    out = tmp_path / "out"
    assert main(["simulate-all", str(scenes), "--out", str(out)]) == 1
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    errors = [line for line in lines if not line.startswith("warning: ")]  # the KP scenes' approximate p_max
    assert len(lines) - len(errors) == 2 and all("p_max approximate" in line for line in lines if line not in errors)
    assert errors[0].startswith("error: broken.toml: separation.y_mm")  # the file named once
    assert "1 of 3 scenes failed" in errors[-1] and len(errors) == 2
    assert not (out / "broken").exists()
    assert (out / "hertz_check" / "result.json").is_file()
    md = (out / "table.md").read_text()
    assert md.startswith("| quantity | unit | hertz_check |")
    summary = captured.out[captured.out.index("contact scenes:"):]  # the summary, not the full table
    table_lines = summary[:summary.index("full table")].splitlines()
    assert max(len(line) for line in table_lines) <= 100 and "| quantity |" not in captured.out
    assert f"  {out / 'table.md'}" in summary.splitlines()          # says where the full table is
    rows = list(csv.reader((out / "table.csv").open()))
    header = rows[0]
    n = len(json.loads((out / "paper_shakedown" / "result.json").read_text())["passes"])
    assert header == ["quantity", "unit", "hertz_check", "hertz_check: Hertz", "paper_shakedown (pass 1)",
                      f"paper_shakedown (pass {n})", "paper_shakedown: paper Table 1"]
    assert [r[0] for r in rows[1:]] == ["patch length", "patch width", "area", "approach delta", "F_x", "F_y",
                                        "p_max", "W_T max", "P_T max", "layer u(0) under load",
                                        "residual u_p(0) of the pass"]
    p_max = dict(zip(header, rows[7]))
    assert float(p_max["paper_shakedown: paper Table 1"]) == 1190.0
    last = json.loads((out / "paper_shakedown" / "result.json").read_text())["passes"][-1]
    assert float(p_max[f"paper_shakedown (pass {n})"]) == pytest.approx(last["p_max_MPa"], abs=0.5)


def write_rail_table(path: Path, y_positions, p2_values):
    """A small rail layer table in the calibration format: 3-segment characteristics with p_2 varying in y."""
    positions = []
    for y, p2 in zip(y_positions, p2_values):
        positions.append({"y_mm": y, "characteristic": {"u_mm": [0.0, p2 / 59000.0, p2 / 59000.0 + 0.01, 0.06],
                                                        "p_MPa": [0.0, p2, p2 + 250.0, p2 + 700.0]}})
    data = {"format": FORMAT, "format_version": FORMAT_VERSION, "header": {"body": "rail", "profile": "test"},
            "positions": positions}
    path.write_text(json.dumps(data))


def table_scene(tmp_path, position_mm, table="rail_table.json") -> Path:
    text = (SCENES / "paper_with_layer.toml").read_text()
    layer = text[text.index("[layers.combined]"):text.index("[tangential]")]
    text = text.replace(layer, f'[layers]\nrail = "tables/{table}"\nposition_mm = {{rail = {position_mm}}}\n'
                        "wheel = {u_mm = [0.0, 0.03, 0.06], p_MPa = [0.0, 1500.0, 2000.0]}\n\n")
    text = text[:text.index("[reference]")]
    path = tmp_path / f"table_{position_mm}.toml"
    path.write_text(text)
    return path


def test_per_body_layers_from_a_calibration_table(tmp_path):
    (tmp_path / "tables").mkdir()
    write_rail_table(tmp_path / "tables" / "rail_table.json", [-10.0, 0.0, 10.0], [1100.0, 1200.0, 1300.0])
    result = run(table_scene(tmp_path, 2.0), tmp_path / "ok")
    first = result["passes"][0]
    assert result["method"]["layer"] == ["rail", "wheel"]
    expected = LayerTable.read(tmp_path / "tables" / "rail_table.json").characteristic_at(2.0)  # interpolated
    assert result["inputs"]["layers"]["rail"].endswith("rail_table.json")
    assert result["inputs"]["layers"]["position_mm"] == {"rail": 2.0}
    grid = result["strip_grid"]
    assert set(grid["residual_mm"]) == {"rail", "wheel"}
    assert max(grid["residual_mm"]["rail"]) > 1e-4 and max(grid["residual_mm"]["wheel"]) < 1e-15  # wheel p_2 = 1500
    # wheel + rail in series at the reference point: u0 = u_rail(p0) + u_wheel(p0)
    p0 = first["patches"][0]["p0_MPa"]
    rail = expected
    wheel = Characteristic.from_dict(result["inputs"]["layers"]["wheel"])
    assert first["u0_mm"] == pytest.approx(float(rail.displacement(p0) + wheel.displacement(p0)), rel=1e-6)


def test_table_not_covering_the_contact_location(tmp_path, capsys):
    (tmp_path / "tables").mkdir()
    write_rail_table(tmp_path / "tables" / "rail_table.json", [-10.0, 0.0, 10.0], [1100.0, 1200.0, 1300.0])
    for position, where in ((9.0, "the patch spans"), (12.0, "contact location y = 12")):
        out = tmp_path / f"out{position}"
        assert main(["simulate", str(table_scene(tmp_path, position)), "--out", str(out)]) == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith(f"error: table_{position}.toml: layers.rail: does not cover the contact location")
        assert where in err and "\n" not in err
        assert not out.exists()


def test_real_command_line(tmp_path):
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "contact", "simulate", str(SCENES / "hertz_check.toml"), "--out",
                           str(out), "--json"], capture_output=True, text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout) == json.loads((out / "result.json").read_text())


def test_sigterm_in_simulate_all_says_which_outputs_are_complete(tmp_path, monkeypatch, capsys):
    """SIGTERM while simulate-all runs its second scene: exit 143, one line naming how many scene outputs are
    complete (the first one's folder holds its whole output), not "nothing written"."""
    import os
    import signal

    import contact.run_files as run_files

    scenes = tmp_path / "scenes"
    scenes.mkdir()
    for name in ("a", "b"):
        shutil.copy(SCENES / "hertz_check.toml", scenes / f"{name}.toml")
    real, calls = run_files.run_scene, []

    def killed_in_the_second(path, out_dir, **kw):
        calls.append(path)
        if len(calls) == 2:
            os.kill(os.getpid(), signal.SIGTERM)
        return real(path, out_dir, **kw)

    monkeypatch.setattr(run_files, "run_scene", killed_in_the_second)
    out = tmp_path / "out"
    assert main(["simulate-all", str(scenes), "--out", str(out), "--no-vtk"]) == 143
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == f"error: terminated (SIGTERM); 1 of 2 scene outputs complete in {out}"
    assert len(err) == 2 and err[0].startswith('warning: a.toml: method.normal = "kik_piotrowski": p_max approximate')
    assert json.loads((out / "a" / "result.json").read_text())["inputs"] and not (out / "b").exists()


def test_simulate_prints_the_key_numbers_of_each_pass(tmp_path, capsys):
    result = run(SCENES / "hertz_check.toml", tmp_path / "h", "--no-vtk")
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "hertz_check.toml: 1 pass"
    assert lines[-1] == f"hertz_check.toml: wrote {tmp_path / 'h' / 'result.json'}"
    row = dict(zip(("pass", "p_max", "length", "width", "delta"), lines[2].split()))
    p = result["passes"][0]
    assert (row["p_max"], row["length"], row["delta"]) == (f"{p['p_max_MPa']:.0f}", f"{p['length_mm']:.2f}",
                                                           f"{p['delta_mm']:.6f}")
    assert max(len(line) for line in lines[:-1]) <= 100


def test_result_records_print_short():
    """print(run.first) and the records show scalars and array shapes, not the arrays."""
    from contact.scenes.simulation import simulate

    sim = simulate(load_scene(SCENES / "paper_no_layer.toml"))
    texts = {"first": repr(sim.first), "tangential": repr(sim.first.tangential[0]), "run": repr(sim),
             "result": repr(sim.result), "pass": repr(sim.result.passes[0]),
             "region": repr(sim.result.passes[0].regions[0]), "strip grid": repr(sim.result.strip_grid)}
    for name, text in texts.items():
        assert len(text) < 2000 and "\n" not in text and "[[" not in text, name
    assert "tx_MPa=array((" in texts["tangential"] and "WT_max_N_per_mm=" in texts["tangential"]
    assert "p_max=1869.83 MPa" in texts["first"] and len(sim.first.tangential[0].tx_MPa.ravel()) > 1000
