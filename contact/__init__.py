r"""Contact mechanics of wheel and rail with a Prandtl-body surface layer (units mm, N, MPa, s).

Subpackages, one concept each; dependencies point one way (left may import right, never the reverse):

    wheel_rail -> scenes -> passes -> normal -> layer
                        \-> tangential -> normal

- :mod:`contact.layer`: the Prandtl element, characteristics and calibration parameter tables.
- :mod:`contact.normal`: normal solvers (Kik-Piotrowski; Boussinesq integrals; the Patch).
- :mod:`contact.tangential`: FASTSIM and Kalker's coefficients.
- :mod:`contact.passes`: repeated passes, residual displacement, shakedown.
- :mod:`contact.scenes`: scene files, the simulation run, results, tables and pictures.
- :mod:`contact.wheel_rail`: track geometry, contact search, kinematics, the wheel solve and its scenes.

``contact`` never imports ``calibration`` or ``meshes`` internals: it reads the parameter-table format and uses the
public profile API :mod:`meshes.profiles`.
"""
