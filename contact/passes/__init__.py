"""Repeated passes over the same track position: residual displacements, shakedown and hardening.

- :mod:`~contact.passes.passes`: the pass loop on a normal solver, with relaxed or kept slider state.

Depends on: contact.normal, contact.layer, wrlayer.
Never imports contact.wheel_rail or contact.scenes.
"""
