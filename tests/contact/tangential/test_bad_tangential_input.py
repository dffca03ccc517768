"""Bad input to the tangential solution: one-line InputErrors naming the key or the patch; a solve that does not
converge is a ConvergenceError naming the patch."""

import dataclasses

import numpy as np
import pytest

from contact.__main__ import main
from contact.normal.kik_piotrowski import NormalProblem, solve_normal
from contact.normal.patch import Patch
from contact.scenes.scene import parse_scene
from contact.tangential.exact_rolling import RollingOptions
from contact.tangential.fastsim import Creepage
from contact.tangential.method import solve_for_normal_solution
from contact.wheel_rail.parse import parse_wheel_rail_scene
from wrlayer.errors import ConvergenceError, InputError

E_MPa, NU, MU = 210000.0, 0.28, 0.3
G_MPa = E_MPa / (2 * (1 + NU))
BASE = {"load": {"normal_force_N": 1e5, "rolling_radius_mm": 460.0}, "material": {"E_MPa": E_MPa, "poisson": NU},
        "separation": {"lateral_radius_mm": 300.0}}


@pytest.mark.parametrize("tangential, message", [
    ({"creepage_x": 0.5, "friction": MU}, "x.toml: tangential.creepage_x: must be within +-0.1, got 0.5"),
    ({"creepage_y": -0.2, "friction": MU}, "x.toml: tangential.creepage_y: must be within +-0.1, got -0.2"),
    ({"spin_per_mm": 0.05, "friction": MU}, "x.toml: tangential.spin_per_mm: must be within +-0.01, got 0.05"),
    ({"creepage_x": 0.002, "friction": 0.0}, "x.toml: tangential.friction: must be > 0 with creepages"),
])
def test_scene_creepages_and_friction(tangential, message):
    with pytest.raises(InputError, match=message.replace("+", r"\+")):
        parse_scene({**BASE, "tangential": tangential}, "x.toml")


def test_friction_zero_without_creepage_is_fine():
    assert parse_scene({**BASE, "tangential": {"friction": 0.0}}, "x.toml").tangential.friction == 0.0


def test_unknown_method_names_the_key():
    with pytest.raises(InputError, match="x.toml: method.tangential: must be one of fastsim, fastrip, exact"):
        parse_scene({**BASE, "method": {"tangential": "contact"}}, "x.toml")


def test_wheel_rail_friction_zero_with_a_tangential_method(tmp_path):
    data = {"type": "wheel_rail", "tangential": {"friction": 0.0}, "method": {"tangential": "exact"}}
    with pytest.raises(InputError, match=r"w.toml: tangential.friction: must be > 0 with method.tangential"):
        parse_wheel_rail_scene(data, tmp_path / "w.toml")
    with pytest.raises(InputError, match=r"w.toml: method.tangential: must be one of"):
        parse_wheel_rail_scene({"type": "wheel_rail", "method": {"tangential": "kalker"}}, tmp_path / "w.toml")


def test_cli_prints_one_line_and_exits_2(tmp_path, capsys):
    scene = tmp_path / "x.toml"
    scene.write_text('[load]\nnormal_force_N = 1e5\nrolling_radius_mm = 460.0\n[material]\nE_MPa = 210000.0\n'
                     'poisson = 0.28\n[separation]\nlateral_radius_mm = 300.0\n[tangential]\ncreepage_x = 2.0\n'
                     'friction = 0.3\n', encoding="utf-8")
    assert main(["simulate", str(scene), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["error: x.toml: tangential.creepage_x: must be within +-0.1, got 2.0"]


def _solution():
    y = np.linspace(-10, 10, 801)
    return solve_normal(NormalProblem(y, y ** 2 / 600.0, 1e5, 460.0, E_MPa, NU))


def test_a_patch_without_pressure_is_named():
    sol = _solution()
    p = sol.patches[0]
    empty = dataclasses.replace(sol, patches=[Patch(p.grid_mm, p.y_mm, p.x_lead_mm, np.zeros_like(p.p_peak_MPa))])
    with pytest.raises(InputError, match="patch 1: carries no pressure"):
        solve_for_normal_solution(empty, Creepage(0.002, 0, 0), MU, G_MPa, NU, "fastsim")


def test_non_converged_exact_solve_names_the_patch():
    with pytest.raises(ConvergenceError, match=r"tangential solution \(exact\) of patch 1: "):
        solve_for_normal_solution(_solution(), Creepage(0.002, 0, 0.0012), MU, G_MPa, NU, "exact", nx=24,
                                  options=RollingOptions(tol=1e-12, max_sweeps=1))
