"""One wheel on its rail: contact search, vertical load balance, passes and layer coverage per patch, and the
retries of a case (units mm, N, MPa, s, rad).

Each wheel's vertical position is solved on its own (:mod:`contact.wheel_rail.balance`): for a whole wheelset with a
given (or rigid-contact, "auto") roll angle the two wheels' approaches differ slightly, which amounts to an extra
roll of (Delta_right - Delta_left) / (wheel distance), ~1e-5 rad at 10 kN, not fed back (the A-2.2 benchmark
prescribes the roll per case). ``vertical_balance_rel`` of the final patches is reported; ConvergenceError above
:data:`BALANCE_RTOL`.

Retries: patches that grow into each other (a patch reaching the barrier to its neighbouring candidate,
:class:`wrlayer.errors.PatchTruncated`) are merged: the contact search is repeated with a larger ``merge_mm``
(:data:`MERGE_RETRY_MM`) so that the neighbours become one candidate with one separation function (in the contact
plane of the lower minimum), on which the normal solver finds the interacting regions itself. Layers are built only
on the strips near contact (:data:`contact.wheel_rail.balance.LAYER_F_CAPS_MM`); a loaded strip without an element
(:class:`wrlayer.errors.LayerElementMissing`) solves the case again with more strips.

Layers: passes (paper section 5) run per patch at the patch's balanced normal force
(:func:`contact.passes.passes.run_passes`); a strip IN CONTACT outside a calibration table's range is a
:class:`wrlayer.errors.LayerNotCovered`. With ``LayerSources.scale_to_patch`` every patch's table
characteristics are scaled to that patch's own solved semi-axes (a, b) = (length/2, width/2)
(``LayerTable.characteristic_at(y, patch_mm)``: displacements x sqrt(ab) / sqrt(a_c b_c)): the balance is solved,
the layers rebuilt at the patches' sizes, and this is repeated until no loaded patch's a or b changes by more than
``PATCH_SCALING_TOLERANCE`` (:func:`contact.layer.patch_scaling.settle_patch_sizes`, shared with the scenes).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from contact.layer.patch_scaling import settle_patch_sizes
from contact.layer.strip_lookup import check_coverage
from contact.normal.kik_piotrowski import NormalSolution
from contact.passes.passes import PassRecord, run_passes
from contact.wheel_rail.balance import (JUMP_BALANCE_RTOL, LAYER_F_CAPS_MM, LoadedPatch, VerticalBalance,
                                        track_vector)
from contact.wheel_rail.contact_search import SearchResult, SearchSettings, search_contacts
from contact.scenes.layers import LayerSources
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.solution import PatchSolution, WheelRailSolution
from contact.wheel_rail.track_geometry import PlacedRail, place_rail, side_sign
from meshes.profiles import Profile
from wrlayer.errors import ConvergenceError, InputError, LayerElementMissing, PatchTruncated, typed_input_error

#: Largest relative vertical load balance residual |sum F_Z - Q| / Q accepted: the iteration stops at 1e-8 (5e-7
#: with "coarse_exact") where F_Z(N) is continuous, and where F_Z jumps across Q at the jump's side nearer Q, within
#: :data:`contact.wheel_rail.balance.JUMP_BALANCE_RTOL`.
BALANCE_RTOL = JUMP_BALANCE_RTOL
#: Barrier heights (mm) up to which neighbouring candidates are merged when their patches grow into each other.
MERGE_RETRY_MM = (0.02, 0.05, 0.1, 0.2, 0.5)


def solve_wheel(rail_profile: Profile, wheel_profile: Profile, inputs: WheelRailInputs,
                layers: LayerSources | None = None, placed_rail: PlacedRail | None = None,
                case: str = "wheel-rail case") -> WheelRailSolution:
    """Solve one wheel on its rail (see the module docstring). ``placed_rail`` may be passed to reuse a placement
    (it depends only on the rail profile and the layout). ``WheelRailSolution.merge_mm`` records the merge level
    used. Errors name ``case``."""
    rail = placed_rail if placed_rail is not None else place_rail(rail_profile, inputs.layout)
    first_error = None
    merges = [inputs.search.merge_mm] + [m for m in MERGE_RETRY_MM if m > inputs.search.merge_mm]
    for merge in merges:
        try:
            sol = _solve_with_search(rail, wheel_profile, inputs, layers, case,
                                     dataclasses.replace(inputs.search, merge_mm=merge))
            sol.merge_mm = merge
            return sol
        except PatchTruncated as err:
            first_error = first_error or err
        except ConvergenceError as err:
            raise ConvergenceError(f"{case}: {err}") from None
    raise PatchTruncated(case, "a contact patch reaches the end of its separation function (the barrier to the "
                         "neighbouring contact candidate, or the search cap of "
                         f"{inputs.search.f_cap_mm:g} mm) even with candidates merged up to merge_mm = "
                         f"{merges[-1]:g} mm ({first_error.problem})") from None


def _solve_with_search(rail: PlacedRail, wheel_profile: Profile, inputs: WheelRailInputs,
                       layers: LayerSources | None, case: str, search: SearchSettings) -> WheelRailSolution:
    """The case at one merge level; solved again with layers on more strips while a loaded strip has none."""
    found = search_contacts(rail, wheel_profile, inputs.layout, inputs.pose.for_side(inputs.side), search, case=case)
    for k, cap in enumerate(LAYER_F_CAPS_MM):
        try:
            return _solve_found(found, rail, wheel_profile, inputs, layers, case, cap)
        except InputError as err:
            typed = typed_input_error(err)
            if isinstance(typed, LayerElementMissing) and k < len(LAYER_F_CAPS_MM) - 1:
                continue
            if typed is err:
                raise
            raise typed from None
    raise AssertionError("unreachable")


def _balanced(found: SearchResult, rail: PlacedRail, wheel_profile: Profile, inputs: WheelRailInputs,
              layers: LayerSources | None, case: str, f_cap_mm: float
              ) -> tuple[VerticalBalance, list[LoadedPatch], float, int, int]:
    """The balanced candidates: (balance, loaded patches, Delta (mm), patch solves, scaled balances); with
    ``scale_to_patch`` at the fixed point over each loaded candidate's patch size (module docstring)."""
    sign = side_sign(inputs.side)
    balance = VerticalBalance(found, rail, wheel_profile, inputs, layers, sign, case, f_cap_mm)
    loaded, Delta, iterations = balance.solve()
    if layers is None or not layers.scale_to_patch:
        return balance, loaded, Delta, iterations, 0
    counts = [iterations]

    def solve_at(sizes: dict):
        scaled = VerticalBalance(found, rail, wheel_profile, inputs, layers, sign, case, f_cap_mm, sizes)
        solved = scaled.solve()
        counts.append(solved[2])
        return (scaled, *solved), _patch_sizes(scaled, solved[0])

    (balance, loaded, Delta, _), _, scaling_solves = settle_patch_sizes(
        solve_at, _patch_sizes(balance, loaded), "layers.scale_to_patch")
    return balance, loaded, Delta, sum(counts), scaling_solves


def _solve_found(found: SearchResult, rail: PlacedRail, wheel_profile: Profile, inputs: WheelRailInputs,
                 layers: LayerSources | None, case: str, f_cap_mm: float) -> WheelRailSolution:
    """The balanced patches of the found candidates, with their passes; the balance residual checked."""
    _, loaded, Delta, iterations, scaling_solves = _balanced(found, rail, wheel_profile, inputs, layers, case,
                                                             f_cap_mm)
    patches = [_patch(lp, inputs, layers, scaling_solves) for lp in loaded]
    Q = inputs.vertical_load_N
    if inputs.balance == "total":
        vertical = sum(float(p.force_track_N()[2]) for p in patches)
    else:
        vertical = sum(p.normal_force_N * math.cos(p.candidate.contact_angle_rad) for p in patches)
    rel = abs(vertical - Q) / Q
    if not rel <= BALANCE_RTOL:
        raise ConvergenceError(f"vertical load balance off by {rel:.3g} (relative) > {BALANCE_RTOL:g}")
    unloaded = [c for c in found.candidates if all(c is not p.candidate for p in patches)]
    return WheelRailSolution(inputs=inputs, search=found, rail=rail, patches=patches, approach_mm=float(Delta),
                             vertical_balance_rel=rel, unloaded=unloaded, wheel=wheel_profile,
                             balance_iterations=iterations)


def _patch(lp: LoadedPatch, inputs: WheelRailInputs, layers: LayerSources | None,
           scaling_solves: int) -> PatchSolution:
    """A balanced candidate as a patch: passes (paper section 5) at the balanced force, pass 1 being the balanced
    solution; the layer tables' coverage of the strips in contact checked."""
    ctx = lp.ctx
    c, pair, coords, sign = ctx.cand, ctx.pair, ctx.coords, ctx.sign
    records: list[PassRecord] = []
    pass_normals: list[NormalSolution] = [lp.normal]
    if pair is not None:
        pass_normals = []
        records, _ = run_passes(lp.prob, pair, inputs.passes.options, on_pass=lambda rec, s: pass_normals.append(s),
                                method=inputs.normal_method, first=lp.normal)
    if not coords:
        eta = sign * lp.prob.strip_y_mm
        coords = {"rail": c.rail_coordinate(eta), "wheel": c.wheel_coordinate(eta)}
    n_track, t_track = lp.frame
    residual = {} if not records else {k: np.asarray(v) for k, v in records[-1].cumulative_residual_mm.items()}
    patch = PatchSolution(candidate=c, side=inputs.side, strip_sign=sign, problem=lp.prob, normal=lp.normal,
                          normal_force_N=float(lp.normal.normal_force_N),
                          point_track=track_vector(lp.ref.point_mm, sign), normal_track=n_track,
                          lateral_track=t_track, kinematics=lp.kin, tangential=lp.tangential, passes=records,
                          rail_y_of_strip=coords.get("rail"), wheel_y_of_strip=coords.get("wheel"),
                          residual_mm=residual, reference=lp.ref, pass_normals=pass_normals,
                          layer_patch_mm=ctx.layer_patch_mm, layer_scaling_solves=scaling_solves)
    if pair is not None and layers is not None:
        in_contact = patch.normal.p_peak_MPa > 0
        for body in ("rail", "wheel"):
            table = getattr(layers, body)
            if table is not None:
                check_coverage(table, coords[body][in_contact], f"layers.{body} ({layers.name(body)})", body,
                               layers.name(body), p_peak_MPa=patch.normal.p_peak_MPa[in_contact])
    return patch


def _patch_sizes(balance: VerticalBalance, loaded: list[LoadedPatch]) -> dict[int, tuple[float, float]]:
    """Candidate index -> solved semi-axes (a, b) = (length/2, width/2) (mm) of every loaded candidate."""
    index = {id(ctx): k for k, ctx in enumerate(balance.ctx)}
    return {index[id(lp.ctx)]: lp.semi_axes_mm for lp in loaded}


__all__ = ["BALANCE_RTOL", "MERGE_RETRY_MM", "solve_wheel"]
