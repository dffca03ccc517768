"""The Prandtl-body surface layer (units mm, MPa).

- :mod:`~contact.layer.characteristic`: the piecewise-linear monotonic characteristic p(u) and series combination.
- :mod:`~contact.layer.prandtl_layer`: the Prandtl element state per strip (springs k_i, sliders T_0i; eqs. 4-8).
- :mod:`~contact.layer.layer_table`: reading and writing calibration parameter tables (the format calibration writes).
- :mod:`~contact.layer.strip_lookup`: a table read strip by strip (clamped to its range) and its coverage of the
  strips in contact.
- :mod:`~contact.layer.patch_scaling`: the fixed point of table characteristics scaled to the solved patch size.

Depends on: wrlayer only. Every other contact subpackage may import it; it imports none of them.
"""
