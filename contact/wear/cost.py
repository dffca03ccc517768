"""Cost estimate and size bounds of a wear run, checked before its first step (:mod:`wrlayer.cost`). Units: s, mm.

Model: steps × (STEP_S + conditions × sides × one wheel–rail case-wheel), where one case-wheel is the wheel–rail
estimate of the scene's method (:func:`contact.scenes.cost.wheel_rail_cost`: contact search, layer lookup,
passes × strips × (strip + cells) per condition) and STEP_S the profile update, rolling-radius difference and
files of a step (measured: 0.05 s update + about 0.5 s conicity and files on the example; rounded up). The steps
are the nominal ``wear.steps`` (the step control may add some); a recalibration ([wear.recalibrate]) is not
included (its own cost is that of the calibration template). The example scene (3 steps × 5 conditions × 2
sides, 30 passes) is estimated at about 16 s and runs in about 12 s.
"""

from __future__ import annotations

from contact.scenes.cost import wheel_rail_cost
from contact.wear.scene import WearScene
from wrlayer.cost import CostEstimate

#: Profile update, rolling-radius difference and the files of one step (s).
STEP_S = 1.0


def wear_cost(scene: WearScene) -> CostEstimate:
    """Estimate of a parsed wear scene (the run is refused above :data:`wrlayer.cost.LIMIT_SECONDS` unless
    forced)."""
    wr = scene.wheel_rail
    one = wheel_rail_cost(wr)
    per_condition = one.seconds / max(1, len(wr.cases) * len(wr.sides))
    steps, conditions, sides = scene.collective.steps, len(scene.collective.conditions), len(wr.sides)
    factors: dict[str, float] = {"steps": steps, "conditions": conditions, "sides": sides}
    factors.update({k: v for k, v in one.factors.items() if k not in ("cases", "wheels")})
    seconds = steps * (STEP_S + conditions * sides * per_condition)
    return CostEstimate(scene.path.name, factors, seconds, "(in-process)")


__all__ = ["STEP_S", "wear_cost"]
