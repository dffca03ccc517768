"""``method.tangential`` in a wheel–rail scene: every method gives the same result keys and creep forces near each
other on a tread contact; FASTSIM's spin taken about the patch centroid."""

import pytest

from contact.wheel_rail.parse import parse_wheel_rail_scene
from contact.run_files import run_wheel_rail_scene


def _run(tmp_path, method):
    data = {"type": "wheel_rail", "wheel": {"side": "right"}, "wheelset": {"lateral_mm": 2.0, "yaw_rad": 0.002},
            "method": {"tangential": method}}
    scene = parse_wheel_rail_scene(data, tmp_path / "w.toml")
    res = run_wheel_rail_scene(scene, tmp_path / method, plots=False, vtk=False).to_dict()
    return res["cases"][0]["wheels"]["right"]["patches"][0]


def test_every_method_gives_the_same_keys_and_close_forces(tmp_path):
    got = {m: _run(tmp_path, m) for m in ("fastsim", "fastrip", "exact")}
    assert set(got["exact"]) == set(got["fastsim"]) == set(got["fastrip"])
    ref = got["exact"]
    scale = 0.3 * ref["normal_force_N"]
    for m in ("fastsim", "fastrip"):
        assert got[m]["Fx_N"] == pytest.approx(ref["Fx_N"], abs=0.1 * scale)
        assert got[m]["Fy_N"] == pytest.approx(ref["Fy_N"], abs=0.1 * scale)
    assert (tmp_path / "exact" / "frictional_cells.csv").is_file()
