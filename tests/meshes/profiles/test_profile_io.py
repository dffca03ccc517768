"""Profile file readers and writers: SIMPACK .prr/.prw and text/CSV; round trips and bad input."""

import numpy as np
import pytest

from wrlayer.errors import InputError
from meshes.profiles.io import (
    read_profile,
    read_simpack,
    read_text,
    write_profile_files,
    write_simpack,
    write_text,
)
from meshes.profiles import S1002, Rail60E1, SplineProfile, get_profile

HEADER = """  header.begin
    type          =  {type}     ! 0=rail profile, 1=wheel profile
  header.end
  spline.begin
    comment        = 'test ! not a comment'
    shift.y        = {sy}
    shift.z        = {sz}
    rotate         = {rot}
    mirror.y       =  {my}
    mirror.z       =  {mz}
    inversion      =  {inv}
    units.len.f    = {lf}
    units.ang.f    = +1.0
"""


def simpack_text(points, type=0, sy=0.0, sz=0.0, rot=0.0, my=0, mz=0, inv=0, lf=1000.0, block=True):
    rows = "\n".join("  ".join(f"{v:.12e}" for v in row) for row in points)
    body = f"    point.begin\n    ! y z\n{rows}\n    point.end\n" if block else ""
    return HEADER.format(type=type, sy=sy, sz=sz, rot=rot, my=my, mz=mz, inv=inv, lf=lf) + body + "  spline.end\n"


@pytest.fixture()
def head_points():
    y = np.linspace(-30.0, 30.0, 61)
    return np.column_stack([y, Rail60E1().z(y)])


def test_simpack_round_trip(tmp_path, head_points):
    path = write_simpack(tmp_path / "rail.prr", head_points, body="rail", comment="it's a test")
    prof = read_simpack(path)
    assert prof.body == "rail" and prof.name == "rail"
    assert np.allclose(prof.points, head_points, atol=1e-10)
    # a SplineProfile writes its own points: a second round trip is exact
    again = read_profile(write_simpack(tmp_path / "again.prw", prof, body="wheel"), accept_unusual=True)  # a rail head as a wheel
    assert again.body == "wheel"
    assert np.allclose(again.points, prof.points, atol=1e-10)


def test_simpack_writes_z_down(tmp_path, head_points):
    text = write_simpack(tmp_path / "rail.prr", head_points, body="rail").read_text()
    rows = [line.split() for line in text.split("point.begin")[1].split("point.end")[0].splitlines()]
    vals = np.array([[float(v) for v in r] for r in rows if r and not r[0].startswith("!")])
    assert np.allclose(vals[:, 1], -head_points[:, 1])


def test_simpack_transformations(tmp_path, head_points):
    # file frame: z down, in metres, mirrored in y, reversed order, shifted: the reader undoes all
    sy, sz = 0.002, -0.001                        # m
    raw = np.column_stack([-head_points[:, 0] / 1000.0 - sy, -head_points[:, 1] / 1000.0 - sz])[::-1]
    path = tmp_path / "t.prr"
    path.write_text(simpack_text(raw, sy=sy, sz=sz, my=1, inv=1, lf=1.0))
    prof = read_simpack(path)
    assert np.allclose(prof.points, head_points, atol=1e-9)
    # mirror.z flips the vertical direction
    path.write_text(simpack_text(raw * [1, -1], sy=sy, sz=-sz, my=1, mz=1, inv=1, lf=1.0))
    assert np.allclose(read_simpack(path).points, head_points, atol=1e-9)


def test_simpack_rotation(tmp_path, head_points):
    a = 0.05
    yd, zd = head_points[:, 0], -head_points[:, 1]       # file frame (z down)
    c, s = np.cos(-a), np.sin(-a)                         # pre-rotate by -a; the reader rotates by +a
    raw = np.column_stack([c * yd - s * zd, s * yd + c * zd])
    path = tmp_path / "r.prr"
    path.write_text(simpack_text(raw, rot=a * 1.0))
    assert np.allclose(read_simpack(path).points, head_points, atol=1e-9)


def test_simpack_three_columns_and_weights(tmp_path, head_points):
    path = tmp_path / "w.prr"
    path.write_text(simpack_text(np.column_stack([head_points * [1, -1], np.full(len(head_points), 2.0)])))
    assert np.allclose(read_simpack(path).points, head_points, atol=1e-9)


def with_row(points, i, row):
    """SIMPACK text with data row i replaced by ``row``, and that row's line number."""
    lines = simpack_text(points).splitlines()
    first = lines.index("    ! y z") + 1
    lines[first + i] = row
    return "\n".join(lines) + "\n", first + i + 1


@pytest.mark.parametrize("row, message", [("1.0 abc", "non-numeric"), ("1.0 nan", "NaN"), ("1 2 3 4", "expected 2 or 3")])
def test_simpack_bad_row_names_line(tmp_path, head_points, row, message):
    text, lineno = with_row(head_points, 5, row)
    path = tmp_path / "bad.prr"
    path.write_text(text)
    with pytest.raises(InputError, match=f"line {lineno}: {message}") as err:
        read_simpack(path)
    assert str(path) in str(err.value)


@pytest.mark.parametrize("mutate, message", [
    (lambda p: simpack_text(p, block=False), "no point block"),
    (lambda p: simpack_text(p[:3]), "at least 4 profile points"),
    (lambda p: simpack_text(np.r_[p[:10], p[5:6], p[10:]]), "not strictly monotone"),
    (lambda p: simpack_text(p, type=3), "header.type: must be 0 \\(rail\\) or 1 \\(wheel\\), got 3"),
])
def test_simpack_bad_input(tmp_path, head_points, mutate, message):
    path = tmp_path / "bad.prr"
    path.write_text(mutate(head_points))
    with pytest.raises(InputError, match=message) as err:
        read_simpack(path)
    assert str(path) in str(err.value)


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        get_profile(str(tmp_path / "nope.prw"))


@pytest.mark.parametrize("suffix, units, z_down", [(".txt", "mm", False), (".csv", "m", True)])
def test_text_round_trip(tmp_path, suffix, units, z_down):
    wheel = S1002()
    path = write_text(tmp_path / f"w{suffix}", wheel, units=units, z_down=z_down, ds=0.5, comment="S1002")
    prof = get_profile(str(path), units=units, z_down=z_down, body="wheel")
    assert isinstance(prof, SplineProfile) and prof.body == "wheel"
    y, z = wheel.sample(0.5)
    assert np.allclose(prof.points, np.column_stack([y, z]), atol=1e-9)
    yy = np.linspace(-60.0, 55.0, 501)
    assert np.abs(prof.z(yy) - wheel.z(yy)).max() < 1e-3


def test_text_header_comments_and_decreasing_order(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text("# measured\ny;z\n3;0.9\n2;0.4\n1;0.1   # inline comment\n0;0\n")
    prof = read_text(path, accept_unusual=True)  # four points: the format, not a real rail head
    assert np.allclose(prof.points, [[0, 0], [1, 0.1], [2, 0.4], [3, 0.9]])


@pytest.mark.parametrize("name, text, message", [
    ("bad.txt", "0 0\n1 1\n2 x\n3 3\n", "line 3: non-numeric"),
    ("bad.txt", "0 0 0\n", "line 1: expected 2 columns"),
    ("bad.txt", "# nothing\n", "no profile points"),
    ("bad.txt", "0 0\n1 1\n0.5 2\n3 3\n", "not strictly monotone"),
    ("bad.whl", "header\n1 2\n3 4\n", "no empty line"),              # MiniProf: header, empty line, data
    ("bad.whl", "header\n\n1 2 3\n", "line 3: expected 2 columns"),
    ("bad.ban", "header\n\n1 x\n", "line 3: non-numeric"),
    ("bad.whl", "header\n\n# only a comment\n", "no measured points"),
])
def test_bad_profile_files(tmp_path, name, text, message):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        read_profile(path)


def test_text_bad_units(tmp_path):
    with pytest.raises(InputError, match="units"):
        read_text(tmp_path / "x.txt", units="inch")


@pytest.mark.parametrize("body, profile", [("rail", Rail60E1()), ("wheel", S1002())])
def test_profile_files_pair_is_read_back_exactly(tmp_path, body, profile):
    """A written profile (SIMPACK with the body's suffix, and CSV) reads back to the same points."""
    y, z = profile.sample(0.5)
    pts = np.column_stack([y, z + 1e-3 * np.sin(y)])  # a deformed profile, not the analytic one
    paths, err = write_profile_files(tmp_path / "sub" / "p", pts, body, "test (deformed)")
    assert [p.name for p in paths] == [f"p.{'prr' if body == 'rail' else 'prw'}", "p.csv"]
    assert err < 1e-9
    for path in paths:
        back = read_profile(path) if path.suffix != ".csv" else read_profile(path, body=body)
        assert back.body == body
        np.testing.assert_allclose(back.z(pts[:, 0]), pts[:, 1], atol=1e-9)
