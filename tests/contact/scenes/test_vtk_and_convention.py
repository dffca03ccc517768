"""Contact fields for ParaView (vtk/contact_fields.pvd, read back with meshio and pyvista) and CONTACT's sign
convention as an output (contact_convention.csv, checked on Manchester A-2.2's left wheel)."""

import csv
import dataclasses
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

from contact.__main__ import main
from contact.scenes.vtk_output import CELL_FIELDS, PVD_FILE, VTK_DIR
from contact.wheel_rail.parse import load_wheel_rail_scene
from contact.run_files import run_wheel_rail_scene
from benchmarks.bench_manchester import contact_reference

ROOT = Path(__file__).resolve().parents[3]
SCENES = ROOT / "scenes"


def _datasets(pvd: Path) -> list[dict]:
    return [d.attrib for d in ET.parse(pvd).getroot().iter("DataSet")]


def test_layered_scene_writes_a_series_over_passes(tmp_path):
    out = tmp_path / "out"
    assert main(["simulate", str(SCENES / "paper_hardening.toml"), "--out", str(out)]) == 0
    pvd = out / VTK_DIR / PVD_FILE
    sets = _datasets(pvd)
    steps = sorted({int(d["timestep"]) for d in sets})
    assert steps == list(range(1, len(steps) + 1)) and len(steps) > 1
    mesh = meshio.read(pvd.parent / sets[0]["file"])
    assert set(CELL_FIELDS) <= set(mesh.cell_data) and mesh.cells[0].type == "quad"
    p = mesh.cell_data["pressure_MPa"][0]
    state = mesh.cell_data["contact_state"][0]
    assert p.max() > 1000 and set(np.unique(state)) == {0, 1, 2}   # outside, adhesion and slip cells
    assert mesh.cell_data["traction_MPa"][0].shape[1] == 3
    assert np.nanmax(mesh.cell_data["slip_velocity_mm_s"][0]) > 0
    assert mesh.cell_data["residual_pass_mm"][0].max() > 0        # the first pass leaves a residual dent
    pv = pytest.importorskip("pyvista")
    reader = pv.get_reader(str(pvd))
    assert len(reader.time_values) == len(steps)
    block = reader.read()
    assert block.n_blocks >= 1 and "pressure_MPa" in block[0].cell_data


def test_no_vtk_flag_and_key(tmp_path):
    out = tmp_path / "a"
    assert main(["simulate", str(SCENES / "paper_no_layer.toml"), "--out", str(out), "--no-vtk"]) == 0
    assert not (out / VTK_DIR).exists()
    text = (SCENES / "paper_no_layer.toml").read_text(encoding="utf-8")
    scene = tmp_path / "s.toml"
    scene.write_text(text + "\n[output]\nvtk = false\nconvention = \"contact\"\n", encoding="utf-8")
    assert main(["simulate", str(scene), "--out", str(tmp_path / "b")]) == 0
    assert not (tmp_path / "b" / VTK_DIR).exists()
    rows = list(csv.DictReader((tmp_path / "b" / "contact_convention.csv").open()))
    assert float(rows[0]["cksi"]) == pytest.approx(-0.002) and float(rows[0]["cphi_per_mm"]) == pytest.approx(-0.0012)
    assert float(rows[0]["fx_N"]) > 0      # wrlayer's Fx < 0 on the wheel: CONTACT's on the rail > 0


def test_contact_convention_on_a22_left_wheel(tmp_path):
    """A-2.2, left wheel, a tread case (1) and a flange case (15): CONTACT's signs and mirrored coordinates agree
    with CONTACT's own output (positions within 0.5 mm, FN within 2 %, creep forces in sign and within 0.1 mu FN)."""
    scene = load_wheel_rail_scene(SCENES / "manchester_a22.toml")
    keep = (0, 14)
    scene = dataclasses.replace(scene, sweep=dataclasses.replace(scene.sweep, cases=tuple(
        scene.cases[k] for k in keep)), output=dataclasses.replace(scene.output, convention="contact"))
    result = run_wheel_rail_scene(scene, tmp_path, plots=False, vtk=True)
    sets = _datasets(tmp_path / VTK_DIR / PVD_FILE)
    assert {int(d["timestep"]) for d in sets} == {0, 1}
    rows = [r for r in csv.DictReader((tmp_path / "contact_convention.csv").open()) if r["wheel"] == "left"]
    ref = contact_reference()
    for r in rows:
        case = int(r["case"])
        ours = result.cases[case].wheels["left"].patches[int(r["patch"])]
        assert float(r["ycp_r_mm"]) == pytest.approx(-ours.y_rail_mm)
        assert float(r["fx_N"]) == pytest.approx(-ours.Fx_N) and float(r["fs_N"]) == pytest.approx(-ours.Fy_N)
        theirs = max(ref[("left", keep[case] + 1)], key=lambda p: p["fn_N"])
        if float(r["fn_N"]) < 0.5 * theirs["fn_N"]:
            continue
        assert float(r["ycp_r_mm"]) == pytest.approx(theirs["ycp_r_mm"], abs=0.5)
        assert float(r["deltcp_rad"]) == pytest.approx(theirs["deltcp_rad"], abs=0.02)
        assert float(r["fn_N"]) == pytest.approx(theirs["fn_N"], rel=0.02)
        for key in ("fx_N", "fs_N"):
            assert abs(float(r[key]) - theirs[key]) < 0.1 * 0.3 * theirs["fn_N"]
        assert float(r["cksi"]) == pytest.approx(theirs["cksi"], abs=4e-4)
