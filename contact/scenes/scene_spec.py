"""The typed Kik–Piotrowski scene: the shared sections (:mod:`contact.scenes.sections`, :mod:`contact.scenes.layers`)
and the contact scene's own [separation] (units mm, N, MPa, s). Built by :func:`contact.scenes.scene.parse_scene`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from contact.normal.problem import NormalProblem
from contact.scenes.layers import LayersSpec
from contact.scenes.sections import CreepageSpec, LoadSpec, MaterialSpec, MethodSpec, OutputSpec, PassesSpec


@dataclass(frozen=True)
class SeparationSpec:
    """[separation]: the profile separation f(y) as a table (a parabola is sampled into one).

    Attributes
    ----------
    y_mm : np.ndarray
        Lateral positions, strictly increasing (mm).
    f_mm : np.ndarray
        Separation at ``y_mm`` (mm).
    kind : str
        How it was given: "table" or "parabola" (-).
    lateral_radius_mm : float | None
        Lateral radius of the parabola f = y^2 / (2 R_y) (mm); None for a table.
    """

    y_mm: np.ndarray
    f_mm: np.ndarray
    kind: str = "table"
    lateral_radius_mm: float | None = None


@dataclass(frozen=True)
class Scene:
    """A validated contact scene.

    Attributes
    ----------
    path : Path
        The scene file.
    title : str
        Free text.
    description : str
        Free text.
    load : LoadSpec
        [load].
    material : MaterialSpec
        [material].
    separation : SeparationSpec
        [separation].
    layers : LayersSpec | None
        [layers]; None: elastic bodies.
    tangential : CreepageSpec | None
        [tangential]; None: no tangential solution.
    passes : PassesSpec
        [passes].
    method : MethodSpec
        [method].
    output : OutputSpec
        [output].
    reference : dict
        [reference]: published numbers to compare with (units in the key names).
    data : dict
        The TOML content as read.
    content_hash : str
        sha256 over the scene file and every file it refers to (hex).
    """

    path: Path
    title: str
    description: str
    load: LoadSpec
    material: MaterialSpec
    separation: SeparationSpec
    layers: LayersSpec | None
    tangential: CreepageSpec | None
    passes: PassesSpec
    method: MethodSpec
    output: OutputSpec = field(default_factory=OutputSpec)
    reference: dict[str, Any] = field(default_factory=dict)
    data: dict[str, Any] = field(default_factory=dict)
    content_hash: str = ""

    def __repr__(self) -> str:
        return (f"Scene({self.path.name}: N={self.load.normal_force_N:g} N, {self.separation.kind} separation, "
                f"layers {'none' if self.layers is None else 'yes'}, passes.max={self.passes.max})")

    @property
    def name(self) -> str:
        return self.path.stem


    def normal_problem(self) -> NormalProblem:
        """The scene's normal problem (separation table, load, material, alpha, strip grid)."""
        sep, load = self.separation, self.load
        return self.method.normal_problem(sep.y_mm, sep.f_mm, load.normal_force_N, load.rolling_radius_mm,
                                          self.material)

    def to_dict(self) -> dict[str, Any]:
        """The resolved inputs as plain data (defaults filled in, resolved paths, hashes): result.json "inputs"."""
        sep = self.separation
        return {
            "scene_file": str(self.path.resolve()),
            "content_sha256": self.content_hash,
            "title": self.title,
            "description": self.description,
            "load": self.load.to_dict(),
            "material": {**self.material.to_dict(), "G_MPa": self.material.G_MPa},
            "separation": {"kind": sep.kind, "lateral_radius_mm": sep.lateral_radius_mm,
                           "y_mm": sep.y_mm.tolist(), "f_mm": sep.f_mm.tolist()},
            "layers": None if self.layers is None else self.layers.to_dict(),
            "tangential": None if self.tangential is None else self.tangential.to_dict(),
            "passes": self.passes.to_dict(),
            "method": self.method.to_dict(),
            "output": self.output.to_dict(),
            "reference": dict(self.reference),
            "scene_toml": self.data,
        }


__all__ = ["Scene", "SeparationSpec"]
