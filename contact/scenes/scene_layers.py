"""The layers of a Kik–Piotrowski scene on its strip grid: built from the scene's characteristics or calibration
tables, their coverage of the contact, and their scaling to the solved patch size (units mm, MPa).

A per-body calibration table is read at ``position_mm + y`` for every strip y (outside the table's range the
nearest tabulated end is used for building, and a contact on such a strip is a
:class:`wrlayer.errors.LayerNotCovered`: the table does not cover the contact location;
:mod:`contact.layer.strip_lookup`).
"""

from __future__ import annotations

import numpy as np

from contact.layer.patch_scaling import settle_patch_sizes
from contact.layer.prandtl_layer import LayerPair
from contact.layer.strip_lookup import check_coverage
from contact.normal.kik_piotrowski import NormalProblem, NormalSolution
from contact.normal.method import solve_normal_with
from contact.scenes.layers import build_layer_pair
from contact.scenes.scene_spec import Scene


def scales_to_patch(scene: Scene) -> bool:
    """A table layer of the scene asks to be scaled to the solved patch size."""
    return scene.layers is not None and scene.layers.scale_to_patch


def build_layers(scene: Scene, strip_y_mm: np.ndarray, patch_mm: tuple[float, float] | None = None
                 ) -> LayerPair | None:
    """The scene's layers on the strip grid (:func:`contact.scenes.layers.build_layer_pair`): a table layer is read
    at ``position_mm + y`` for every strip y, clamped to the table's range (coverage is checked after each pass, on
    the strips in contact: :func:`check_table_coverage`); with ``scale_to_patch`` scaled to ``patch_mm`` = (a, b)
    (mm)."""
    if scene.layers is None:
        return None
    sources = scene.layers.sources
    return build_layer_pair(sources, strip_y_mm, lambda body: sources.position_mm[body] + strip_y_mm, patch_mm,
                            f"{scene.path.name}: layers")


def check_table_coverage(scene: Scene, solution: NormalSolution) -> None:
    """LayerNotCovered when a strip in contact lies outside a body's calibration table, LayerRangeExceeded when its
    peak pressure lies above the table's calibrated range."""
    if scene.layers is None:
        return
    sources = scene.layers.sources
    loaded = solution.p_peak_MPa > 0
    in_contact = solution.strip_y_mm[loaded]
    for body, table in sources.tables().items():
        check_coverage(table, sources.position_mm[body] + in_contact, f"{scene.path.name}: layers.{body}", body,
                       sources.name(body), tolerance_mm=1e-9, p_peak_MPa=solution.p_peak_MPa[loaded])


def scale_layers_to_patch(scene: Scene, prob: NormalProblem, layers: LayerPair):
    """A table characteristic holds for the patch size it was calibrated on (its displacements scale
    with sqrt(a b)). Solve the first pass's normal problem, rebuild the layers scaled to the solved semi-axes
    (a, b) = (length/2, width/2) and solve again until the patch settles
    (:func:`contact.layer.patch_scaling.settle_patch_sizes`). Returns (the layers at the settled (a, b), (a, b),
    normal solves including the first, unscaled one); ConvergenceError when the patch does not settle."""
    method = scene.method.normal_method()

    def sizes_of(sol) -> dict:
        return {0: (0.5 * sol.length_mm, 0.5 * sol.width_mm)}

    def solve_at(sizes: dict):
        scaled = build_layers(scene, prob.strip_y_mm, sizes[0])
        return scaled, sizes_of(solve_normal_with(prob, scaled, method=method))

    first = sizes_of(solve_normal_with(prob, layers, method=method))
    layers, sizes, solves = settle_patch_sizes(solve_at, first, f"{scene.path.name}: scale_to_patch")
    return layers, sizes[0], solves + 1


__all__ = ["build_layers", "check_table_coverage", "scale_layers_to_patch", "scales_to_patch"]
