"""Rail and wheel profiles and their Gmsh meshes (units mm).

- :mod:`meshes.profiles`: the standard sections (S1002, 60E1, 54E1) and profiles read from files; the public API.
- :mod:`meshes.meshing`: 2D section and 3D local meshes refined at the load.
- :mod:`meshes.plots`: pictures of meshes.

Depends on: wrlayer. Imports neither calibration nor contact.
"""
