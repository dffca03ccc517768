"""Jumps of the contact point: positions where a small lateral step moves the contact point far (units mm).

A jump is a step between neighbouring lateral displacements of the sweep over which the contact point moves by
more than ``threshold_mm`` on the rail or on the wheel profile (e.g. from the tread to the gauge corner, or onto
the flange): the contact does not travel continuously across the profiles in between, which a multibody
pre-processor marks because the contact stiffness, creepage and wear jump there. The threshold is per step, so
the sweep's step must be small compared with it (the default 0.1 mm step and 1 mm threshold: a continuous contact
point moves faster than 10 mm per mm of lateral displacement only on a nearly conformal tread).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contact.geometry.defaults import DEFAULT_JUMP_MM
from wrlayer.errors import InputError



@dataclass(frozen=True)
class ContactJump:
    """One jump: side ("right"/"left"), the lateral step (mm) and the contact point's profile coordinates (mm) on
    the rail and the wheel before and after it."""

    side: str
    lateral_from_mm: float
    lateral_to_mm: float
    y_rail_from_mm: float
    y_rail_to_mm: float
    y_wheel_from_mm: float
    y_wheel_to_mm: float


def jump_steps(y_rail_mm: np.ndarray, y_wheel_mm: np.ndarray, threshold_mm: float = DEFAULT_JUMP_MM) -> np.ndarray:
    """Boolean (n,): True at each sweep position reached by a jump from the previous one."""
    if not (np.isfinite(threshold_mm) and threshold_mm > 0.0):
        raise InputError("jump_mm", f"must be a positive number of mm, got {threshold_mm!r}")
    moved = np.maximum(np.abs(np.diff(y_rail_mm)), np.abs(np.diff(y_wheel_mm)))
    return np.r_[False, moved > threshold_mm]


def contact_jumps(side: str, lateral_mm: np.ndarray, y_rail_mm: np.ndarray, y_wheel_mm: np.ndarray,
                  threshold_mm: float = DEFAULT_JUMP_MM) -> list[ContactJump]:
    """The jumps of one side, by increasing lateral displacement."""
    at = np.flatnonzero(jump_steps(y_rail_mm, y_wheel_mm, threshold_mm))
    return [ContactJump(side, float(lateral_mm[i - 1]), float(lateral_mm[i]), float(y_rail_mm[i - 1]),
                        float(y_rail_mm[i]), float(y_wheel_mm[i - 1]), float(y_wheel_mm[i])) for i in at]


__all__ = ["DEFAULT_JUMP_MM", "ContactJump", "contact_jumps", "jump_steps"]
