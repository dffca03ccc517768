"""VTK in track coordinates, read back with meshio: the rail and wheel surfaces and each patch placed on both, the
patch's cells on the (deformed) rail surface, its pressure where the solver put it; the local frame on request."""

import re
from pathlib import Path

import meshio
import numpy as np

from contact.__main__ import main
from contact.wheel_rail.track_geometry import TrackLayout, place_rail
from meshes.profiles import get_profile

SCENES = Path(__file__).resolve().parents[3] / "scenes"


def _scene(tmp_path: Path, frame: str | None) -> Path:
    text = (SCENES / "wheel_rail_sweep_layers.toml").read_text(encoding="utf-8")
    text = text.replace('lateral_mm = { start = 0.0, stop = 10.0, step = 0.5 }', 'lateral_mm = [3.0, 7.0]')
    text = text.replace('yaw_rad = { start = 0.0, stop = 0.024, step = 0.0012 }', 'yaw_rad = [0.006, 0.0]')
    text = text.replace("[passes]\nmax = 1", "[passes]\nmax = 2")
    if frame is not None:
        text = text.replace("[output]\n", f'[output]\nvtk_frame = "{frame}"\n', 1)
    (tmp_path / "tables").symlink_to(SCENES / "tables")
    path = tmp_path / "scene.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_track_frame_surfaces_and_patches_read_back(tmp_path):
    out = tmp_path / "out"
    assert main(["simulate", str(_scene(tmp_path, None)), "--out", str(out)]) == 0
    vtk = out / "vtk"
    pvd = (vtk / "contact_fields.pvd").read_text(encoding="utf-8")
    files = re.findall(r'file="([^"]+)"', pvd)
    assert all((vtk / f).is_file() for f in files)
    for case in (0, 1):
        for side in ("right", "left"):
            assert f"case{case:03d}_{side}_rail_surface.vtu" in files
            assert f"case{case:03d}_{side}_wheel_surface.vtu" in files
    layout = TrackLayout(inclination_rad=np.arctan(1 / 40))
    placed = place_rail(get_profile("60E1"), layout)
    rail_patches = [f for f in files if f.endswith("_rail.vtu") and "_patch" in f]
    assert len(rail_patches) >= 4 and len(rail_patches) == len([f for f in files if f.endswith("_wheel.vtu")])
    dented = 0
    for name in rail_patches:
        mesh = meshio.read(vtk / name)
        pts = mesh.points
        sign = 1 if "_right_" in name else -1
        assert np.all(sign * pts[:, 1] > 650.0)                         # on its rail, in track coordinates
        depth = placed.Z_at(sign * pts[:, 1]) - pts[:, 2]               # below the undeformed rail surface
        assert np.all(depth > -1e-6) and np.all(depth < 0.05)
        dented += int(np.any(depth > 1e-5))
        p = mesh.cell_data["pressure_MPa"][0]
        assert p.max() > 100.0 and np.all(p >= 0.0)
        assert np.ptp(pts[:, 2]) > 0.0                                  # not flat: it follows the profile
    assert dented > 0                                                   # the layers' residual deforms the rail
    surface = meshio.read(vtk / "case000_right_rail_surface.vtu")
    assert surface.point_data["residual_mm"].max() > 0.0


def test_local_frame_stays_an_option(tmp_path):
    out = tmp_path / "out"
    assert main(["simulate", str(_scene(tmp_path, "local")), "--out", str(out)]) == 0
    files = re.findall(r'file="([^"]+)"', (out / "vtk" / "contact_fields.pvd").read_text(encoding="utf-8"))
    assert files and not any("surface" in f for f in files)
    mesh = meshio.read(out / "vtk" / files[0])
    assert np.ptp(mesh.points[:, 2]) == 0.0                             # flat in the patch's own frame
