"""Mesh benchmark: sizes, meshing times, element quality and geometric accuracy of the Gmsh section (2D) and
local (3D) meshes for several h_min levels (mm, s).

Geometry references: rails -- the exact area of the arc/line outline (``profile.section_area``); S1002 wheel --
the outline area by Green's theorem of the exact profile pieces (``meshes.profiles.outline_area``). 3D volume
reference: outline area x length.
"""

from __future__ import annotations

import pathlib
from functools import partial

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from benchmarks.harness import max_rss_mb, median_time, peak_memory_mb
from meshes.meshing.local_mesh import local_mesh
from meshes.meshing.mesh_quality import element_quality, mesh_measure
from meshes.profiles import get_profile, outline_area
from meshes.meshing.section_mesh import default_depth_mm, section_mesh
from wrlayer.plotting import save_figure

PROFILES = (("60E1", 0.0), ("S1002", 0.0))
SETTINGS_2D = {"h_max": 5.0, "refine_radius_mm": 2.0}
SETTINGS_3D = {"h_max": 8.0, "length_mm": 30.0, "refine_box": (3.0, 4.0, 2.0)}


def _reference_area(profile) -> float:
    depth = default_depth_mm(profile)
    if profile.body == "rail":
        return float(profile.section_area(depth))
    return float(outline_area(profile.section_outline(depth)))


def _row(kind, name, h_min, order, build, exact, repeat):
    seconds, _ = median_time(build, repeat=repeat, warmup=0)
    mesh, heap = peak_memory_mb(build)
    q = element_quality(mesh)
    return {"mesh": kind, "profile": name, "h_min_mm": h_min, "order": order, "vertices": int(mesh.nvertices),
            "nodes": int(mesh.doflocs.shape[1]), "elements": int(mesh.nelements), "time_s": seconds,
            "heap_peak_MiB": heap, "quality_min": float(q.min()), "quality_p1": float(np.percentile(q, 1)),
            "measure_rel_err": mesh_measure(mesh) / exact - 1.0}


def run(mode: str, out: pathlib.Path) -> dict:
    quick = mode == "quick"
    levels_2d = (1.0, 0.5, 0.3, 0.2) if quick else (1.0, 0.5, 0.3, 0.2, 0.1, 0.05)
    levels_3d = (1.0, 0.5, 0.3) if quick else (1.0, 0.5, 0.3, 0.2, 0.15)
    repeat = 3 if quick else 5
    rows = []
    for name, y0 in PROFILES:
        profile = get_profile(name)
        area = _reference_area(profile)
        for h in levels_2d:
            for order in (1, 2):
                rows.append(_row("2D", name, h, order, partial(
                    section_mesh, profile, y0, h, order=order, **SETTINGS_2D), area, repeat))
        for h in levels_3d:
            for order in ((1, 2) if h == levels_3d[-1] else (1,)):
                rows.append(_row("3D", name, h, order, partial(
                    local_mesh, profile, y0, h, order=order, **SETTINGS_3D), area * SETTINGS_3D["length_mm"],
                    1 if quick or h < 0.3 else repeat))
        rows.append(_row("3D no Netgen", name, 0.5, 1, partial(
            local_mesh, profile, y0, 0.5, optimize_netgen=False, **SETTINGS_3D), area * SETTINGS_3D["length_mm"],
            1 if quick else repeat))

    head = ("| mesh | profile | h_min mm | order | vertices | nodes | elements | time s | heap MiB | min quality "
            "| 1 % quality | area/volume rel. error |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    table = "".join(f"| {r['mesh']} | {r['profile']} | {r['h_min_mm']:g} | {r['order']} | {r['vertices']} | "
                    f"{r['nodes']} | {r['elements']} | {r['time_s']:.3f} | {r['heap_peak_MiB']:.1f} | "
                    f"{r['quality_min']:.3f} | {r['quality_p1']:.3f} | {r['measure_rel_err']:.2e} |\n"
                    for r in rows)
    markdown = (
        f"Load point y0 = 0 (60E1 crown, S1002 taping line). 2D: h_max {SETTINGS_2D['h_max']} mm, disc of radius "
        f"{SETTINGS_2D['refine_radius_mm']} mm at h_min; 3D: h_max {SETTINGS_3D['h_max']} mm, length "
        f"{SETTINGS_3D['length_mm']} mm, h_min box of half-sizes {SETTINGS_3D['refine_box']} mm; grading 0.3 "
        "mm/mm; default depths (rail 60 mm, wheel 40 mm). 3D meshes are optimised by Gmsh's default and Netgen "
        "optimisers (\"3D no Netgen\": without the latter, for comparison). Time: median wall time of whole "
        "meshing calls (Gmsh + conversion to scikit-fem), single thread (quick mode: median of 3 runs for 2D, "
        "one run for 3D; full: 5 runs, one below h_min 0.3 mm). Heap: tracemalloc peak of the Python side (Gmsh's "
        "native memory is not included; see the process peak RSS below). Quality: mean ratio (1 = equilateral). "
        "Area (2D) / volume (3D) error against the exact outline area (x length); order-2 elements are curved "
        "on the exact geometry.\n\n" + head + table
        + f"\nPeak resident memory of the process after the mesh runs: {max_rss_mb():.0f} MiB.\n")

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for kind, marker in (("2D", "o"), ("3D", "s")):
        for name, _ in PROFILES:
            sel = [r for r in rows if r["mesh"] == kind and r["profile"] == name and r["order"] == 1]
            a1.loglog([r["h_min_mm"] for r in sel], [r["vertices"] for r in sel], marker=marker,
                      label=f"{kind} {name}")
            a2.loglog([r["vertices"] for r in sel], [r["time_s"] for r in sel], marker=marker,
                      label=f"{kind} {name}")
    a1.set(xlabel="h_min (mm)", ylabel="vertices", title="mesh size vs h_min (order 1)")
    a2.set(xlabel="vertices", ylabel="meshing time (s)", title="meshing time (median)")
    for ax in (a1, a2):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    fig_path = out / "meshes_sizes_times.png"
    save_figure(fig, fig_path)
    return {"title": "Meshes: Gmsh section (2D) and local (3D) meshes", "markdown": markdown,
            "figures": [str(fig_path)], "data": {"rows": rows, "max_rss_MiB": max_rss_mb()}}
