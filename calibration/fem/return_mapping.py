"""Radial return for J2 plasticity with linear isotropic + kinematic hardening, vectorised over points.

Simo & Hughes (1998), Box 3.2 / eq. (3.3.10): closed-form plastic multiplier for linear hardening and the
algorithmically consistent tangent ``C_ep = K 1(x)1 + 2G theta P - 2G theta_bar n(x)n``. All arrays are Mandel
(see :mod:`calibration.fem.material`), any leading shape (e.g. (n_elements, n_qp)). Units MPa.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from calibration.fem.material import DEVIATOR_M, IDENTITY_M, SQRT23, J2Material


@dataclass
class ReturnResult:
    """Outcome of the return mapping at every point: new stress, consistent tangent and internal variables."""

    stress_MPa: np.ndarray          # (..., 6)
    tangent_MPa: np.ndarray         # (..., 6, 6) consistent tangent d stress / d strain
    plastic_strain: np.ndarray      # (..., 6)
    back_stress_MPa: np.ndarray     # (..., 6)
    eq_plastic_strain: np.ndarray   # (...)
    plastic: np.ndarray             # (...) bool: this step is plastic (yield surface active)


def radial_return(material: J2Material, strain: np.ndarray, plastic_strain_old: np.ndarray,
                  back_stress_old_MPa: np.ndarray, eq_plastic_strain_old: np.ndarray,
                  with_tangent: bool = True) -> ReturnResult:
    """Return-map the total strains ``strain`` (..., 6) from the converged internal variables of the last step.

    Plane strain is the special case eps_33 = eps_13 = eps_23 = 0 in ``strain``; sigma_33 and eps^p_33 come
    out non-zero. Elastic points get the elastic tangent; plastic points the consistent elastoplastic one.
    """
    G, K = material.shear_modulus_MPa, material.bulk_modulus_MPa
    H = material.H_iso_MPa + material.H_kin_MPa
    C = material.elastic_matrix()
    stress_trial = (strain - plastic_strain_old) @ C
    xi = stress_trial @ DEVIATOR_M - back_stress_old_MPa
    norm_xi = np.sqrt(np.einsum("...i,...i->...", xi, xi))
    radius = SQRT23 * (material.yield_MPa + material.H_iso_MPa * eq_plastic_strain_old)
    f_trial = norm_xi - radius
    plastic = f_trial > 1e-12 * material.yield_MPa
    dgamma = np.where(plastic, f_trial / (2.0 * G + 2.0 / 3.0 * H), 0.0)
    safe_norm = np.where(plastic, norm_xi, 1.0)
    n = xi / safe_norm[..., None]
    dg = dgamma[..., None]
    stress = stress_trial - 2.0 * G * dg * n
    plastic_strain = plastic_strain_old + dg * n
    back_stress = back_stress_old_MPa + (2.0 / 3.0) * material.H_kin_MPa * dg * n
    eq_plastic_strain = eq_plastic_strain_old + SQRT23 * dgamma
    tangent = None
    if with_tangent:
        tangent = np.broadcast_to(C, strain.shape[:-1] + (6, 6)).copy()
        if np.any(plastic):
            npl = n[plastic]
            theta = 1.0 - 2.0 * G * dgamma[plastic] / norm_xi[plastic]
            theta_bar = 1.0 / (1.0 + H / (3.0 * G)) - (1.0 - theta)
            tangent[plastic] = (K * np.outer(IDENTITY_M, IDENTITY_M)
                                + 2.0 * G * theta[:, None, None] * DEVIATOR_M
                                - 2.0 * G * theta_bar[:, None, None] * npl[:, :, None] * npl[:, None, :])
    return ReturnResult(stress, tangent, plastic_strain, back_stress, eq_plastic_strain, plastic)
