"""The typed Kik–Piotrowski scene: one frozen dataclass per TOML section, field names = TOML keys (units mm, N, MPa,
s). Built by :func:`contact.scenes.scene.parse_scene`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from wrlayer.characteristic import Characteristic
from wrlayer.layer_table import LayerTable
from contact.normal.method import NormalMethod
from contact.passes.passes import PassesOptions
from contact.passes.rolling_memory import MEMORY_RULES
from contact.scenes.result_io import Record
from wrlayer.elastic import shear_modulus_MPa
from wrlayer.errors import InputError

BODIES = ("wheel", "rail")
#: The keys of [passes] (the contact and the wheel–rail scenes).
PASSES_KEYS = ("max", "hardening", "tolerance_mm", "memory", "traction_coefficient")


@dataclass(frozen=True)
class LoadSpec:
    """[load]: the normal load of the contact.

    Attributes
    ----------
    normal_force_N : float
        Normal force N (N).
    rolling_radius_mm : float
        Rolling radius in the rolling direction (mm, paper eq. 10).
    """

    normal_force_N: float
    rolling_radius_mm: float


@dataclass(frozen=True)
class MaterialSpec:
    """[material]: elastic constants of both bodies.

    Attributes
    ----------
    E_MPa : float
        Young's modulus (MPa).
    poisson : float
        Poisson's ratio (-).
    """

    E_MPa: float
    poisson: float

    @property
    def G_MPa(self) -> float:
        """Shear modulus E / (2 (1 + nu)) (MPa)."""
        return shear_modulus_MPa(self.E_MPa, self.poisson)


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
class BodyLayerSpec:
    """[layer.wheel] / [layer.rail]: one body's layer, a characteristic or a calibration table read at
    ``position_mm`` (+ strip offsets).

    Attributes
    ----------
    body : str
        "wheel" or "rail" (-).
    characteristic : Characteristic | None
        The characteristic p(u) (``u_mm``, ``p_MPa``; MPa over mm, paper eq. 13).
    table_path : Path | None
        The calibration table (``table``, resolved path).
    position_mm : float | None
        Profile coordinate of the contact point on that body (mm).
    table : LayerTable | None
        The table as read.
    scale_to_patch : bool
        Scale the table's characteristic to the solved patch size (-).
    """

    body: str
    characteristic: Characteristic | None = None
    table_path: Path | None = None
    position_mm: float | None = None
    table: LayerTable | None = None
    scale_to_patch: bool = False

    def characteristic_at(self, offset_mm: float = 0.0, what: str = "layer",
                          patch_mm: tuple[float, float] | None = None) -> Characteristic:
        """The characteristic at the contact point shifted by ``offset_mm`` along the profile (InputError if the
        table does not cover it); with ``scale_to_patch`` and ``patch_mm`` = (a, b) in mm, scaled to that patch
        (``LayerTable.characteristic_at``)."""
        if self.characteristic is not None:
            return self.characteristic
        y = float(self.position_mm) + float(offset_mm)
        lo, hi = (float(v) for v in self.table.y_range_mm)
        if not lo <= y <= hi:
            raise InputError(f"{what}.table", f"does not cover the contact location y = {y:.4g} mm on the "
                             f"{self.body} (table {self.table_path.name} covers {lo:.4g}..{hi:.4g} mm)")
        try:
            if self.scale_to_patch and patch_mm is not None:
                return self.table.characteristic_at(y, patch_mm=patch_mm)
            return self.table.characteristic_at(y)
        except InputError as err:
            raise InputError(f"{what}.table", str(err)) from None


@dataclass(frozen=True)
class LayerSpec:
    """[layer]: either one combined characteristic for wheel and rail together (the paper's eq. 13 layer) or one
    layer per body.

    Attributes
    ----------
    combined : Characteristic | None
        The combined characteristic (``layer.u_mm``, ``layer.p_MPa``; MPa over mm, paper eq. 13).
    wheel : BodyLayerSpec | None
        The wheel's layer.
    rail : BodyLayerSpec | None
        The rail's layer.
    """

    combined: Characteristic | None = None
    wheel: BodyLayerSpec | None = None
    rail: BodyLayerSpec | None = None

    @property
    def uses_tables(self) -> bool:
        return any(b is not None and b.table_path is not None for b in (self.wheel, self.rail))


@dataclass(frozen=True)
class TangentialSpec:
    """[tangential]: creepages and friction of the tangential solution (``method.tangential``); the creepages hold
    at the scene's origin (x = 0, y = 0; docs/conventions.md).

    Attributes
    ----------
    creepage_x : float
        Longitudinal creepage xi at the scene's origin (-), |xi| <= 0.1.
    creepage_y : float
        Lateral creepage eta at the scene's origin (-), |eta| <= 0.1.
    spin_per_mm : float
        Spin creepage phi (1/mm), |phi| <= 0.01.
    friction : float
        Coulomb friction coefficient mu (-), > 0 when a creepage is given.
    speed_mm_s : float
        Rolling speed (mm/s).
    flexibility : str
        FASTSIM flexibility rule: "three", "single" or "blended" (-).
    """

    creepage_x: float = 0.0
    creepage_y: float = 0.0
    spin_per_mm: float = 0.0
    friction: float = 0.3
    speed_mm_s: float = 1000.0
    flexibility: str = "three"

    @property
    def has_creepage(self) -> bool:
        return not (self.creepage_x == 0.0 and self.creepage_y == 0.0 and self.spin_per_mm == 0.0)


@dataclass(frozen=True)
class PassesSpec(Record):
    """[passes]: repeated passes (paper section 5), in the contact and the wheel–rail scenes.

    Attributes
    ----------
    max : int
        Largest number of passes (-).
    hardening : bool
        Keep the sliders' state between passes (strain hardening): the same as `memory = "state_kept"` (-).
    tolerance_mm : float
        Residual displacement below which a pass counts as elastic (shakedown) (mm).
    memory : str
        What a pass leaves for the next (-): "rolling" (the layer table's rolling law, docs/rolling.md; "relaxed"
        for a layer without one), "relaxed" (the paper's model: sliders relaxed before each pass, section 5) or
        "state_kept" (= ``hardening = true``).
    traction_coefficient : float
        Traction coefficient c = q / p of the rolling law (-, in [-1, 1]; its magnitude is used; 0: free rolling).
    """

    max: int = 1
    hardening: bool = False
    tolerance_mm: float = 1e-6
    memory: str = "rolling"
    traction_coefficient: float = 0.0

    @property
    def options(self) -> PassesOptions:
        """The passes' options of :func:`contact.passes.passes.run_passes`."""
        return PassesOptions(max_passes=self.max, tolerance_mm=self.tolerance_mm, hardening=self.hardening,
                             memory=self.memory, traction_coefficient=self.traction_coefficient)


def parse_passes_memory(keys) -> tuple[bool, str, float]:
    """(hardening, memory, traction_coefficient) of a [passes] table (a :class:`wrlayer.validate.Keys`).
    ``hardening = true`` is ``memory = "state_kept"``; a table setting both so that they disagree is an
    InputError naming ``memory``."""
    hardening = keys.boolean("hardening", False)
    memory = keys.text("memory", "state_kept" if hardening else "rolling", MEMORY_RULES)
    if "hardening" in keys.table and "memory" in keys.table and hardening != (memory == "state_kept"):
        raise keys.error("memory", f"{memory!r} contradicts hardening = {str(hardening).lower()} (hardening = true "
                                   "is memory = 'state_kept'; set one of them)")
    traction = keys.number("traction_coefficient", 0.0, ge=-1.0, le=1.0)
    return memory == "state_kept", memory, traction


@dataclass(frozen=True)
class MethodSpec:
    """[method]: solver settings.

    Attributes
    ----------
    alpha : float
        Kik–Piotrowski's virtual penetration factor (-, paper eq. 9).
    grid_mm : float
        Strip grid spacing (mm).
    fastsim_cells : int
        FASTSIM cells per strip (-).
    normal : str
        The normal solver: "kik_piotrowski", "exact" or "coarse_exact" (the half-space on a coarse grid) (-).
    exact_cells : int | None
        Exact solver grid: cells along x over the patch length (-); None: the solver's default.
    layer_mode : str
        Exact solver's layer mode: "indentation" or "rolling" (-).
    tangential : str
        The tangential solver: "fastsim" (Kalker's simplified theory), "fastrip" (FaStrip) or "exact" (Kalker's
        full theory on the grid) (-; docs/tangential.md).
    """

    alpha: float = 0.55
    grid_mm: float = 0.1
    fastsim_cells: int = 60
    normal: str = "kik_piotrowski"
    exact_cells: int | None = None
    layer_mode: str = "indentation"
    tangential: str = "fastsim"

    def normal_method(self) -> NormalMethod:
        """The :class:`contact.normal.method.NormalMethod` of these keys."""
        return NormalMethod(self.normal, self.exact_cells, self.layer_mode)


#: Values of ``output.convention``: wrlayer's signs only, or also CONTACT's (contact_convention.csv).
OUTPUT_CONVENTIONS = ("wrlayer", "contact")


@dataclass(frozen=True)
class OutputSpec:
    """[output]: extra output files of a contact scene.

    Attributes
    ----------
    vtk : bool
        Write the patches' fields for ParaView (vtk/contact_fields.pvd and one .vtu per patch and pass) (-).
    convention : str
        "wrlayer" (default) or "contact": also write the creep forces, moment and creepages in CONTACT's sign
        convention (contact_convention.csv; docs/conventions.md) (-).
    """

    vtk: bool = True
    convention: str = "wrlayer"


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
    layer : LayerSpec | None
        [layer]; None: elastic bodies.
    tangential : TangentialSpec | None
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
    layer: LayerSpec | None
    tangential: TangentialSpec | None
    passes: PassesSpec
    method: MethodSpec
    output: OutputSpec = field(default_factory=OutputSpec)
    reference: dict[str, Any] = field(default_factory=dict)
    data: dict[str, Any] = field(default_factory=dict)
    content_hash: str = ""

    def __repr__(self) -> str:
        return (f"Scene({self.path.name}: N={self.load.normal_force_N:g} N, {self.separation.kind} separation, "
                f"layer {'none' if self.layer is None else 'yes'}, passes.max={self.passes.max})")

    @property
    def name(self) -> str:
        return self.path.stem


__all__ = ["BODIES", "BodyLayerSpec", "LayerSpec", "LoadSpec", "MaterialSpec", "MethodSpec", "PassesSpec", "OUTPUT_CONVENTIONS",
           "OutputSpec", "Scene", "SeparationSpec", "TangentialSpec"]
