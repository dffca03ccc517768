"""Material and boundary conditions shared by the FEM tests."""

from calibration.fem.material import J2Material

STEEL = J2Material(210000.0, 0.3, 500.0)
#: far boundaries clamped, symmetry planes as rollers
DIRICHLET_2D = {"fixed": [0, 1], "side": [0, 1], "sym_y": [0]}
DIRICHLET_3D = {"fixed": [0, 1, 2], "side": [0, 1, 2], "symmetry": [0], "sym_y": [1]}
