"""The result records of a Kik–Piotrowski scene run, as written to result.json (units mm, N, MPa, s; units of
every field: :data:`contact.scenes.result_io.UNITS`). Field names are the JSON keys; the passes are
:class:`contact.passes.record.PassRecord` written in :data:`contact.passes.record.SCENE_PASS_LAYOUT`; converted to
JSON only when written (:class:`wrlayer.json_io.Record`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from contact.passes.record import SCENE_PASS_LAYOUT, PassRecord
from wrlayer.json_io import Layout, Record

OMIT_NONE = {"omit_none": True}


@dataclass(frozen=True, kw_only=True)
class MethodDescription(Record):
    """The methods a run used, in words.

    Attributes
    ----------
    normal : str
        The normal solver.
    tangential : str | None
        The tangential solver; None without creepage.
    layer : tuple[str, ...] | None
        The layers ("combined", "rail", "wheel"); None without a layer.
    """

    normal: str
    tangential: str | None
    layer: tuple[str, ...] | None


@dataclass(frozen=True, kw_only=True)
class PatchScaling(Record):
    """The patch size the table layers were scaled to (``scale_to_patch``; ``layers.scale_to_patch`` of a
    wheel–rail scene, written in :data:`PATCH_SCALING_LAYOUT`).

    Attributes
    ----------
    a_mm : float
        Semi-axis along the rolling direction (mm).
    b_mm : float
        Lateral semi-axis (mm).
    solves : int
        Solves of the fixed point, the unscaled first one included (-): normal solves of a contact scene, balances
        of a wheel–rail patch (written ``balances``).
    """

    a_mm: float
    b_mm: float
    solves: int


#: A wheel–rail patch's ``layer_scaled_to_patch`` (result.json).
PATCH_SCALING_LAYOUT: Layout = (("a_mm", "a_mm"), ("b_mm", "b_mm"), ("balances", "solves"))


@dataclass(frozen=True, kw_only=True)
class StripGrid(Record):
    """The fixed strip grid of the run and the separation on it.

    Attributes
    ----------
    y_mm : tuple[float, ...]
        Strip positions (mm).
    separation_before_mm : tuple[float, ...]
        Separation before the first pass, shifted to min 0 (mm).
    separation_after_mm : tuple[float, ...]
        Separation after the last pass's dents (mm).
    residual_mm : dict[str, tuple[float, ...]]
        Per layer ("wheel", "rail", "combined"): cumulative residual displacement after the last pass (mm).
    """

    y_mm: tuple[float, ...]
    separation_before_mm: tuple[float, ...]
    separation_after_mm: tuple[float, ...]
    residual_mm: dict[str, tuple[float, ...]]

    def __repr__(self) -> str:
        return f"StripGrid({len(self.y_mm)} strips, layers {sorted(self.residual_mm)})"


@dataclass(frozen=True, kw_only=True)
class SolverStats(Record):
    """Run statistics.

    Attributes
    ----------
    total_s : float
        Wall-clock time of the run (s).
    delta_evaluations : int
        Approach evaluations of the normal solver over all passes (-).
    """

    total_s: float
    delta_evaluations: int


@dataclass(frozen=True, kw_only=True)
class SceneResult(Record):
    """The result of a Kik–Piotrowski scene (result.json).

    Attributes
    ----------
    inputs : dict
        The resolved inputs (the scene's ``to_dict()``).
    code_version : Any
        Version of the code that ran.
    units : dict
        Units of the result fields.
    method : MethodDescription
        The methods used.
    layer_scaled_to_patch : PatchScaling | None
        The patch size the table layers were scaled to; None when not scaled.
    n_passes : int
        Passes run (-).
    shakedown_pass : int | None
        First pass that added no residual beyond the tolerance (-); None when none did or without a layer.
    passes : tuple[PassRecord, ...]
        Every pass (written in :data:`contact.passes.record.SCENE_PASS_LAYOUT`).
    reference_deviation : dict
        Relative deviation (value - reference) / |reference| of the last pass from the scene's [reference], a
        fraction (-), keyed ``<quantity>_rel`` (:func:`relative_key`: ``length_rel``, ``p_max_rel``, ...).
    strip_grid : StripGrid
        The strip grid and the separation on it.
    solver : SolverStats
        Run statistics.
    frictional_outputs : tuple[str, ...] | None
        The wear-ready frictional CSV files written (by the command line).
    pictures : tuple[str, ...] | None
        The pictures written (with ``--plots``).
    """

    inputs: dict
    code_version: Any
    units: dict
    method: MethodDescription
    layer_scaled_to_patch: PatchScaling | None
    n_passes: int
    shakedown_pass: int | None
    passes: tuple[PassRecord, ...] = field(metadata={"layout": SCENE_PASS_LAYOUT})
    reference_deviation: dict
    strip_grid: StripGrid
    solver: SolverStats
    frictional_outputs: tuple[str, ...] | None = field(default=None, metadata=OMIT_NONE)
    pictures: tuple[str, ...] | None = field(default=None, metadata=OMIT_NONE)

    def __repr__(self) -> str:
        last = self.passes[-1]
        return (f"SceneResult({self.n_passes} passes, shakedown_pass={self.shakedown_pass}, last: "
                f"delta={last.delta_mm:.6g} mm, p_max={last.p_max_MPa:.5g} MPa)")


#: Unit suffixes of the result keys, dropped in a relative deviation's key (longest first).
UNIT_SUFFIXES = ("_W_per_mm2", "_N_per_mm", "_Nmm", "_mm2", "_MPa", "_mm", "_N")


def relative_key(key: str) -> str:
    """The key of a relative deviation of result key ``key``: its unit suffix replaced by ``_rel``
    (``length_mm`` -> ``length_rel``, ``passes`` -> ``passes_rel``)."""
    stem = next((key[:-len(s)] for s in UNIT_SUFFIXES if key.endswith(s)), key)
    return f"{stem}_rel"


def reference_deviation(reference: dict[str, Any], last: PassRecord) -> dict[str, float]:
    """Relative deviation (value - reference) / |reference| of the last pass from the scene's [reference] numbers
    (by the keys of a result's pass; ``passes``: the pass count), keyed by :func:`relative_key` (a fraction, -);
    empty without a reference."""
    values = last.to_dict(SCENE_PASS_LAYOUT)
    out = {}
    for key, ref in reference.items():
        value = last.index if key == "passes" else values.get(key)
        if isinstance(ref, float) and ref != 0.0 and value is not None:
            out[relative_key(key)] = (float(value) - ref) / abs(ref)
    return out


__all__ = ["PATCH_SCALING_LAYOUT", "MethodDescription", "PatchScaling", "SceneResult", "SolverStats", "StripGrid",
           "reference_deviation", "relative_key"]
