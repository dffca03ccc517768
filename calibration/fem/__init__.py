"""The FEM engine: small-strain J2 elastoplasticity on scikit-fem (units mm, N, MPa).

- :mod:`~calibration.fem.material`, :mod:`~calibration.fem.return_mapping`: von Mises material, radial return.
- :mod:`~calibration.fem.assembly`: B-matrices and batched-matmul assembly on scikit-fem bases.
- :mod:`~calibration.fem.elastoplastic_solver`: load paths followed level by level (step control, predictors).
- :mod:`~calibration.fem.newton`: one Newton increment and the assembled problem (tangent, corrections).
- :mod:`~calibration.fem.solver_state`: solver options, converged states (save/load), increment records.
- :mod:`~calibration.fem.linear_solvers`: sparse factorisations (PARDISO, SuperLU, CHOLMOD where present).
- :mod:`~calibration.fem.output`: VTK files and renders of the fields.
- :mod:`~calibration.fem.verification_meshes`: structured meshes for verification and benchmarks.

Depends on: wrlayer, scikit-fem. Knows nothing about profiles or contact.
"""
