"""The rolling configuration: keys validated once (InputError naming file and key, exit code 2), the shipped
configuration parses, the cost guard refuses oversized runs before any FEM, and the command line."""

from pathlib import Path

import pytest

from calibration.__main__ import main
from calibration.rolling.config import load_rolling_config, parse_rolling_config
from calibration.rolling.cost import dof_count, rolling_cost
from calibration.rolling.run import run_rolling
from calibration.rolling.track_mesh import track_mesh
from wrlayer.cost import CostError
from wrlayer.errors import InputError

ROOT = Path(__file__).resolve().parents[3]
TINY = """
[contact]
model = "2d"
a_mm = 1.0
levels = [3.5]
level_unit = "k"
[track]
length_factor = 1.0
step_factor = 1.0
n_passes = 1
ramp_steps = 1
[mesh]
elements_per_semi_axis = 2
size_factor = 4
[run]
plots = false
linear_solver = "scipy"
"""


def test_shipped_configuration_parses():
    cfg = load_rolling_config(ROOT / "calibration" / "configs" / "rolling_halfspace.toml")
    assert cfg.contact.model == "3d" and cfg.contact.traction_coefficient == 0.0
    assert list(cfg.contact.levels) == [1.3, 1.7, 2.1] and cfg.contact.level_unit == "p_y"
    assert cfg.track.n_passes >= 3
    assert cfg.track.substeps == 4 and cfg.track.step_factor == 0.125   # within 2 % of the step-converged groove
    assert (cfg.material.E_MPa, cfg.material.poisson, cfg.material.yield_MPa) == (210000.0, 0.3, 500.0)
    assert cfg.material.H_iso_MPa == cfg.material.H_kin_MPa == 0.0


@pytest.mark.parametrize("table,key,value", [
    ("contact", "a_mm", -1.0), ("contact", "levels", []), ("contact", "model", "1d"),
    ("contact", "traction_coefficient", 2.0), ("track", "n_passes", 0), ("track", "n_passes", 51),
    ("track", "length_factor", 100.0), ("track", "step_factor", 0.0), ("mesh", "order", 3),
    ("material", "poisson", 0.5), ("run", "bogus", 1), ("track", "steps", 3), ("track", "substeps", 0),
    ("track", "substeps", 17), ("track", "substeps", 2.5)])
def test_bad_values_name_the_key(table, key, value):
    data = {"contact": {"a_mm": 1.0, "levels": [1.3]}}
    data.setdefault(table, {})[key] = value
    with pytest.raises(InputError, match=f"cfg.toml: {table}.{key}"):
        parse_rolling_config(data, "cfg.toml")


def test_missing_contact_table():
    with pytest.raises(InputError, match="contact"):
        parse_rolling_config({"track": {}}, "cfg.toml")


def test_cost_guard_refuses_before_any_fem(tmp_path):
    data = {"contact": {"a_mm": 1.0, "levels": [1.3] * 10}, "track": {"n_passes": 50, "step_factor": 0.02,
                                                                      "length_factor": 20.0},
            "mesh": {"elements_per_semi_axis": 8}}
    cfg = parse_rolling_config(data, "big.toml")
    with pytest.raises(CostError, match="big.toml: estimated cost"):
        run_rolling(cfg, tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_cost_grows_with_passes_and_steps():
    base = parse_rolling_config({"contact": {"a_mm": 1.0, "levels": [1.3]}}, "c")
    more = parse_rolling_config({"contact": {"a_mm": 1.0, "levels": [1.3]}, "track": {"n_passes": 6,
                                                                                     "step_factor": 0.125}}, "c")
    assert rolling_cost(more).seconds > 3 * rolling_cost(base).seconds
    sub = parse_rolling_config({"contact": {"a_mm": 1.0, "levels": [1.3]}, "track": {"substeps": 4}}, "c")
    assert sub.track.substeps == 4 and base.track.substeps == 1
    assert rolling_cost(sub).seconds == pytest.approx(1.6 * rolling_cost(base).seconds)


@pytest.mark.parametrize("model,order", [("2d", 1), ("2d", 2), ("3d", 1), ("3d", 2)])
def test_dof_count_matches_the_mesh(model, order):
    cfg = parse_rolling_config({"contact": {"a_mm": 1.0, "levels": [1.3], "model": model},
                                "mesh": {"order": order, "elements_per_semi_axis": 2, "size_factor": 3}}, "c")
    mesh = track_mesh(cfg.contact, cfg.track, cfg.mesh).mesh
    assert dof_count(cfg) == mesh.dim() * mesh.p.shape[1]


def test_command_line(tmp_path, capsys):
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY)
    assert main(["rolling", str(cfg), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    assert (tmp_path / "out" / "rolling.json").is_file()
    bad = tmp_path / "bad.toml"
    bad.write_text(TINY.replace("a_mm = 1.0", "a_mm = -1.0"))
    assert main(["rolling", str(bad), "--out", str(tmp_path / "out2")]) == 2
    assert "bad.toml: contact.a_mm" in capsys.readouterr().err
