"""Pictures of section (2D, matplotlib) and local (3D, pyvista off-screen) meshes, refinement visible (mm).

- :func:`plot_section`: the triangles with the named boundaries coloured, and a close-up of the load point.
- :func:`plot_local`: the boundary facets of the 3D mesh coloured by boundary name with element edges, an
  overview with x, y, z axes ticked in mm and a close-up of the load region with scale bars (lateral and in depth,
  mm; the x = 0 symmetry face shows the refinement in depth); an x-y-z orientation triad in both.
PNG files are written atomically.
"""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import skfem
from matplotlib.collections import LineCollection

from wrlayer.plotting import save_figure

BOUNDARY_COLOURS = {"surface": "tab:red", "side": "tab:blue", "fixed": "tab:green", "symmetry": "tab:orange",
                    "end": "tab:gray"}


def _draw_section(ax, mesh: skfem.Mesh) -> None:
    ax.triplot(mesh.p[0], mesh.p[1], mesh.t.T, color="0.35", lw=0.3)
    for name, facets in mesh.boundaries.items():
        segments = mesh.p[:, mesh.facets[:, facets]].transpose(2, 1, 0)  # (n, 2 ends, (y, z))
        ax.add_collection(LineCollection(segments, colors=BOUNDARY_COLOURS.get(name, "k"), lw=1.2, label=name))


def plot_section(mesh: skfem.Mesh, profile, y0: float, path: str | os.PathLike, title: str = "",
                 zoom_mm: float | None = None) -> Path:
    """PNG of a 2D section mesh: the whole section and a close-up of +-``zoom_mm`` around (y0, z(y0))."""
    z0 = float(profile.z(y0))
    lengths = np.linalg.norm(mesh.p[:, mesh.facets[0]] - mesh.p[:, mesh.facets[1]], axis=0)
    zoom = zoom_mm or max(4.0, 15.0 * float(lengths.min()))
    inward = -1.0 if profile.body == "rail" else 1.0  # direction from the surface into the material
    window = (y0 - zoom, y0 + zoom, *sorted((z0 - 0.25 * inward * zoom, z0 + 1.25 * inward * zoom)))
    fig, (ax, close) = plt.subplots(1, 2, figsize=(13, 6), gridspec_kw={"width_ratios": [1.3, 1]})
    for axis in (ax, close):
        _draw_section(axis, mesh)
        axis.plot([y0], [z0], "k+", ms=14, mew=1.5)
        axis.set_aspect("equal")
        axis.set_xlabel("y (mm)")
        axis.set_ylabel("z (mm)")
    close.set_xlim(window[:2])
    close.set_ylim(window[2:])
    ax.indicate_inset_zoom(close, edgecolor="k")
    close.legend(loc="lower right" if profile.body == "rail" else "upper right", fontsize=8, framealpha=0.9)
    ax.set_title(title or f"{profile.name}: {mesh.nvertices} nodes, {mesh.nelements} elements")
    close.set_title(f"load point y0 = {y0:g} mm (+)")
    fig.tight_layout()
    return save_figure(fig, path)


def _boundary_polydata(mesh: skfem.Mesh):
    import pyvista

    faces, group = [], []
    names = list(mesh.boundaries)
    for k, name in enumerate(names):
        tri = mesh.facets[:, mesh.boundaries[name]].T
        faces.append(np.c_[np.full(len(tri), 3), tri])
        group.append(np.full(len(tri), k))
    poly = pyvista.PolyData(mesh.p.T.copy(), np.concatenate(faces).ravel())
    poly.cell_data["boundary"] = np.concatenate(group)
    return poly, names


def _scale_bar(plotter, pyvista, a: np.ndarray, b: np.ndarray, label: str) -> None:
    """A white scale bar from a to b (mm) with ticks at its ends and a boxed label at its middle."""
    plotter.add_mesh(pyvista.Line(a, b), color="white", line_width=6, render_lines_as_tubes=True)
    plotter.add_mesh(pyvista.PolyData(np.vstack([a, b])), color="white", point_size=14,
                     render_points_as_spheres=True)
    plotter.add_point_labels(np.array([0.5 * (a + b)]), [label], font_size=16, text_color="black",
                             shape_color="white", shape_opacity=0.85, always_visible=True, show_points=False)


def plot_local(mesh: skfem.Mesh, profile, y0: float, path: str | os.PathLike, title: str = "",
               zoom_mm: float = 10.0) -> Path:
    """PNG of a 3D local mesh: overview and close-up (+-``zoom_mm``) of the load point (0, y0, z(y0))."""
    from matplotlib.colors import ListedColormap

    from wrlayer.offscreen import offscreen_pyvista

    pyvista = offscreen_pyvista()
    poly, names = _boundary_polydata(mesh)
    cmap = ListedColormap([BOUNDARY_COLOURS.get(n, "k") for n in names])
    load = np.array([0.0, y0, float(profile.z(y0))])
    view = np.array([-1.0, 0.7, 0.8 if profile.body == "rail" else -0.8])
    plotter = pyvista.Plotter(off_screen=True, shape=(1, 2), window_size=(1600, 800), border=False)
    inward = np.array([0.0, 0.0, -1.0 if profile.body == "rail" else 1.0])  # from the surface into the material
    half = 0.5 * zoom_mm
    for col in (0, 1):
        plotter.subplot(0, col)
        plotter.add_mesh(poly, scalars="boundary", cmap=cmap, clim=(-0.5, len(names) - 0.5), show_edges=True,
                         edge_color="black", line_width=0.5, show_scalar_bar=False)
        plotter.add_mesh(pyvista.PolyData(load[None, :]), color="black", point_size=12,
                         render_points_as_spheres=True)
        plotter.view_vector(view, viewup=(0.0, 0.0, 1.0))
        plotter.add_axes(xlabel="x", ylabel="y", zlabel="z", line_width=2, viewport=(0.0, 0.0, 0.14, 0.14))
        if col == 0:  # axes with tick labels in mm around the whole mesh
            plotter.show_bounds(xtitle="x (mm)", ytitle="y (mm)", ztitle="z (mm)", location="outer",
                                ticks="outside", font_size=12, color="black", fmt="%.0f", use_3d_text=False)
            plotter.reset_camera()
            plotter.camera.zoom(0.85)  # room for the axis titles
            plotter.add_text(title or f"{profile.name}: {mesh.nvertices} nodes, {mesh.nelements} tetrahedra",
                             font_size=10)
        else:
            # scale bars of zoom_mm / 2 from the load point, lateral and into the depth, drawn just in front of
            # the x = 0 face (towards the camera) so that the mesh does not hide them
            front = np.array([-0.02 * zoom_mm, 0.0, 0.0]) - 0.01 * zoom_mm * inward
            _scale_bar(plotter, pyvista, load + front, load + front + [0.0, half, 0.0], f"{half:g} mm (y)")
            _scale_bar(plotter, pyvista, load + front, load + front + half * inward, f"{half:g} mm (depth)")
            plotter.camera.focal_point = load
            plotter.camera.position = load + 3.0 * zoom_mm * view / np.linalg.norm(view)
            plotter.add_text("load region (x = 0 is the symmetry plane)", font_size=10)
    plotter.subplot(0, 0)
    plotter.add_legend([(n, BOUNDARY_COLOURS.get(n, "k")) for n in names], bcolor="white", size=(0.16, 0.18),
                       loc="upper right")
    image = plotter.screenshot(None, return_img=True)
    plotter.close()
    fig = plt.figure(figsize=(image.shape[1] / 150, image.shape[0] / 150))
    fig.figimage(image)
    return save_figure(fig, path)


#: The meshes drawn by ``python -m meshes plots``: (profile, y0 mm, 2D h_min/h_max/refine radius mm,
#: 3D h_min/h_max/length mm/refine box half-sizes mm).
DEFAULT_PLOTS = (("60E1", 0.0), ("S1002", 0.0))
DEFAULT_2D = {"h_min": 0.3, "h_max": 5.0, "refine_radius_mm": 2.0}
DEFAULT_3D = {"h_min": 0.5, "h_max": 8.0, "length_mm": 30.0, "refine_box": (3.0, 4.0, 2.0)}


def write_default_plots(out_dir: str | os.PathLike) -> list[Path]:
    """PNG pictures of the default 2D and 3D meshes of the 60E1 rail and S1002 wheel into ``out_dir``."""
    from meshes.meshing.local_mesh import local_mesh
    from meshes.meshing.section_mesh import section_mesh
    from meshes.profiles import get_profile
    from wrlayer.atomic_write import atomic_output_dir
    from wrlayer.progress import progress

    names = []
    jobs = [(name, y0, dim) for name, y0 in DEFAULT_PLOTS for dim in (2, 3)]
    with atomic_output_dir(out_dir) as tmp:
        for name, y0, dim in progress(jobs, desc="meshes", unit="mesh"):
            profile = get_profile(name)
            if dim == 2:
                plot_section(section_mesh(profile, y0, **DEFAULT_2D), profile, y0, tmp / f"section_{name}.png")
                names.append(f"section_{name}.png")
            else:
                plot_local(local_mesh(profile, y0, **DEFAULT_3D), profile, y0, tmp / f"local_{name}.png")
                names.append(f"local_{name}.png")
    return [Path(out_dir) / n for n in names]
