"""The TOML "wear" scene (units mm, N, MPa, s, rad; distance in km). Run by ``python -m contact wear SCENE --out DIR``.

Everything of a wheel_rail scene (:mod:`contact.wheel_rail.parse`: [profiles], [track], [wheel], [wheelset], [load],
[material], [tangential], [layers], [passes], [method]) except [sweep] and [output], plus::

    type = "wear"                                          (required)
    [method]    normal = "auto" | "kik_piotrowski" |       the method.normal choice of every scene (default
                "exact" | "coarse_exact",                  "auto" = "exact", contact.normal.method); exact_cells,
                layer_mode                                 the exact solver's options (contact.normal.method)
    [wear]      law = "archard" | "usfd"                  the abrasive wear law (contact.wear.laws)
                distance_km (required, > 0)                total running distance of the wheel
                steps (required, 1..1000)                  nominal number of profile-update steps
                max_depth_per_step_mm = 0.1                step control: a step is shortened so that the largest
                                                           depth change (wear + inelastic) stays below this
                smoothing_mm = 1.0                         standard deviation (mm of arc length) of the Gaussian
                                                           filter applied to each step's depth distributions
                                                           (<= 1000 x grid_mm)
                grid_mm = 0.2                              arc-length spacing of the profile update grid
                density_kg_m3 = 7850                       steel density (mass loss, USFD law)
                rail_passes_per_wheel_pass = 1.0           passes a rail section sees per wheel revolution
                inelastic = true                           add the layer's residual displacement (needs [layers])
                layer_state = "hardening" | "virgin"       keep each profile position's largest load between steps
                                                           (contact.wear.layer_state) or start virgin every step
                workers = 1, scheduler = ""                local processes per step / a Dask scheduler address
                conicity_amplitude_mm = 3.0                lateral amplitude of the rolling-radius difference
    [wear.archard.wheel], [wear.archard.rail]              ArchardMap keys (hardness_MPa, k_seizure, k_low_speed,
                                                           k_mid_speed, k_high_speed, v_low_m_s, v_high_m_s)
    [wear.recalibrate] config = "template.toml", every_steps = 1   recalibrate the layer tables on the worn profiles
                                                           (contact.wear.recalibrate; placeholders @wheel_profile@,
                                                           @rail_profile@ as [[bodies]] profile or mate);
                                  reanchor = false         by similarity: a position whose patch left its anchor's
                                                           by the master alone (true: by the direct FEM)
    [wear.usfd]  wheel = "R8T", rail = "R8T"              a published material, or a table {t1, t2, mild_slope,
                                                           severe_rate, cat_slope, cat_offset}
    [collective] [[collective.condition]] tables (straight track or a steady curve), a sweep (lateral_mm, yaw_rad,
                 weights) or a multibody export (csv, weight_by, max_conditions): contact.wear.collective_scene.
                 At most 10 000 conditions.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from calibration.similarity.anchor import table_references
from contact.normal.method import NormalMethod
from contact.scenes.scene import SceneKeys
from contact.wear.collective import LoadCollective
from contact.wear.collective_scene import parse_collective
from contact.wear.laws import USFD_MATERIALS, ArchardMap, UsfdTable, WearLaw
from contact.wear.recalibrate import Recalibration, read_template
from contact.wheel_rail.parse import parse_wheel_rail_scene
from contact.wheel_rail.scene import WheelRailScene
from wrlayer.hashing import file_sha256
from meshes.profiles import Profile
from wrlayer.errors import InputError
from wrlayer.runner import check_scheduler_address
from wrlayer.section_keys import key, read_section
from wrlayer.validate import top_keys

WHEEL_RAIL_SECTIONS = ("title", "description", "accept_implausible", "profiles", "track", "wheel", "wheelset", "load", "material",
                       "tangential", "layers", "passes", "method")
WEAR_KEYS = ("law", "distance_km", "steps", "max_depth_per_step_mm", "smoothing_mm", "grid_mm", "density_kg_m3",
             "rail_passes_per_wheel_pass", "inelastic", "layer_state", "workers", "scheduler", "conicity_amplitude_mm",
             "archard", "recalibrate",
             "usfd")
ARCHARD_KEYS = ("hardness_MPa", "k_seizure", "k_low_speed", "k_mid_speed", "k_high_speed", "v_low_m_s",
                "v_high_m_s", "seizure_pressure_ratio")
#: Largest ``wear.steps`` (each step writes its profiles; the step control may add steps up to the same bound).
MAX_STEPS = 1000
#: Largest ``smoothing_mm`` in update-grid cells (``grid_mm``): a wider Gaussian smooths more than the profile.
MAX_SMOOTHING_CELLS = 1000
#: Values of ``wear.layer_state``.
LAYER_STATES = ("hardening", "virgin")
USFD_KEYS = ("t1", "t2", "mild_slope", "severe_rate", "cat_slope", "cat_offset")


@dataclass(frozen=True)
class WearSettings:
    """The ``[wear]`` numbers of the step loop (mm, km).

    Attributes
    ----------
    max_depth_per_step_mm : float
        Step control: a step is shortened so that its largest smoothed wear depth stays below this (mm).
    smoothing_mm : float
        Standard deviation of the Gaussian filter applied to each step's depth distributions (mm of arc length;
        0 = none).
    grid_mm : float
        Arc-length spacing of the profile update grid (mm).
    rail_passes_per_wheel_pass : float
        Passes a rail section sees per wheel revolution (-).
    inelastic : bool
        Add the layer's residual displacement to the profile change (needs ``[layers]``).
    layer_state : str
        ``"hardening"``: each profile position keeps its largest peak pressure between steps; ``"virgin"``: the
        layer starts virgin every step.
    workers : int
        Local processes solving a step's conditions (1 = in-process).
    scheduler : str
        Address of a Dask scheduler solving the conditions (and recalibrations); empty = local.
    conicity_amplitude_mm : float
        Lateral wheelset displacement at which the rolling-radius difference is evaluated (mm).
    recalibrate : Recalibration or None
        ``[wear.recalibrate]``: the calibration template run on the worn profiles (None = the scene's tables
        throughout).
    """

    max_depth_per_step_mm: float = key(0.1, "mm", gt=0.0)
    smoothing_mm: float = key(1.0, "mm", ge=0.0)
    grid_mm: float = key(0.2, "mm", gt=0.0, le=2.0)
    rail_passes_per_wheel_pass: float = key(1.0, "-", ge=0.0)
    inelastic: bool = key(True)
    layer_state: str = key("hardening", choices=LAYER_STATES)
    workers: int = key(1, ge=1)
    scheduler: str = key("")
    conicity_amplitude_mm: float = key(3.0, "mm", gt=0.0)
    recalibrate: Recalibration | None = None

    def to_dict(self) -> dict[str, Any]:
        """The settings as result.json records them (the recalibration as its file, text and interval)."""
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "recalibrate"}
        recal = self.recalibrate
        out.update(recalibrate_config=recal.config if recal else "", recalibrate_template=recal.template if recal
                   else "", recalibrate_every=recal.every_steps if recal else 0)
        return out


@dataclass(frozen=True)
class WearScene:
    """A parsed wear scene (units mm, N, MPa, s, rad; distance in km).

    Attributes
    ----------
    path : Path
        The scene file.
    data : dict
        The scene's TOML tables as read (recorded in result.json).
    wheel_rail : WheelRailScene
        The wheel–rail part (profiles, track, wheel, wheelset, load, material, tangential, layers, passes, method;
        :mod:`contact.wheel_rail.parse`), including ``[method] normal``, ``exact_cells``, ``layer_mode``: the
        normal contact method of every condition.
    law : WearLaw
        ``[wear] law`` with its coefficients (``[wear.archard]``, ``[wear.usfd]``, ``density_kg_m3``).
    collective : LoadCollective
        ``[collective]`` with ``[wear] distance_km`` and ``steps``.
    settings : WearSettings
        The other ``[wear]`` keys.
    """

    path: Path
    data: dict
    wheel_rail: WheelRailScene
    law: WearLaw
    collective: LoadCollective
    settings: WearSettings

    @property
    def normal(self) -> NormalMethod:
        """The normal contact method of every condition (``[method] normal``)."""
        return self.wheel_rail.method.normal_method()

    def to_dict(self) -> dict[str, Any]:
        """The resolved inputs as plain data (result.json "inputs"): the file and its sha256, profiles, sides, the
        normal method, the wear law, the collective, the step settings, the layers' tables and the TOML content."""
        wr, col, law = self.wheel_rail, self.collective, self.law
        path = Path(self.path)
        return {
            "scene_file": str(path.resolve()),
            "content_sha256": file_sha256(path) if path.is_file() else None,
            "rail_profile": wr.rail_profile.name, "wheel_profile": wr.wheel_profile.name,
            "sides": wr.sides, "normal_method": self.normal.name, "law": law.name,
            "archard": {b: vars(m) for b, m in law.archard.items()},
            "usfd": {b: vars(t) for b, t in law.usfd.items()}, "density_kg_m3": law.density_kg_m3,
            "distance_km": col.distance_km, "nominal_steps": col.steps, "settings": self.settings.to_dict(),
            "conditions": [c.to_dict() for c in col.conditions],
            "collective_source": {"file": col.source_file, "sha256": col.source_sha256,
                                  **({"creepages": "export"} if col.creepages_given else {})}
            if col.source_file else None,
            "passes_cap": wr.passes.max,
            "layers": None if wr.solver_layers is None else dict(wr.solver_layers.names),
            "scene_toml": self.data}

    @property
    def initial_profiles(self) -> dict[str, dict[str, Profile]]:
        """``profiles[side][body]``: the scene's profiles on every simulated side."""
        wr = self.wheel_rail
        return {side: {"rail": wr.rail_profile, "wheel": wr.wheel_profile} for side in wr.sides}


def parse_wear_scene(data: dict[str, Any], scene_path: Path, accept_unusual_profile: bool = False) -> WearScene:
    """Validate a wear scene (InputError naming ``<file>: <section>.<key>``); ``accept_unusual_profile``: as
    :func:`contact.wheel_rail.parse.parse_wheel_rail_scene`."""
    scene_path = Path(scene_path)
    file = scene_path.name
    top = top_keys(file, data, SceneKeys)
    top.check_known(("type",) + WHEEL_RAIL_SECTIONS + ("wear", "collective"))
    if data.get("type") != "wear":
        raise top.error("type", f"must be \"wear\" for python -m contact wear, got {data.get('type')!r}")
    wheel_rail = parse_wheel_rail_scene({"type": "wheel_rail", **{k: v for k, v in data.items()
                                                                   if k in WHEEL_RAIL_SECTIONS}}, scene_path,
                                       accept_unusual_profile)
    wear = top.sub("wear")
    if wear is None:
        raise top.error("wear", "a wear scene needs a [wear] table (law, distance_km, steps)")
    wear.check_known(WEAR_KEYS)
    law = _law(wear)
    settings = _settings(wear, scene_path.parent, wheel_rail)
    distance = wear.number("distance_km")
    if not distance > 0:
        raise wear.error("distance_km", f"must be a positive distance, got {distance:g}")
    steps = wear.integer("steps", 1, ge=1, le=MAX_STEPS) if "steps" in wear.table else None
    if steps is None:
        raise wear.error("steps", "required (number of profile-update steps)")
    col = top.sub("collective")
    if col is None:
        raise top.error("collective", "a wear scene needs a [collective] (running conditions with weights)")
    conds, export = parse_collective(col, wheel_rail, scene_path.parent)
    try:
        collective = LoadCollective(tuple(conds), distance, steps, where=f"{file}: collective",
                                    source_file=export.file if export else "",
                                    source_sha256=export.sha256 if export else "")
    except InputError as err:
        raise InputError(err.what if err.what.startswith(file) else f"{file}: {err.what}", err.problem) from None
    return WearScene(scene_path, data, wheel_rail, law, collective, settings)


def _settings(wear: SceneKeys, base: Path, wheel_rail: WheelRailScene) -> WearSettings:
    scheduler = check_scheduler_address(wear.table.get("scheduler", ""), wear.what("scheduler"))
    settings = read_section(WearSettings, wear, also_known=WEAR_KEYS,
                            given={"scheduler": scheduler, "recalibrate": _recalibration(wear, base, wheel_rail)})
    if settings.smoothing_mm > MAX_SMOOTHING_CELLS * settings.grid_mm:
        raise wear.error("smoothing_mm", f"must be <= {MAX_SMOOTHING_CELLS} x grid_mm = "
                         f"{MAX_SMOOTHING_CELLS * settings.grid_mm:g} mm (a Gaussian wider than the profile), got "
                         f"{settings.smoothing_mm:g}")
    if settings.inelastic and wheel_rail.layers is None:
        raise wear.error("inelastic", "true needs [layers] (the Prandtl layer gives the inelastic displacement); "
                         "set inelastic = false for abrasive wear alone")
    return settings


def _recalibration(wear: SceneKeys, base: Path, wheel_rail: WheelRailScene) -> Recalibration | None:
    """[wear.recalibrate]: the calibration template (read and validated here) and the interval in steps."""
    sub = wear.sub("recalibrate") if "recalibrate" in wear.table else None
    if sub is None:
        return None
    sub.check_known(("config", "every_steps", "reanchor"))
    rel = sub.text("config")
    try:
        path = (base / rel).resolve()
    except (RuntimeError, OSError):  # a symbolic-link loop (RuntimeError before Python 3.13)
        raise sub.error("config", f"{rel!r}: a symbolic-link loop") from None
    if not path.exists() and not path.is_symlink():
        raise sub.error("config", f"no such calibration template {rel!r} (looked at {path})")
    every = sub.integer("every_steps", 1, ge=1)
    reanchor = sub.boolean("reanchor", False)
    layers = wheel_rail.solver_layers
    text, cfg = read_template(path, sub.what("config"), {"wheel": wheel_rail.wheel_profile,
                                                         "rail": wheel_rail.rail_profile},
                              wheel_rail.layout.inclination_rad)
    if layers is None or layers.combined is not None:
        raise sub.error("config", "recalibration needs per-body [layers] tables (rail and/or wheel)")
    kept = {b: getattr(layers, b) for b in ("rail", "wheel") if getattr(layers, b) is not None}
    initial = {"wheel": wheel_rail.wheel_profile, "rail": wheel_rail.rail_profile}
    anchors = {key: ref for b, table in kept.items() if table.profile_name == initial[b].name
               for key, ref in table_references(table, initial[b]).items()}
    return Recalibration(str(path), text, cfg, every, kept, anchors, reanchor)


def _law(wear: SceneKeys) -> WearLaw:
    name = wear.text("law", "archard")
    if name not in ("archard", "usfd"):
        raise wear.error("law", f"must be 'archard' or 'usfd', got {name!r}")
    archard = {}
    sub = wear.sub("archard") if "archard" in wear.table else None
    for body in ("wheel", "rail"):
        keys = sub.sub(body) if sub is not None and body in sub.table else None
        if sub is not None:
            sub.check_known(("wheel", "rail"))
        vals = {}
        if keys is not None:
            keys.check_known(ARCHARD_KEYS)
            vals = {k: keys.number(k, ge=0.0) for k in ARCHARD_KEYS if k in keys.table}
        try:
            archard[body] = ArchardMap(**vals)
        except InputError as err:
            raise InputError(f"{wear.what('archard')}.{body}.{err.what}", err.problem) from None
    usfd = {}
    sub = wear.sub("usfd") if "usfd" in wear.table else None
    if sub is not None:
        sub.check_known(("wheel", "rail"))
    for body in ("wheel", "rail"):
        value = sub.table.get(body, "R8T") if sub is not None else "R8T"
        if isinstance(value, str):
            if value not in USFD_MATERIALS:
                raise sub.error(body, f"unknown material {value!r}; published: {', '.join(USFD_MATERIALS)}, or give "
                                f"a table {{{', '.join(USFD_KEYS)}}}")
            usfd[body] = USFD_MATERIALS[value]
        else:
            keys = sub.sub(body)
            keys.check_known(USFD_KEYS)
            vals = {k: keys.number(k) for k in USFD_KEYS}
            try:
                usfd[body] = UsfdTable(name=f"custom {body}", **vals)
            except InputError as err:
                raise InputError(sub.what(body), err.problem) from None
    return WearLaw(name, archard, usfd, wear.number("density_kg_m3", 7850.0, gt=0.0))


__all__ = ["WearScene", "WearSettings", "parse_wear_scene"]
