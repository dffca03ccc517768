"""The moving-load FEM: its load vector is the engine's Hertz load; a load that does not move reproduces the
static indentation; 2D frictionless EPP rolling shakes down at p0/k = 3.5 and ratchets at p0/k = 5.0 (Bhargava,
Hahn & Wert 1985; Johnson's shakedown limit 4 k); a coarse 3D pass gives a groove of the order of the static dent;
a failed step names the level, pass and step and the completed passes are written."""

import json

import numpy as np
import pytest

import calibration.rolling.passes as passes_module
from calibration.fem.assembly import discretise
from calibration.fem.solver_state import SolverState
from calibration.hertz.load import HertzLoad
from calibration.rolling.config import (ContactSettings, RollingConfig, RollingRunSettings, TrackMeshSettings,
                                        TrackSettings)
from calibration.rolling.moving_load import MovingHertzLoad, SurfaceForces
from calibration.rolling.passes import MovingLoadPass, RollingConvergenceError, RollingSolver, roll
from calibration.rolling.run import build_model, level_pressures, run_rolling, static_dents
from calibration.rolling.track_mesh import track_mesh
from wrlayer.errors import ConvergenceError


def config(model="2d", levels=(3.5,), unit="k", n=3.0, length=1.5, step=0.5, passes=1, c=0.0, size=5.0):
    return RollingConfig(contact=ContactSettings(a_mm=1.0, levels=levels, model=model, level_unit=unit,
                                                 traction_coefficient=c),
                         track=TrackSettings(length_factor=length, step_factor=step, n_passes=passes, ramp_steps=2),
                         mesh=TrackMeshSettings(elements_per_semi_axis=n, size_factor=size),
                         run=RollingRunSettings(plots=False, linear_solver="scipy"))


@pytest.mark.parametrize("model", ["2d", "3d"])
def test_load_vector_is_the_engines_hertz_load(model):
    cfg = config(model, n=2.0, size=3.0)
    tm = track_mesh(cfg.contact, cfg.track, cfg.mesh)
    disc = discretise(tm.mesh)
    b = None if model == "2d" else 1.0
    sf = SurfaceForces(disc.basis, MovingHertzLoad(1.0, b, 0.3), (-1.5, 1.5))
    f = sf.force(0.4, 2.0)
    ref = (HertzLoad(0.4, 1.0) if b is None else HertzLoad(0.0, 1.0, 1.0, centre_x_mm=0.4)).prepare(disc.basis)
    dim = tm.dim
    assert np.allclose(f[dim - 1::dim], 2.0 * ref.force_per_MPa[dim - 1::dim], rtol=0, atol=1e-12)
    assert np.allclose(f[0::dim], -0.3 * f[dim - 1::dim])  # traction q = c p along +x
    assert -f[dim - 1::dim].sum() == pytest.approx(2.0 * sf.load.resultant_per_MPa(), rel=2e-3)


@pytest.mark.parametrize("model,levels", [("2d", (5.0,)), pytest.param("3d", (1.5,), marks=pytest.mark.slow)])
def test_load_that_does_not_move_is_the_static_indentation(model, levels):
    cfg = config(model, levels=levels, unit="k" if model == "2d" else "p_y", n=3.0 if model == "2d" else 2.0,
                 size=5.0 if model == "2d" else 3.0)
    tm = track_mesh(cfg.contact, cfg.track, cfg.mesh)
    m = build_model(cfg, tm)
    p0 = level_pressures(cfg, m.p_y_MPa)[0]
    static = static_dents(m, cfg, [p0])[0]
    solver = RollingSolver(m.prob, m.forces, p0)
    ramp = int(np.ceil(p0 / (0.1 * m.p_y_MPa) - 1e-9))  # the static path's increments (EPP: path dependent)
    records = list(roll(solver, SolverState.virgin(m.disc), [0.0], 1, ramp))
    state = [r for r in records if isinstance(r, MovingLoadPass)][0].state
    dent = m.probe.depth_at(state.u_mm, 0.0)
    assert static.dent_mm > 0
    assert dent == pytest.approx(static.dent_mm, rel=5e-3)
    loaded = [r for r in records if not isinstance(r, MovingLoadPass)]
    assert len(loaded) == ramp + 1


@pytest.fixture(scope="module")
def rolling_2d(tmp_path_factory):
    """Frictionless EPP line contact at p0/k = 3.5 (below the shakedown limit 4 k) and 5.0 (above), 4 passes."""
    return run_rolling(config("2d", levels=(3.5, 5.0), passes=4, size=15.0), tmp_path_factory.mktemp("roll2d"))


def increments(values):
    v = np.asarray(values)
    return np.diff(v)


def test_2d_shakedown_at_3_5_k(rolling_2d):
    lv = rolling_2d.levels[0]
    eq = increments(lv.max_eq_plastic_strain)
    g = np.abs(increments(lv.groove_mm))
    assert lv.max_eq_plastic_strain[0] > 0  # it yields (p_y ~ 3.1 k) ...
    assert np.all(eq <= 1e-3 * lv.max_eq_plastic_strain[0])  # ... and then no more plastic strain: shakedown
    assert g[-1] <= 1e-3 * lv.groove_mm[0] and g[-1] <= g[0]


def test_2d_ratcheting_at_5_k(rolling_2d):
    lv = rolling_2d.levels[1]
    eq = increments(lv.max_eq_plastic_strain)
    assert np.all(eq > 0.1 * lv.max_eq_plastic_strain[0])  # a steady plastic strain increment every pass
    assert eq[-1] == pytest.approx(eq[-2], rel=0.3)


@pytest.mark.slow
def test_coarse_3d_pass(tmp_path):
    cfg = config("3d", levels=(1.7,), unit="p_y", n=2.0, length=1.0, step=0.5, size=3.0)
    res = run_rolling(cfg, tmp_path)
    lv = res.levels[0]
    assert 600.0 < res.p_y_MPa < 900.0  # analytic 1.61 Y = 805 MPa, coarse mesh
    assert 0.6 < lv.groove_mm[0] / lv.static_dent_mm < 1.0
    data = json.loads((tmp_path / "rolling.json").read_text())
    assert data["levels"][0]["groove_mm"] == lv.groove_mm
    assert data["levels"][0]["layer_groove_mm"]["relaxed"][0] == pytest.approx(lv.static_dent_mm, rel=0.05)


def test_failed_step_names_level_pass_and_step_and_keeps_passes(tmp_path, monkeypatch):
    cfg = config("2d", levels=(3.5,), passes=3, n=2.0, length=1.0, step=1.0, size=4.0)
    real = passes_module.newton_increment
    after_first_pass = []

    def failing(*args, **kwargs):
        if after_first_pass:
            raise ConvergenceError("Newton did not converge (test)")
        return real(*args, **kwargs)

    monkeypatch.setattr(passes_module, "newton_increment", failing)
    with pytest.raises(RollingConvergenceError, match=r"level 0 \(p0 = [0-9.]+ MPa\), pass 2, step 0 "):
        run_rolling(cfg, tmp_path, progress=after_first_pass.append)
    data = json.loads((tmp_path / "rolling.json").read_text())
    assert data["failed"].startswith("level 0")
    assert len(data["levels"][0]["groove_mm"]) == 1


def test_traction_pushes_the_surface_forward(tmp_path):
    """A traction q = c p along +x (c = 0.3) moves the surface forward and deepens the plastic strain at p0/k = 3.5
    (with c > 0.25 the largest shear is at the surface: Johnson's shakedown limit drops below 4 k)."""
    dry, wet = (run_rolling(config("2d", levels=(3.5,), n=2.0, length=1.0, c=c), tmp_path / str(c)).levels[0]
                for c in (0.0, 0.3))
    assert wet.shift_mm[0] > dry.shift_mm[0] + 1e-4
    assert wet.max_eq_plastic_strain[0] > dry.max_eq_plastic_strain[0]
