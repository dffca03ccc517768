"""The calibration configuration model: frozen dataclasses whose fields are the TOML keys (units mm, N, MPa).

Each dataclass holds the defaults of its table (the one place they are written); :mod:`calibration.config`
reads a TOML file into them, validating every key. The layout of a file::

    [run] [material] [load] [mesh] [fit]   (every key optional)
    [[bodies]]                             (at least one; body, profile and positions required)
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

from calibration.hertz.geometry import DEFAULT_MAX_LATERAL_RADIUS_MM

#: The models of RunSettings.model.
MODELS = ("2d", "3d")
#: The calibration routes of RunSettings.method.
METHODS = ("direct", "similarity")
#: What RunSettings.similarity_outside does with a position outside the similarity master's domain.
SIMILARITY_OUTSIDE = ("direct", "nearest")
#: Which served positions get their own section's elastic solve (``[run] similarity_elastic``).
SIMILARITY_ELASTIC = ("none", "all", "unanchored")
#: The linear solvers of RunSettings.linear_solver.
LINEAR_SOLVERS = ("auto", "pardiso", "scipy")
#: The 3D mesh styles of MeshSettings.style.
MESH_STYLES = ("isotropic", "stretched", "extruded", "structured", "auto")
#: Default wheel load for the Hertz semi-axes (N): the paper's example, 100 kN.
REFERENCE_LOAD_N = 100000.0


@dataclass(frozen=True)
class RunSettings:
    """How the calibration runs (TOML table ``[run]``).

    Attributes
    ----------
    model : str
        FEM model: "3d" (local half model under the elliptic Hertz pressure) or "2d" (plane-strain section).
    method : str
        "direct" (the FEM at every position) or "similarity" (3D only: positions from the material's master
        curves over the surface convexity, the patch aspect ratio a/b and the patch size; those outside the
        master's domain as ``similarity_outside`` says; docs/calibration.md, "Calibration by similarity").
    similarity_outside : str
        "direct" (a position outside the master's domain by its own FEM) or "nearest" (from the master at the
        nearest point of its domain, the reason in the entry's warnings; the wear loop's recalibration).
    similarity_elastic : str
        Under "similarity", which served positions take their first-yield pressure p_y and elastic compliance
        from an elastic solve of their own section (meshing, one factorisation, one solve: a few seconds a
        position, cached in OUT/cache) instead of the master's, the plastic curves from the master at equal
        p0 / p_y (:mod:`calibration.similarity.elastic`): "none"; "all" (a position whose patch is within
        :data:`calibration.similarity.elastic.REUSE_LIMITS` of its reference's, a direct FEM or an earlier solve,
        keeps the reference's ratios instead of a solve of its own); or "unanchored" (only those without a direct
        reference whose patch is like theirs, :func:`calibration.similarity.anchor.applies`; the anchored ones take
        p_y and c_el from the reference's correction). true / false read as "all" / "none".
    master_dir : str
        Folder of the similarity master's FEM cache, shared between runs ("" : the run's own OUT/cache).
    workers : int
        Local worker processes (1..64); the machine's cores are shared among them as BLAS threads.
    scheduler : str
        Dask scheduler address, e.g. "tcp://host:8786" ("" : local processes).
    plots : bool
        Write the tables' pictures (PNG) and each position's VTK/PNG fields.
    linear_solver : str
        "auto" (PARDISO when installed, else SuperLU), "pardiso" or "scipy" (SuperLU, faster for 2D sections).
    """

    model: str = "3d"
    method: str = "direct"
    similarity_outside: str = "direct"
    similarity_elastic: str = "none"
    master_dir: str = ""
    workers: int = 2
    scheduler: str = ""
    plots: bool = True
    linear_solver: str = "scipy"


@dataclass(frozen=True)
class MaterialSettings:
    """J2 material with linear isotropic and kinematic hardening (TOML table ``[material]``, and
    ``[bodies.material]`` overriding it per body). Defaults: rail/wheel steel, initial yield in the R260 0.2 %
    proof stress range, hardening moduli a stated assumption.

    Attributes
    ----------
    E_MPa : float
        Young's modulus (MPa, > 0).
    poisson : float
        Poisson's ratio (-, in (-1, 0.4999]).
    yield_MPa : float
        Initial yield stress (MPa, > 0).
    H_iso_MPa : float
        Linear isotropic hardening modulus (MPa, >= 0).
    H_kin_MPa : float
        Linear kinematic hardening modulus (MPa, >= 0).
    """

    E_MPa: float = 210000.0
    poisson: float = 0.3
    yield_MPa: float = 500.0
    H_iso_MPa: float = 10000.0
    H_kin_MPa: float = 10000.0


@dataclass(frozen=True)
class LoadSettings:
    """The load path of one position (TOML table ``[load]``): p0 up to max_factor * p_y in n_levels equal steps
    above p_y (plus 0.5 p_y and p_y), unloading runs from the peaks unload_factors * p_y; p_y is the FEM
    first-yield pressure. ``[load]`` also holds ``reference_load_N`` (:class:`CalibrationConfig`).

    Attributes
    ----------
    max_factor : float
        Peak Hertz pressure p0 as a multiple of the FEM first-yield pressure p_y (-, in (1, 10]).
    n_levels : int
        Load levels above first yield (1..200).
    unload_factors : tuple of float
        Peaks, as multiples of p_y (each > 1 and <= max_factor), from which the FEM unloads to zero (-).
    max_increment_factor : float
        Largest solver load step as a multiple of p_y (-, in (0, 1]).
    """

    max_factor: float = 3.0
    n_levels: int = 8
    unload_factors: tuple[float, ...] = (1.05, 1.1, 1.2, 1.3, 1.5, 1.7, 2.0, 2.5, 3.0)
    max_increment_factor: float = 0.125


@dataclass(frozen=True)
class MeshSettings:
    """The FEM mesh of one position (TOML table ``[mesh]``); docs/calibration.md, "Mesh styles" and "Validated accuracy". The mesh
    size is h_min = min(a, b) / elements_per_semi_axis at the load point (2D: b / it), growing to h_max_mm.

    Attributes
    ----------
    elements_per_semi_axis : float
        Elements across the contact's shorter semi-axis at the load point (-, in (0.5, 100], at least 2 used).
    h_max_mm : float
        Largest element size far from the contact (mm, in (0, 100]).
    order : int
        Element order, 1 (linear) or 2 (quadratic).
    depth_mm : float or None
        Depth of the section below the surface (mm; None: the mesh module's default per body).
    rail_support_below_mm : float or None
        The rail head is also held on its side/underside boundary below z = -this (mm), so that the section does
        not bend over the thin web (a plane-strain artefact); None: clamped cut only.
    length_factor : float
        3D half-model length as a multiple of a (-, > 1; at least 4 b).
    grading : float
        Growth rate of the element size away from the contact (-, in (0, 5]).
    yield_search_radius_factor : float
        First yield is searched within this many b of the load centre (-, > 0).
    reference_depth_factor : float
        > 0: the layer displacement is measured against the material point this many max(a, b) (2D: b) below
        the load centre; 0: against the clamped far field, as a half-space's (-).
    refine_depth_factor : float
        3D: h_min fills the box of half-sizes (1.2 a, 1.2 b, this * b) at the load point, the plastic zone (-).
    style : str
        3D mesh style: "isotropic", "stretched" (the isotropic mesh of a patch of a/b = 1.4 stretched along x to
        the patch's a/b), "extruded" (structured layers along x), "structured" (a structured core along the
        surface, the normal and x) or "auto" (extruded for a/b >= 4, else isotropic).
    x_elements_per_semi_axis : float or None
        Extruded style: layers of a / this along x (-, >= 2; None: elements_per_semi_axis).
    yield_zone_refinement : float
        Isotropic and stretched styles: h_min / this around the point of first yield (-, 1..4; 1: off).
    """

    elements_per_semi_axis: float = 8.0
    h_max_mm: float = 6.0
    order: int = 2
    depth_mm: float | None = None
    rail_support_below_mm: float | None = 35.0
    length_factor: float = 5.0
    grading: float = 0.3
    yield_search_radius_factor: float = 3.0
    reference_depth_factor: float = 0.0
    refine_depth_factor: float = 1.0
    style: str = "isotropic"  # the library default; calibration/configs/default.toml sets "auto"
    x_elements_per_semi_axis: float | None = None
    yield_zone_refinement: float = 1.0


#: The fit modes of FitSettings.mode.
FIT_MODES = ("operating_range", "paper")


@dataclass(frozen=True)
class FitSettings:
    """The Prandtl element fit of each position (TOML table ``[fit]``; paper eqs. 4-8, docs/calibration-method.md).

    Attributes
    ----------
    mode : str
        "operating_range" (default): u_pl fitted in relative terms over ``weight_range``, the number of segments
        chosen by ``target_error`` (up to ``max_segments``), the element's reverse slider threshold fitted to the
        FEM's residual dents; "paper": ``n_segments`` segments fitted in absolute terms over the whole path, the
        paper's symmetric (Masing) element (the tables of earlier versions).
    n_segments : int
        Segments N of the "paper" fit (2..16; p_2 is pinned to the FEM first yield).
    max_segments : int
        Most segments of the "operating_range" fit (2..16).
    target_error : float
        "operating_range": the fewest segments whose u_pl error at every level inside ``weight_range`` is at most
        this, relative to max(u_pl, error_floor u_pl(1.5 p_2)) (-, in (0, 1)).
    error_floor : float
        "operating_range": f in the fit's error measure max(v, f v(1.5 p_2)), v the FEM's u_pl or residual dent
        (-, in (0, 1]): the default 1/30, about v(1.1 p_2) / v(1.5 p_2), makes the fit relative from about 1.1 p_2
        up; 1/3 is the target's measure (the fit of earlier versions).
    weight_range : tuple of float
        "operating_range": the levels p0 / p_2 fitted with full weight, [low, high] (-, 1 <= low < high); levels
        above it count a tenth.
    elastic_tolerance : float
        t in S_1 = p_max / (t u_pl(p_max)): the layer's elastic displacement at the largest calibrated pressure
        is t times its inelastic one (-, in (0, 1]; the layer has no elasticity of its own, the half-space
        carries it).
    elastic_fraction : float or None
        f of the former rule S_1 = 1 / (f c_hs), c_hs the half-space centre compliance (-, in (0, 1]); used only
        when given.
    max_relative_error : float
        Largest accepted fit error relative to max u (-, in (0, 10]).
    """

    mode: str = "operating_range"
    n_segments: int = 5
    max_segments: int = 16
    target_error: float = 0.02
    error_floor: float = 1.0 / 30.0
    weight_range: tuple[float, float] = (1.0, 3.0)
    elastic_tolerance: float = 0.01
    elastic_fraction: float | None = None
    max_relative_error: float = 0.1


@dataclass(frozen=True)
class BodySettings:
    """One calibrated body (TOML array of tables ``[[bodies]]``).

    Attributes
    ----------
    body : str
        "rail" or "wheel".
    profile : str or Profile
        Profile name (e.g. "60E1") or file path (relative to the configuration file when read from one); in
        Python also a :class:`meshes.profiles.Profile` object (e.g. a worn profile).
    mate : str or Profile or None
        The mating profile for the Hertz semi-axes (name, file or Profile object); None only with semi_axes_mm.
    positions_mm : tuple of float
        Lateral positions y of the calibration (mm, sorted, unique; TOML: ``positions_mm = [...]`` or
        ``positions = {start_mm, stop_mm, step_mm}``).
    semi_axes_mm : tuple of float or None
        Given Hertz semi-axes [a, b] (mm; rolling, lateral) instead of the mate's.
    inclination : float or None
        Rail inclination 1:n of the track relative to the rail profile's own frame, as the wheel-rail scenes'
        ``track.inclination`` (-, n >= 5, or 0 for a profile already placed as in the track, e.g. a canted
        file); the rail is the body's profile (rail) or its mate (wheel). None: 1:40 for a builtin rail; a rail
        from a file or a Profile object must give it (or inclination_rad).
    inclination_rad : float or None
        The same as an angle (rad, in [-0.2, 0.2]; TOML alias ``rail_cant_rad``); give at most one of the two.
    max_lateral_radius_mm : float
        Largest lateral radius of the curvature sum (mm, > 0): a flatter contact is taken as this curved.
    wheel_radius_mm : float or None
        Wheel rolling radius (mm, > 0; None: the profile's default).
    material : MaterialSettings
        The body's material (``[bodies.material]`` overrides ``[material]``).
    accept_unusual_profile : bool
        Read the body's and the mate's profile files without the plausibility checks of
        :mod:`meshes.profiles.plausibility` (units, orientation, steps; a profile unusual on purpose).
    units : str or None
        Length unit of the body's and the mate's profile files ("mm" or "m"; None: mm for text, CSV and MiniProf
        files, the header's ``units.len.f`` for SIMPACK files).
    anchor_table : str or None
        A direct 3D layer table of this body (e.g. the new profile's shipped table; path relative to the
        configuration file): under ``run.method = "similarity"`` each of its positions anchors the same position
        here (:mod:`calibration.similarity.anchor`); its reference profile is its header's ``profile_source``.
    """

    body: str
    profile: Any
    mate: Any
    positions_mm: tuple[float, ...]
    semi_axes_mm: tuple[float, float] | None = None
    inclination: float | None = None
    inclination_rad: float | None = None
    max_lateral_radius_mm: float = DEFAULT_MAX_LATERAL_RADIUS_MM
    wheel_radius_mm: float | None = None
    material: MaterialSettings = MaterialSettings()
    accept_unusual_profile: bool = False
    units: str | None = None
    anchor_table: str | None = None


@dataclass(frozen=True)
class CalibrationConfig:
    """A whole calibration: the bodies and positions and the settings shared by them.

    Attributes
    ----------
    source : str
        Where the configuration came from (the file name in error messages; "config" when built in Python).
    run : RunSettings
        TOML table ``[run]``.
    load : LoadSettings
        TOML table ``[load]`` (without reference_load_N).
    reference_load_N : float
        Wheel load for the Hertz semi-axes (N, > 0; TOML key ``load.reference_load_N``).
    mesh : MeshSettings
        TOML table ``[mesh]``.
    fit : FitSettings
        TOML table ``[fit]``.
    bodies : tuple of BodySettings
        TOML ``[[bodies]]``, each body at most once.
    """

    source: str
    run: RunSettings
    load: LoadSettings
    reference_load_N: float
    mesh: MeshSettings
    fit: FitSettings
    bodies: tuple[BodySettings, ...]

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d.pop("source")
        return d


__all__ = ["BodySettings", "CalibrationConfig", "FIT_MODES", "FitSettings", "LINEAR_SOLVERS", "LoadSettings", "MESH_STYLES",
           "METHODS", "MODELS", "MaterialSettings", "MeshSettings", "REFERENCE_LOAD_N", "RunSettings"]
