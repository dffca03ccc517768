"""``wrlayer geometry`` through its command module: outputs with unit-suffixed columns, the key numbers on the
terminal, and one ``error:`` line with exit 2 for bad input."""

import csv

import numpy as np
import pytest

from contact.geometry.command import main

SMALL = ["--lateral-mm", "-4", "4", "--step-mm", "0.25", "--amplitudes-mm", "1", "3"]


def _table(path):
    return list(csv.DictReader(ln for ln in path.read_text(encoding="utf-8").splitlines() if not ln.startswith("#")))


def test_writes_tables_and_pictures(tmp_path, capsys):
    out = tmp_path / "geo"
    assert main(["geometry", "--rail", "60E1", "--wheel", "S1002", "--out", str(out), *SMALL]) == 0
    printed = capsys.readouterr().out
    assert "amplitude  3.0 mm: tan gamma_e" in printed
    assert max(len(ln) for ln in printed.splitlines()[:-1]) < 100  # the last line: "wrote ... in OUT"
    rows = _table(out / "geometry.csv")
    assert len(rows) == 33
    assert all(k.endswith(("_mm", "_rad", "_-")) for k in rows[0])
    centre = next(r for r in rows if float(r["lateral_mm"]) == 0.0)
    assert float(centre["delta_r_mm"]) == pytest.approx(0.0, abs=1e-9) and centre["roll_parameter_-"] == ""
    right = np.array([float(r["rolling_radius_right_mm"]) - float(r["rolling_radius_left_mm"]) for r in rows])
    assert np.allclose(right, [float(r["delta_r_mm"]) for r in rows], atol=1e-8)
    con = _table(out / "conicity.csv")
    assert [float(r["amplitude_mm"]) for r in con] == [1.0, 3.0]
    assert 0.1 < float(con[1]["equivalent_conicity_-"]) < 0.3
    for name in ("delta_r.png", "contact_points.png", "conicity.png"):
        assert (out / name).stat().st_size > 10000


@pytest.mark.parametrize("extra, message", [
    (["--rail", "S1002", "--wheel", "S1002"], "error: --rail: S1002 is a wheel profile, expected a rail profile"),
    (["--rail", "60E1", "--wheel", "nowhere.whl"], "error: --wheel: no such profile file 'nowhere.whl'"),
    (["--rail", "60E1", "--wheel", "S1002", "--inclination", "2"], "error: --inclination: 1:n needs n >= 5"),
    (["--rail", "60E1", "--wheel", "S1002", "--gauge-mm", "1300"], "error: gauge_mm: impossible gauge 1300 mm"),
    (["--rail", "60E1", "--wheel", "S1002", "--amplitudes-mm", "6"], "error: conicity amplitude_mm: 6 mm: the "
                                                                      "oscillation leaves the lateral range"),
])
def test_bad_input_is_one_error_line_and_exit_2(tmp_path, capsys, extra, message):
    args = ["geometry", *extra, "--out", str(tmp_path / "o"), "--lateral-mm", "-4", "4", "--step-mm", "0.5",
            "--amplitudes-mm", "1"]
    if "--amplitudes-mm" in extra:
        args = args[:-2]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(message)
    assert not (tmp_path / "o").exists()


def test_measured_profile_files_and_units(tmp_path, capsys):
    """A MiniProf wheel (.whl, made to the public description) and a rail CSV in metres give the standard
    profiles' result; the same CSV read as mm is refused with the unit named."""
    from meshes.profiles import S1002, Rail60E1
    from meshes.profiles.io import write_text

    y = np.linspace(-69.0, 59.0, 513)
    wheel = tmp_path / "s1002.whl"
    wheel.write_text("\n".join(["MiniProf (test file)", "", *(f"{a:.6f} {b:.6f}" for a, b in
                                                                zip(y, S1002().z(y)))]) + "\n", encoding="utf-8")
    rail = write_text(tmp_path / "rail.csv", Rail60E1(), units="m", ds=0.1)
    args = ["geometry", "--lateral-mm", "-4", "4", "--step-mm", "0.5", "--amplitudes-mm", "2", "--no-plots"]
    assert main([*args, "--rail", str(rail), "--wheel", str(wheel), "--units", "m", "--out",
                 str(tmp_path / "m")]) == 2     # --units applies to both files: the wheel in mm is read as metres
    assert "error: --wheel:" in capsys.readouterr().err
    assert main([*args, "--rail", "60E1", "--wheel", str(wheel), "--out", str(tmp_path / "a")]) == 0
    assert main([*args, "--rail", "60E1", "--wheel", "S1002", "--out", str(tmp_path / "b")]) == 0
    measured, standard = (_table(tmp_path / d / "conicity.csv")[0]["equivalent_conicity_-"] for d in "ab")
    assert float(measured) == pytest.approx(float(standard), rel=0.02)
    assert main([*args, "--rail", str(rail), "--wheel", "S1002", "--out", str(tmp_path / "c")]) == 2
    assert "lengths in metres" in capsys.readouterr().err
    assert main([*args, "--rail", str(rail), "--wheel", "S1002", "--units", "m", "--out", str(tmp_path / "d")]) == 0
    in_metres = _table(tmp_path / "d" / "conicity.csv")[0]["equivalent_conicity_-"]
    assert float(in_metres) == pytest.approx(float(standard), rel=0.02)


def test_unusual_profile_file_refused_unless_accepted(tmp_path, capsys):
    """A rail file with a one-point spike far on the field side fails the plausibility checks (exit 2, the option
    named); --accept-unusual-profile reads it."""
    from meshes.profiles import Rail60E1
    from meshes.profiles.io import write_text

    y, z = Rail60E1().sample(0.5)
    z = np.asarray(z, float).copy()
    z[int(np.argmin(np.abs(np.asarray(y) - 34.0)))] -= 2.0
    rail = write_text(tmp_path / "notched.csv", np.column_stack([y, z]))
    args = ["geometry", "--rail", str(rail), "--wheel", "S1002", "--lateral-mm", "-2", "2", "--step-mm", "0.5",
            "--amplitudes-mm", "1", "--no-plots"]
    assert main([*args, "--out", str(tmp_path / "refused")]) == 2
    assert "--accept-unusual-profile" in capsys.readouterr().err
    assert main([*args, "--out", str(tmp_path / "accepted"), "--accept-unusual-profile"]) == 0
    assert (tmp_path / "accepted" / "conicity.csv").is_file()
