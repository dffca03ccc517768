"""mesh.style = "stretched" (docs/calibration.md, "Mesh styles"): the isotropic mesh of a patch of aspect
STRETCH_ASPECT, stretched along x to the patch's own aspect. The configuration key, the identity with "isotropic" on
round patches, and the elastic solution and first yield of an elongated patch against the isotropic mesh."""

import numpy as np
import pytest

from calibration.config import parse_config
from calibration.fem.assembly import discretise
from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
from calibration.fem.material import J2Material
from calibration.hertz.geometry import given_geometry
from calibration.hertz.load import HertzLoad
from calibration.indentation import local_first_yield_MPa
from calibration.position_mesh import STRETCH_ASPECT, add_support_boundary, build_mesh, mesh_style, x_stretch
from calibration.settings import MeshSettings
from meshes.profiles import get_profile

BODY = {"body": "rail", "profile": "60E1", "mate": "S1002", "positions_mm": [0.0]}
STEEL = J2Material(210000.0, 0.3, 500.0, H_iso_MPa=10000.0, H_kin_MPa=10000.0)


def test_config_accepts_stretched():
    assert parse_config({"mesh": {"style": "stretched"}, "bodies": [BODY]}).mesh.style == "stretched"


def test_stretch_factor_follows_the_aspect_ratio():
    rail = get_profile("60E1")
    stretched = MeshSettings(style="stretched")
    assert x_stretch(given_geometry(rail, 0.0, 7.16, 5.39), stretched) == 1.0  # round: as isotropic
    assert x_stretch(given_geometry(rail, 0.0, 8.0, 2.0), stretched) == pytest.approx(4.0 / STRETCH_ASPECT)
    assert x_stretch(given_geometry(rail, 0.0, 2.0, 3.0), stretched) == 1.0  # wider than long: not compressed
    assert x_stretch(given_geometry(rail, 0.0, 8.0, 2.0), MeshSettings(style="isotropic")) == 1.0
    assert mesh_style(given_geometry(rail, 0.0, 8.0, 2.0), stretched) == "stretched"


def test_round_patch_mesh_is_the_isotropic_one():
    rail = get_profile("60E1")
    geo = given_geometry(rail, 0.0, 7.16, 5.39)
    kw = dict(elements_per_semi_axis=2, h_max_mm=12.0, order=1)
    iso = build_mesh(rail, geo, "3d", MeshSettings(style="isotropic", **kw))
    st = build_mesh(rail, geo, "3d", MeshSettings(style="stretched", **kw))
    np.testing.assert_array_equal(st.doflocs, iso.doflocs)
    np.testing.assert_array_equal(st.t, iso.t)


def _elastic(style: str, a: float, b: float):
    """(dofs, first-yield p0 / Y, centre displacement per MPa of p0 in mm, load resultant / analytic) of the 60E1
    crown under the elliptic Hertz pressure of semi-axes a (x) and b (y), 3 elements per semi-axis, P2."""
    rail = get_profile("60E1")
    geo = given_geometry(rail, 0.0, a, b)
    mesh = build_mesh(rail, geo, "3d", MeshSettings(elements_per_semi_axis=3, h_max_mm=10.0, style=style))
    disc = discretise(mesh, 2)
    load = HertzLoad(geo.y_mm, b, a, z0_mm=geo.z_mm)
    res = solve_load_path(mesh, STEEL, load, [1.0], disc=disc,
                          options=SolverOptions(dirichlet=add_support_boundary(mesh, 35.0)))
    force = load.prepare(disc.basis).force_per_MPa  # nodal forces of the half model, dofs blocked (x, y, z)
    resultant = np.linalg.norm([force[c::3].sum() for c in range(3)]) / (load.total_force_per_MPa() / 2)
    return (disc.n_dofs, local_first_yield_MPa(disc, res, STEEL, 3 * b) / STEEL.yield_MPa,
            res.history[-1].u_centre_mm, resultant)


def test_elongated_patch_stretched_agrees_with_isotropic_at_fewer_dofs():
    """a/b = 3: the stretched mesh has about 0.64x the isotropic one's dofs (2.1x the aspect it is meshed at), and
    its first yield and elastic centre displacement agree with the isotropic mesh's (measured 0.6 % and 0.3 %)."""
    n_iso, fy_iso, u_iso, _ = _elastic("isotropic", 6.0, 2.0)
    n_st, fy_st, u_st, resultant = _elastic("stretched", 6.0, 2.0)
    assert n_st < 0.75 * n_iso
    assert resultant == pytest.approx(1.0, abs=1e-3)  # the load is integrated exactly on the stretched facets
    assert fy_st == pytest.approx(fy_iso, rel=0.015)
    assert u_st == pytest.approx(u_iso, rel=0.01)
    # an elongated ellipse yields later than the a/b = 1.33 one (1.62 Y) and earlier than a line load (1.79 Y)
    assert 1.62 < fy_st < 1.79
