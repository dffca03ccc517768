"""Rolling configuration: TOML file -> frozen dataclasses (keys = field names; units mm, N, MPa).

Layout of a file (every key optional except ``contact.a_mm`` and ``contact.levels``)::

    [material]  E_MPa, poisson, yield_MPa, H_iso_MPa, H_kin_MPa
    [contact]   model, a_mm, b_mm, traction_coefficient, levels, level_unit, body, table, profile, y_mm,
                accept_unusual_profile
    [track]     length_factor, step_factor, n_passes, ramp_steps, substeps
    [mesh]      elements_per_semi_axis, order, fine_width_factor, fine_depth_factor, size_factor, growth
    [run]       linear_solver, plots, layer_segments

``body = "section"``: the profile section at a calibration position instead of the block, given as a shipped
layer ``table`` + ``y_mm`` (a, b and the material from the table's position; no ``a_mm``, ``b_mm`` or
``[material]`` then) or as ``profile`` + ``y_mm`` + ``a_mm`` + ``b_mm``.

Bad values are InputError naming ``<file>: <table>.<key>`` (:mod:`wrlayer.validate`).
"""

from __future__ import annotations

import tomllib
from dataclasses import asdict, dataclass, fields
from pathlib import Path

from calibration.fem.material import J2Material
from calibration.rolling.section_position import table_position
from calibration.settings import MaterialSettings
from meshes.profiles import Profile, named_profile
from wrlayer.errors import InputError
from wrlayer.validate import Keys

#: The models of ContactSettings.model.
MODELS = ("2d", "3d")
#: The units of ContactSettings.levels: multiples of the FEM first-yield pressure p_y, of k = Y / sqrt(3), or MPa.
LEVEL_UNITS = ("p_y", "k", "MPa")
#: The bodies of ContactSettings.body: the half-space block or the profile section at a position.
BODIES = ("block", "section")
#: Hard bounds (the cost guard refuses long runs below them unless forced).
MAX_PASSES = 50
MAX_LEVELS = 10
MAX_TRACK_FACTOR = 20.0


@dataclass(frozen=True)
class RollingMaterial(MaterialSettings):
    """J2 material of the block (TOML table ``[material]``): the calibration's material keys
    (:class:`calibration.settings.MaterialSettings`), elastic-perfectly plastic by default (the rolling reference's
    material).

    Attributes
    ----------
    E_MPa : float
        Young's modulus (MPa, > 0).
    poisson : float
        Poisson's ratio (-, in (-1, 0.4999]).
    yield_MPa : float
        Initial uniaxial yield stress Y (MPa, > 0).
    H_iso_MPa : float
        Linear isotropic hardening modulus (MPa, >= 0; 0 with H_kin_MPa = 0: elastic-perfectly plastic).
    H_kin_MPa : float
        Linear kinematic (Prager) hardening modulus (MPa, >= 0).
    """

    H_iso_MPa: float = 0.0
    H_kin_MPa: float = 0.0

    def j2(self) -> J2Material:
        """The engine's material."""
        return J2Material(self.E_MPa, self.poisson, self.yield_MPa, self.H_iso_MPa, self.H_kin_MPa)


@dataclass(frozen=True)
class ContactSettings:
    """The moving Hertz load (TOML table ``[contact]``). 3D: p = p0 sqrt(1 - (s/a)^2 - (y/b)^2), s = x - x_c;
    2D plane strain (line contact): p = p0 sqrt(1 - (s/a)^2) per unit length; traction q = c p along +x.

    Attributes
    ----------
    model : str
        "3d" (half model about the track centreline y = 0) or "2d" (plane-strain line contact).
    a_mm : float
        Contact semi-axis along the rolling direction x (mm, > 0; from the table with ``contact.table``).
    b_mm : float
        Lateral semi-axis (mm, > 0; 3D only; 0: circular, b = a; from the table with ``contact.table``).
    traction_coefficient : float
        c of the surface traction q = c p in the rolling direction (-, in [-1, 1]; 0: frictionless).
    levels : tuple of float
        Peak pressures p0 of the runs, in ``level_unit`` (each > 0; one run per level).
    level_unit : str
        "p_y" (multiples of the FEM first-yield pressure of the static load, frictionless), "k" (multiples of the
        shear yield stress k = Y / sqrt(3)) or "MPa".
    body : str
        "block" (the half-space block) or "section" (the profile section at y_mm extruded along x; 3D only).
    table : str
        Section: a layer table giving the profile, a_mm, b_mm and the material at y_mm: a path, or a shipped
        table as "scenes/tables/NAME.json" ("": give profile, a_mm and b_mm).
    profile : str
        Section without a table: the profile's name (e.g. "60E1", "S1002") or file.
    y_mm : float
        Section: the profile coordinate y0 of the track centreline (mm).
    accept_unusual_profile : bool
        Section: read the profile file without the plausibility checks of :mod:`meshes.profiles.plausibility`
        (units, orientation, steps; a profile unusual on purpose; command line ``--accept-unusual-profile``).
    """

    a_mm: float
    levels: tuple[float, ...]
    model: str = "3d"
    b_mm: float = 0.0
    traction_coefficient: float = 0.0
    level_unit: str = "p_y"
    body: str = "block"
    table: str = ""
    profile: str = ""
    y_mm: float = 0.0
    accept_unusual_profile: bool = False

    def section_profile(self) -> Profile:
        """The section's profile (``profile``, a name or a file; see ``accept_unusual_profile``)."""
        return named_profile(self.profile, accept_unusual=self.accept_unusual_profile)

    @property
    def lateral_mm(self) -> float:
        """The lateral semi-axis b (mm): a when not given."""
        return self.b_mm if self.b_mm > 0 else self.a_mm


@dataclass(frozen=True)
class TrackSettings:
    """The passes (TOML table ``[track]``). The load centre moves from x_start = -L/2 to x_end = +L/2 in steps
    of ds, then is removed; each pass starts again at x_start.

    Attributes
    ----------
    length_factor : float
        Track length L in contact lengths 2a (-, in [1, 20]).
    step_factor : float
        Step length ds as a multiple of a (-, in [0.02, 1]).
    n_passes : int
        Passes per level (1..50).
    ramp_steps : int
        Load steps in which p0 is applied at x_start (1..50; removal at x_end: one step, cut on failure).
    substeps : int
        Material sub-steps per step along the load's path (-, 1..16; 1: plain backward-Euler steps;
        :mod:`calibration.rolling.substeps`, docs/rolling-verification.md).
    """

    length_factor: float = 3.0
    step_factor: float = 0.25
    n_passes: int = 3
    ramp_steps: int = 4
    substeps: int = 1

    def positions_over_a(self) -> list[float]:
        """Load-centre positions x_c / a of one pass (from -L/2 to +L/2; the last step lands on +L/2)."""
        half = self.length_factor  # L / 2 = length_factor * 2a / 2, in units of a
        n = max(1, int(round(2.0 * half / self.step_factor)))
        return [-half + 2.0 * half * i / n for i in range(n + 1)]


@dataclass(frozen=True)
class TrackMeshSettings:
    """The block refined along the loaded strip (TOML table ``[mesh]``). Lengths in units of a.

    Attributes
    ----------
    elements_per_semi_axis : float
        Element size h = a / this in the refined strip (-, in [1, 40]).
    order : int
        Element order, 1 (linear) or 2 (quadratic).
    fine_width_factor : float
        Refined half-width of the strip across the track, in b (-, in [0.5, 5]; 3D only).
    fine_depth_factor : float
        Refined depth below the surface, in a (-, in [0.5, 5]).
    size_factor : float
        Block depth, lateral half-width and run-out beyond the track ends, in a (-, in [3, 50]).
    growth : float
        Growth ratio of the element size outside the refined strip (-, in (1, 3]).
    """

    elements_per_semi_axis: float = 4.0
    order: int = 2
    fine_width_factor: float = 1.5
    fine_depth_factor: float = 1.5
    size_factor: float = 8.0
    growth: float = 1.5


@dataclass(frozen=True)
class RollingRunSettings:
    """How the run is done (TOML table ``[run]``).

    Attributes
    ----------
    linear_solver : str
        "auto" (PARDISO when installed, else SuperLU), "pardiso" or "scipy".
    plots : bool
        Write the ParaView series (plastic strain and residual stress after each pass, .pvd).
    layer_segments : int
        Most segments N of the layer characteristic fitted to the static indentation as the calibration fits
        (2..8).
    """

    linear_solver: str = "auto"
    plots: bool = True
    layer_segments: int = 8


@dataclass(frozen=True)
class RollingConfig:
    """A rolling configuration: its tables and the file it came from (``source``, for messages)."""

    contact: ContactSettings
    material: RollingMaterial = RollingMaterial()
    track: TrackSettings = TrackSettings()
    mesh: TrackMeshSettings = TrackMeshSettings()
    run: RollingRunSettings = RollingRunSettings()
    source: str = "rolling"

    def to_dict(self) -> dict:
        """The configuration as TOML-like tables (JSON-serialisable)."""
        out = {}
        for name in ("material", "contact", "track", "mesh", "run"):
            obj = getattr(self, name)
            out[name] = {f.name: (list(v) if isinstance(v := getattr(obj, f.name), tuple) else v)
                         for f in fields(obj)}
        return out


def _names(cls) -> tuple[str, ...]:
    return tuple(f.name for f in fields(cls))


def _numbers(k: Keys, cls, bounds: dict[str, dict]) -> dict:
    k.check_known(_names(cls))
    return {name: k.number(name, **b) for name, b in bounds.items() if name in k.table}


def _material(k: Keys) -> RollingMaterial:
    return RollingMaterial(**_numbers(k, RollingMaterial, {
        "E_MPa": dict(gt=0.0), "poisson": dict(gt=-1.0, le=0.4999), "yield_MPa": dict(gt=0.0),
        "H_iso_MPa": dict(ge=0.0), "H_kin_MPa": dict(ge=0.0)}))


def _contact(k: Keys) -> tuple[ContactSettings, RollingMaterial | None]:
    """The contact table and, for a section given by a table, the table's material."""
    kw = _numbers(k, ContactSettings, {"a_mm": dict(gt=0.0, le=1000.0), "b_mm": dict(ge=0.0, le=1000.0),
                                       "traction_coefficient": dict(ge=-1.0, le=1.0), "y_mm": dict()})
    for name, choices in (("model", MODELS), ("level_unit", LEVEL_UNITS), ("body", BODIES), ("table", None),
                          ("profile", None)):
        if name in k.table:
            kw[name] = k.text(name, choices=choices)
    if "accept_unusual_profile" in k.table:
        kw["accept_unusual_profile"] = k.boolean("accept_unusual_profile", False)
    material = None
    if kw.get("body", "block") == "section":
        kw, material = _section(k, kw)
    else:
        for name in ("table", "profile", "y_mm"):
            if name in k.table:
                raise k.error(name, 'only with body = "section"')
    if "a_mm" not in kw:
        raise k.error("a_mm", "missing (required)")
    kw["levels"] = tuple(float(x) for x in k.array("levels", min_len=1, max_len=MAX_LEVELS, gt=0.0))
    return ContactSettings(**kw), material


def _section(k: Keys, kw: dict) -> tuple[dict, RollingMaterial | None]:
    """The section's position: from ``table`` + ``y_mm`` or ``profile`` + ``y_mm`` + ``a_mm`` + ``b_mm``."""
    if kw.get("model", "3d") != "3d":
        raise k.error("model", 'must be "3d" with body = "section"')
    if "y_mm" not in kw:
        raise k.error("y_mm", 'missing (required with body = "section")')
    material = None
    if kw.get("table"):
        for name in ("a_mm", "b_mm", "profile"):
            if name in kw:
                raise k.error(name, "given by the table (remove it)")
        try:
            pos = table_position(kw["table"], kw["y_mm"])
        except InputError as err:
            raise k.error(err.what, err.problem) from None
        kw.update(a_mm=pos.a_mm, b_mm=pos.b_mm, profile=pos.profile)
        material = RollingMaterial(**asdict(pos.material))
    else:
        for name in ("profile", "a_mm", "b_mm"):
            if not kw.get(name):
                raise k.error(name, 'missing (required with body = "section" and no table)')
    try:
        profile = named_profile(kw["profile"], accept_unusual=kw.get("accept_unusual_profile", False))
        profile.check_y(kw["y_mm"], "y_mm")
    except InputError as err:
        raise k.error("profile" if err.what != "y_mm" else "y_mm", err.problem) from None
    return kw, material


def _track(k: Keys) -> TrackSettings:
    kw = _numbers(k, TrackSettings, {"length_factor": dict(ge=1.0, le=MAX_TRACK_FACTOR),
                                     "step_factor": dict(ge=0.02, le=1.0)})
    for name, hi in (("n_passes", MAX_PASSES), ("ramp_steps", 50), ("substeps", 16)):
        if name in k.table:
            kw[name] = k.integer(name, None, ge=1, le=hi)
    return TrackSettings(**kw)


def _mesh(k: Keys) -> TrackMeshSettings:
    kw = _numbers(k, TrackMeshSettings, {
        "elements_per_semi_axis": dict(ge=1.0, le=40.0), "fine_width_factor": dict(ge=0.5, le=5.0),
        "fine_depth_factor": dict(ge=0.5, le=5.0), "size_factor": dict(ge=3.0, le=50.0),
        "growth": dict(gt=1.0, le=3.0)})
    if "order" in k.table:
        kw["order"] = k.integer("order", None, ge=1, le=2)
    return TrackMeshSettings(**kw)


def _run(k: Keys) -> RollingRunSettings:
    k.check_known(_names(RollingRunSettings))
    kw: dict = {}
    if "linear_solver" in k.table:
        kw["linear_solver"] = k.text("linear_solver", choices=("auto", "pardiso", "scipy"))
    if "plots" in k.table:
        kw["plots"] = k.boolean("plots", True)
    if "layer_segments" in k.table:
        kw["layer_segments"] = k.integer("layer_segments", None, ge=2, le=8)
    return RollingRunSettings(**kw)


def parse_rolling_config(data: dict, source: str = "rolling", accept_unusual_profile: bool = False
                         ) -> RollingConfig:
    """Validate a TOML-like mapping into a :class:`RollingConfig` (InputError naming ``source`` and the key);
    ``accept_unusual_profile``: as ``contact.accept_unusual_profile = true`` (the command line's
    ``--accept-unusual-profile``)."""
    if accept_unusual_profile and isinstance(data.get("contact"), dict):
        data = {**data, "contact": {**data["contact"], "accept_unusual_profile": True}}
    top = Keys(source, "", data)
    top.check_known(("material", "contact", "track", "mesh", "run"))
    contact = top.sub("contact")
    if contact is None:
        raise top.error("contact", "missing (required table)")
    kw: dict = {}
    kw["contact"], table_material = _contact(contact)
    for name, reader in (("material", _material), ("track", _track), ("mesh", _mesh), ("run", _run)):
        sub = top.sub(name)
        if sub is not None:
            kw[name] = reader(sub)
    if table_material is not None:
        if "material" in kw:
            raise top.error("material", "given by contact.table (remove the table [material])")
        kw["material"] = table_material
    return RollingConfig(source=source, **kw)


def load_rolling_config(path: str | Path, accept_unusual_profile: bool = False) -> RollingConfig:
    """Read and validate a rolling TOML file (``accept_unusual_profile``: as :func:`parse_rolling_config`);
    InputError when missing, unreadable or invalid."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as err:
        raise InputError(str(path), f"cannot read: {err.strerror or err}") from err
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise InputError(str(path), f"not valid TOML: {err}") from err
    return parse_rolling_config(data, str(path), accept_unusual_profile)


__all__ = ["BODIES", "ContactSettings", "LEVEL_UNITS", "MAX_LEVELS", "MAX_PASSES", "MAX_TRACK_FACTOR", "MODELS",
           "RollingConfig", "RollingMaterial", "RollingRunSettings", "TrackMeshSettings", "TrackSettings",
           "load_rolling_config", "parse_rolling_config"]
