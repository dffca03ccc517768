"""Contact fields for ParaView: every patch as a VTK quad grid, a ``.pvd`` series over passes or sweep cases.

Units: mm, MPa, mm/s. One unstructured grid (``.vtu``, meshio) per patch and pass (contact scene) or per patch,
wheel and case (wheel–rail sweep): the patch's square cells (:meth:`contact.normal.patch.Patch.grid`, spacing the
strip width h) in the patch's plane, x the rolling direction, y the strip coordinate (the scene frame; a wheel–rail
patch's contact-plane strip coordinate), z = 0. Cell data (NaN or 0 outside the contact):

    pressure_MPa             normal pressure p(x, y) (Kik–Piotrowski's semi-ellipse per strip, eq. 11)
    traction_MPa             tangential traction (tx, ty, 0) on body 1 (NaN without a tangential solution)
    traction_magnitude_MPa   |t|
    slip_velocity_mm_s       |slip velocity|
    contact_state            0 outside, 1 adhesion, 2 slip
    layer_residual_mm        cumulative residual displacement of the layers after the pass (all bodies), per strip
    residual_pass_mm         residual displacement added by this pass, per strip

A ``.pvd`` collection lists the files with the pass number (contact scene) or case number (sweep) as ``timestep``
and the patch as ``part``: ParaView's time slider steps through them. Written unless ``output.vtk = false`` or
``--no-vtk``.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from contact.normal.patch import Patch
from contact.tangential.fastsim import TangentialResult
from contact.tangential.grid_sample import sample_on_grid
from contact.tangential.method import strip_rows

#: The folder (inside a result folder) of the VTK files and the collection's name.
VTK_DIR = "vtk"
PVD_FILE = "contact_fields.pvd"
CELL_FIELDS = ("pressure_MPa", "traction_MPa", "traction_magnitude_MPa", "slip_velocity_mm_s", "contact_state",
               "layer_residual_mm", "residual_pass_mm")


@dataclass(frozen=True, eq=False)
class PatchFields:
    """One patch to write: the patch (strip y in the frame to show), its tangential solution (or None), the
    residual displacement per strip after the pass and added by it (mm; None without a layer), the series step
    (pass or case number), the part (the patch within a step) and a name for the file."""

    patch: Patch
    tangential: TangentialResult | None
    residual_mm: np.ndarray | None
    residual_pass_mm: np.ndarray | None
    step: int
    part: str
    name: str


def cell_edges(patch: Patch) -> tuple[np.ndarray, np.ndarray]:
    """(x edges (nx + 1,), strip edges (ny + 1,)) of a patch's picture grid (mm, the patch's frame)."""
    h = patch.grid_mm
    x, _ = patch.grid()
    return np.append(x - 0.5 * h, x[-1] + 0.5 * h), np.append(patch.y_mm - 0.5 * h, patch.y_mm[-1] + 0.5 * h)


def patch_mesh(item: PatchFields, points: np.ndarray | None = None):
    """The meshio quad mesh of one patch with the cell data of the module docstring; ``points`` ((ny + 1) (nx + 1),
    3) place the grid's corners (strip by strip) elsewhere, e.g. on a body's surface in track coordinates (default:
    the patch's plane, z = 0)."""
    import meshio  # here: only runs that write VTK files import it

    patch = item.patch
    x, mask = patch.grid()
    ny, nx = mask.shape
    if points is None:
        X, Y = np.meshgrid(*cell_edges(patch))
        points = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    j, i = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
    p0 = (j * (nx + 1) + i).ravel()
    quads = np.column_stack([p0, p0 + 1, p0 + nx + 2, p0 + nx + 1])
    data = {name: arr.reshape(ny * nx, *arr.shape[2:]) for name, arr in cell_fields(item, x, mask).items()}
    return meshio.Mesh(points, [("quad", quads)], cell_data={k: [v] for k, v in data.items()})


def cell_fields(item: PatchFields, x: np.ndarray, mask: np.ndarray) -> dict[str, np.ndarray]:
    """The (ny, nx[, 3]) cell fields of one patch on its picture grid (``x``, ``mask`` of ``Patch.grid``)."""
    patch, tr = item.patch, item.tangential
    shape = mask.shape
    pressure = np.where(mask, patch.pressure_MPa(x[:, None]).T, 0.0)
    nan = np.full(shape, np.nan)
    tx = ty = speed = nan
    state = mask.astype(np.int32)
    if tr is not None and tr.x_mm.shape[0] == patch.n_strips:
        g = sample_on_grid(patch, tr)
        tx, ty, speed = g.tx_MPa, g.ty_MPa, g.slip_velocity_mm_s
        state = state + g.slip.astype(np.int32)
    traction = np.stack([tx, ty, np.where(np.isnan(tx), np.nan, 0.0)], axis=-1)

    def per_strip(values):
        v = np.zeros(patch.n_strips) if values is None else np.asarray(values, dtype=float)
        return np.where(mask, v[:, None], 0.0)

    return {"pressure_MPa": pressure, "traction_MPa": traction, "traction_magnitude_MPa": np.hypot(tx, ty),
            "slip_velocity_mm_s": speed, "contact_state": state,
            "layer_residual_mm": per_strip(item.residual_mm), "residual_pass_mm": per_strip(item.residual_pass_mm)}


def write_series(items: Iterable[PatchFields], out_dir: Path) -> list[str]:
    """Write every item as ``vtk/<name>.vtu`` and the collection ``vtk/contact_fields.pvd``; returns the written
    paths relative to ``out_dir`` (the collection first; [] without items)."""
    return write_meshes(((item.step, item.part, item.name, patch_mesh(item)) for item in items), out_dir)


def write_meshes(meshes: Iterable[tuple], out_dir: Path) -> list[str]:
    """Write every (step, part, name, meshio mesh) as ``vtk/<name>.vtu`` and the collection
    ``vtk/contact_fields.pvd`` listing them by step and part; returns the written paths relative to ``out_dir``
    (the collection first; [] without meshes)."""
    folder = Path(out_dir) / VTK_DIR
    entries = []
    for step, part, stem, mesh in meshes:
        folder.mkdir(parents=True, exist_ok=True)
        name = f"{stem}.vtu"
        mesh.write(folder / name, file_format="vtu")
        entries.append((step, part, name))
    if not entries:
        return []
    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    parts = sorted({part for _, part, _ in entries})
    for step, part, name in entries:
        lines.append(f'    <DataSet timestep="{step}" part="{parts.index(part)}" file={quoteattr(name)}/>')
    lines += ["  </Collection>", "</VTKFile>", ""]
    (folder / PVD_FILE).write_text("\n".join(lines), encoding="utf-8")
    return [f"{VTK_DIR}/{PVD_FILE}"] + [f"{VTK_DIR}/{name}" for _, _, name in entries]


def scene_items(run) -> list[PatchFields]:
    """The patches of every pass of a contact scene run (:class:`contact.scenes.simulation.SimulationRun`), strip y
    in the scene frame; residuals summed over the layers."""
    items = []
    previous = None
    for snap in run.every_pass or [run.first]:
        total = _layer_sum(snap.residual_mm)
        added = None if total is None else total - (0.0 if previous is None else previous)
        previous = total
        y = snap.solution.strip_y_mm
        tangential = strip_rows(snap.tangential, snap.solution)
        for i, patch in enumerate(snap.solution.patches):
            def on_strips(v):
                return None if v is None else np.interp(patch.y_mm, y, v)
            items.append(PatchFields(patch, tangential[i], on_strips(total), on_strips(added), snap.number,
                                     f"patch{i}", f"pass{snap.number:03d}_patch{i}"))
    return items


def sweep_items(all_sols: list) -> list[PatchFields]:
    """The patches of every solved case and wheel of a wheel–rail sweep (``all_sols[case] = {side:
    WheelRailSolution}``, None for a failed case): the balanced solution (pass 1's normal and tangential
    solutions, strips in the patch problem's coordinate), residuals after the last pass and added by it."""
    return [item for *_, item in sweep_patches(all_sols)]


def sweep_patches(all_sols: list) -> Iterator[tuple]:
    """(case index, side, WheelRailSolution, PatchSolution, PatchFields) of every region of every loaded patch of
    a wheel–rail sweep (:func:`sweep_items`)."""
    for k, case in enumerate(all_sols):
        for side, sol in (case or {}).items():
            for i, p in enumerate(sol.patches):
                y = p.problem.strip_y_mm
                recs = [r.cumulative_residual_mm for r in p.passes]
                total = _layer_sum(recs[-1]) if recs else None
                before = _layer_sum(recs[-2]) if len(recs) > 1 else None
                added = None if total is None else total - (0.0 if before is None else before)
                tangential = strip_rows(p.tangential or [None] * len(p.normal.patches),     # [] without friction
                                        p.normal, p.eta_ref_mm)
                for r, (patch, tang) in enumerate(zip(p.normal.patches, tangential)):
                    def on_strips(v):
                        return None if v is None else np.interp(patch.y_mm, y, v)
                    part = f"{side}_patch{i}_region{r}"
                    yield k, side, sol, p, PatchFields(patch, tang, on_strips(total), on_strips(added), k, part,
                                                       f"case{k:03d}_{part}")


def _layer_sum(cumulative: dict) -> np.ndarray | None:
    """Cumulative residual displacement summed over the layers (mm), None without."""
    return np.sum([np.asarray(v, dtype=float) for v in cumulative.values()], axis=0) if cumulative else None


__all__ = ["CELL_FIELDS", "PVD_FILE", "VTK_DIR", "PatchFields", "cell_edges", "cell_fields", "patch_mesh",
           "scene_items", "sweep_items", "sweep_patches", "write_meshes", "write_series"]
