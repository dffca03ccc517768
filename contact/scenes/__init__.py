"""Single-contact scenes: reading scene files, running them, writing results, tables and pictures.

- :mod:`~contact.scenes.scene`: scene TOML -> validated dataclasses.
- :mod:`~contact.scenes.simulation`: a scene run (normal, passes, tangential) -> result dictionary.
- :mod:`~contact.scenes.result_io` / :mod:`~contact.scenes.result_table`: result.json, units, code version, tables.
- :mod:`~contact.scenes.plots`: patch, pressure and residual-displacement pictures.
- :mod:`~contact.scenes.paper_example`: the paper's example scene (Table 1).

Depends on: contact.normal, contact.tangential, contact.layer, contact.passes. Never imports contact.wheel_rail.
"""
