"""Wear-ready frictional CSVs: consistent with the FASTSIM result (work sums, P_T = 1e-3 V Tgamma/A), written by
both scene types beside result.json."""

import csv
import io

import numpy as np
import pytest

from contact.__main__ import main
from contact.normal.patch import Patch
from contact.tangential.fastsim import Creepage, solve_tangential
from contact.tangential.frictional_outputs import cell_fields, frictional_tables, strip_fields


def _result():
    y = np.arange(-1.5, 1.5001, 0.1)
    xl = 5.0 * np.sqrt(np.clip(1 - (y / 1.6) ** 2, 0.02, None))
    patch = Patch(0.1, y, xl, 800.0 * xl / xl.max())
    return patch, solve_tangential(patch, Creepage(0.002, -0.001, 0.0005), 82000.0, 0.28, 0.3, 3000.0, nx=24)


def test_fields_are_consistent():
    patch, t = _result()
    c = cell_fields(t)
    assert np.allclose(c["work_N_per_mm"].sum(axis=1), t.WT_N_per_mm, rtol=1e-12)
    assert np.allclose(c["PT_W_per_mm2"], 1e-3 * 3000.0 * c["Tgamma_A_N_per_mm2"], rtol=1e-12)
    s = strip_fields(t, patch.x_lead_mm, patch.p_peak_MPa)
    assert np.allclose(s["Tgamma_A_mean_N_per_mm2"] * 2 * patch.x_lead_mm, t.WT_N_per_mm)
    _strips, cells = frictional_tables([({"pass": 1}, t, patch.y_mm, patch.x_lead_mm, patch.p_peak_MPa, {})])
    rows = list(csv.DictReader(io.StringIO(cells)))
    assert len(rows) == patch.n_strips * 24
    total = sum(float(r["work_N_per_mm"]) * float(r["dx_mm"]) * 0.1 for r in rows)
    assert total == pytest.approx(float(np.sum(t.WT_N_per_mm * 0.1 * t.dx_mm)), rel=1e-5)


def test_scenes_write_the_csvs(tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text('type = "wheel_rail"\n[wheel]\nside = "right"\n[method]\ngrid_mm = 0.2\nfastsim_cells = 10\n')
    assert main(["simulate", str(scene), "--out", str(tmp_path / "wr")]) == 0
    text = (tmp_path / "wr" / "frictional_strips.csv").read_text()
    assert "y_wheel_mm" in text and "Tgamma_A_mean_N_per_mm2" in text
    assert (tmp_path / "wr" / "frictional_cells.csv").stat().st_size > 0


def test_coarse_grid_exact_theory_writes_one_row_per_strip(tmp_path):
    """coarse_exact normal with the exact theory (solved on the coarse grid's lines): the CSVs and the VTK files
    carry one row per strip of the patch, tractions included."""
    scene = tmp_path / "s.toml"
    scene.write_text('type = "wheel_rail"\n[wheel]\nside = "right"\n[method]\ngrid_mm = 0.2\n'
                     'normal = "coarse_exact"\ntangential = "exact"\n[output]\nvtk = true\n')
    assert main(["simulate", str(scene), "--out", str(tmp_path / "wr")]) == 0
    rows = list(csv.DictReader(io.StringIO((tmp_path / "wr" / "frictional_strips.csv").read_text())))
    y = [float(r["y_mm"]) for r in rows]
    assert len(rows) > 5 and np.allclose(np.diff(y), 0.2)            # the strips, not the grid's lines
    cells = list(csv.DictReader(io.StringIO((tmp_path / "wr" / "frictional_cells.csv").read_text())))
    assert any(float(r["tx_MPa"]) != 0.0 for r in cells)
    assert list((tmp_path / "wr" / "vtk").glob("*.vtu"))


def test_kik_piotrowski_scene_writes_every_pass(tmp_path):
    from pathlib import Path

    scene = Path(__file__).resolve().parents[3] / "scenes" / "paper_shakedown.toml"
    assert main(["simulate", str(scene), "--out", str(tmp_path / "kp")]) == 0
    import json

    res = json.loads((tmp_path / "kp" / "result.json").read_text())
    rows = list(csv.DictReader(io.StringIO((tmp_path / "kp" / "frictional_strips.csv").read_text())))
    assert {int(r["pass"]) for r in rows} == set(range(1, res["n_passes"] + 1))
    assert res["frictional_outputs"] == ["frictional_strips.csv", "frictional_cells.csv"]


def test_wheel_rail_scene_writes_every_pass(tmp_path):
    from pathlib import Path

    tables = Path(__file__).resolve().parents[3] / "scenes" / "tables"
    scene = tmp_path / "s.toml"
    scene.write_text('type = "wheel_rail"\n[wheel]\nside = "right"\n[load]\nvertical_load_N = 80000.0\n'
                     f'[layers]\nrail = "{tables / "rail_60E1_default.json"}"\n'
                     f'wheel = "{tables / "wheel_S1002_default.json"}"\n'
                     '[passes]\nmax = 3\n[method]\ngrid_mm = 0.2\nfastsim_cells = 10\n'
                     '[wheelset]\nlateral_mm = 2.0\nyaw_rad = 0.002\n')
    assert main(["simulate", str(scene), "--out", str(tmp_path / "wr")]) == 0
    import json

    res = json.loads((tmp_path / "wr" / "result.json").read_text())
    n_passes = len(res["cases"][0]["wheels"]["right"]["patches"][0]["passes"])
    assert n_passes > 1
    rows = list(csv.DictReader(io.StringIO((tmp_path / "wr" / "frictional_strips.csv").read_text())))
    assert {int(r["pass"]) for r in rows if r["patch"] == "0"} == set(range(1, n_passes + 1))


def test_csv_reads_with_numpy_header_names():
    patch, t = _result()
    strips, cells = frictional_tables([({"case": 0, "pass": 1}, t, patch.y_mm, patch.x_lead_mm, patch.p_peak_MPa,
                                        {})])
    arr = np.genfromtxt(io.StringIO(cells), delimiter=",", names=True)
    assert arr.size == patch.n_strips * 24
    assert np.allclose(arr["PT_W_per_mm2"], 1e-3 * 3000.0 * arr["Tgamma_A_N_per_mm2"], rtol=1e-5, atol=1e-12)
