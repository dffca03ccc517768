"""Isotropic linear elasticity relations used by every package (units MPa)."""

from __future__ import annotations


def shear_modulus_MPa(E_MPa: float, poisson: float) -> float:
    """Shear modulus G = E / (2 (1 + nu)) (MPa) of an isotropic material with Young's modulus ``E_MPa`` (MPa) and
    Poisson's ratio ``poisson`` (-)."""
    return E_MPa / (2.0 * (1.0 + poisson))


def youngs_modulus_MPa(G_MPa: float, poisson: float) -> float:
    """Young's modulus E = 2 G (1 + nu) (MPa): the inverse of :func:`shear_modulus_MPa`."""
    return 2.0 * G_MPa * (1.0 + poisson)


__all__ = ["shear_modulus_MPa", "youngs_modulus_MPa"]
