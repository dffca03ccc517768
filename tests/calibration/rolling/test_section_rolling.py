"""The rolling FEM on a profile section: the moving load's resultant is the Hertz resultant and acts along the
inward normal of the (tilted) surface, rail and wheel; a load that does not move reproduces the static indentation on the same
section mesh; a tiny coarse pass leaves a groove of the order of the static dent, deepest on the centreline."""

import numpy as np
import pytest

from calibration.fem.assembly import discretise
from calibration.fem.solver_state import SolverState
from calibration.rolling.config import parse_rolling_config
from calibration.rolling.cost import dof_count
from calibration.rolling.moving_load import MovingHertzLoad, SurfaceForces
from calibration.rolling.passes import MovingLoadPass, RollingSolver, roll
from calibration.rolling.run import build_model, level_pressures, run_rolling, static_dents
from calibration.rolling.section_track import section_track_mesh
from meshes.profiles import load_profile

TABLE = "scenes/tables/rail_60E1_default.json"
WHEEL = "scenes/tables/wheel_S1002_default.json"


def config(y_mm=0.0, n=1.0, levels=(1.3,), c=0.0, passes=1, step=0.5, table=TABLE):
    return parse_rolling_config({
        "contact": {"body": "section", "table": table, "y_mm": y_mm, "levels": list(levels),
                    "traction_coefficient": c},
        "track": {"length_factor": 1.0, "step_factor": step, "n_passes": passes, "ramp_steps": 2},
        "mesh": {"elements_per_semi_axis": n, "size_factor": 3.0},
        "run": {"plots": False, "linear_solver": "auto"}}, "section")


@pytest.mark.parametrize("table,y_mm", [(TABLE, 0.0), (TABLE, -35.0), (WHEEL, -37.5)])
def test_resultant_is_hertz_along_the_inward_normal(table, y_mm):
    cfg = config(y_mm, table=table)
    c = cfg.contact
    tm = section_track_mesh(cfg)
    disc = discretise(tm.mesh)
    profile = load_profile(c.profile)
    load = MovingHertzLoad(c.a_mm, c.b_mm, 0.2, profile, y_mm)
    sf = SurfaceForces(disc.basis, load, (-tm.track_half_mm, tm.track_half_mm))
    f = sf.force(0.3 * c.a_mm, 2.0)
    pressure = sf.S @ (2.0 * load.shape(sf.x_qp, 0.3 * c.a_mm, sf.lateral_qp).ravel())
    assert pressure.sum() == pytest.approx(2.0 * 2.0 / 3.0 * np.pi * c.a_mm * c.b_mm, rel=2e-3)
    assert f[0::3].sum() == pytest.approx(0.2 * pressure.sum(), rel=1e-12)   # traction q = c p along +x
    normal = np.array([f[1::3].sum(), f[2::3].sum()])
    inward = -np.asarray(profile.normal(y_mm))
    assert np.linalg.norm(normal) == pytest.approx(pressure.sum(), rel=1e-2)  # curvature over the patch: < 1 %
    assert normal / np.linalg.norm(normal) == pytest.approx(inward, abs=1e-3)   # within 0.06 degrees
    if y_mm != 0.0:
        assert abs(inward[0]) > 0.3     # the gauge corner's and flange root's normals are tilted


@pytest.mark.slow  # two elastoplastic paths on 30,000 dofs (12 increments each)
def test_load_that_does_not_move_is_the_static_indentation():
    cfg = config(-35.0, levels=(1.2,))
    m = build_model(cfg, section_track_mesh(cfg))
    p0 = level_pressures(cfg, m.p_y_MPa)[0]
    static = static_dents(m, cfg, [p0])[0]
    ramp = int(np.ceil(p0 / (0.1 * m.p_y_MPa) - 1e-9))  # the static path's increments
    records = list(roll(RollingSolver(m.prob, m.forces, p0), SolverState.virgin(m.disc), [0.0], 1, ramp))
    state = [r for r in records if isinstance(r, MovingLoadPass)][0].state
    assert static.dent_mm > 0
    assert m.probe.depth_at(state.u_mm, 0.0) == pytest.approx(static.dent_mm, rel=5e-3)


@pytest.mark.slow
def test_tiny_section_pass(tmp_path):
    cfg = config(0.0, levels=(1.5,), step=1.0)
    res = run_rolling(cfg, tmp_path)
    lv = res.levels[0]
    assert res.n_dofs == dof_count(cfg)
    assert lv.static_dent_mm > 0 and len(lv.groove_mm) == 1
    assert 0.5 < lv.groove_mm[0] / lv.static_dent_mm < 1.5
    prof = lv.profiles[0]
    across = np.asarray(prof.depth_across_mm)
    assert abs(prof.y_mm[int(np.argmax(across))]) <= 0.2 * cfg.contact.b_mm   # deepest at the centreline y0
    assert across.max() > 5 * abs(across[0])                                  # and small 1.5 b away
