"""Numbers of one body's depth distributions in one wear step (units mm, mm^2, g, km).

The worn area is the integral of the node depth over the profile's arc length (:meth:`ArcGrid.area_mm2`). The mass
loss takes the worn area around the body: the wheel's whole circumference 2 pi r0 (g per km of running), the rail
per metre of rail (1000 mm; g per metre of rail per km of running), times the density.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from contact.wear.profile_grid import ArcGrid

#: The result key of the mass loss per body (the unit differs: the whole wheel, a metre of rail).
MASS_LOSS_KEY = {"wheel": "mass_loss_g_per_km", "rail": "mass_loss_g_per_m_rail_per_km"}


@dataclass(frozen=True)
class BodyStats:
    """One body on one side in one step (result.json ``steps[].bodies[]``, steps.csv).

    Attributes
    ----------
    body : str
        ``"wheel"`` or ``"rail"`` (selects the mass-loss key; not written itself).
    wear_max_mm : float
        Largest smoothed wear depth of the step (mm).
    wear_max_y_mm : float
        Profile coordinate y of that largest wear depth (mm).
    worn_area_mm2 : float
        Wear depth integrated over the arc length (mm^2).
    inelastic_max_mm : float
        Largest smoothed inelastic (residual) depth of the step (mm).
    inelastic_max_y_mm : float
        Profile coordinate y of that largest inelastic depth (mm).
    inelastic_area_mm2 : float
        Inelastic depth integrated over the arc length (mm^2).
    mass_loss : float
        Wear mass loss rate; written as ``mass_loss_g_per_km`` for the wheel (g per km of running, whole
        circumference) and ``mass_loss_g_per_m_rail_per_km`` for the rail (g per metre of rail per km).
    """

    body: str
    wear_max_mm: float
    wear_max_y_mm: float
    worn_area_mm2: float
    inelastic_max_mm: float
    inelastic_max_y_mm: float
    inelastic_area_mm2: float
    mass_loss: float

    def to_dict(self) -> dict[str, Any]:
        return {"wear_max_mm": self.wear_max_mm, "wear_max_y_mm": self.wear_max_y_mm,
                "worn_area_mm2": self.worn_area_mm2, "inelastic_max_mm": self.inelastic_max_mm,
                "inelastic_max_y_mm": self.inelastic_max_y_mm, "inelastic_area_mm2": self.inelastic_area_mm2,
                MASS_LOSS_KEY[self.body]: self.mass_loss}


def body_stats(grid: ArcGrid, wear: np.ndarray, inel: np.ndarray, length_km: float, body: str,
               nominal_radius_mm: float, density_kg_m3: float) -> BodyStats:
    """Largest depths and their place, areas (mm^2) and the mass loss rate of one body (see the module docstring)."""
    area = grid.area_mm2(wear)
    iw, ii = int(np.argmax(wear)), int(np.argmax(inel))
    around_mm = 2.0 * math.pi * nominal_radius_mm if body == "wheel" else 1000.0
    mass_g = area * around_mm * density_kg_m3 * 1e-9 * 1e3
    return BodyStats(body=body, wear_max_mm=float(wear[iw]), wear_max_y_mm=float(grid.y_mm[iw]), worn_area_mm2=area,
                     inelastic_max_mm=float(inel[ii]), inelastic_max_y_mm=float(grid.y_mm[ii]),
                     inelastic_area_mm2=grid.area_mm2(inel),
                     mass_loss=mass_g / length_km if length_km > 0 else 0.0)


__all__ = ["MASS_LOSS_KEY", "BodyStats", "body_stats"]
