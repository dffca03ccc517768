"""The 3D layer displacement does not depend on the rail's support or on the depth of the section's cut:
a real (coarse, P2) FEM indentation of the 60E1 crown, three boundary variants."""

import numpy as np
import pytest
from threadpoolctl import threadpool_limits

from calibration.fem.material import J2Material
from calibration.hertz.geometry import local_geometry
from calibration.indentation import IndentationJob, LoadSettings, MeshSettings, indent
from meshes.profiles import get_profile

MATERIAL = J2Material(210000.0, 0.3, 500.0, 10000.0, 10000.0)
LOAD = LoadSettings(max_factor=2.0, n_levels=2, unload_factors=(2.0,), max_increment_factor=0.35)


@pytest.fixture(scope="module")
def crown_variants():
    rail, wheel = get_profile("60E1"), get_profile("S1002")
    geo = local_geometry(rail, 0.0, wheel, 100000.0, MATERIAL.E_MPa, MATERIAL.poisson)
    out = {}
    with threadpool_limits(1):
        for name, kw in {"support 35 mm, cut 60 mm": dict(rail_support_below_mm=35.0),
                         "no support, cut 60 mm": dict(rail_support_below_mm=None),
                         "support 35 mm, cut 120 mm": dict(rail_support_below_mm=35.0, depth_mm=120.0)}.items():
            mesh = MeshSettings(elements_per_semi_axis=2.5, h_max_mm=12.0, order=2, **kw)
            out[name] = indent(IndentationJob(profile=rail, geometry=geo, material=MATERIAL, model="3d", mesh=mesh,
                                              load=LOAD, linear_solver="auto", extra_depth_factors=(3.0,)))
    return out


def test_characteristic_changes_less_than_one_percent(crown_variants):
    base = crown_variants["support 35 mm, cut 60 mm"]
    p = np.asarray(base.p_MPa)
    assert base.u_pl_mm[-1] > 0.01  # a real dent (tens of micrometres), not a trivial comparison
    for name, res in crown_variants.items():
        assert res.first_yield_MPa == pytest.approx(base.first_yield_MPa, rel=0.01), name
        # the inelastic characteristic at the same multiples of its elastic limit p_2 (the FEM first yield, equal
        # within 1 % above), relative to the peak dent (the load levels are multiples of each model's p_2)
        u_pl = np.interp(p / base.first_yield_MPa, np.asarray(res.p_MPa) / res.first_yield_MPa, res.u_pl_mm)
        assert np.max(np.abs(u_pl - base.u_pl_mm)) < 0.01 * max(base.u_pl_mm), name
        assert res.residual_fem_mm[-1] == pytest.approx(base.residual_fem_mm[-1], rel=0.01), name


def test_absolute_displacement_does_depend_on_the_cut(crown_variants):
    """The elastic part is what the cut changes (so the test above can fail): the same-mesh subtraction removes it."""
    a = crown_variants["support 35 mm, cut 60 mm"].fem_absolute_compliance_mm_per_MPa
    b = crown_variants["no support, cut 60 mm"].fem_absolute_compliance_mm_per_MPa
    assert abs(b / a - 1) > 0.005


def test_reference_depth_measure_is_close_to_the_far_cut_one(crown_variants):
    """The optional measure against the material point 3 max(a, b) below the centre (mesh.reference_depth_factor)
    differs from the far-cut one by a few per cent (measured 2 % on a finer mesh, docs/calibration.md) and is
    support-independent too."""
    base = crown_variants["support 35 mm, cut 60 mm"]
    rel = np.asarray(base.u_pl_depth_mm["3"])
    assert rel[-1] == pytest.approx(base.u_pl_mm[-1], rel=0.05)
    for name, res in crown_variants.items():
        assert res.u_pl_depth_mm["3"][-1] == pytest.approx(rel[-1], rel=0.01), name
