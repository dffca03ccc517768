"""The FEM engine: small-strain J2 elastoplasticity on scikit-fem (units mm, N, MPa).

Its parts, in the order felupe separates them:

- mesh, region, field: :mod:`~calibration.fem.assembly` (:class:`~calibration.fem.assembly.Discretisation`:
  the scikit-fem basis, B-matrices, strains, internal forces and batched-matmul assembly);
  :mod:`~calibration.fem.verification_meshes`: structured meshes for verification and benchmarks.
- material: :mod:`~calibration.fem.material` (von Mises with linear isotropic/kinematic hardening),
  :mod:`~calibration.fem.return_mapping` (radial return and its consistent tangent).
- boundary: :mod:`~calibration.fem.boundary` (constrained dofs from named boundaries). Loads come from the jobs
  as nodal force vectors of p0 = 1 MPa: the static Hertz pressure (:mod:`calibration.hertz.load`, anything with
  ``prepare(basis)``) and the moving Hertz load (:mod:`calibration.rolling.moving_load`).
- solver: :mod:`~calibration.fem.problem` (the assembled problem: kept elastic factorisation, consistent tangent,
  Newton corrections), :mod:`~calibration.fem.newton` (the one Newton loop, with a material-response hook),
  :mod:`~calibration.fem.linear_solvers` (PARDISO, SuperLU), :mod:`~calibration.fem.solver_state` (options,
  converged states, increment records).
- steps: :mod:`~calibration.fem.elastoplastic_solver`: a load path as a generator of converged levels
  (``LoadPath.levels()``: the caller iterates, records, stops or keeps the state to restart from).
- output: :mod:`~calibration.fem.output` (VTK files and renders of the fields).

Two jobs run on it: the indentation of a calibration position (:mod:`calibration.indentation`, a load path up
and down) and the moving load (:mod:`calibration.rolling.passes`: the passes as a generator of step and pass
records; each step one :func:`~calibration.fem.newton.newton_increment`).

Depends on: wrlayer, scikit-fem, meshes.meshing (the Gmsh start of the verification meshes). Knows nothing about
profiles or contact.
"""
