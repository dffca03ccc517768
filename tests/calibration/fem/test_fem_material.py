"""J2 material: input validation, radial return, consistent tangent against finite differences, quadrature."""

import numpy as np
import pytest
import skfem
from skfem.quadrature import get_quadrature
from skfem.refdom import RefTet

from calibration.fem.assembly import QUADRATURE
from calibration.fem.material import SQRT23, J2Material, von_mises_MPa
from calibration.fem.return_mapping import radial_return
from wrlayer.errors import InputError

MAT = J2Material(210000.0, 0.3, 500.0, H_iso_MPa=8000.0, H_kin_MPa=12000.0)


@pytest.mark.parametrize("kwargs, name", [
    (dict(E_MPa=0.0), "E_MPa"), (dict(E_MPa=-1.0), "E_MPa"), (dict(poisson=0.5), "poisson"),
    (dict(poisson=-1.0), "poisson"), (dict(yield_MPa=0.0), "yield_MPa"), (dict(H_iso_MPa=-1.0), "H_iso_MPa"),
    (dict(H_kin_MPa=-5.0), "H_kin_MPa"), (dict(E_MPa=float("nan")), "E_MPa")])
def test_bad_material_names_parameter(kwargs, name):
    args = dict(E_MPa=210000.0, poisson=0.3, yield_MPa=500.0) | kwargs
    with pytest.raises(InputError) as err:
        J2Material(**args)
    assert err.value.what == name


def _random_state(rng, shape, plane_strain):
    """Random strains that are clearly plastic for MAT, and a random previous plastic state."""
    eps = rng.normal(scale=4e-3, size=shape + (6,))
    eps_p = rng.normal(scale=1e-3, size=shape + (6,))
    eps_p[..., :3] -= eps_p[..., :3].mean(axis=-1, keepdims=True)  # plastic strain is deviatoric
    if plane_strain:
        eps[..., [2, 3, 4]] = 0.0
    alpha = rng.normal(scale=20.0, size=shape + (6,))
    alpha[..., :3] -= alpha[..., :3].mean(axis=-1, keepdims=True)
    kappa = rng.uniform(0.0, 0.01, size=shape)
    return eps, eps_p, alpha, kappa


@pytest.mark.parametrize("plane_strain", [False, True])
@pytest.mark.parametrize("material", [MAT, J2Material(210000.0, 0.3, 500.0)], ids=["hardening", "perfect"])
def test_consistent_tangent_matches_finite_differences(plane_strain, material):
    rng = np.random.default_rng(7)
    eps, eps_p, alpha, kappa = _random_state(rng, (50,), plane_strain)
    res = radial_return(material, eps, eps_p, alpha, kappa)
    assert res.plastic.sum() > 25  # the check must exercise the plastic branch
    comps = [0, 1, 5] if plane_strain else range(6)
    h = 1e-8
    for j in comps:
        d = np.zeros(6)
        d[j] = h
        sp_ = radial_return(material, eps + d, eps_p, alpha, kappa, with_tangent=False).stress_MPa
        sm_ = radial_return(material, eps - d, eps_p, alpha, kappa, with_tangent=False).stress_MPa
        fd = (sp_ - sm_) / (2 * h)
        np.testing.assert_allclose(res.tangent_MPa[:, :, j], fd, rtol=1e-5, atol=1e-4 * material.E_MPa * 1e-3)
    np.testing.assert_allclose(res.tangent_MPa, np.swapaxes(res.tangent_MPa, 1, 2), atol=1e-6)


def test_return_lands_on_the_hardened_yield_surface_and_plane_strain_out_of_plane_values():
    rng = np.random.default_rng(3)
    eps, eps_p, alpha, kappa = _random_state(rng, (200,), True)
    res = radial_return(MAT, eps, eps_p, alpha, kappa)
    pl = res.plastic
    xi = res.stress_MPa - res.stress_MPa[:, :3].mean(axis=1, keepdims=True) * np.array([1, 1, 1, 0, 0, 0]) \
        - res.back_stress_MPa
    radius = SQRT23 * (MAT.yield_MPa + MAT.H_iso_MPa * res.eq_plastic_strain)
    np.testing.assert_allclose(np.linalg.norm(xi[pl], axis=1), radius[pl], rtol=1e-10)
    assert np.all(np.linalg.norm(xi[~pl], axis=1) <= radius[~pl] * (1 + 1e-12))
    # plane strain: sigma_zz and eps^p_zz are non-zero at plastic points
    assert np.all(np.abs(res.stress_MPa[:, 2]) > 0)
    assert np.all(np.abs(res.plastic_strain[pl, 2] - eps_p[pl, 2]) > 0)
    # plastic flow is incompressible
    np.testing.assert_allclose(res.plastic_strain[:, :3].sum(axis=1), eps_p[:, :3].sum(axis=1), atol=1e-15)


def _uniaxial_stress_path(material, axial_strains):
    """Axial stress (MPa) at each axial strain of a uniaxial stress path (sigma_22 = sigma_33 = 0 solved for the
    lateral strain by Newton on the consistent tangent), and the last return-mapping result."""
    eps_p, alpha, kappa = np.zeros(6), np.zeros(6), np.zeros(())
    lateral, stress = 0.0, []
    for e11 in axial_strains:
        for _ in range(30):
            eps = np.array([e11, lateral, lateral, 0, 0, 0])
            r = radial_return(material, eps, eps_p, alpha, kappa)
            D = r.tangent_MPa
            lateral -= r.stress_MPa[1] / (D[1, 1] + D[1, 2])
        eps_p, alpha, kappa = r.plastic_strain, r.back_stress_MPa, r.eq_plastic_strain
        stress.append(float(r.stress_MPa[0]))
    return np.array(stress), r


def test_uniaxial_stress_with_combined_hardening_follows_the_analytic_curve():
    """Uniaxial stress path: sigma = Y + E_t (eps - Y/E) with E_t = E H / (E + H), H = H_iso + H_kin."""
    E, Y, H = MAT.E_MPa, MAT.yield_MPa, MAT.H_iso_MPa + MAT.H_kin_MPa
    stress, r = _uniaxial_stress_path(MAT, np.linspace(0.0, 0.01, 41)[1:])
    Et = E * H / (E + H)
    assert stress[-1] == pytest.approx(Y + Et * (0.01 - Y / E), rel=1e-6)
    assert von_mises_MPa(r.stress_MPa) == pytest.approx(r.stress_MPa[0], rel=1e-9)


@pytest.mark.parametrize("H_iso, H_kin", [(8000.0, 12000.0), (10000.0, 10000.0), (0.0, 20000.0), (20000.0, 0.0)])
def test_reverse_plasticity_follows_the_closed_form_bauschinger_loop(H_iso, H_kin):
    """Tension to eps_max, then compression to -eps_max (uniaxial stress), against the closed form of linear mixed
    hardening: back stress X = H_kin eps_p, radius R = Y + H_iso eps_p_eq. Unloading is elastic down to the reverse
    yield stress X - R = (H_kin - H_iso) eps_p,max - Y (the Bauschinger effect: -Y for H_iso = H_kin, +20 GPa x
    eps_p,max - Y for pure kinematic, -(Y + 20 GPa eps_p,max) for pure isotropic hardening), then plastic along
    sigma = (H eps - Y - 2 H_iso eps_p,max) E / (E + H). This is the reverse plasticity the calibration's unloading
    can trigger (``reverse_plasticity_mm`` in the tables)."""
    mat = J2Material(210000.0, 0.3, 500.0, H_iso_MPa=H_iso, H_kin_MPa=H_kin)
    E, Y, H, eps_max = mat.E_MPa, mat.yield_MPa, H_iso + H_kin, 0.01
    strains = np.concatenate([np.linspace(0.0, eps_max, 21)[1:], np.linspace(eps_max, -eps_max, 161)[1:]])
    stress, _ = _uniaxial_stress_path(mat, strains)
    s_max = Y + E * H / (E + H) * (eps_max - Y / E)
    ep_max = eps_max - s_max / E
    s_rev = (H_kin - H_iso) * ep_max - Y
    closed = np.where(strains >= eps_max - 1e-15, s_max, 0.0)
    back = np.arange(strains.size) >= 20
    elastic = s_max + E * (strains - eps_max)
    plastic = (H * strains - Y - 2 * H_iso * ep_max) * E / (E + H)
    closed[back] = np.maximum(elastic, plastic)[back]
    assert stress[19] == pytest.approx(s_max, rel=1e-9)
    assert np.max(np.abs(stress[back] - closed[back])) < 1e-6 * s_max
    # the reverse yield point: the last elastic unloading stress and the first plastic one bracket X - R
    first_plastic = np.argmax(back & (elastic < plastic - 1e-9))
    assert stress[first_plastic - 1] >= s_rev - 1e-9 * s_max
    assert plastic[first_plastic] < s_rev + 1e-6 * s_max < elastic[first_plastic - 1] + 1e-6 * s_max


def test_quadrature_rules_have_positive_weights_and_integrate_degree_two():
    for (kind, order), (X, W) in QUADRATURE.items():
        assert np.all(W > 0), (kind, order)
        vol = 1 / 6 if kind == "tet" else 1 / 2
        assert W.sum() == pytest.approx(vol)
        if order == 2:  # exact for x^2: int_ref x^2 = 1/60 (tet), 1/12 (tri)
            assert W @ X[0] ** 2 == pytest.approx(1 / 60 if kind == "tet" else 1 / 12)
    # the reason for our own rules: scikit-fem's default tetrahedral rules of order 3 and 4 are not positive
    assert min(get_quadrature(RefTet, 3)[1].min(), get_quadrature(RefTet, 4)[1].min()) < 0
    assert skfem.__version__  # scikit-fem is the base of the discretisation
