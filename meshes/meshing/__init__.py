"""Gmsh meshes of rail and wheel sections (units mm): 2D plane-strain sections and 3D local meshes refined at the load.

- :mod:`~meshes.meshing.gmsh_session`, :mod:`~meshes.meshing.gmsh_outline`, :mod:`~meshes.meshing.gmsh_to_skfem`: Gmsh plumbing.
- :mod:`~meshes.meshing.section_mesh`, :mod:`~meshes.meshing.local_mesh`, :mod:`~meshes.meshing.extruded_mesh`,
  :mod:`~meshes.meshing.structured_core_mesh`, :mod:`~meshes.meshing.mesh_size`: the meshes.
- :mod:`~meshes.meshing.mesh_quality`, :mod:`~meshes.meshing.mesh_io`: checks and files.

Depends on: meshes.profiles, wrlayer.
"""
