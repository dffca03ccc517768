"""Hertz pressure: consistent nodal forces add up to the analytic resultant; bad inputs are named."""

import numpy as np
import pytest
import skfem

from calibration.fem.assembly import discretise
from calibration.hertz.load import HertzLoad, UniformPressure
from calibration.fem.verification_meshes import hertz_block, quarter_annulus
from wrlayer.errors import InputError


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("y0", [0.0, 1.37])
def test_total_force_2d(order, y0):
    ax = np.linspace(-4.0, 4.0, 33)
    m = skfem.MeshTri1.init_tensor(ax, np.linspace(-3.0, 0.0, 7))
    m = (skfem.MeshTri2.from_mesh(m) if order == 2 else m).with_boundaries(
        {"surface": lambda x: x[1] > -1e-9, "fixed": lambda x: x[1] < -3 + 1e-9})
    d = discretise(m)
    load = HertzLoad(y0, 0.9)
    prep = load.prepare(d.basis)
    fz = prep.force_per_MPa[d.basis.get_dofs().all("u^2")].sum()
    fy = prep.force_per_MPa[d.basis.get_dofs().all("u^1")].sum()
    assert -fz == pytest.approx(np.pi / 2 * 0.9, rel=1e-2)
    assert abs(fy) < 1e-12
    np.testing.assert_allclose(prep.centre_mm, [y0, 0.0], atol=1e-12)
    # the force's centre of action is the load centre
    ys = d.basis.doflocs[0, d.basis.get_dofs().all("u^2")]
    assert (ys * prep.force_per_MPa[d.basis.get_dofs().all("u^2")]).sum() / fz == pytest.approx(y0, abs=1e-3)


def test_total_force_3d_ellipse_and_centre_probe():
    m = hertz_block(0.2, 2.0, 4.0, order=1, dim=3)
    d = discretise(m)
    load = HertzLoad(0.0, 1.0, a_mm=1.6)
    prep = load.prepare(d.basis)
    fz = prep.force_per_MPa[d.basis.get_dofs().all("u^3")].sum()
    assert -fz == pytest.approx(load.total_force_per_MPa() / 4, rel=1e-2)  # quarter model
    u = np.zeros(d.n_dofs)
    u[d.basis.get_dofs().all("u^3")] = -2.5e-3  # rigid downward shift = 2.5 um into the body
    assert prep.centre_displacement_mm(u) == pytest.approx(2.5e-3)


def test_uniform_pressure_resultant_on_a_quarter_bore():
    m = quarter_annulus(1.0, 2.0, 4, 12, order=2)
    d = discretise(m)
    f = UniformPressure("inner").prepare(d.basis).force_per_MPa
    # resultant of p on the quarter bore: p * a along each axis (outwards)
    assert f[d.basis.get_dofs().all("u^1")].sum() == pytest.approx(1.0, rel=1e-3)
    assert f[d.basis.get_dofs().all("u^2")].sum() == pytest.approx(1.0, rel=1e-3)


def test_bad_load_inputs_are_named():
    m2 = hertz_block(0.5, 1.0, 4.0, order=1, dim=2)
    d2 = discretise(m2)
    with pytest.raises(InputError, match="load centre"):
        HertzLoad(10.0, 0.5).prepare(d2.basis)  # beyond the surface
    with pytest.raises(InputError, match="load centre"):
        HertzLoad(0.5, 0.5, z0_mm=-1.0).prepare(d2.basis)  # off the surface
    with pytest.raises(InputError, match="b_mm"):
        HertzLoad(0.0, 0.0)
    with pytest.raises(InputError, match="a_mm"):
        HertzLoad(0.0, 1.0, a_mm=1.0).prepare(d2.basis)  # 3D load on a 2D mesh
    bare = skfem.MeshTri1.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3))
    with pytest.raises(InputError, match="surface"):
        HertzLoad(0.5, 0.1).prepare(discretise(bare).basis)
