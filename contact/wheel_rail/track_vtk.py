"""ParaView files of a wheel–rail sweep in track coordinates: the deformed rail and wheel surfaces and the contact
fields placed on them (``output.vtk_frame = "track"``, the default; ``"local"``: each patch flat in its own frame).

Units: mm, MPa, mm/s. Track frame X forward, Y lateral towards the right rail, Z up
(:mod:`contact.wheel_rail.track_geometry`). Per case (the ``.pvd`` time step) and wheel:

- ``case<k>_<side>_rail_surface.vtu``: the rail head, the placed profile extruded over X in +-
  :data:`SURFACE_HALF_LENGTH_MM`, moved into the rail by the rail layers' residual displacement after the last pass
  (point data ``residual_mm``);
- ``case<k>_<side>_wheel_surface.vtu``: the wheel tread band, the profile revolved about the axle over the same
  length, moved into the wheel by its residual;
- ``case<k>_<side>_patch<i>_region<r>_rail.vtu`` and ``..._wheel.vtu``: the patch's cells with the fields of
  :mod:`contact.scenes.vtk_output` (pressure, traction, slip velocity, contact state, residuals) on the rail and on
  the wheel surface (:mod:`contact.wheel_rail.track_surfaces`), the strips at their profile coordinates.

The surfaces are the wheelset at its rigid-contact height (the approach under load, well below the residual, is
left out, so that both bodies touch at the patch).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from contact.scenes.vtk_output import cell_edges, patch_mesh, sweep_patches, write_meshes
from contact.wheel_rail.deformed import residual_on_profiles
from contact.wheel_rail.track_geometry import side_sign
from contact.wheel_rail.track_surfaces import patch_on_rail, patch_on_wheel, quads, rail_points, wheel_points

#: Half-length (mm) of the rail and wheel surfaces along X about the wheelset centre.
SURFACE_HALF_LENGTH_MM = 20.0
#: Spacing (mm) of the surfaces along the profiles (their shape) and along X (straight rail, wheel radius ~460 mm:
#: the chord of 2 mm departs 1 um from the circle).
SURFACE_STEP_MM = 0.5
SURFACE_X_STEP_MM = 2.0


def _depth(residual: dict, body: str):
    """The body's residual displacement (mm) as a function of its profile coordinate (0 off the loaded strips)."""
    if body not in residual:
        return lambda q: np.zeros(np.shape(q))
    coords, u = residual[body]
    order = np.argsort(coords)
    return lambda q: np.interp(q, coords[order], u[order], left=0.0, right=0.0)


def _surface(points: np.ndarray, depth: np.ndarray):
    import meshio  # here: only runs that write VTK files import it

    n_i, n_j, _ = points.shape
    return meshio.Mesh(points.reshape(-1, 3), [("quad", quads(n_i, n_j))],
                       point_data={"residual_mm": depth.reshape(-1)})


def body_surfaces(sol, residual: dict) -> tuple:
    """(rail mesh, wheel mesh) of one solved wheel (:class:`~contact.wheel_rail.solution.WheelRailSolution`) with
    its residual on the profiles (:func:`contact.wheel_rail.deformed.residual_on_profiles`)."""
    side = sol.inputs.side
    sign, pose, layout = side_sign(side), sol.inputs.pose.for_side(side), sol.inputs.layout
    n_x = int(round(2.0 * SURFACE_HALF_LENGTH_MM / SURFACE_X_STEP_MM)) + 1
    X = np.linspace(-SURFACE_HALF_LENGTH_MM, SURFACE_HALF_LENGTH_MM, n_x)
    prof = sol.rail.profile
    q = np.linspace(prof.y_min, prof.y_max, int((prof.y_max - prof.y_min) / SURFACE_STEP_MM) + 1)
    d_rail = np.broadcast_to(_depth(residual, "rail")(q), (n_x, q.size))
    rail = _surface(rail_points(sol.rail, sign, X, q, d_rail), d_rail)
    wheel = sol.wheel
    y = np.linspace(wheel.y_min + 1e-3, wheel.y_max, int((wheel.y_max - wheel.y_min) / SURFACE_STEP_MM) + 1)
    phi = X / layout.nominal_radius_mm
    d_wheel = np.broadcast_to(_depth(residual, "wheel")(y), (n_x, y.size))
    wheel_mesh = _surface(wheel_points(wheel, layout, pose, sol.search.wheel_height_mm, sign, phi, y, d_wheel),
                          d_wheel)
    return rail, wheel_mesh


def track_meshes(all_sols: list):
    """(step, part, name, mesh) of every surface and placed patch of a sweep (``all_sols[case] = {side:
    WheelRailSolution}``)."""
    residuals: dict = {}
    for k, side, sol, p, item in sweep_patches(all_sols):
        if (k, side) not in residuals:          # the wheel's surfaces and residual, once per case and wheel
            residuals[k, side] = residual_on_profiles(sol.patches)
            rail, wheel = body_surfaces(sol, residuals[k, side])
            yield k, f"{side}_rail_surface", f"case{k:03d}_{side}_rail_surface", rail
            yield k, f"{side}_wheel_surface", f"case{k:03d}_{side}_wheel_surface", wheel
        sign, pose, layout = side_sign(side), sol.inputs.pose.for_side(side), sol.inputs.layout
        residual = residuals[k, side]
        xe, ye = cell_edges(item.patch)
        eta = p.strip_sign * ye                      # the problem's strips are strip_sign * eta of the candidate
        cand = p.candidate
        d_rail = np.broadcast_to(_depth(residual, "rail")(cand.rail_coordinate(eta)), (xe.size, eta.size))
        d_wheel = np.broadcast_to(_depth(residual, "wheel")(cand.wheel_coordinate(eta)), (xe.size, eta.size))
        on_rail = patch_on_rail(sol.rail, cand, sign, xe, eta, d_rail)
        on_wheel = patch_on_wheel(sol.wheel, layout, pose, sol.search.wheel_height_mm, cand, sign, xe, eta, d_wheel)
        for body, pts in (("rail", on_rail), ("wheel", on_wheel)):
            points = np.transpose(pts, (1, 0, 2)).reshape(-1, 3)     # strip by strip, as patch_mesh numbers them
            yield k, f"{item.part}_{body}", f"{item.name}_{body}", patch_mesh(item, points)


def write_track_series(all_sols: list, out_dir: Path) -> list[str]:
    """Write the sweep's surfaces and placed patches (module docstring) with their ``.pvd`` collection; returns the
    written paths relative to ``out_dir``."""
    return write_meshes(track_meshes(all_sols), out_dir)


__all__ = ["SURFACE_HALF_LENGTH_MM", "SURFACE_STEP_MM", "SURFACE_X_STEP_MM", "body_surfaces", "track_meshes", "write_track_series"]
