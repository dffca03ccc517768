"""Small-strain J2 (von Mises) material with linear isotropic and kinematic hardening. Units: MPa.

Tensors are stored in Mandel (orthonormal Voigt) notation with six components
``[11, 22, 33, sqrt2*23, sqrt2*13, sqrt2*12]`` for stress and strain alike, so that
``sigma : eps = sigma_M . eps_M``, ``|dev sigma| = |dev sigma_M|`` and all 6x6 tangents are symmetric.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wrlayer.errors import require

SQRT2 = math.sqrt(2.0)
SQRT23 = math.sqrt(2.0 / 3.0)
#: Mandel identity tensor (second order).
IDENTITY_M = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
#: Mandel deviatoric projector P = I - (1/3) 1 (x) 1.
DEVIATOR_M = np.eye(6) - np.outer(IDENTITY_M, IDENTITY_M) / 3.0


@dataclass(frozen=True)
class J2Material:
    """Von Mises plasticity with linear hardening (small strain, rate independent).

    E_MPa: Young's modulus; poisson: Poisson's ratio in (-1, 0.5); yield_MPa: initial uniaxial yield stress;
    H_iso_MPa: linear isotropic hardening modulus (d sigma_y / d eps_p_eq); H_kin_MPa: linear (Prager)
    kinematic hardening modulus (back-stress rate = 2/3 H_kin * plastic strain rate).
    H_iso = H_kin = 0 is perfect plasticity. Raises ``InputError`` naming the bad parameter.
    """

    E_MPa: float
    poisson: float
    yield_MPa: float
    H_iso_MPa: float = 0.0
    H_kin_MPa: float = 0.0

    def __post_init__(self) -> None:
        for name in ("E_MPa", "poisson", "yield_MPa", "H_iso_MPa", "H_kin_MPa"):
            value = getattr(self, name)
            require(isinstance(value, (int, float, np.floating, np.integer)) and math.isfinite(value),
                    name, f"must be a finite number, got {value!r}")
        require(self.E_MPa > 0, "E_MPa", f"must be > 0, got {self.E_MPa}")
        require(-1.0 < self.poisson < 0.5, "poisson", f"must lie in (-1, 0.5), got {self.poisson}")
        require(self.yield_MPa > 0, "yield_MPa", f"must be > 0, got {self.yield_MPa}")
        require(self.H_iso_MPa >= 0, "H_iso_MPa", f"must be >= 0, got {self.H_iso_MPa}")
        require(self.H_kin_MPa >= 0, "H_kin_MPa", f"must be >= 0, got {self.H_kin_MPa}")

    @property
    def shear_modulus_MPa(self) -> float:
        """G = E / (2 (1 + nu))."""
        return self.E_MPa / (2.0 * (1.0 + self.poisson))

    @property
    def bulk_modulus_MPa(self) -> float:
        """K = E / (3 (1 - 2 nu))."""
        return self.E_MPa / (3.0 * (1.0 - 2.0 * self.poisson))

    def elastic_matrix(self) -> np.ndarray:
        """Isotropic elasticity in Mandel notation, 6x6 (MPa): C = K 1(x)1 + 2G P."""
        return (self.bulk_modulus_MPa * np.outer(IDENTITY_M, IDENTITY_M)
                + 2.0 * self.shear_modulus_MPa * DEVIATOR_M)


def von_mises_MPa(stress_M: np.ndarray) -> np.ndarray:
    """Von Mises equivalent stress sqrt(3/2) |dev sigma| of Mandel stresses (..., 6) -> (...)."""
    dev = stress_M @ DEVIATOR_M
    return np.sqrt(1.5 * np.einsum("...i,...i->...", dev, dev))


def mandel_to_tensor(v: np.ndarray) -> np.ndarray:
    """Mandel vectors (..., 6) -> symmetric tensors (..., 3, 3)."""
    t = np.empty(v.shape[:-1] + (3, 3))
    t[..., 0, 0], t[..., 1, 1], t[..., 2, 2] = v[..., 0], v[..., 1], v[..., 2]
    t[..., 1, 2] = t[..., 2, 1] = v[..., 3] / SQRT2
    t[..., 0, 2] = t[..., 2, 0] = v[..., 4] / SQRT2
    t[..., 0, 1] = t[..., 1, 0] = v[..., 5] / SQRT2
    return t
