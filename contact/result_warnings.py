"""Warnings of a result: a p_max that is approximate by method (``method.normal = "kik_piotrowski"``,
:data:`contact.normal.method.P_MAX_APPROXIMATE`), and results outside the plausible ranges of steel wheel/rail
contact (peak pressure, approach, patch size; :data:`wrlayer.plausibility.RESULT_RANGES`): the inputs passed their
checks, yet a p_max of 5 MPa or an approach of 2 mm says a unit is wrong somewhere. Units: mm, MPa.

A result record carries the lines in ``warnings`` (result.json; left out when there are none) and the command
line prints them on stderr; the numbers are written as solved.
"""

from __future__ import annotations

from contact.normal.method import P_MAX_APPROXIMATE
from contact.scenes.run_result import SceneResult
from contact.wheel_rail.results import SweepResult
from wrlayer.plausibility import result_warnings


def _values(p_max_MPa, delta_mm, length_mm, width_mm) -> dict[str, float]:
    values = {"p_max_MPa": p_max_MPa, "approach_mm": delta_mm}
    semi = [0.5 * v for v in (length_mm, width_mm) if v is not None]
    if semi:
        values["semi_axis_mm"] = min(semi) if min(semi) < 0.05 else max(semi)
    return {k: float(v) for k, v in values.items() if v is not None}


def method_warnings(name: str, normal: str) -> list[str]:
    """The line saying that p_max is approximate when the normal method ``normal`` (``method.normal``, resolved)
    gives an approximate one (``name``: the scene); none for the half-space solvers."""
    if normal not in P_MAX_APPROXIMATE:
        return []
    return [f"warning: {name}: method.normal = \"{normal}\": p_max approximate (up to 27 % below the exact "
            "half-space on wheel-rail patches, 50 % on flat-topped ones; the default \"auto\", the exact half-space "
            "solver, is within 0.7 % of CONTACT: docs/validation/fast-normal.md)"]


def scene_warnings(name: str, result: SceneResult | SweepResult) -> tuple[str, ...]:
    """The method's line (:func:`method_warnings`), then one line per implausible value of the result's passes
    (contact scene) or loaded patches (wheel–rail sweep), the first pass or case only when the same quantity repeats
    (``name``: the scene)."""
    method = result.inputs.get("method") if isinstance(result.inputs, dict) else None   # the inputs echo
    lines = method_warnings(name, method.get("normal", "") if isinstance(method, dict) else "")
    seen: set[str] = set()
    if isinstance(result, SweepResult):
        places = [(f"{name}, case {c.case}, {side} wheel, patch {i}", p)
                  for c in result.cases for side, w in (c.wheels or {}).items() for i, p in enumerate(w.patches)]
    else:
        places = [(f"{name}, pass {k + 1}", p) for k, p in enumerate(result.passes)]
    for where, rec in places:
        values = _values(rec.p_max_MPa, rec.delta_mm, rec.length_mm, rec.width_mm)
        for quantity, value in values.items():
            if quantity not in seen and (found := result_warnings(where, {quantity: value})):
                seen.add(quantity)
                lines += found
    return tuple(lines)


__all__ = ["method_warnings", "scene_warnings"]
