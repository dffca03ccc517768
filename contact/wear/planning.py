"""Step planning of the wear loop: how long a step is and which (condition, side) tasks it solves (units mm, N,
MPa, s, rad; distances in km).

Passes: abrasive wear is linear in distance for a fixed profile; a wheel point passes the contact once per
revolution, n_w = 1e6 / (2 pi r0) passes per km (r0: the nominal rolling radius), and a rail section sees
``rail_passes_per_wheel_pass`` times as many (:func:`passes_per_km`). A condition of weight w runs
min(passes cap, ceil(w x step length x n_w)) passes of the layer machinery in a step.

Position: a condition whose wheelset position comes from the quasi-static curving balance
(``wheelset_position = "balance"``) is balanced on the current profiles before the step's tasks are built
(:func:`balanced_positions`, in the loop's process: both wheels at once); its tasks run at the found lateral
position, yaw and pitch rate.

Length: the nominal step is (remaining distance) / (remaining nominal steps) (:func:`nominal_length_km`). If the
largest smoothed wear depth of that step exceeds ``max_depth_per_step_mm`` the step is shortened in proportion
(wear is linear in distance on a fixed profile); the inelastic increment does not scale with the step (it
saturates within a few passes) and is only reported (:func:`controlled_length`). At most
:data:`MAX_STEP_FACTOR` times the nominal number of steps are run.
"""

from __future__ import annotations

import dataclasses
import math

from contact.wear.collective import LoadCollective
from contact.wear.condition import ConditionTask
from contact.wear.layer_state import History, side_layers
from contact.wear.quasi_static import QuasiStaticCurving, Wheelset, WheelsetBalance
from contact.wear.scene import WearScene
from contact.wheel_rail.deformed import rigid_roll
from contact.wheel_rail.sections import WheelLoadSpec
from contact.wheel_rail.track_geometry import SIDES, WheelsetPose, place_rail
from meshes.profiles import Profile
from wrlayer.errors import ConvergenceError, InputError

#: At most this many times the nominal number of steps (guard of the step control).
MAX_STEP_FACTOR = 50
#: Relative tolerance below which the remaining distance counts as run.
DISTANCE_RTOL = 1e-12


def passes_per_km(scene: WearScene) -> dict[str, float]:
    """Passes per km of wheel running distance: {"wheel": 1e6/(2 pi r0), "rail": that * rail_passes_per_wheel_pass}."""
    r0 = scene.wheel_rail.wheel.nominal_radius_mm
    n = 1e6 / (2.0 * math.pi * r0)
    return {"wheel": n, "rail": n * scene.settings.rail_passes_per_wheel_pass}


def distance_left(collective: LoadCollective, done_km: float) -> bool:
    """True while the running distance ``done_km`` (km) falls short of the collective's."""
    return done_km < collective.distance_km * (1.0 - DISTANCE_RTOL)


def nominal_length_km(collective: LoadCollective, done_km: float, steps_done: int) -> float:
    """The next step's nominal length (km): the remaining distance over the remaining nominal steps (at least
    one); InputError when the step control has already asked for more than MAX_STEP_FACTOR x steps."""
    step = steps_done + 1
    if step > MAX_STEP_FACTOR * collective.steps:
        raise InputError(f"step {step}", f"the step control needs more than {MAX_STEP_FACTOR} x steps; "
                         "raise max_depth_per_step_mm or steps")
    return (collective.distance_km - done_km) / max(1, collective.steps - steps_done)


def controlled_length(nominal_km: float, max_wear_rate_mm_km: float, max_inelastic_mm: float,
                      max_depth_mm: float) -> tuple[float, tuple[str, ...]]:
    """(step length in km, notes): the nominal length, shortened so that the largest wear depth stays at
    ``max_depth_mm``; a note also when the inelastic increment alone exceeds it."""
    length, notes = nominal_km, []
    if max_wear_rate_mm_km * length > max_depth_mm:
        length = max_depth_mm / max_wear_rate_mm_km
        notes.append(f"step shortened from {nominal_km:.6g} km to {length:.6g} km (max wear depth "
                     f"{max_wear_rate_mm_km * nominal_km:.4g} mm > {max_depth_mm:g} mm)")
    if max_inelastic_mm > max_depth_mm:
        notes.append(f"inelastic increment {max_inelastic_mm:.4g} mm exceeds max_depth_per_step_mm (it saturates "
                     "within the step's passes and does not scale with the step length)")
    return length, tuple(notes)


def wheelset_roll(scene: WearScene, profiles: dict[str, dict[str, Profile]], pose: WheelsetPose) -> float:
    """Roll (rad) of the rigid wheelset at which both wheels touch their rails
    (:func:`contact.wheel_rail.deformed.rigid_roll`). One simulated side stands for both; with both sides
    simulated each side has its own worn profiles."""
    layout = scene.wheel_rail.layout
    right = profiles.get("right") or profiles["left"]
    left = profiles.get("left") or right
    placed_right = place_rail(right["rail"], layout)
    other = None if left is right else (place_rail(left["rail"], layout), left["wheel"])
    return rigid_roll(placed_right, right["wheel"], layout, pose, scene.wheel_rail.method.search, left=other)


def balanced_positions(scene: WearScene, profiles: dict[str, dict[str, Profile]], step: int
                       ) -> dict[int, WheelsetBalance]:
    """Condition index -> its wheelset balanced on ``profiles`` (:mod:`contact.wear.quasi_static`), for the
    conditions with ``wheelset_position = "balance"``. One simulated side stands for both (as
    :func:`wheelset_roll`); a free pitch rate (none given) is solved too."""
    wheel_rail = scene.wheel_rail
    layout = wheel_rail.layout
    right = profiles.get("right") or profiles["left"]
    sides = {"right": right, "left": profiles.get("left") or right}
    placed = {s: place_rail(sides[s]["rail"], layout) for s in SIDES}
    out = {}
    for k, c in enumerate(scene.collective.conditions):
        if c.balance is None:
            continue
        inputs = {s: dataclasses.replace(wheel_rail.inputs(s), load=WheelLoadSpec(c.load_on(s), c.speed_mm_s),
                                         yaw_rate_rad_s=c.yaw_rate_rad_s) for s in SIDES}
        roll_of = (lambda pose: wheelset_roll(scene, profiles, pose)) if wheel_rail.roll_auto else None
        wheelset = Wheelset({s: (sides[s]["rail"], sides[s]["wheel"]) for s in SIDES}, placed, inputs,
                            0.0 if wheel_rail.roll_auto else float(wheel_rail.wheelset.roll_rad), roll_of)
        pitch = wheel_rail.wheelset.pitch_rate_rad_s if c.pitch_rate_rad_s is None else c.pitch_rate_rad_s
        where = f"step {step}, condition {k} ({c.describe()})"
        out[k] = QuasiStaticCurving(wheelset, c.balance, c.curvature_1_per_m * 1e-3, layout.taping_line_mm, where,
                                    pitch).solve(k)
    return out


def build_tasks(scene: WearScene, profiles: dict[str, dict[str, Profile]], step: int, step_km: float,
                history: History | None = None, tables: dict | None = None,
                balances: dict[int, WheelsetBalance] | None = None) -> list[ConditionTask]:
    """The (condition, side) tasks of a step of nominal length ``step_km`` on the current profiles. ``history``:
    the layer state (used in the hardening mode); ``tables[(side, body)]``: tables recalibrated on the worn
    profiles; ``balances``: the balanced positions (:func:`balanced_positions`) of the conditions that have one
    (found here when not given)."""
    wheel_rail, settings = scene.wheel_rail, scene.settings
    opts = wheel_rail.passes
    n_km = passes_per_km(scene)["wheel"]
    layers = wheel_rail.solver_layers if settings.inelastic else None
    hardening = history if settings.layer_state == "hardening" else None
    tasks = []
    balances = balanced_positions(scene, profiles, step) if balances is None else balances
    for k, c in enumerate(scene.collective.conditions):
        found = balances.get(k)
        lateral, yaw = (found.lateral_mm, found.yaw_rad) if found else (c.lateral_mm, c.yaw_rad)
        pose = WheelsetPose(lateral, yaw, 0.0)
        if wheel_rail.roll_auto:
            try:
                pose = WheelsetPose(lateral, yaw, wheelset_roll(scene, profiles, pose))
            except (InputError, ConvergenceError) as err:
                raise InputError(f"step {step}, condition {k} ({c.describe()})", f"no rigid contact: {err}") from None
        n_pass = int(max(1, min(opts.max, math.ceil(c.weight * step_km * n_km))))
        pitch = wheel_rail.wheelset.pitch_rate_rad_s if c.pitch_rate_rad_s is None else c.pitch_rate_rad_s
        pitch = found.pitch_rate_rad_s if found else pitch
        for side in profiles:
            inputs = dataclasses.replace(wheel_rail.inputs(side, pose), pitch_rate_rad_s=pitch,
                                         load=WheelLoadSpec(c.vertical_load_N, c.speed_mm_s),
                                         passes=dataclasses.replace(opts, max=n_pass))
            tasks.append(ConditionTask(k, side, c, profiles[side]["rail"], profiles[side]["wheel"], inputs,
                                       side_layers(layers, hardening, side, tables), scene.law, step))
    return tasks


__all__ = ["DISTANCE_RTOL", "MAX_STEP_FACTOR", "balanced_positions", "build_tasks", "controlled_length",
           "distance_left", "nominal_length_km", "passes_per_km", "wheelset_roll"]
