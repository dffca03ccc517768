"""The sections shared by every scene kind (contact, wheel–rail, wear), defined once: [material], [tangential],
[passes], [method], [output] and the contact scene's [load]. Each key's unit, default and bounds are declared on its
field (:func:`wrlayer.section_keys.key`) and read by :func:`wrlayer.section_keys.read_section`; a scene kind that
needs more keys extends a section (:class:`contact.wheel_rail.scene.WheelRailMethodSpec`), the contact scene's
[tangential] adds the creepages (:class:`CreepageSpec`). Units mm, N, MPa, s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contact.normal.method import NORMAL_CHOICES, NormalMethod, resolve_normal_name
from contact.normal.problem import ALPHA, GRID_MM, NormalProblem
from contact.passes.passes import PassesOptions
from contact.passes.rolling_memory import MEMORY_RULES
from contact.scenes.result_io import Record
from wrlayer.elastic import shear_modulus_MPa, youngs_modulus_MPa
from wrlayer.errors import InputError
from wrlayer.section_keys import key, read_section
from wrlayer.validate import (MAX_E_MPA, MAX_FASTSIM_CELLS, MAX_PASSES, MAX_RADIUS_MM, MIN_ALPHA, MIN_E_MPA,
                              MIN_FORCE_N, MIN_GRID_MM, MIN_RADIUS_MM, Keys)

#: Values of ``output.convention``: wrlayer's signs only, or also CONTACT's (contact_convention.csv).
OUTPUT_CONVENTIONS = ("wrlayer", "contact")
#: Largest |creepage_x|, |creepage_y| (-) and |spin_per_mm| (1/mm) of a scene: beyond them the creepages are not
#: small (rolling contact theory's assumption) and almost surely a unit or sign slip (e.g. percent for -).
MAX_CREEPAGE = 0.1
MAX_SPIN_PER_MM = 0.01


def _tangential_methods() -> tuple[str, ...]:
    from contact.tangential.method import TANGENTIAL_METHODS  # here: the tangential solvers compile with numba

    return TANGENTIAL_METHODS


def _flexibility_rules() -> tuple[str, ...]:
    from contact.tangential.fastsim import FLEXIBILITY_RULES  # here: fastsim compiles with numba

    return FLEXIBILITY_RULES


@dataclass(frozen=True)
class LoadSpec(Record):
    """[load] of a contact scene: the normal load of the contact.

    Attributes
    ----------
    normal_force_N : float
        Normal force N (N).
    rolling_radius_mm : float
        Rolling radius in the rolling direction (mm, paper eq. 10).
    """

    normal_force_N: float = key(unit="N", ge=MIN_FORCE_N, plausible="normal_force_N")
    rolling_radius_mm: float = key(unit="mm", ge=MIN_RADIUS_MM, le=MAX_RADIUS_MM,
                                   plausible="rolling_radius_mm")


@dataclass(frozen=True)
class MaterialSpec(Record):
    """[material]: elastic constants of wheel and rail (a scene may give ``G_MPa`` instead of ``E_MPa``).

    Attributes
    ----------
    E_MPa : float
        Young's modulus (MPa).
    poisson : float
        Poisson's ratio (-).
    """

    E_MPa: float = key(210000.0, "MPa", ge=MIN_E_MPA, le=MAX_E_MPA, plausible="E_MPa")
    poisson: float = key(0.28, "-", ge=0.0, lt=0.5, plausible="poisson")

    @property
    def G_MPa(self) -> float:
        """Shear modulus E / (2 (1 + nu)) (MPa)."""
        return shear_modulus_MPa(self.E_MPa, self.poisson)


def read_material(keys: Keys, required: bool = False) -> MaterialSpec:
    """[material]; ``G_MPa`` becomes ``E_MPa`` = 2 G (1 + nu). ``required``: E_MPa (or G_MPa) and poisson must be
    given (the contact scene)."""
    nu = keys.number("poisson", None if required else MaterialSpec.poisson, ge=0.0, lt=0.5)
    if "E_MPa" in keys.table and "G_MPa" in keys.table:
        raise keys.error("G_MPa", "give either E_MPa or G_MPa, not both")
    given = {"poisson": nu}
    if "G_MPa" in keys.table:
        shear = keys.plausible_number("G_MPa", "G_MPa", ge=MIN_E_MPA / 3.0, le=MAX_E_MPA / 2.0)
        given["E_MPa"] = youngs_modulus_MPa(shear, nu)
    return read_section(MaterialSpec, keys, required=("E_MPa",) if required else (), given=given,
                        also_known=("G_MPa",))


@dataclass(frozen=True)
class TangentialSpec(Record):
    """[tangential]: the friction of the tangential solution (``method.tangential``).

    Attributes
    ----------
    friction : float
        Coulomb friction coefficient mu (-); 0: no tangential solution.
    """

    friction: float = key(0.3, "-", ge=0.0)


@dataclass(frozen=True)
class CreepageSpec(TangentialSpec):
    """[tangential] of a contact scene: the friction, creepages and speed of the tangential solution
    (``method.tangential``); the creepages hold at the scene's origin (x = 0, y = 0; docs/conventions.md).

    Attributes
    ----------
    friction : float
        Coulomb friction coefficient mu (-), > 0 when a creepage is given (required).
    creepage_x : float
        Longitudinal creepage xi at the scene's origin (-), |xi| <= 0.1.
    creepage_y : float
        Lateral creepage eta at the scene's origin (-), |eta| <= 0.1.
    spin_per_mm : float
        Spin creepage phi (1/mm), |phi| <= 0.01.
    speed_mm_s : float
        Rolling speed (mm/s).
    flexibility : str
        FASTSIM flexibility rule: "three", "single" or "blended" (-).
    """

    creepage_x: float = key(0.0, "-")
    creepage_y: float = key(0.0, "-")
    spin_per_mm: float = key(0.0, "1/mm")
    speed_mm_s: float = key(1000.0, "mm/s", gt=0.0, plausible="speed_mm_s")
    flexibility: str = key("three", choices=_flexibility_rules)

    @property
    def has_creepage(self) -> bool:
        return not (self.creepage_x == 0.0 and self.creepage_y == 0.0 and self.spin_per_mm == 0.0)


def read_creepages(keys: Keys) -> CreepageSpec:
    """[tangential] of a contact scene: friction required, creepages within range, friction > 0 with creepages."""
    tangential = read_section(CreepageSpec, keys, required=("friction",))
    for name, limit in (("creepage_x", MAX_CREEPAGE), ("creepage_y", MAX_CREEPAGE), ("spin_per_mm", MAX_SPIN_PER_MM)):
        value = getattr(tangential, name)
        if not abs(value) <= limit:
            raise keys.error(name, f"must be within +-{limit:g}, got {value!r}")
    if tangential.has_creepage and not tangential.friction > 0:
        raise keys.error("friction", f"must be > 0 with creepages (a tangential solution), got {tangential.friction!r}")
    return tangential


@dataclass(frozen=True)
class PassesSpec(Record):
    """[passes]: repeated passes (paper section 5).

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

    max: int = key(1, ge=1, le=MAX_PASSES)
    hardening: bool = key(PassesOptions.hardening)
    tolerance_mm: float = key(PassesOptions.tolerance_mm, "mm", gt=0.0)
    memory: str = key(PassesOptions.memory, choices=MEMORY_RULES)
    traction_coefficient: float = key(PassesOptions.traction_coefficient, "-", ge=-1.0, le=1.0)

    @property
    def options(self) -> PassesOptions:
        """The passes' options of :func:`contact.passes.passes.run_passes`."""
        return PassesOptions(max_passes=self.max, tolerance_mm=self.tolerance_mm, hardening=self.hardening,
                             memory=self.memory, traction_coefficient=self.traction_coefficient)


def read_passes(keys: Keys) -> PassesSpec:
    """[passes]. ``hardening = true`` is ``memory = "state_kept"``; a table setting both so that they disagree is
    an InputError naming ``memory``."""
    hardening = keys.boolean("hardening", PassesSpec.hardening)
    memory = keys.text("memory", "state_kept" if hardening else PassesSpec.memory, MEMORY_RULES)
    if "hardening" in keys.table and "memory" in keys.table and hardening != (memory == "state_kept"):
        raise keys.error("memory", f"{memory!r} contradicts hardening = {str(hardening).lower()} (hardening = true "
                                   "is memory = 'state_kept'; set one of them)")
    return read_section(PassesSpec, keys, given={"hardening": memory == "state_kept", "memory": memory})


@dataclass(frozen=True)
class MethodSpec(Record):
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
        The normal solver: "auto" (default: "exact", the FFT half-space solver), "kik_piotrowski" (the paper's;
        p_max approximate), "exact" or "coarse_exact" (the half-space on a coarse grid) (-; held resolved, so a
        result's inputs name the solver that ran).
    exact_cells : int | None
        Exact solver grid: cells along x over the patch length (-); None: the solver's default.
    layer_mode : str
        Exact solver's layer mode: "indentation" or "rolling" (-).
    tangential : str
        The tangential solver: "fastsim" (Kalker's simplified theory), "fastrip" (FaStrip) or "exact" (Kalker's
        full theory on the grid) (-; docs/tangential.md).
    """

    alpha: float = key(ALPHA, "-", ge=MIN_ALPHA, le=1.0)
    grid_mm: float = key(GRID_MM, "mm", ge=MIN_GRID_MM)
    fastsim_cells: int = key(60, ge=2, le=MAX_FASTSIM_CELLS)
    normal: str = key(NormalMethod.name, choices=NORMAL_CHOICES)
    exact_cells: int | None = key(NormalMethod.exact_cells, ge=1)
    layer_mode: str = key(NormalMethod.layer_mode)
    tangential: str = key("fastsim", choices=_tangential_methods)

    def __post_init__(self):
        object.__setattr__(self, "normal", resolve_normal_name(self.normal, self.layer_mode))

    def normal_method(self) -> NormalMethod:
        """The :class:`contact.normal.method.NormalMethod` of these keys."""
        return NormalMethod(self.normal, self.exact_cells, self.layer_mode)

    def normal_problem(self, y_mm: np.ndarray, f_mm: np.ndarray, force_N: float, rolling_radius_mm: float,
                       material: MaterialSpec, interpolation: str = "linear") -> NormalProblem:
        """The normal problem of a separation table f(y) (mm) at the normal force (N) with these settings."""
        return NormalProblem(y_mm, f_mm, force_N, rolling_radius_mm, material.E_MPa, material.poisson,
                             alpha=self.alpha, grid_mm=self.grid_mm, interpolation=interpolation)


def read_method(keys: Keys, kind: type[MethodSpec] = MethodSpec) -> MethodSpec:
    """[method] as ``kind`` (a :class:`MethodSpec` or an extension of it), the normal solver's options checked
    (InputError naming ``method.normal``, ``method.exact_cells`` or ``method.layer_mode``)."""
    method = read_section(kind, keys)
    try:
        method.normal_method()
    except InputError as err:
        name = err.what.removeprefix("method.")
        raise keys.error(name if name in ("exact_cells", "layer_mode") else "normal", err.problem) from None
    return method


@dataclass(frozen=True)
class OutputSpec(Record):
    """[output]: extra output files.

    Attributes
    ----------
    vtk : bool
        Write the patches' fields for ParaView (vtk/contact_fields.pvd and one .vtu per patch and pass) (-).
    convention : str
        "wrlayer" (default) or "contact": also write the creep forces, moment and creepages in CONTACT's sign
        convention (contact_convention.csv; docs/conventions.md) (-).
    """

    vtk: bool = key(True)
    convention: str = key("wrlayer", choices=OUTPUT_CONVENTIONS)


__all__ = ["CreepageSpec", "LoadSpec", "MAX_CREEPAGE", "MAX_SPIN_PER_MM", "MaterialSpec", "MethodSpec",
           "OUTPUT_CONVENTIONS", "OutputSpec", "PassesSpec", "TangentialSpec", "read_creepages", "read_material",
           "read_method", "read_passes"]
