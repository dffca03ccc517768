"""The shared validation layer (wrlayer.validate) and the cost guard (wrlayer.cost, contact.scenes.cost)."""

import math

import numpy as np
import pytest

from wrlayer import validate
from wrlayer.cost import CostError, CostEstimate, guard
from wrlayer.errors import InputError


@pytest.mark.parametrize("value,problem", [
    (True, "must be a number, got boolean"), ("1.0", "must be a number, got string"),
    ([1.0], "must be a number, got list"), (math.nan, "must be a finite number"),
    (-math.inf, "must be a finite number"), (1e300, "must be of magnitude"), (10 ** 400, "huge integer"),
    (None, "must be a number, got NoneType"),
])
def test_number_refuses_what_is_not_a_finite_real(value, problem):
    with pytest.raises(InputError, match=problem) as err:
        validate.number(value, "a.toml: load.x")
    assert str(err.value).startswith("a.toml: load.x: ")


def test_number_bounds_and_integer():
    assert validate.number(3, "x", gt=0, le=3) == 3.0
    with pytest.raises(InputError, match="must be <= 3, got 4"):
        validate.number(4, "x", le=3)
    with pytest.raises(InputError, match="must be an integer, got number 3.0"):
        validate.integer(3.0, "x")
    with pytest.raises(InputError, match="must be <= 10, got 11"):
        validate.integer(11, "x", le=10)


def test_number_list_is_flat_finite_and_bounded():
    assert validate.number_list([0, 1.5], "x").tolist() == [0.0, 1.5]
    with pytest.raises(InputError, match=r"x\[1\]: must be a number \(a flat list is expected\)"):
        validate.number_list([0.0, [1.0]], "x")
    with pytest.raises(InputError, match=r"x\[0\]: must be a number, got boolean"):
        validate.number_list([True], "x")
    with pytest.raises(InputError, match="has 11 values"):
        validate.number_list([0.0] * 11, "x", max_len=10)
    with pytest.raises(InputError, match="needs at least 2 values"):
        validate.number_list([0.0], "x", min_len=2)
    with pytest.raises(InputError, match=r"x\[2\]: must be > 0"):
        validate.number_list([1.0, 2.0, -1.0], "x", gt=0)


def test_messages_stay_one_short_line():
    long = list(range(10000))
    with pytest.raises(InputError) as err:
        validate.text(long, "a.toml: title")
    assert len(str(err.value)) < 150 and "\n" not in str(err.value)


def test_keys_name_the_file_and_key_path():
    keys = validate.Keys("s.toml", "", {"load": {"f": "x"}, "typo": 1})
    with pytest.raises(InputError, match="^s.toml: typo: unknown key"):
        keys.check_known(("load",))
    with pytest.raises(InputError, match="^s.toml: load.f: must be a number"):
        keys.sub("load").number("f")
    with pytest.raises(InputError, match="^s.toml: load.g: missing"):
        keys.sub("load").number("g")


def test_rewrap_never_names_an_input_twice():
    inner = InputError("a.toml: track.gauge_mm", "must be > 0")
    assert str(validate.rewrap(inner, "a.toml: track")) == "a.toml: track.gauge_mm: must be > 0"
    assert str(validate.rewrap(InputError("a.toml: x", "bad"), "a.toml: layer")) == "a.toml: layer: x: bad"
    assert str(validate.rewrap(InputError("gauge_mm", "bad"), "a.toml: track")) == "a.toml: track: gauge_mm: bad"


def test_cost_guard_refuses_with_the_estimate_unless_forced():
    est = CostEstimate("big.toml", {"cases": 1e7, "wheels": 2}, 4e5)
    with pytest.raises(CostError) as err:
        guard(est)
    msg = str(err.value)
    assert msg.startswith("big.toml: estimated cost 1e+07 cases x 2 wheels ~ 4.63 days exceeds the limit")
    assert "--force" in msg and err.value.exit_code == 2
    assert guard(est, force=True) is est
    assert guard(CostEstimate("small.toml", {"passes": 3}, 0.5)).seconds == 0.5
    with pytest.raises(CostError):
        guard(CostEstimate("nan.toml", {}, math.nan))


def test_scene_cost_grows_with_passes_cells_and_grid(tmp_path):
    import dataclasses
    from pathlib import Path

    from contact.scenes.cost import scene_cost
    from contact.scenes.scene import load_scene

    scene = load_scene(Path(__file__).resolve().parents[2] / "scenes" / "paper_shakedown.toml")
    base = scene_cost(scene)
    assert 0 < base.seconds < 60 and base.factors["passes"] == scene.passes.max
    finer = dataclasses.replace(scene, method=dataclasses.replace(scene.method, grid_mm=scene.method.grid_mm / 10))
    more = dataclasses.replace(scene, passes=dataclasses.replace(scene.passes, max=100 * scene.passes.max))
    assert scene_cost(finer).seconds == pytest.approx(10 * base.seconds, rel=0.01)
    assert scene_cost(more).seconds == pytest.approx(100 * base.seconds, rel=1e-9)
    assert np.isfinite(base.seconds)


def test_absurd_scene_cost_is_refused_through_the_command_line(tmp_path, capsys):
    """passes.max = 100000 (the hard limit) on a 0.01 mm grid over 80 mm with FASTSIM: refused up front with the
    estimate, exit 2, nothing written; --force would run it."""
    from contact.__main__ import main

    scene = tmp_path / "costly.toml"
    scene.write_text("[load]\nnormal_force_N = 1e5\nrolling_radius_mm = 460.0\n[material]\nE_MPa = 2.1e5\n"
                     "poisson = 0.3\n[separation]\nlateral_radius_mm = 300.0\nhalf_width_mm = 40.0\n"
                     "[layers.combined]\nu_mm = [0.0, 0.02, 0.03, 0.06]\np_MPa = [0.0, 1190.0, 1456.0, 1900.0]\n"
                     "[tangential]\ncreepage_x = 0.002\nfriction = 0.3\n[passes]\nmax = 100000\n"
                     "tolerance_mm = 1e-9\n[method]\ngrid_mm = 0.01\nfastsim_cells = 200\n")
    out = tmp_path / "out"
    t0 = __import__("time").perf_counter()
    rc = main(["simulate", str(scene), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and "\n" not in err and not out.exists()
    assert err.startswith("error: costly.toml: estimated cost 100000 passes x 8000 strips x 200 cells x 48 exact "
                          "cells ~ ")                                   # the default normal method: exact
    assert "--force" in err
    assert __import__("time").perf_counter() - t0 < 30


def test_exact_solver_scenes_cost_more():
    import dataclasses
    from pathlib import Path

    from contact.scenes.cost import scene_cost
    from contact.scenes.scene import load_scene

    scene = load_scene(Path(__file__).resolve().parents[2] / "scenes" / "paper_with_layer.toml")
    exact = dataclasses.replace(scene, method=dataclasses.replace(scene.method, normal="exact", exact_cells=1024))
    assert scene_cost(exact).seconds > 10 * scene_cost(scene).seconds
    assert scene_cost(exact).factors["exact cells"] == 1024
