"""Single-contact scenes: reading scene files, running them, writing results, tables and pictures.

- :mod:`~contact.scenes.sections`: the sections every scene kind shares ([load], [material], [tangential],
  [passes], [method], [output]), each key's unit, default and bounds declared once.
- :mod:`~contact.scenes.layers`: [layers] of every scene kind and the one builder of a patch's layers.
- :mod:`~contact.scenes.scene`: scene TOML -> validated dataclasses (:mod:`~contact.scenes.scene_spec`).
- :mod:`~contact.scenes.scene_layers`: the scene's layers on the strip grid, table coverage, patch-size scaling.
- :mod:`~contact.scenes.simulation`: a scene run (normal, passes, tangential) -> result records.
- :mod:`~contact.scenes.run_result`: the result records of a scene run (SceneResult, ...;
  the pass record: contact.passes.record).
- :mod:`~contact.scenes.result_io` / :mod:`~contact.scenes.result_table`: result.json, units, code version, the
  inputs echo of every scene kind, tables (the Record base and the JSON converter: :mod:`wrlayer.json_io`).
- :mod:`~contact.scenes.cost`: cost estimates of scene runs (the guard before a run).
- :mod:`~contact.scenes.plots`: patch, pressure and residual-displacement pictures.
- :mod:`~contact.scenes.paper_example`: the paper's example scene (Table 1).

Depends on: contact.normal, contact.tangential, contact.layer, contact.passes. Never imports contact.wheel_rail.
"""
