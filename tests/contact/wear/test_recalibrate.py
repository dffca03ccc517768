"""Recalibration on the worn profiles: the template validated when the scene is parsed, the calibration called
through its Python API with the worn profiles in place of the placeholders, its typed errors stopping the loop."""

import dataclasses
import json
import shutil
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from calibration.tables import previous_table, with_rolling_law
from calibration.tasks import PositionNote
from contact.__main__ import main
from contact.wear import condition as condition_mod
from contact.wear import recalibrate as recal_mod
from contact.wear.loop import run_wear
from contact.wear.recalibrate import PLACEHOLDERS, recalibrate_side, worn_config
from contact.wear.records import WearStopped
from meshes.profiles.io import read_profile
from wrlayer.layer_table import LayerTable
from wrlayer.errors import ConvergenceError, InputError

REPO = Path(__file__).resolve().parents[3]
TABLES = REPO / "scenes" / "tables"

TEMPLATE_2D = """
[run]
model = "2d"
workers = 1
plots = false
[load]
max_factor = 2.0
n_levels = 3
unload_factors = [2.0]
max_increment_factor = 0.5
[mesh]
elements_per_semi_axis = 3
h_max_mm = 10.0
order = 1
[fit]
n_segments = 3
max_relative_error = 0.3
[[bodies]]
body = "wheel"
profile = "@wheel_profile@"
mate = "@rail_profile@"
wheel_radius_mm = 460.0
positions_mm = [-25.0, -12.0, 0.0, 12.0, 25.0]
"""


def _template(tmp_path, text=TEMPLATE_2D, name="recal.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _recal_scene(make_scene, template, **wear):
    return make_scene(wear={"distance_km": 100.0, "steps": 2, "recalibrate": {"config": str(template)}, **wear},
                      passes={"max": 3})


def test_recalibration_on_worn_profiles(make_scene, tmp_path, monkeypatch):
    """After step 1 the wheel table is recomputed (coarse 2D FEM) on the worn wheel and used in step 2."""
    seen = []
    real = condition_mod.solve_condition

    def spy(task):
        seen.append((task.step, task.layers.names["wheel"], task.layers.wheel.table))
        return real(task)

    monkeypatch.setattr(condition_mod, "solve_condition", spy)
    run = run_wear(_recal_scene(make_scene, _template(tmp_path)), show_progress=False, work_dir=tmp_path / "work")
    assert len(run.steps) == 2
    assert any("recalibrated" in n for n in run.steps[0].notes) and "recalibration_s" in run.steps[0].timings
    assert not any("recalibrated" in n for n in run.steps[1].notes)  # not after the last step
    folder = tmp_path / "work" / "calibration" / "step_001_right"
    table = folder / "tables" / "wheel_layer_table.json"
    assert table.is_file()
    worn = read_profile(folder / "wheel.prw")
    assert np.allclose(worn.points, run.steps[0].profiles["right"]["wheel"].points, atol=1e-9)
    (step1, name1, table1), (step2, name2, table2) = seen
    assert (step1, step2) == (1, 2)
    assert "recalibrated" not in name1 and name2 == "recalibrated wheel table"
    assert Path(table2.source) == table and Path(table1.source) != table


@pytest.mark.parametrize("edit, match", [
    (("workers = 1", "workers = 0"), r"wear.recalibrate.config \(recal.toml\): run.workers: must be >= 1"),
    (('profile = "@wheel_profile@"\nmate = "@rail_profile@"', 'profile = "S1002"\nmate = "60E1"'),
     r"wear.recalibrate.config: recal.toml uses neither placeholder"),
    (("[-25.0, -12.0, 0.0, 12.0, 25.0]", "[0.0, 500.0]"), r"bodies\[0\].positions_mm: position y = 500 mm"),
    (("order = 1", "order = 1\nspeed = 2"), r"mesh.speed: unknown key"),
    (("wheel_radius_mm = 460.0\n", ""), r"wheel_radius_mm"),
    (("n_levels = 3", "n_levels = 200", "elements_per_semi_axis = 3", "elements_per_semi_axis = 30"),
     r"estimated cost .* exceeds the limit"),
])
def test_bad_template_is_refused_when_the_scene_is_parsed(make_scene, tmp_path, edit, match):
    """Everything the calibration checks before its FEM fails at parse time, before any wear step (the cost:
    5 positions x 203 load stages on a 2D mesh of 30 elements per semi-axis, about 3 h)."""
    text = TEMPLATE_2D
    for old, new in zip(edit[::2], edit[1::2]):
        assert old in text
        text = text.replace(old, new)
    with pytest.raises(InputError, match=match):
        _recal_scene(make_scene, _template(tmp_path, text))


def test_cli_refuses_a_bad_template_before_writing(tmp_path, wear_dict, write_scene, capsys):
    """``python -m contact wear``: one line naming the template's key, exit code 2, no output folder."""
    template = _template(tmp_path, TEMPLATE_2D.replace("workers = 1", "workers = 0"))
    scene_file = write_scene(wear_dict(wear={"distance_km": 100.0, "steps": 2,
                                             "recalibrate": {"config": str(template)}}))
    assert main(["wear", str(scene_file), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["error: w.toml: wear.recalibrate.config (recal.toml): run.workers: must be >= 1, got 0"]
    assert not (tmp_path / "out").exists()


def test_recalibration_needs_a_template_and_per_body_tables(make_scene, tmp_path):
    with pytest.raises(InputError, match=r"wear.recalibrate.config: no such calibration template"):
        _recal_scene(make_scene, tmp_path / "missing.toml")
    with pytest.raises(InputError, match=r"wear.recalibrate.config: recalibration needs per-body \[layers\]"):
        make_scene(layers=None, wear={"inelastic": False, "recalibrate": {"config": str(_template(tmp_path))}})
    with pytest.raises(InputError, match=r"wear.recalibrate.every_steps"):
        make_scene(wear={"recalibrate": {"config": str(_template(tmp_path)), "every_steps": 0}})


def test_parsed_template_keeps_the_placeholders(make_scene, tmp_path):
    recal = _recal_scene(make_scene, _template(tmp_path)).settings.recalibrate
    (body,) = recal.calibration.bodies
    assert (body.profile, body.mate) == (PLACEHOLDERS["wheel"], PLACEHOLDERS["rail"])
    assert body.positions_mm == (-25.0, -12.0, 0.0, 12.0, 25.0) and recal.calibration.run.model == "2d"
    assert recal.bodies == ("wheel", "rail") and recal.every_steps == 1 and recal.due(1) and recal.due(2)
    assert recal.template == TEMPLATE_2D and recal.config == str((tmp_path / "recal.toml").resolve())


def test_worn_config_replaces_only_the_placeholders(make_scene, tmp_path):
    text = TEMPLATE_2D.replace('mate = "@rail_profile@"', 'mate = "60E1"')
    cfg = _recal_scene(make_scene, _template(tmp_path, text)).settings.recalibrate.calibration
    worn = worn_config(cfg, {"wheel": Path("/w/wheel.prw"), "rail": Path("/w/rail.prr")})
    assert (worn.bodies[0].profile, worn.bodies[0].mate) == ("/w/wheel.prw", "60E1")
    assert dataclasses.replace(worn.bodies[0], profile=cfg.bodies[0].profile) == cfg.bodies[0]


def _fake_calibration(calls, tables=("wheel",)):
    def fake(cfg, out_dir, scheduler=None, plots=None, show_progress=True, log=print, force=False, anchors=None,
             reanchor=False):
        calls.append({"cfg": cfg, "out_dir": Path(out_dir), "scheduler": scheduler, "plots": plots,
                      "show_progress": show_progress})
        Path(out_dir).mkdir(parents=True, exist_ok=True)
        written = {}
        for body in tables:
            shutil.copy(TABLES / ("wheel_S1002_default.json" if body == "wheel" else "rail_60E1_default.json"),
                        Path(out_dir) / f"{body}_layer_table.json")
            written[body] = Path(out_dir) / f"{body}_layer_table.json"
        return SimpleNamespace(tables=written, failed=[PositionNote("wheel", 9.0, "no table")])

    return fake


def test_the_calibration_gets_the_worn_profiles(make_scene, tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(recal_mod, "calibrate", _fake_calibration(calls))
    scene = _recal_scene(make_scene, _template(tmp_path))
    run = run_wear(scene, show_progress=False, work_dir=tmp_path / "work")
    (call,) = calls
    folder = tmp_path / "work" / "calibration" / "step_001_right"
    body = call["cfg"].bodies[0]
    assert (body.profile, body.mate) == (str((folder / "wheel.prw").resolve()), str((folder / "rail.prr").resolve()))
    assert call["cfg"].run == scene.settings.recalibrate.calibration.run
    assert call["out_dir"] == folder / "tables"
    assert (call["scheduler"], call["plots"], call["show_progress"]) == (None, False, False)
    for name, key in (("wheel.prw", "wheel"), ("rail.prr", "rail")):
        assert np.allclose(read_profile(folder / name).points, run.steps[0].profiles["right"][key].points, atol=1e-9)
    recalibrate_side(scene.settings.recalibrate, run.steps[0].profiles["right"], tmp_path / "dask",
                     scheduler="tcp://cluster:8786")
    assert calls[-1]["scheduler"] == "tcp://cluster:8786"


def test_cli_keeps_the_step_before_a_failed_recalibration(tmp_path, wear_dict, write_scene, monkeypatch, capsys):
    """The step is written before its recalibration runs: a failed calibration leaves step 1's files, exit 3."""
    def failing(*args, **kwargs):
        raise ConvergenceError("Newton did not converge")

    monkeypatch.setattr(recal_mod, "calibrate", failing)
    scene_file = write_scene(wear_dict(wear={"distance_km": 100.0, "steps": 2,
                                             "recalibrate": {"config": str(_template(tmp_path))}},
                                       passes={"max": 3}))
    out = tmp_path / "out"
    assert main(["wear", str(scene_file), "--out", str(out), "--quiet", "--no-plots"]) == 5
    assert "step 1: wear.recalibrate (right side): calibration of the worn profiles failed" in capsys.readouterr().err
    assert (out / "profiles" / "step_001_right_wheel.prw").is_file()
    res = json.loads((out / "result.json").read_text())
    assert res["status"].startswith("stopped: step 1: ") and "wear.recalibrate" in res["status"]
    assert len(res["steps"]) == 1
    assert res["steps"][0]["files"]


def test_recalibrate_side_returns_the_written_tables(make_scene, tmp_path, monkeypatch):
    monkeypatch.setattr(recal_mod, "calibrate", _fake_calibration([], tables=("wheel", "rail")))
    scene = _recal_scene(make_scene, _template(tmp_path))
    profiles = {"wheel": scene.wheel_rail.wheel_profile, "rail": scene.wheel_rail.rail_profile}
    tables = recalibrate_side(scene.settings.recalibrate, profiles, tmp_path / "side").tables
    assert sorted(tables) == ["rail", "wheel"] and tables["rail"].body == "rail"
    monkeypatch.setattr(recal_mod, "calibrate", _fake_calibration([], tables=()))
    with pytest.raises(InputError, match=r"here: the calibration wrote no layer table .*: no table"):
        recalibrate_side(scene.settings.recalibrate, profiles, tmp_path / "none", what="here")


@pytest.mark.parametrize("error, kind", [(ConvergenceError("Newton did not converge at 1.2 MPa"), ConvergenceError),
                                         (InputError("mesh.h_max_mm", "below h_min"), InputError)])
def test_a_failed_calibration_stops_the_loop_naming_the_step(make_scene, tmp_path, monkeypatch, error, kind):
    def failing(*args, **kwargs):
        raise error

    monkeypatch.setattr(recal_mod, "calibrate", failing)
    scene = _recal_scene(make_scene, _template(tmp_path))
    profiles = {"wheel": scene.wheel_rail.wheel_profile, "rail": scene.wheel_rail.rail_profile}
    with pytest.raises(kind, match=rf"^here: calibration of the worn profiles failed: {error}$"):
        recalibrate_side(scene.settings.recalibrate, profiles, tmp_path / "side", what="here")
    with pytest.raises(WearStopped, match=r"stopped at step 1 .*step 1: wear.recalibrate \(right side\): "
                                          rf"calibration of the worn profiles failed: {error}") as stop:
        run_wear(scene, show_progress=False, work_dir=tmp_path / "work")
    assert len(stop.value.run.steps) == 1 and stop.value.run.stopped.startswith("step 1: ")


def test_settings_record_the_recalibration_under_the_former_keys(make_scene, tmp_path):
    """result.json ``inputs.settings`` keeps its keys (the template as file, text and interval)."""
    keys = ["max_depth_per_step_mm", "smoothing_mm", "grid_mm", "rail_passes_per_wheel_pass", "inelastic",
            "layer_state", "workers", "scheduler", "conicity_amplitude_mm", "recalibrate_config",
            "recalibrate_template", "recalibrate_every"]
    plain = make_scene().settings.to_dict()
    assert list(plain) == keys and (plain["recalibrate_config"], plain["recalibrate_every"]) == ("", 0)
    with_recal = _recal_scene(make_scene, _template(tmp_path)).settings.to_dict()
    assert list(with_recal) == keys and with_recal["recalibrate_template"] == TEMPLATE_2D


@pytest.mark.slow
def test_coarse_3d_template_on_one_rail_position(make_scene, tmp_path):
    """calibration/configs/test_coarse.toml with the placeholders: one 3D FEM position (4-21 s measured on the
    shared machine) on the scene's profiles gives a rail table at that position."""
    text = (REPO / "calibration" / "configs" / "test_coarse.toml").read_text()
    text = text.replace('profile = "60E1"', 'profile = "@rail_profile@"')
    text = text.replace('mate = "S1002"', 'mate = "@wheel_profile@"\nwheel_radius_mm = 460.0')
    scene = _recal_scene(make_scene, _template(tmp_path, text))
    profiles = {"wheel": scene.wheel_rail.wheel_profile, "rail": scene.wheel_rail.rail_profile}
    tables = recalibrate_side(scene.settings.recalibrate, profiles, tmp_path / "side").tables
    assert list(tables) == ["rail"] and tables["rail"].y_range_mm == (0.0, 0.0)
    assert tables["rail"].characteristic_at(0.0).elastic_limit_MPa > 0


def _fake_lawless_calibration(out_tables):
    """A calibration writing the shipped tables without their rolling law (as a fresh calibration does)."""
    def fake(cfg, out_dir, scheduler=None, plots=None, show_progress=True, log=print, force=False, anchors=None,
             reanchor=False):
        Path(out_dir).mkdir(parents=True, exist_ok=True)
        written = {}
        for body in out_tables:
            data = json.loads((TABLES / ("wheel_S1002_default.json" if body == "wheel" else
                                         "rail_60E1_default.json")).read_text())
            data.pop("rolling_law")  # a lawless table of format 4 stays version 4
            written[body] = Path(out_dir) / f"{body}_layer_table.json"
            written[body].write_text(json.dumps(data))
        return SimpleNamespace(tables=written, failed=[])

    return fake


def test_recalibrated_tables_keep_the_scene_tables_rolling_law(make_scene, tmp_path, monkeypatch):
    """A table recalibrated on the worn profiles carries the scene table's rolling law (else its passes would
    silently fall back to the relaxed rule)."""
    monkeypatch.setattr(recal_mod, "calibrate", _fake_lawless_calibration(("wheel", "rail")))
    scene = _recal_scene(make_scene, _template(tmp_path))
    recal = scene.settings.recalibrate
    assert all(t.rolling_law is not None for t in recal.scene_tables.values())
    profiles = {"wheel": scene.wheel_rail.wheel_profile, "rail": scene.wheel_rail.rail_profile}
    tables = recalibrate_side(recal, profiles, tmp_path / "side").tables
    assert LayerTable.read(tmp_path / "side" / "tables" / "rail_layer_table.json").rolling_law is None
    for body, table in tables.items():
        assert table.rolling_law is recal.scene_tables[body].rolling_law


def test_with_rolling_law_keeps_a_tables_own_law(tmp_path):
    shipped = LayerTable.read(TABLES / "rail_60E1_default.json")
    data = json.loads((TABLES / "rail_60E1_default.json").read_text())
    data.pop("rolling_law")  # a lawless table of format 4 stays version 4
    (tmp_path / "t.json").write_text(json.dumps(data))
    lawless = previous_table(tmp_path / "t.json")
    assert lawless is not None and lawless.rolling_law is None
    assert previous_table(tmp_path / "missing.json") is None
    carried = with_rolling_law(lawless, shipped)
    assert carried.rolling_law is shipped.rolling_law and carried.positions == lawless.positions
    assert with_rolling_law(lawless, None) is lawless
    assert with_rolling_law(shipped, lawless) is shipped
