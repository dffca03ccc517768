"""wheel_rail scenes: validation naming the key, a sweep with a bad case still computes the others, CLI run."""

import dataclasses
import json
from pathlib import Path

import pytest

from contact.__main__ import main
from contact.scenes.scene import read_scene_data
from contact.wheel_rail.parse import parse_wheel_rail_scene
from contact.run_files import run_wheel_rail_scene
from wrlayer.errors import InputError


def _run(data, scene_path, out_dir, plots=False):
    return run_wheel_rail_scene(parse_wheel_rail_scene(data, scene_path), out_dir, plots).to_dict()


def _scene(**sections):
    data = {"type": "wheel_rail", "wheel": {"side": "right"}}
    data.update(sections)
    return data


@pytest.mark.parametrize("data, match", [
    (_scene(track={"gauge": 1435.0}), r"s.toml: track.gauge: unknown key"),
    (_scene(wheel={"side": "middle"}), r"s.toml: wheel.side: must be one of right, left, both, got 'middle'"),
    (_scene(track={"gauge_mm": 1300.0}), r"s.toml: track.gauge_mm: impossible gauge"),
    (_scene(load={"vertical_load_N": -1.0}), r"s.toml: load.vertical_load_N: must be >= 0.001"),
    (_scene(profiles={"rail": "S1002"}), r"s.toml: profiles.rail: S1002 is a wheel profile"),
    (_scene(profiles={"wheel": "missing.prw"}), r"s.toml: profiles.wheel: no such profile file"),
    (_scene(sweep={"lateral_mm": [0.0, 1.0], "yaw_rad": [0.0]}), r"s.toml: sweep.mode: 'zip' needs"),
    (_scene(layers={"rail": "none.json"}), r"s.toml: layers.rail: no such calibration table"),
    (_scene(layers={"rail": {"u_mm": [0.0, 0.01], "p_MPa": [0.0, 100.0]}}),
     r"s.toml: layers.rail: must be a calibration table file"),
    (_scene(layers={"rail": "none.json", "position_mm": {"rail": 0.0}}), r"s.toml: layers.position_mm: unknown key"),
    (_scene(material={"E_MPa": 2e5, "G_MPa": 8e4}), r"s.toml: material.G_MPa: give either"),
    (_scene(passes={"memory": "sticky"}), r"s.toml: passes.memory: must be one of rolling, relaxed, state_kept"),
    (_scene(passes={"memory": "relaxed", "hardening": True}), r"s.toml: passes.memory: 'relaxed' contradicts"),
    (_scene(passes={"traction_coefficient": -2.0}), r"s.toml: passes.traction_coefficient: must be >= -1"),
])
def test_validation_names_the_key(tmp_path, data, match):
    with pytest.raises(InputError, match=match):
        parse_wheel_rail_scene(data, tmp_path / "s.toml")


@pytest.mark.parametrize("passes, rule", [({}, "rolling"), ({"memory": "relaxed"}, "relaxed"),
                                         ({"hardening": True}, "state_kept")])
def test_passes_memory_reaches_the_solver_inputs(tmp_path, passes, rule):
    scene = parse_wheel_rail_scene(_scene(passes={"max": 4, "traction_coefficient": 0.2, **passes}),
                                   tmp_path / "s.toml")
    opts = scene.inputs("right").passes.options
    assert (opts.rule, opts.traction_coefficient, opts.max_passes) == (rule, 0.2, 4)


def test_sweep_with_bad_case_computes_the_others(tmp_path):
    data = _scene(sweep={"lateral_mm": [0.0, 25.0, 3.0]}, wheel={"side": "both"},
                  wheelset={"roll_rad": 0.0})
    result = _run(data, tmp_path / "s.toml", tmp_path, plots=False)
    cases = result["cases"]
    assert result["n_failed"] == 1
    assert "flange through the rail" in cases[1]["error"] and "lateral 25 mm" in cases[1]["error"]
    for k in (0, 2):
        for side in ("right", "left"):
            w = cases[k]["wheels"][side]
            assert abs(w["vertical_force_N"] - 10000.0) / 10000.0 < 1e-6
            assert w["patches"][0]["creepage_x"] is not None
    json.dumps(result)  # JSON-serialisable


def test_cli_runs_a_scene_with_pictures(tmp_path):
    scene = tmp_path / "wr.toml"
    scene.write_text('type = "wheel_rail"\n[wheel]\nside = "both"\n[wheelset]\nroll_rad = "auto"\n'
                     '[sweep]\nlateral_mm = [0.0, 6.0]\nyaw_rad = [0.0, 0.012]\n', encoding="utf-8")
    out = tmp_path / "out"
    assert main(["simulate", str(scene), "--out", str(out), "--plots"]) == 0
    result = json.loads((out / "result.json").read_text())
    assert {"profiles_in_contact.png", "sweep.png"} <= set(result["pictures"])
    assert all((out / p).is_file() for p in result["pictures"])
    assert result["cases"][1]["roll_rad"] > 0  # the rigid wheelset rolls when the right flange climbs
    # a rerun into the same folder without pictures leaves none of the earlier ones behind
    assert main(["simulate", str(scene), "--out", str(out)]) == 0
    assert not list(out.glob("*.png")) and (out / "result.json").is_file()


#: Baseline of the shipped layered sweep (scenes/wheel_rail_sweep_layers.toml, passes to shakedown on the shipped
#: tables; the default normal method, the exact half-space solver; FASTSIM's spin about each patch's force centroid):
#: case -> side -> per patch (normal force N, Fx N, Fy N, rail profile coordinate mm).
LAYERED_SWEEP = {
    0: {"right": [(9997.46414849901, -475.6107847403642, 225.88189793747864, 0.19148214311347828)],
        "left": [(9997.464148499013, -475.6107847395733, -225.88189793686246, 0.19148214311347828)]},
    10: {"right": [(2551.6724425167886, 362.3036430092829, 673.805662299334, -26.52468085055775),
                   (7158.16009521087, 504.0050211334485, 2086.592965121193, -15.523483665065557)],
         "left": [(10025.944860228177, -164.73179791327362, 3003.259175946201, 4.942844800275009)]},
    20: {"right": [(11996.735044267461, 2769.5581530407153, 2281.098547435183, -32.10518400123569)],
         "left": [(10034.81187610517, -139.6656290563679, 3007.195480697671, 4.089986196581998)]},
}


def test_shipped_calibrated_tables_cover_the_shipped_layered_sweep(tmp_path):
    """scenes/tables/*_default.json (output of `make calibrate`) reach the contacts of the layered sweep: its first,
    middle and last case (tread, tread + gauge corner, flange) give the baseline forces and dents."""
    path, data = read_scene_data(Path(__file__).resolve().parents[3] / "scenes" / "wheel_rail_sweep_layers.toml")
    scene = parse_wheel_rail_scene(data, path)
    assert len(scene.cases) == 21
    few = dataclasses.replace(scene, sweep=dataclasses.replace(scene.sweep, cases=tuple(
        scene.cases[k] for k in LAYERED_SWEEP)))
    result = run_wheel_rail_scene(few, tmp_path, plots=False)
    assert result.n_failed == 0
    for case, expected in zip(result.cases, LAYERED_SWEEP.values()):
        for side, patches in expected.items():
            got = [(p.normal_force_N, p.Fx_N, p.Fy_N, p.y_rail_mm) for p in case.wheels[side].patches]
            assert len(got) == len(patches)
            for values, baseline in zip(got, patches):
                assert values == pytest.approx(baseline, rel=1e-6, abs=1e-6)
    flange = result.cases[2].wheels["right"].patches[0].passes[-1]
    # the dents of the tables' rolling law at five levels (tables fitted relative to the value from 1.1 p_2 on the FEM
    # curve read every 0.025 p_2; in the target's measure every 0.05 p_2 0.0068700 / 0.0030759 mm; fitted
    # on its levels alone 0.0068374 / 0.0031331 mm, the law at three levels 0.0068374 / 0.0031473 mm,
    # Kik-Piotrowski 0.0099145 / 0.0046098 mm; the law of the round patches alone, without its patch-shape nodes,
    # 0.0068457 / 0.0030831 mm)
    assert flange.max_cumulative_residual_mm["rail"] == pytest.approx(0.006955621072572088, rel=1e-6)
    assert flange.max_cumulative_residual_mm["wheel"] == pytest.approx(0.0031221013536401787, rel=1e-6)
    assert len(result.cases[2].deformed_profiles) > 0
    tables = [json.loads((path.parent / "tables" / f).read_text()) for f in
              ("rail_60E1_default.json", "wheel_S1002_default.json")]
    assert all(t["header"]["model"] == "3d" and t["header"]["config"] == "calibration/configs/default.toml"
               for t in tables)


def test_sweep_picture_abscissa_and_panels(tmp_path):
    """sweep.png: the lateral displacement as abscissa when it varies, else the case number; one panel per
    quantity (Y/Q included); a failed case is drawn, not dropped."""
    from types import SimpleNamespace as Record

    from contact.wheel_rail.plots import _sweep_axis, _sweep_plot

    def case(lateral, yq, error=False):
        if error:
            return Record(lateral_mm=lateral, wheels=None, error="x")
        patch = Record(y_rail_mm=-lateral, contact_angle_rad=0.01 * lateral, normal_force_N=1e4, p_max_MPa=900.0,
                       Fx_N=100.0, Fy_N=-50.0, normal_track=(0.0, 0.1, 0.99))
        return Record(lateral_mm=lateral, error=None, wheels={"right": Record(
            patches=[patch], Y_over_Q=yq, force_on_wheel_track_N=(0.0, 1e4 * yq, 1e4))})

    varying = Record(inputs={"title": "t"}, cases=[case(0.0, 0.1), case(1.0, 0.2), case(2.0, 0.0, error=True)])
    assert _sweep_axis(varying)[0] == "lateral_mm"
    fixed = Record(inputs={"title": "t"}, cases=[case(1.0, 0.1), case(1.0, 0.3)])
    assert _sweep_axis(fixed) == ("case", "case")
    for result, name in ((varying, "a.png"), (fixed, "b.png")):
        path = _sweep_plot(result, tmp_path / name)
        assert path.stat().st_size > 10_000


def test_a_sigterm_dropped_inside_a_c_callback_ends_the_sweep_after_the_case(tmp_path, monkeypatch):
    """A SIGTERM whose exception a C callback swallowed (numba compiling a kernel on a clean checkout) leaves only its
    flag: the sweep stops after the case it arrived in, not after all of them (a kill during a first run's
    compilation once let a 201-case sweep run on for more than 60 s)."""
    from contact.wheel_rail.run import solve_cases
    from contact.wheel_rail.track_geometry import place_rail
    from wrlayer import errors

    scene = parse_wheel_rail_scene(_scene(sweep={"lateral_mm": [0.0, 1.0, 2.0]}), tmp_path / "s.toml")
    cases = solve_cases(scene, place_rail(scene.rail_profile, scene.layout), tmp_path)
    assert next(cases)[0].error is None
    monkeypatch.setattr(errors, "_terminated", True)
    with pytest.raises(errors.Terminated):
        next(cases)
