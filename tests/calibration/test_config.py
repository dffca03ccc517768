"""Configuration validation: the shipped configurations parse; every broken configuration of the corpus is a
one-line error with exit code 2 and writes nothing."""

from pathlib import Path

import pytest

from calibration.__main__ import main
from calibration.config import load_config
from wrlayer.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
BAD = sorted((ROOT / "tests" / "inputs" / "bad_calibration_configs").glob("*.toml"))


@pytest.mark.parametrize("name", ["default.toml", "default_2d.toml", "test_coarse.toml"])
def test_shipped_configurations_parse(name):
    cfg = load_config(ROOT / "calibration" / "configs" / name)
    assert cfg.bodies and all(b.positions_mm for b in cfg.bodies)
    assert 2 <= cfg.fit.n_segments <= 10


def test_default_configuration_covers_rail_and_wheel():
    cfg = load_config(ROOT / "calibration" / "configs" / "default.toml")
    bodies = {b.body: b for b in cfg.bodies}
    assert bodies["rail"].profile == "60E1" and bodies["wheel"].profile == "S1002"
    assert cfg.run.model == "3d"  # 3D is the default; 2D is default_2d.toml
    assert len(bodies["rail"].positions_mm) >= 5 and len(bodies["wheel"].positions_mm) >= 5


def test_corpus_is_not_empty():
    assert len(BAD) >= 15


@pytest.mark.parametrize("path", BAD, ids=[p.stem for p in BAD])
def test_bad_configuration_is_a_one_line_error_and_writes_nothing(path, tmp_path, capsys):
    out = tmp_path / "out"
    rc = main(["run", str(path), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert rc == 2
    assert err.startswith("error: ") and "\n" not in err, err
    assert path.name in err or "profile" in err, err
    assert not out.exists()


def test_unusual_profile_file_accepted_on_request(tmp_path):
    """A profile file that fails the plausibility checks (here a rail head 4 mm wide) is refused, naming the file
    and the switch; with accept_unusual_profile = true it is read (and kept in memory, not read again)."""
    import numpy as np

    from calibration.config import parse_config
    from meshes.profiles.io import write_text

    y = np.linspace(-2.0, 2.0, 41)
    write_text(tmp_path / "narrow.csv", np.column_stack([y, -y ** 2 / 600.0]))
    body = {"body": "rail", "profile": "narrow.csv", "mate": "S1002", "positions_mm": [0.0], "inclination": 0}
    with pytest.raises(InputError, match="narrow.csv: spans only 4 mm.*accept_unusual_profile"):
        parse_config({"bodies": [body]}, "c.toml", tmp_path)
    cfg = parse_config({"bodies": [{**body, "accept_unusual_profile": True}]}, "c.toml", tmp_path)
    assert cfg.bodies[0].accept_unusual_profile and cfg.bodies[0].profile.name == "narrow"


def test_profile_files_units_and_the_command_line_option(tmp_path, monkeypatch):
    """``units = "m"`` reads a body's and its mate's files in metres (the same profile as in mm); without it the
    file is diagnosed; ``--accept-unusual-profile`` of ``wrlayer calibrate`` is accept_unusual_profile = true in
    every body."""
    import numpy as np

    import calibration.config as config
    from calibration.__main__ import main
    from calibration.config import parse_config
    from meshes.profiles import get_profile

    for name, file in (("60E1", "rail_m.csv"), ("S1002", "wheel_m.csv")):
        y, z = get_profile(name).sample(0.5)
        np.savetxt(tmp_path / file, np.column_stack([y, z]) * 1e-3, fmt="%.17g", delimiter=",")
    body = {"body": "rail", "profile": "rail_m.csv", "mate": "wheel_m.csv", "positions_mm": [0.0], "inclination": 0}
    with pytest.raises(InputError, match=r"c.toml: bodies\[0\].profile: .*spans only 0.0.* mm.*metres"):
        parse_config({"bodies": [body]}, "c.toml", tmp_path)
    with pytest.raises(InputError, match=r"c.toml: bodies\[0\].units: must be one of"):
        parse_config({"bodies": [{**body, "units": "inch"}]}, "c.toml", tmp_path)
    cfg = parse_config({"bodies": [{**body, "units": "m"}]}, "c.toml", tmp_path)
    b = cfg.bodies[0]
    assert b.units == "m" and b.profile.body == "rail" and b.mate.body == "wheel"
    assert b.profile.z(10.0) == pytest.approx(get_profile("60E1").z(10.0), abs=1e-4)   # spline through 0.5 mm samples
    assert b.mate.z(-20.0) == pytest.approx(get_profile("S1002").z(-20.0), abs=1e-4)

    narrow = tmp_path / "narrow.csv"
    yy = np.linspace(-2.0, 2.0, 41)
    np.savetxt(narrow, np.column_stack([yy, -yy ** 2 / 600.0]), delimiter=",")
    assert parse_config({"bodies": [{**body, "profile": "narrow.csv", "mate": "S1002"}]}, "c.toml", tmp_path,
                        accept_unusual_profile=True).bodies[0].accept_unusual_profile
    seen = []

    def fake_load(path, accept_unusual_profile=False):
        seen.append(accept_unusual_profile)
        raise InputError(str(path), "stop here")

    monkeypatch.setattr(config, "load_config", fake_load)
    assert main(["run", "c.toml", "--out", str(tmp_path / "out"), "--accept-unusual-profile"]) == 2
    assert main(["run", "c.toml", "--out", str(tmp_path / "out")]) == 2
    assert seen == [True, False]
