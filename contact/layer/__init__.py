"""The Prandtl-body surface layer (units mm, MPa).

The layer's data, shared with the calibration that produces it, live in :mod:`wrlayer`:
:mod:`wrlayer.characteristic` (the piecewise-linear monotonic characteristic p(u), series combination, the element
parameters of eqs. 4-6) and :mod:`wrlayer.layer_table` (the parameter table format calibration writes and the
scenes read).

- :mod:`~contact.layer.prandtl_layer`: the Prandtl element state per strip (springs k_i, sliders T_0i; eqs. 4-8).
- :mod:`~contact.layer.strip_lookup`: a table read strip by strip (clamped to its range) and its coverage of the
  strips in contact.
- :mod:`~contact.layer.patch_scaling`: the fixed point of table characteristics scaled to the solved patch size.

Depends on: wrlayer only. Every other contact subpackage may import it; it imports none of them.
"""
