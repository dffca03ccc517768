"""Normal contact solvers (units mm, N, MPa).

- :mod:`~contact.normal.problem`: the normal problem (separation, force, radius, E_MPa, poisson) on its strip grid.
- :mod:`~contact.normal.solution`: what every solver returns (:class:`NormalSolution`, one RegionSolution per region).
- :mod:`~contact.normal.kik_piotrowski`: the paper's fast method (virtual penetration, eqs. 7-15) with the Prandtl
  layer, built on :mod:`~contact.normal.regions` (N at one approach, interacting contact regions),
  :mod:`~contact.normal.layer_at_strip` (the layers' loading curve at a reference strip, exact in p_0),
  :mod:`~contact.normal.delta_search` (the approach for the target force) and
  :mod:`~contact.normal.boussinesq` (Boussinesq integrals of the elliptic-paraboloid pressure).
- :mod:`~contact.normal.patch`: the discretised contact patch (strips in y, cells in x) every solver hands on.
- :mod:`~contact.normal.exact`: the exact half-space solver with the layer cell by cell (``method.normal = "exact"``),
  built on :mod:`~contact.normal.halfspace` (Love coefficients, FFT), :mod:`~contact.normal.constrained_cg`
  (Polonsky–Keer) and :mod:`~contact.normal.exact_layer` (indentation / rolling layer); its pressure field and
  what FASTSIM takes from it: :mod:`~contact.normal.exact_field`; docs/exact-solver.md.
- :mod:`~contact.normal.coarse_exact`: the same half-space problem on a coarse grid fitted to the patch.
- :mod:`~contact.normal.method`: the choice between them (``solve_normal_with(prob, layer, method=...)``; the
  default "auto" resolved once there: the exact solver).

Depends on: contact.layer, wrlayer.
Never imports contact.wheel_rail, contact.scenes or contact.tangential.
"""
