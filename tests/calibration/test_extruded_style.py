"""mesh.style = "extruded" (structured layers along x, docs/calibration.md, "Mesh styles"): the
configuration key, the mesh build_mesh makes with it, and a coarse 3D calibration of one position with it."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from calibration.config import load_config, parse_config
from calibration.hertz.geometry import given_geometry
from calibration.position_mesh import AUTO_EXTRUDED_ASPECT, build_mesh, mesh_style
from calibration.settings import MeshSettings
from calibration.pipeline import run_calibration
from wrlayer.layer_table import LayerTable
from meshes.profiles import get_profile
from wrlayer.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
COARSE = ROOT / "calibration" / "configs" / "test_coarse.toml"
BODY = {"body": "rail", "profile": "60E1", "mate": "S1002", "positions_mm": [0.0]}


@pytest.mark.parametrize("style", ["isotropic", "extruded", "structured", "auto"])
def test_config_accepts_the_styles(style):
    assert parse_config({"mesh": {"style": style}, "bodies": [BODY]}).mesh.style == style


@pytest.mark.parametrize("bad", ["Extruded", "Structured", "", 1, True, ["extruded"]])
def test_config_rejects_other_styles(bad):
    with pytest.raises(InputError) as err:
        parse_config({"mesh": {"style": bad}, "bodies": [BODY]}, "my.toml")
    msg = str(err.value)
    assert "my.toml: mesh.style" in msg
    assert "isotropic, stretched, extruded, structured, auto" in msg or "must be a string" in msg


@pytest.mark.parametrize("bad", [1.5, 0, "3", 101])
def test_config_rejects_bad_x_elements(bad):
    with pytest.raises(InputError) as err:
        parse_config({"mesh": {"x_elements_per_semi_axis": bad}, "bodies": [BODY]}, "my.toml")
    assert "my.toml: mesh.x_elements_per_semi_axis" in str(err.value)


def test_auto_style_follows_the_aspect_ratio():
    rail = get_profile("60E1")
    auto = MeshSettings(style="auto")
    assert mesh_style(given_geometry(rail, 0.0, 7.16, 5.39), auto) == "isotropic"
    assert mesh_style(given_geometry(rail, 0.0, AUTO_EXTRUDED_ASPECT * 2.0, 2.0), auto) == "extruded"
    assert mesh_style(given_geometry(rail, 0.0, 8.0, 2.0), MeshSettings(style="isotropic")) == "isotropic"


def test_build_mesh_extruded_has_layers_of_a_over_n():
    rail = get_profile("60E1")
    geo = given_geometry(rail, 0.0, 8.0, 2.0)  # elongated: a/b = 4
    mesh = build_mesh(rail, geo, "3d", MeshSettings(elements_per_semi_axis=2, h_max_mm=12.0, style="extruded"))
    x = mesh.p[0, :mesh.nvertices]
    planes = np.linspace(0.0, 1.2 * 8.0, 3 + 1)  # core 1.2 a in ceil(1.2 n) = 3 layers of <= a / n = 4 mm
    core = x <= planes[-1] + 1e-9
    assert np.min(np.abs(x[core][:, None] - planes[None, :]), axis=1).max() < 1e-9
    with pytest.raises(InputError):
        build_mesh(rail, geo, "3d", MeshSettings(style="layers"))


def test_coarse_calibration_with_the_extruded_style(tmp_path):
    cfg = load_config(COARSE)
    cfg = dataclasses.replace(cfg, mesh=dataclasses.replace(cfg.mesh, style="extruded"))
    summary = run_calibration(cfg, tmp_path, show_progress=False, log=lambda *a, **k: None)
    assert summary["failed"] == [] and summary["positions_computed"] == 1
    pos = LayerTable.read(tmp_path / "rail_layer_table.json").positions[0]
    # half-space first yield at p0 = 1.62 Y for a/b ~ 1.33 (as tests/calibration/test_pipeline.py), within 5 %
    assert pos["first_yield_fem_MPa"] == pytest.approx(1.62 * cfg.bodies[0].material.yield_MPa, rel=0.05)
    assert all(r > 0 for r in pos["residual_fem_mm"][1:])
    assert pos["max_error_mm"] <= cfg.fit.max_relative_error * max(pos["fem_points"]["u_mm"])
