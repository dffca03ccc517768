"""Normal contact solvers (units mm, N, MPa).

- :mod:`~contact.normal.kik_piotrowski`: the paper's fast method (virtual penetration, eqs. 7-15) with the Prandtl layer.
- :mod:`~contact.normal.boussinesq`: Boussinesq integrals of the elliptic-paraboloid pressure used by it.
- :mod:`~contact.normal.patch`: the discretised contact patch (strips in y, cells in x) every solver hands on.
- :mod:`~contact.normal.exact`: the exact half-space solver with the layer cell by cell (``method.normal = "exact"``),
  built on :mod:`~contact.normal.halfspace` (Love coefficients, FFT), :mod:`~contact.normal.constrained_cg`
  (Polonsky–Keer) and :mod:`~contact.normal.exact_layer` (indentation / rolling layer); docs/exact-solver.md.
- :mod:`~contact.normal.method`: the choice between the two (``solve_normal_with``).

Depends on: contact.layer. Never imports contact.wheel_rail, contact.scenes or contact.tangential.
"""
