"""Wear simulation: wheel and rail profiles that evolve by abrasive wear and by the inelastic displacement of the
Prandtl surface layer (units mm, N, MPa, s; distances in km where named so).

Modules (one concept each): :mod:`laws` (Archard with the Jendel map, USFD T-gamma), :mod:`collective` (load
collective), :mod:`scene` (the TOML "wear" scene), :mod:`profile_grid` (deposit, smoothing, profile update),
:mod:`condition` (one running condition solved and turned into depths), :mod:`loop` (the step loop),
:mod:`outputs` (files), :mod:`plots` (pictures).
"""
