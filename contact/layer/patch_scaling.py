"""Table layers scaled to the solved contact patch: the fixed point over the patch sizes.

A table characteristic holds for the patch it was calibrated on; ``LayerTable.characteristic_at(y, patch_mm)``
scales it to another patch (a, b) (mm). The patch a solve finds depends on the layers, so scenes and wheel–rail
scenes with ``scale_to_patch`` iterate: solve, rebuild the layers at the solved semi-axes, solve again, until no
patch's a or b changes by more than PATCH_SCALING_TOLERANCE (relative).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable
from typing import TypeVar

from wrlayer.errors import ConvergenceError

#: Solves (at most) with scaled layers, and the relative change of the semi-axes that ends them.
PATCH_SCALING_ITERATIONS, PATCH_SCALING_TOLERANCE = 6, 1e-3

Result = TypeVar("Result")
PatchSizes = dict[Hashable, tuple[float, float]]


def settle_patch_sizes(solve_at: Callable[[PatchSizes], tuple[Result, PatchSizes]], sizes: PatchSizes,
                       what: str) -> tuple[Result, PatchSizes, int]:
    """Fixed point of the layer scaling. ``sizes``: semi-axes (a, b) in mm of every loaded patch (keyed by patch)
    from a first solve; ``solve_at(sizes)`` solves with the layers scaled to them and returns (its result, the
    semi-axes it found). Repeated until no a or b changes by more than PATCH_SCALING_TOLERANCE and the same patches
    are loaded. Returns (the result solved with the layers at the returned sizes, those sizes, the number of
    solves); ConvergenceError naming ``what`` after PATCH_SCALING_ITERATIONS solves."""
    change = math.inf
    for solves in range(1, PATCH_SCALING_ITERATIONS + 1):
        result, new = solve_at(sizes)
        change = max((abs(n / o - 1.0) for k in new for n, o in zip(new[k], sizes.get(k, (math.inf, math.inf)))),
                     default=0.0)
        if change <= PATCH_SCALING_TOLERANCE and new.keys() == sizes.keys():
            return result, sizes, solves
        sizes = new
    raise ConvergenceError(f"{what}: the patch sizes did not settle within {PATCH_SCALING_ITERATIONS} solves "
                           f"(last change {change:.3g}, relative)")
