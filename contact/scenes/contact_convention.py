"""CONTACT's sign convention as an output (``output.convention = "contact"``): contact_convention.csv.

Units: mm, N, N mm, rad. wrlayer reports the creep forces of the rail on the wheel (body 1) and the creepages of
the wheel relative to the rail; CONTACT (Vollebregt) reports the forces on the rail and the creepages with the
opposite sign; on the left wheel it measures the rail profile coordinate and the contact angle in the mirrored
frame (docs/conventions.md, docs/wheel-rail.md "Comparing with CONTACT"):

    CONTACT          wrlayer
    FN               normal_force_N
    FX, FS, MZ       -Fx_N, -Fy_N, -Mz_Nmm
    CKSI, CETA, CPHI -creepage_x, -creepage_y, -spin_per_mm
    YCP(R)           y_rail_mm (right wheel), -y_rail_mm (left wheel)
    DELTCP           -contact_angle_rad (right), +contact_angle_rad (left)
    FY(TR)           -force_on_wheel_track_N[1] (the wheel's total lateral force)
    ROLL, VPITCH     -roll_rad, -pitch_rate_rad_s

The CSV has CONTACT's quantity names (lower case, with units) and one row per patch: per pass of a contact scene,
per case, wheel and patch of a wheel–rail sweep. result.json keeps wrlayer's convention.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from wrlayer.atomic_write import atomic_write_text

if TYPE_CHECKING:
    from contact.passes.record import RegionRecord
    from contact.scenes.run_result import SceneResult

#: A wheel–rail patch record (:class:`contact.wheel_rail.patch_result.PatchResult`; this package does not import
#: the wheel–rail package) and a sweep's result record (:class:`contact.wheel_rail.results.SweepResult`).
PatchResult = SweepResult = Any


class Creepages(Protocol):
    """The creepages of a patch or a scene: longitudinal, lateral (-) and spin (1/mm)."""

    creepage_x: float
    creepage_y: float
    spin_per_mm: float

CONVENTION_FILE = "contact_convention.csv"
SCENE_COLUMNS = ("pass", "patch", "fn_N", "fx_N", "fs_N", "mz_Nmm", "cksi", "ceta", "cphi_per_mm")
SWEEP_COLUMNS = ("case", "wheel", "patch", "roll_rad", "vpitch_rad_s", "ycp_r_mm", "deltcp_rad", "fn_N", "fx_N",
                 "fs_N", "mz_Nmm", "cksi", "ceta", "cphi_per_mm", "approach_mm", "pmax_MPa", "area_mm2", "fy_tr_N")


def creep_in_contact(patch: RegionRecord | PatchResult, creepages: Creepages) -> dict[str, float]:
    """FN, FX, FS, MZ and the creepages of one patch (a region of a contact scene's pass or a wheel–rail patch) in
    CONTACT's signs; ``creepages``: anything with ``creepage_x``, ``creepage_y``, ``spin_per_mm``."""
    return {"fn_N": patch.normal_force_N, "fx_N": -patch.Fx_N, "fs_N": -patch.Fy_N, "mz_Nmm": -patch.Mz_Nmm,
            "cksi": -creepages.creepage_x, "ceta": -creepages.creepage_y, "cphi_per_mm": -creepages.spin_per_mm}


def wheel_patch_in_contact(patch: PatchResult, side: str) -> dict[str, float]:
    """A wheel–rail patch (result.json's ``cases[k].wheels[side].patches[i]``) in CONTACT's convention."""
    mirror = -1.0 if side == "left" else 1.0
    return {"ycp_r_mm": mirror * patch.y_rail_mm, "deltcp_rad": -mirror * patch.contact_angle_rad,
            **creep_in_contact(patch, patch), "approach_mm": patch.delta_mm, "pmax_MPa": patch.p_max_MPa,
            "area_mm2": patch.area_mm2}


def _csv(columns: tuple[str, ...], rows: list[dict[str, Any]]) -> str:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=columns, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: (f"{v:.10g}" if isinstance(v, float) else v) for k, v in r.items()})
    return buf.getvalue()


def scene_rows(result: SceneResult, creepages: Creepages | None) -> list[dict[str, Any]]:
    """Rows of a contact scene's result with a tangential solution (``creepages``: the scene's, None without):
    every pass and patch."""
    if creepages is None:
        return []
    return [{"pass": p.index, "patch": i, **creep_in_contact(q, creepages)}
            for p in result.passes for i, q in enumerate(p.regions)]


def sweep_rows(result: SweepResult) -> list[dict[str, Any]]:
    """Rows of a wheel–rail sweep result: every solved case, wheel and patch."""
    rows = []
    for case in result.cases:
        for side, wheel in (case.wheels or {}).items():
            for i, patch in enumerate(wheel.patches):
                rows.append({"case": case.case, "wheel": side, "patch": i, "roll_rad": -case.roll_rad,
                             "vpitch_rad_s": None if case.pitch_rate_rad_s is None else -case.pitch_rate_rad_s,
                             **wheel_patch_in_contact(patch, side), "fy_tr_N": -wheel.force_on_wheel_track_N[1]})
    return rows


def write_contact_convention(result: SceneResult | SweepResult, out_dir: Path,
                             creepages: Creepages | None = None) -> list[str]:
    """Write contact_convention.csv for a contact scene's result (``creepages``: the scene's tangential section,
    None without creepage) or a sweep's; returns [its name] ([] when there is nothing to write: a scene without
    tangential solution)."""
    sweep = hasattr(result, "cases")
    rows = sweep_rows(result) if sweep else scene_rows(result, creepages)
    if not rows:
        return []
    atomic_write_text(Path(out_dir) / CONVENTION_FILE, _csv(SWEEP_COLUMNS if sweep else SCENE_COLUMNS, rows))
    return [CONVENTION_FILE]


__all__ = ["CONVENTION_FILE", "SCENE_COLUMNS", "SWEEP_COLUMNS", "creep_in_contact", "scene_rows", "sweep_rows",
           "wheel_patch_in_contact", "write_contact_convention"]
