"""Layer characteristics looked up strip by strip in a per-position table (units mm, MPa).

A calibration table (:class:`wrlayer.layer_table.LayerTable`, or anything with ``characteristic_at`` and
``y_range_mm``, :class:`LayerLookup`) is read at the profile coordinate of every strip of a patch. Strips outside
the table's range take its end value (the layer must exist on every strip the solver may load); a strip IN CONTACT
outside the range is a :class:`wrlayer.errors.LayerNotCovered`, and one whose peak pressure lies above the
pressure its characteristic was calibrated to a :class:`wrlayer.errors.LayerRangeExceeded` (:func:`check_coverage`,
after the solve).
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from wrlayer.characteristic import Characteristic
from wrlayer.errors import InputError, LayerNotCovered, LayerRangeExceeded


class LayerLookup(Protocol):
    """A per-position layer table (e.g. :class:`wrlayer.layer_table.LayerTable`)."""

    def characteristic_at(self, y_mm: float, patch_mm: tuple[float, float] | None = None) -> Characteristic: ...

    @property
    def y_range_mm(self) -> tuple[float, float]: ...

    def calibrated_max_MPa(self, y_mm: float) -> float | None: ...

    def lateral_curvature_at(self, y_mm): ...


def clamped_characteristics(table: LayerLookup, y_mm: np.ndarray, what: str,
                            patch_mm: tuple[float, float] | None = None) -> tuple[list[Characteristic], np.ndarray]:
    """The table's characteristic at every profile coordinate ``y_mm`` (mm), clamped to the table's range (each
    distinct y read once); returns (characteristics, mask of the clamped coordinates). ``patch_mm`` = (a, b) (mm):
    characteristics scaled to that patch (``LayerTable.characteristic_at``). An InputError of the table is
    re-attributed to ``what``."""
    y_mm = np.asarray(y_mm, dtype=float)
    lo, hi = (float(v) for v in table.y_range_mm)
    clamped = (y_mm < lo) | (y_mm > hi)
    cache: dict[float, Characteristic] = {}
    chars = []
    for y in np.clip(y_mm, lo, hi):
        key = round(float(y), 9)
        if key not in cache:
            try:
                cache[key] = (table.characteristic_at(float(y)) if patch_mm is None
                              else table.characteristic_at(float(y), patch_mm=patch_mm))
            except InputError as err:
                raise InputError(what, str(err)) from None
        chars.append(cache[key])
    return chars, clamped


def check_coverage(table: LayerLookup, y_contact_mm: np.ndarray, what: str, body: str, name: str,
                   tolerance_mm: float = 0.0, p_peak_MPa: np.ndarray | None = None) -> None:
    """:class:`LayerNotCovered` (naming ``what``) when a strip in contact, at the profile coordinates
    ``y_contact_mm`` (mm) on ``body``, lies outside the range of the table ``name`` by more than ``tolerance_mm``;
    :class:`LayerRangeExceeded` when its peak pressure ``p_peak_MPa`` (MPa, per strip in contact) lies above the
    largest pressure the table was calibrated to there (0.1 % slack for the solver's rounding)."""
    y = np.asarray(y_contact_mm, dtype=float)
    if y.size == 0:
        return
    lo, hi = (float(v) for v in table.y_range_mm)
    first, last = float(y.min()), float(y.max())
    if first < lo - tolerance_mm or last > hi + tolerance_mm:
        raise LayerNotCovered(what, f"does not cover the contact location: the patch spans y = {first:.4g}.."
                              f"{last:.4g} mm on the {body}, the table {name} covers {lo:.4g}..{hi:.4g} mm")
    if p_peak_MPa is None:
        return
    p = np.asarray(p_peak_MPa, dtype=float)
    limits = [table.calibrated_max_MPa(float(v)) for v in np.clip(y, lo, hi)]
    if any(v is None for v in limits):
        return
    ratio = p / np.asarray(limits)
    j = int(np.argmax(ratio))
    if ratio[j] > 1.0 + 1e-3:
        raise LayerRangeExceeded(what, f"the {body} table {name} at y = {y[j]:.4g} mm is calibrated up to "
                                       f"{limits[j]:.6g} MPa; the contact's peak pressure there is {p[j]:.6g} MPa "
                                       "(recalibrate with a larger load.max_factor)")


__all__ = ["LayerLookup", "check_coverage", "clamped_characteristics"]
