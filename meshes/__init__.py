"""Rail and wheel profiles and their Gmsh meshes (units mm).

- :mod:`meshes.profiles`: the standard sections (S1002, 60E1, 54E1) and profiles read from files; the public API.
- :mod:`meshes.meshing`: 2D section and 3D local meshes refined at the load.
- :mod:`meshes.plots`: pictures of meshes.

Public API (imported on first use: ``import meshes`` loads neither scipy nor gmsh; docs/api.md):

- ``load_profile(name_or_path, **options) -> Profile``: "S1002", "60E1"/"UIC60", "54E1"/"UIC54" or a profile file
  (.prr/.prw SIMPACK, .txt/.csv two columns in mm); ``get_profile`` is the same function.
- ``Profile``: z(y) in mm with ``z``, ``dz``, ``curvature`` (1/mm), ``normal``, ``arc_length``, ``sample``;
  ``S1002`` (wheel, nominal radius ``r0`` in mm), ``Rail60E1``, ``Rail54E1``, ``SplineProfile`` (through points).
- ``read_profile(path)``, ``write_simpack(path, profile)``: profile files.

Depends on: wrlayer.
"""

from wrlayer import lazy_exports

#: Public name -> the module that defines it.
API = {
    "load_profile": "meshes.profiles.lookup",
    "get_profile": "meshes.profiles.lookup",
    "Profile": "meshes.profiles.base",
    "S1002": "meshes.profiles.s1002",
    "Rail60E1": "meshes.profiles.rail_heads",
    "Rail54E1": "meshes.profiles.rail_heads",
    "SplineProfile": "meshes.profiles.spline",
    "read_profile": "meshes.profiles.io",
    "write_simpack": "meshes.profiles.io",
}
__all__ = sorted(API)
__getattr__, __dir__ = lazy_exports(__name__, API)
