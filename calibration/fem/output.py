"""Output of an FE state: VTK (.vtu via meshio) and off-screen PNG renders (pyvista) around the load.

Points are written in physical 3D coordinates: 3D meshes as (x, y, z), plane-strain meshes (y, z) as (0, y, z).
Point data: displacement_mm (3 components, physical order). Cell data (element averages of the quadrature-point
values): stress_MPa (3x3 tensor, physical (x, y, z) order; in plane strain sigma_xx is the out-of-plane stress),
von_mises_MPa, eq_plastic_strain, plastic (1 where any quadrature point has yielded). Field data: p0_MPa (the
load level). :class:`FieldSeries` writes a whole load path as a ParaView time series (.pvd). Files are written
atomically.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from dataclasses import field as dataclass_field
from pathlib import Path

import meshio
import numpy as np

from calibration.fem.material import mandel_to_tensor, von_mises_MPa
from wrlayer.atomic_write import atomic_write_bytes, atomic_write_text

# plane strain: tensor indices (0, 1, 2) = (y, z, x) -> physical order (x, y, z)
_PLANE_TO_PHYSICAL = np.array([2, 0, 1])


def _write_via_temp(path: Path, writer) -> Path:
    """Call ``writer(tmp_path)`` in a scratch folder and move the bytes into ``path`` atomically."""
    with tempfile.TemporaryDirectory() as tmp:
        tmp_path = Path(tmp) / path.name
        writer(str(tmp_path))
        return atomic_write_bytes(path, tmp_path.read_bytes())


def cell_fields(disc, state, material) -> dict[str, np.ndarray]:
    """Element-averaged stress tensor (n_el, 3, 3), von Mises, eq. plastic strain and plastic flag."""
    stress = state.stress_MPa if state.stress_MPa is not None else np.zeros(state.plastic_strain.shape)
    w = disc.dx / disc.dx.sum(axis=1, keepdims=True)
    sig = np.einsum("eq,eqi->ei", w, stress)
    tensor = mandel_to_tensor(sig)
    if disc.plane_strain:
        tensor = tensor[:, _PLANE_TO_PHYSICAL][:, :, _PLANE_TO_PHYSICAL]
    return {"stress_MPa": tensor.reshape(-1, 9),
            "von_mises_MPa": np.einsum("eq,eq->e", w, von_mises_MPa(stress)),
            "eq_plastic_strain": np.einsum("eq,eq->e", w, state.eq_plastic_strain),
            "plastic": (state.eq_plastic_strain > 0).any(axis=1).astype(np.int8)}


def to_meshio(disc, state, material) -> meshio.Mesh:
    """Linear-cell meshio mesh (vertices only) with the displacement and cell fields."""
    mesh = disc.mesh
    dim = mesh.dim()
    nodal = disc.basis.nodal_dofs  # (dim, n_vertices)
    nv = nodal.shape[1]
    pts = np.zeros((nv, 3))
    disp = np.zeros((nv, 3))
    if dim == 3:
        pts[:] = mesh.p[:, :nv].T
        disp[:] = state.u_mm[nodal].T
    else:
        pts[:, 1:] = mesh.p[:, :nv].T
        disp[:, 1:] = state.u_mm[nodal].T
    cells = [("tetra" if dim == 3 else "triangle", mesh.t[:dim + 1].T)]
    fields = cell_fields(disc, state, material)
    return meshio.Mesh(pts, cells, point_data={"displacement_mm": disp},
                       cell_data={k: [v] for k, v in fields.items()},
                       field_data={"p0_MPa": np.array([state.p0_MPa])})  # the load level (ParaView: FieldData)


def write_vtu(path: str | os.PathLike, disc, state, material) -> Path:
    """Write the state as a .vtu file (atomic), with the load level p0_MPa as FieldData (written through VTK:
    meshio's .vtu writer drops field data)."""
    import pyvista as pv

    m = to_meshio(disc, state, material)
    grid = pv.from_meshio(m)
    for name, value in m.field_data.items():
        grid.field_data[name] = value
    return _write_via_temp(Path(path), lambda p: grid.save(p, binary=True))


@dataclass
class FieldSeries:
    """The FE fields along a load path as a ParaView time series: ``<folder>/<stem>_NNN.vtu``, one per converged
    load level (loading and unloading), and ``<folder>/<stem>.pvd`` listing them.

    ParaView's time is the step number along the path (0, 1, 2, ...; the pressure goes up and down, so it cannot
    be the time); the load level p0 (MPa, peak Hertz pressure) of each step is in the file's FieldData
    ``p0_MPa`` (shown by ParaView's "Annotate Global Data" filter) and in a comment of the .pvd. Use as the
    ``on_level`` callback of :func:`calibration.fem.elastoplastic_solver.solve_load_path`; call :meth:`write_pvd`
    at the end.
    """

    folder: Path
    material: object
    stem: str = "load_path"
    steps: list = dataclass_field(default_factory=list)

    def __call__(self, disc, state, prepared=None) -> Path:
        path = write_vtu(Path(self.folder) / f"{self.stem}_{len(self.steps):03d}.vtu", disc, state, self.material)
        self.steps.append((float(state.p0_MPa), path))
        return path

    def write_pvd(self) -> Path:
        """Write ``<stem>.pvd`` (atomic); returns its path."""
        rows = "\n".join(f'    <DataSet timestep="{i}" part="0" file="{path.name}"/>  <!-- p0 = {p0:.6g} MPa -->'
                         for i, (p0, path) in enumerate(self.steps))
        text = ('<?xml version="1.0"?>\n<!-- FE fields along the load path (units mm, MPa); timestep = step number, '
                'the load level p0_MPa is in each file\'s FieldData -->\n'
                '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n  <Collection>\n'
                f"{rows}\n  </Collection>\n</VTKFile>\n")
        return atomic_write_text(Path(self.folder) / f"{self.stem}.pvd", text)


def _scale_length(h: float) -> float:
    """A round length (1, 2 or 5 x 10^k mm) of about half the box half-width, for the scale bar."""
    target = 0.5 * h
    k = 10.0 ** np.floor(np.log10(target))
    return float(max(m * k for m in (1.0, 2.0, 5.0) if m * k <= target))


@dataclass(frozen=True)
class ViewFrame:
    """Where the 3D picture looks from (mm): camera position, focal point, view-up (the surface's outward normal,
    so the loaded surface is at the top of every picture, rail or wheel), the "symmetry plane" label (inside the
    body) and the scale bar's two ends (on the surface, across the rolling direction)."""

    camera: np.ndarray
    focal: np.ndarray
    up: np.ndarray
    label: np.ndarray
    bar: tuple[np.ndarray, np.ndarray]


def view_frame(centre_mm, normal_out, half_width_mm: float, bar_mm: float) -> ViewFrame:
    """The :class:`ViewFrame` of a 3D load point ``centre_mm`` with outward unit normal ``normal_out`` (x, y, z): seen
    from the -x side (the symmetry plane x = 0), from outside the body, 2 h along the lateral direction t = e_x x n
    and 1.6 h along n (h = half_width_mm). For n = +z (the rail crown) t = -y."""
    c = np.asarray(centre_mm, dtype=float)
    n = np.asarray(normal_out, dtype=float)
    n = n / np.linalg.norm(n)
    ex = np.array([1.0, 0.0, 0.0])
    t = np.cross(ex, n)
    t = t / np.linalg.norm(t)
    h = float(half_width_mm)
    start = c + 0.9 * h * t + 0.05 * h * n
    return ViewFrame(camera=c - 3.0 * h * ex + 2.0 * h * t + 1.6 * h * n, focal=c - 0.3 * h * n, up=n,
                     label=c - 0.6 * h * t - 0.8 * h * n, bar=(start, start - bar_mm * t))


def render_png(path: str | os.PathLike, disc, state, material, field: str, centre_mm, half_width_mm: float,
               title: str = "", normal_out=None) -> Path:
    """Off-screen pyvista render of a cell field in a box of half width ``half_width_mm`` around the centre.

    3D: the half model is cut smoothly by the box (clipped cells, not whole jagged elements) and seen obliquely
    from the -x side and from outside the loaded surface (``normal_out``, the outward normal at the centre; default
    +z), which is at the top of the picture for the rail and the wheel alike, so that the symmetry plane x = 0 (a
    section through the plastic zone, outlined and labelled) and the loaded surface are visible
    (:func:`view_frame`); a scale bar gives the length in mm and the colour bar sits below the model. 2D: the
    zoomed section (camera along x) with the same scale bar and colour bar.
    """
    from wrlayer.offscreen import offscreen_pyvista

    pv = offscreen_pyvista()
    grid = pv.from_meshio(to_meshio(disc, state, material))
    c = np.zeros(3)
    if centre_mm is not None:
        c[3 - len(centre_mm):] = centre_mm
    h = half_width_mm
    bounds = [c[0] - h, c[0] + h, c[1] - h, c[1] + h, c[2] - h, c[2] + h]
    if disc.plane_strain:
        bounds[0:2] = [-1.0, 1.0]
        centres = grid.cell_centers().points
        inside = np.all((centres >= np.array(bounds[0::2]) - 1e-12)
                        & (centres <= np.array(bounds[1::2]) + 1e-12), axis=1)
        part = grid.extract_cells(np.nonzero(inside)[0])
    else:
        # smooth: element averages interpolated to the vertices (no faceted element pattern)
        part = grid.clip_box(bounds, invert=False, crinkle=False).cell_data_to_point_data()
    plotter = pv.Plotter(off_screen=True, window_size=(1000, 800))
    label = {"von_mises_MPa": "von Mises stress (MPa)", "eq_plastic_strain": "equivalent plastic strain"}[field]
    plotter.add_mesh(part, scalars=field, cmap="viridis", show_edges=False,
                     scalar_bar_args={"title": label, "vertical": False, "position_x": 0.2, "position_y": 0.03,
                                      "width": 0.6, "height": 0.06, "title_font_size": 14, "label_font_size": 12,
                                      "fmt": "%.3g"})
    plotter.add_text(title or label, font_size=11, position="upper_edge")
    L = _scale_length(h)
    if disc.plane_strain:
        p0 = np.array([0.0, c[1] - 0.9 * h, c[2] - 0.9 * h])
        p1 = p0 + np.array([0.0, L, 0.0])
    else:
        frame = view_frame(c, (0.0, 0.0, 1.0) if normal_out is None else normal_out, h, L)
        p0, p1 = frame.bar
        # the symmetry plane x = 0 through the load centre: outline of its part in the box, labelled
        sym = part.slice(normal="x", origin=(c[0] + 1e-6 * h, c[1], c[2]))
        if sym.n_points:
            plotter.add_mesh(sym.extract_feature_edges(boundary_edges=True, feature_edges=False,
                                                       manifold_edges=False), color="white", line_width=3)
            plotter.add_point_labels([frame.label], ["symmetry plane x = 0"], font_size=12, text_color="black",
                                     shape_opacity=0.6, always_visible=True)
    plotter.add_mesh(pv.Line(p0, p1), color="red", line_width=5)
    plotter.add_point_labels([0.5 * (p0 + p1)], [f"{L:g} mm"], font_size=14, text_color="black",
                             shape_opacity=0.6, always_visible=True)
    if disc.plane_strain:
        plotter.view_yz()
    else:
        plotter.camera_position = [tuple(frame.camera), tuple(frame.focal), tuple(frame.up)]
    plotter.show_axes()
    out = _write_via_temp(Path(path), lambda p: plotter.screenshot(p))
    plotter.close()
    return out


def plastic_zone_half_width(disc, state, centre_mm, minimum_mm: float) -> float:
    """Half width (mm) of a box around the centre containing all yielded points (x1.5), at least ``minimum_mm``."""
    yielded = state.eq_plastic_strain > 0
    if centre_mm is None or not yielded.any():
        return minimum_mm
    x = disc.qp_coordinates()[:, yielded]
    d = np.max(np.abs(x - np.asarray(centre_mm)[:, None]))
    return max(minimum_mm, 1.5 * float(d))


def write_increment_output(disc, state, material, prepared, out_dir: Path, index: int,
                           minimum_half_width_mm: float | None = None, label: str = "") -> list[Path]:
    """VTK and two PNGs (von Mises, equivalent plastic strain) for level ``index`` into ``out_dir``; ``label``
    (e.g. body, profile and position) heads the pictures' titles."""
    out_dir = Path(out_dir)
    stem = f"level_{index:03d}"
    files = [write_vtu(out_dir / f"{stem}.vtu", disc, state, material)]
    size = float(np.max(np.ptp(disc.mesh.p, axis=1)))
    hw = plastic_zone_half_width(disc, state, prepared.centre_mm, minimum_half_width_mm or 0.1 * size)
    names = {"von_mises_MPa": "von Mises stress", "eq_plastic_strain": "equivalent plastic strain"}
    for field, tag in (("von_mises_MPa", "von_mises"), ("eq_plastic_strain", "eq_plastic_strain")):
        title = f"{label + ': ' if label else ''}{names[field]} at p0 = {state.p0_MPa:.0f} MPa"
        files.append(render_png(out_dir / f"{stem}_{tag}.png", disc, state, material, field, prepared.centre_mm,
                                hw, title, normal_out=prepared.normal_out))
    return files
