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
    """Outcome of the return mapping at every point: new stress, consistent tangent and internal variables.

    The tangent is kept only at the plastic points (``plastic_tangent_MPa``, in the order of
    ``np.nonzero(plastic)``); every other point's tangent is the elastic matrix ``elastic_MPa``.
    :attr:`tangent_MPa` makes the full array (..., 6, 6) on demand; :meth:`tangent_of` the rows of some elements.
    """

    stress_MPa: np.ndarray          # (..., 6)
    plastic_strain: np.ndarray      # (..., 6)
    back_stress_MPa: np.ndarray     # (..., 6)
    eq_plastic_strain: np.ndarray   # (...)
    plastic: np.ndarray             # (...) bool: this step is plastic (yield surface active)
    plastic_tangent_MPa: np.ndarray | None = None   # (n_plastic, 6, 6) consistent tangent d stress / d strain
    elastic_MPa: np.ndarray | None = None           # (6, 6)
    #: the trial yield function |dev sigma_trial - back stress| - sqrt(2/3) radius at every point (...), MPa
    trial_yield_MPa: np.ndarray | None = None

    @property
    def tangent_MPa(self) -> np.ndarray | None:
        """The consistent tangent at every point (..., 6, 6) (None without tangent)."""
        if self.elastic_MPa is None:
            return None
        tangent = np.broadcast_to(self.elastic_MPa, self.plastic.shape + (6, 6)).copy()
        tangent[self.plastic] = self.plastic_tangent_MPa
        return tangent

    def tangent_of(self, elements: np.ndarray) -> np.ndarray | None:
        """The tangent (n_sel, n_qp, 6, 6) at the points of the ``elements`` (rows of a (n_elem, n_qp) field;
        None without tangent)."""
        if self.elastic_MPa is None:
            return None
        return tangent_of_elements(elements, self.plastic, self.plastic_tangent_MPa, self.elastic_MPa)


def tangent_of_elements(elements: np.ndarray, marked: np.ndarray, marked_tangent: np.ndarray,
                        default: np.ndarray) -> np.ndarray:
    """Tangents (n_sel, n_qp, 6, 6) at the points of ``elements`` from the tangents ``marked_tangent`` (n_marked,
    6, 6) of the ``marked`` points (bool (n_elem, n_qp), in the order of ``np.nonzero(marked)``) and ``default``
    (6, 6) at every other point."""
    tangent = np.broadcast_to(default, (len(elements),) + marked.shape[1:] + (6, 6)).copy()
    rank = np.cumsum(marked.ravel()).reshape(marked.shape) - 1  # index into marked_tangent
    sel = marked[elements]
    tangent[sel] = marked_tangent[rank[elements][sel]]
    return tangent


def radial_return(material: J2Material, strain: np.ndarray, plastic_strain_old: np.ndarray,
                  back_stress_old_MPa: np.ndarray, eq_plastic_strain_old: np.ndarray,
                  with_tangent: bool = True) -> ReturnResult:
    """Return-map the total strains ``strain`` (..., 6) from the converged internal variables of the last step.

    Plane strain is the special case eps_33 = eps_13 = eps_23 = 0 in ``strain``; sigma_33 and eps^p_33 come
    out non-zero. Elastic points get the elastic tangent; plastic points the consistent elastoplastic one. The
    elastic points (most of a body) only get their trial stress: the correction, the new internal variables and
    the tangent are computed at the plastic points alone (the same numbers as for all points, measured at half the
    time on the calibration meshes, benchmarks/bench_fem_position.py).
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
    stress, plastic_strain = stress_trial, plastic_strain_old.copy()
    back_stress, eq_plastic_strain = back_stress_old_MPa.copy(), eq_plastic_strain_old.copy()
    dgamma = f_trial[plastic] / (2.0 * G + 2.0 / 3.0 * H)
    n = xi[plastic] / norm_xi[plastic][:, None]
    dg = dgamma[:, None]
    stress[plastic] -= 2.0 * G * dg * n
    plastic_strain[plastic] += dg * n
    back_stress[plastic] += (2.0 / 3.0) * material.H_kin_MPa * dg * n
    eq_plastic_strain[plastic] += SQRT23 * dgamma
    if not with_tangent:
        return ReturnResult(stress, plastic_strain, back_stress, eq_plastic_strain, plastic, trial_yield_MPa=f_trial)
    theta = 1.0 - 2.0 * G * dgamma / norm_xi[plastic]
    theta_bar = 1.0 / (1.0 + H / (3.0 * G)) - (1.0 - theta)
    tangent = (K * np.outer(IDENTITY_M, IDENTITY_M)
               + 2.0 * G * theta[:, None, None] * DEVIATOR_M
               - 2.0 * G * theta_bar[:, None, None] * n[:, :, None] * n[:, None, :])
    return ReturnResult(stress, plastic_strain, back_stress, eq_plastic_strain, plastic, tangent, C, f_trial)
