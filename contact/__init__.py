r"""Contact mechanics of wheel and rail with a Prandtl-body surface layer (units mm, N, MPa, s).

Subpackages, one concept each; dependencies point one way (left may import right, never the reverse):

    wear -> wheel_rail -> scenes -> passes -> normal -> layer
                                \-> tangential -> normal

- :mod:`contact.layer`: the Prandtl element, characteristics and calibration parameter tables.
- :mod:`contact.normal`: normal solvers (Kik-Piotrowski; the exact half-space solver; Boussinesq integrals; the Patch).
- :mod:`contact.tangential`: FASTSIM and Kalker's coefficients.
- :mod:`contact.passes`: repeated passes, residual displacement, shakedown.
- :mod:`contact.scenes`: scene files, the simulation run, results, tables and pictures.
- :mod:`contact.wheel_rail`: track geometry, contact search, kinematics, the wheel solve and its scenes.
- :mod:`contact.wear`: profiles evolving by wear and the layer's inelastic displacement.
- :mod:`contact.run_files`: a scene file of any kind run into an output folder (every file written); the command
  line (:mod:`contact.__main__`) only parses arguments.

Public API (imported on first use: ``import contact`` loads no solver; the full table is docs/api.md):

- Scenes: ``load_scene(path) -> Scene``, ``simulate(scene) -> SimulationRun`` (``.result``: a frozen
  ``SceneResult``; ``.result.to_dict()`` is the result.json data), ``run_scene_file(path, out_dir, plots=False)``: any scene file (single contact, wheel-rail case or
  sweep) run into ``out_dir`` (result.json, cases.csv, pictures), returns the result dictionary.
- Normal contact: ``NormalProblem`` (separation mm, force N, radius mm, ``E_MPa``, ``poisson``),
  ``solve_normal(prob, layer)`` (Kik-Piotrowski), ``solve_normal_with(prob, layer, method=...)`` ("auto", the
  default: the exact half-space solver; "kik_piotrowski", "exact", "coarse_exact" or a ``NormalMethod``)
  -> ``NormalSolution``; ``paper_problem()`` / ``paper_layers(prob)``: the paper's example.
- Layer: ``Characteristic`` (p(u), MPa over mm), ``PrandtlLayer`` (elements along y), ``LayerPair`` (wheel, rail,
  combined), ``LayerTable`` (a calibration table file).
- Passes: ``run_passes(prob, layer, PassesOptions(...), method=...)`` -> ``PassRecord`` per pass.
- Wheel on rail: ``solve_wheel(rail_profile, wheel_profile, WheelRailInputs(...))`` -> ``WheelRailSolution``;
  ``TrackLayout``, ``WheelsetPose``; a wheel-rail scene file: ``load_wheel_rail_scene(path) -> WheelRailScene``,
  ``run_wheel_rail_scene(scene, out_dir, plots) -> SweepResult``.
- Wear: ``run_wear_file(scene_path, out_dir)`` -> the wear run (profiles per step, steps.csv, result.json).
- Contact geometry: ``contact_geometry(WheelsetProfiles(rail, wheel), TrackLayout(...))`` -> ``GeometryResult``
  (Delta r, contact angles, roll, contact points and jumps, equivalent conicity after EN 15302).

Depends on: wrlayer, meshes, calibration.
The contact package uses the public profile API :mod:`meshes.profiles`; only the wear loop's recalibration imports
:mod:`calibration` (its Python API, ``calibration.calibrate``).
"""

from wrlayer import lazy_exports

#: Public name -> the module that defines it.
API = {
    "load_scene": "contact.scenes.scene",
    "Scene": "contact.scenes.scene_spec",
    "MaterialSpec": "contact.scenes.sections",
    "MethodSpec": "contact.scenes.sections",
    "PassesSpec": "contact.scenes.sections",
    "TangentialSpec": "contact.scenes.sections",
    "simulate": "contact.scenes.simulation",
    "SimulationRun": "contact.scenes.simulation",
    "run_scene_file": "contact.run_files",
    "paper_problem": "contact.scenes.paper_example",
    "paper_layers": "contact.scenes.paper_example",
    "paper_characteristic": "contact.scenes.paper_example",
    "NormalProblem": "contact.normal.problem",
    "NormalSolution": "contact.normal.solution",
    "solve_normal": "contact.normal.kik_piotrowski",
    "solve_normal_with": "contact.normal.method",
    "NormalMethod": "contact.normal.method",
    "Characteristic": "wrlayer.characteristic",
    "PrandtlLayer": "contact.layer.prandtl_layer",
    "LayerPair": "contact.layer.prandtl_layer",
    "LayerTable": "wrlayer.layer_table",
    "run_passes": "contact.passes.passes",
    "PassesOptions": "contact.passes.passes",
    "PassRecord": "contact.passes.record",
    "solve_wheel": "contact.wheel_rail.solve",
    "WheelRailInputs": "contact.wheel_rail.inputs",
    "LayerSources": "contact.scenes.layers",
    "WheelLoadSpec": "contact.wheel_rail.sections",
    "WheelRailMethodSpec": "contact.wheel_rail.sections",
    "WheelRailSolution": "contact.wheel_rail.solution",
    "load_wheel_rail_scene": "contact.wheel_rail.parse",
    "WheelRailScene": "contact.wheel_rail.scene",
    "run_wheel_rail_scene": "contact.run_files",
    "SweepResult": "contact.wheel_rail.results",
    "TrackLayout": "contact.wheel_rail.track_geometry",
    "WheelsetPose": "contact.wheel_rail.track_geometry",
    "run_wear_file": "contact.run_files",
    "contact_geometry": "contact.geometry.analysis",
    "GeometryResult": "contact.geometry.analysis",
    "WheelsetProfiles": "contact.geometry.sweep",
}
__all__ = sorted(API)
__getattr__, __dir__ = lazy_exports(__name__, API)
