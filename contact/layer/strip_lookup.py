"""Layer characteristics looked up strip by strip in a per-position table (units mm, MPa).

A calibration table (:class:`contact.layer.layer_table.LayerTable`, or anything with ``characteristic_at`` and
``y_range_mm``, :class:`LayerLookup`) is read at the profile coordinate of every strip of a patch. Strips outside
the table's range take its end value (the layer must exist on every strip the solver may load); a strip IN CONTACT
outside the range is a :class:`wrlayer.errors.LayerNotCovered` (:func:`check_coverage`, after the solve).
"""

from __future__ import annotations

from typing import Protocol

from contact.layer.characteristic import Characteristic


class LayerLookup(Protocol):
    """A per-position layer table (e.g. :class:`contact.layer.layer_table.LayerTable`)."""

    def characteristic_at(self, y_mm: float, patch_mm: tuple[float, float] | None = None) -> Characteristic: ...

    @property
    def y_range_mm(self) -> tuple[float, float]: ...


__all__ = ["LayerLookup"]
