"""Normal contact solvers (units mm, N, MPa).

- :mod:`~contact.normal.kik_piotrowski`: the paper's fast method (virtual penetration, eqs. 7-15) with the Prandtl layer.
- :mod:`~contact.normal.boussinesq`: Boussinesq integrals of the elliptic-paraboloid pressure used by it.
- :mod:`~contact.normal.patch`: the discretised contact patch (strips in y, cells in x) every solver hands on.

Depends on: contact.layer. Never imports contact.wheel_rail, contact.scenes or contact.tangential.
"""
