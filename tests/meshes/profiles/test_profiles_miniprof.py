"""MiniProf files (.whl wheel, .ban rail) made to the public description (header lines, an empty line, the
measured data; '#' comments; malformed ones: test_profile_io.py), and the length unit of every profile reader."""

import numpy as np
import pytest

from meshes.profiles import S1002, Rail60E1, load_profile
from meshes.profiles.io import read_miniprof, read_profile, write_simpack, write_text
from meshes.profiles.miniprof import parse_miniprof
from meshes.profiles.plausibility import ImplausibleProfile
from wrlayer.errors import InputError

HEADER = ["MiniProf profile export (made for the test)", "Type = Wheel", "Date: 2026-12-02"]


def miniprof_file(path, y, z, header=HEADER, scale=1.0, comments=True):
    """A MiniProf-like file: header lines, one empty line, '#' comments among two-column data."""
    rows = [f"{a * scale:.6f} {b * scale:.6f}" for a, b in zip(y, z)]
    if comments:
        rows.insert(len(rows) // 2, "# a comment in the data")
    path.write_text("\n".join([*header, "", *rows]) + "\n", encoding="utf-8")
    return path


def test_wheel_in_the_project_frame_reads_back(tmp_path):
    s1002 = S1002()
    y = np.linspace(-69.0, 59.0, 257)
    prof = load_profile(miniprof_file(tmp_path / "w.whl", y, s1002.z(y)))
    assert prof.body == "wheel" and prof.name == "w"
    yy = np.linspace(-60.0, 55.0, 50)
    assert np.max(np.abs(prof.z(yy) - s1002.z(yy))) < 0.02   # spline through 0.5 mm samples of the arcs


def test_header_items_and_comments(tmp_path):
    parsed = parse_miniprof(miniprof_file(tmp_path / "r.ban", [-30.0, 0.0, 30.0], [-3.0, 0.0, -3.0]))
    assert parsed.body == "rail" and parsed.header == tuple(HEADER)
    assert parsed.items == {"Type": "Wheel", "Date": "2026-12-02"}
    assert parsed.points.shape == (3, 2)


def test_turned_shifted_metres_and_z_down_options(tmp_path):
    """A rail measured from its gauge face towards the field side in metres with z down: mirror_y / y_offset_mm /
    units / z_down bring it back to the project frame."""
    rail = Rail60E1()
    y = np.linspace(-35.0, 35.0, 141)
    x = 32.5 - y            # the lateral coordinate of the file: turned and shifted
    path = miniprof_file(tmp_path / "m.ban", x, -rail.z(y), scale=1e-3)
    prof = read_miniprof(path, units="m", mirror_y=True, y_offset_mm=32.5, z_down=True)
    assert np.max(np.abs(prof.z(y[5:-5]) - rail.z(y[5:-5]))) < 1e-3
    with pytest.raises(ImplausibleProfile, match="lengths in metres"):
        read_miniprof(path, mirror_y=True, y_offset_mm=32.5, z_down=True)
    with pytest.raises(ImplausibleProfile, match="upside down"):
        read_miniprof(path, units="m", mirror_y=True, y_offset_mm=32.5)


def test_body_must_match_the_suffix(tmp_path):
    path = miniprof_file(tmp_path / "r.ban", np.linspace(-30, 30, 61), -0.004 * np.linspace(-30, 30, 61) ** 2)
    with pytest.raises(InputError, match="holds a rail profile, not a wheel profile"):
        read_profile(path, body="wheel")


def test_units_for_text_and_simpack_files(tmp_path):
    rail = Rail60E1()
    metres = write_text(tmp_path / "r.csv", rail, units="m")
    assert np.allclose(read_profile(metres, units="m").z([-10.0, 0.0, 10.0]), rail.z([-10.0, 0.0, 10.0]), atol=1e-6)
    with pytest.raises(ImplausibleProfile, match="lengths in metres"):
        read_profile(metres)                       # read as mm: the plausibility check names the unit
    simpack = write_simpack(tmp_path / "r.prr", rail)   # states units.len.f = 1000 (mm)
    assert read_profile(simpack, units="mm").body == "rail"
    with pytest.raises(InputError, match="units.len.f: the file states 1000 length units per metre, not m"):
        read_profile(simpack, units="m")
    with pytest.raises(InputError, match="not one of"):
        read_profile(simpack, units="inch")
    with pytest.raises(InputError, match="holds a rail profile, not a wheel profile"):
        read_profile(simpack, body="wheel")


def test_simpack_without_a_stated_unit_takes_the_given_one(tmp_path):
    text = (tmp_path / "r.prr")
    src = write_simpack(tmp_path / "src.prr", Rail60E1()).read_text(encoding="utf-8")
    lines = [ln for ln in src.splitlines() if "units.len.f" not in ln]
    pts = [i for i, ln in enumerate(lines) if ln.strip() == "point.begin"][0]
    body = [f"{float(a) / 1000:+.12e}  {float(b) / 1000:+.12e}" if k > pts and " " in ln.strip() and
            not ln.strip().startswith(("!", "point")) else ln
            for k, ln in enumerate(lines) for a, b in [(ln.split() + ["0", "0"])[:2]]]
    text.write_text("\n".join(body) + "\n", encoding="utf-8")
    assert np.allclose(read_profile(text, units="m").z([-10.0, 10.0]), Rail60E1().z([-10.0, 10.0]), atol=1e-6)
