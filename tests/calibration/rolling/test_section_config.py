"""The section's configuration keys: ``[contact] body = "section"`` with a shipped table + y_mm (a, b and the
material from the table's position) or profile + y_mm + a_mm + b_mm; bad keys are one-line input errors (exit 2);
the block stays the default; the cost guard counts the section's dofs exactly."""

import pytest

from calibration.__main__ import main
from calibration.rolling.config import parse_rolling_config
from calibration.rolling.cost import dof_count
from calibration.rolling.section_position import table_position
from calibration.rolling.section_track import section_track_mesh
from wrlayer.errors import InputError

TABLE = "scenes/tables/rail_60E1_default.json"


def section(**contact):
    return {"contact": {"body": "section", "levels": [1.7], **contact}}


def test_block_is_the_default():
    cfg = parse_rolling_config({"contact": {"a_mm": 1.0, "levels": [1.3]}}, "c")
    assert cfg.contact.body == "block" and cfg.contact.table == "" and cfg.material.H_iso_MPa == 0.0


def test_table_position_gives_semi_axes_and_material():
    cfg = parse_rolling_config(section(table=TABLE, y_mm=-35.0), "c")
    pos = table_position(TABLE, -35.0)
    assert (cfg.contact.a_mm, cfg.contact.b_mm, cfg.contact.profile) == (pos.a_mm, pos.b_mm, "60E1")
    assert pos.a_mm == pytest.approx(3.5147, abs=1e-4) and pos.b_mm == pytest.approx(2.6, abs=1e-9)
    assert cfg.material.H_iso_MPa == 10000.0 and cfg.material.H_kin_MPa == 10000.0


def test_profile_position():
    cfg = parse_rolling_config(section(profile="S1002", y_mm=-37.5, a_mm=3.5, b_mm=2.6), "c")
    assert cfg.contact.profile == "S1002" and cfg.contact.a_mm == 3.5 and cfg.material.H_iso_MPa == 0.0


@pytest.mark.parametrize("data,key,what", [
    ({"contact": {"body": "cylinder", "a_mm": 1.0, "levels": [1.3]}}, "contact.body", "must be one of"),
    (section(table=TABLE), "contact.y_mm", "missing"),
    (section(table=TABLE, y_mm=-3.0), "contact.y_mm", "not a position of rail_60E1_default.json"),
    (section(table="scenes/tables/none.json", y_mm=0.0), "contact.table", "no such layer table"),
    (section(table=TABLE, y_mm=0.0, a_mm=2.0), "contact.a_mm", "given by the table"),
    ({**section(table=TABLE, y_mm=0.0), "material": {"yield_MPa": 400.0}}, "material", "given by contact.table"),
    (section(table=TABLE, y_mm=0.0, model="2d"), "contact.model", '"3d"'),
    (section(profile="60E1", y_mm=0.0, a_mm=2.0), "contact.b_mm", "missing"),
    (section(profile="60E1", y_mm=50.0, a_mm=2.0, b_mm=1.0), "contact.y_mm", "outside the profile"),
    (section(profile="XYZ", y_mm=0.0, a_mm=2.0, b_mm=1.0), "contact.profile", "unknown profile"),
    ({"contact": {"a_mm": 1.0, "levels": [1.3], "y_mm": 0.0}}, "contact.y_mm", 'only with body = "section"'),
])
def test_bad_section_keys(data, key, what):
    with pytest.raises(InputError) as err:
        parse_rolling_config(data, "f.toml")
    assert err.value.what == f"f.toml: {key}" and what in err.value.problem


def test_bad_body_on_the_command_line(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('[contact]\nbody = "section"\nprofile = "60E1"\na_mm = 2.0\nb_mm = 1.5\nlevels = [1.3]\n')
    assert main(["rolling", str(bad), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"error: {bad}: contact.y_mm: missing (required with body = \"section\")"]


def test_dof_count_is_the_section_mesh():
    cfg = parse_rolling_config({**section(profile="60E1", y_mm=0.0, a_mm=6.0, b_mm=4.5),
                                "track": {"length_factor": 1.0}, "mesh": {"elements_per_semi_axis": 1,
                                                                          "size_factor": 3}}, "c")
    mesh = section_track_mesh(cfg).mesh
    assert dof_count(cfg) == 3 * mesh.p.shape[1]


def test_too_many_layers_is_refused_before_meshing():
    cfg = parse_rolling_config({**section(profile="60E1", y_mm=0.0, a_mm=6.0, b_mm=4.5),
                                "track": {"length_factor": 20.0}, "mesh": {"elements_per_semi_axis": 10}}, "c")
    with pytest.raises(InputError) as err:
        dof_count(cfg)
    assert err.value.what == "c: mesh.elements_per_semi_axis" and "at most 200" in err.value.problem


def test_shipped_table_is_found_from_any_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    cfg = parse_rolling_config(section(table=TABLE, y_mm=0.0), "c")
    assert cfg.contact.a_mm == pytest.approx(7.161, abs=1e-3) and cfg.contact.profile == "60E1"


def test_unusual_profile_file_accepted_by_the_key_or_the_command_line(tmp_path, monkeypatch, capsys):
    """A section profile file that fails the plausibility checks is refused naming the key; the key
    accept_unusual_profile or ``wrlayer rolling --accept-unusual-profile`` reads it (the section then uses it)."""
    import numpy as np

    from meshes.profiles import get_profile
    from meshes.profiles.io import write_text

    y, z = get_profile("60E1").sample(0.5)
    z = np.asarray(z, float).copy()
    z[int(np.argmin(np.abs(np.asarray(y) - 34.0)))] -= 2.0        # a notch far from the load
    path = write_text(tmp_path / "notched.csv", np.column_stack([y, z]))
    data = section(profile=str(path), y_mm=0.0, a_mm=3.5, b_mm=2.6)
    with pytest.raises(InputError, match=r"c: contact.profile: .*accept_unusual_profile"):
        parse_rolling_config(data, "c")
    cfg = parse_rolling_config(data, "c", accept_unusual_profile=True)
    assert cfg.contact.accept_unusual_profile and cfg.to_dict()["contact"]["accept_unusual_profile"] is True
    assert cfg.contact.section_profile().name == "notched"
    assert parse_rolling_config(section(profile=str(path), y_mm=0.0, a_mm=3.5, b_mm=2.6, accept_unusual_profile=True),
                                "c").contact.section_profile().z(0.0) == pytest.approx(0.0, abs=1e-9)
    toml = tmp_path / "r.toml"
    toml.write_text(f'[contact]\nbody = "section"\nlevels = [1.7]\nprofile = "{path}"\ny_mm = 0.0\na_mm = 3.5\n'
                    'b_mm = 2.6\n')
    import calibration.rolling.run as rolling_run

    seen = []

    def fake_run(cfg, out, force=False, progress=None):
        seen.append(cfg.contact.accept_unusual_profile)
        raise InputError("stop", "here")

    monkeypatch.setattr(rolling_run, "run_rolling", fake_run)
    assert main(["rolling", str(toml), "--out", str(tmp_path / "o")]) == 2
    assert "accept_unusual_profile" in capsys.readouterr().err and seen == []
    assert main(["rolling", str(toml), "--out", str(tmp_path / "o"), "--accept-unusual-profile"]) == 2
    assert seen == [True]
