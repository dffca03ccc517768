"""3D local meshes with a core structured in all three directions around the load point (mm).

The core block, 0 <= x <= core.length_mm over a curvilinear quadrilateral of the section (y, z): bounded by the
running surface over |s| <= half_width_mm (s: arc length along the profile from the load point y0), the curve
offset by depth_mm along the inward normal, and the two normals at s = -half_width_mm and s = +half_width_mm. Its
section is meshed transfinite (``cells_s`` cells along s, ``cells_depth`` along the normal, growing by
``depth_progression`` away from the surface; each quadrilateral split into two triangles, diagonals alternating)
and extruded along x in ``layers`` equal structured layers (each prism split into three tetrahedra by Gmsh): its
nodes lie on the normals at s_i, at the depths d_k, on the planes x_j. Everything else -- the rest of the section
over 0 <= x <= core.length_mm and the whole section beyond -- is unstructured tetrahedra (Gmsh Delaunay, Netgen
optimiser) conforming to the core, of size h + grading * (distance from the core block) up to h_max, with
h = StructuredCore.h_mm. Refining the core moves its nodes smoothly, which an unstructured triangulation around
the load point does not (docs/calibration.md, "Mesh styles").

Boundaries as in the other local meshes: "surface", "side", "fixed" (the far cut, extruded), "symmetry" (x = 0)
and "end" (x = length_mm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import skfem

from wrlayer.errors import require
from meshes.meshing.gmsh_outline import check_outline, min_radius, segment_points
from meshes.meshing.gmsh_session import generate, gmsh_session
from meshes.meshing.gmsh_to_skfem import gmsh_to_skfem
from meshes.meshing.mesh_size import curvature_size, set_background_size
from meshes.meshing.section_mesh import DEFAULT_GRADING, check_mesh_inputs, check_quality, default_depth_mm
from meshes.profiles.base import Arc, Line, PointCurve

#: Largest number of cells in any structured direction (a guard against typing errors).
MAX_CELLS = 200
#: Points per structured cell of the spline that carries the core's surface and offset curves.
SPLINE_POINTS_PER_CELL = 8
#: Cut points closer than this (mm) to a segment end are moved onto it (no sliver segments).
SNAP_MM = 1e-6


def graded_nodes(length: float, cells: int, ratio: float) -> np.ndarray:
    """Node offsets 0 .. length (mm) of ``cells`` cells, each ``ratio`` times the previous one."""
    sizes = float(ratio) ** np.arange(cells)
    return float(length) * np.r_[0.0, np.cumsum(sizes)] / np.sum(sizes)


@dataclass(frozen=True)
class StructuredCore:
    """The structured core (mm): half-width along the surface arc, depth along the inward normal, length along x;
    cell counts along s (total over the width, even: a node line through the load point), the depth and x;
    s_progression, depth_progression, x_progression: ratio of successive cells away from the load point (s: from
    s = 0 outwards, depth: from the surface, x: from the plane x = 0); 1 = equal cells."""

    half_width_mm: float
    depth_mm: float
    length_mm: float
    cells_s: int
    cells_depth: int
    layers: int
    s_progression: float = 1.0
    depth_progression: float = 1.0
    x_progression: float = 1.0

    def __post_init__(self):
        for name in ("half_width_mm", "depth_mm", "length_mm"):
            v = getattr(self, name)
            require(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0,
                    f"core.{name}", f"must be a positive number of mm, got {v!r}")
        for name in ("cells_s", "cells_depth", "layers"):
            v = getattr(self, name)
            require(isinstance(v, (int, np.integer)) and not isinstance(v, bool) and 1 <= v <= MAX_CELLS,
                    f"core.{name}", f"must be an integer in [1, {MAX_CELLS}], got {v!r}")
        require(self.cells_s % 2 == 0, "core.cells_s", f"must be even (a node line at s = 0), got {self.cells_s}")
        for name in ("s_progression", "depth_progression", "x_progression"):
            p = getattr(self, name)
            require(isinstance(p, (int, float)) and not isinstance(p, bool) and math.isfinite(p) and 0.5 <= p <= 2.0,
                    f"core.{name}", f"must lie in [0.5, 2], got {p!r}")

    def s_nodes(self) -> np.ndarray:
        """Arc lengths (mm) of the node columns from the load point, -half_width_mm .. half_width_mm."""
        half = graded_nodes(self.half_width_mm, self.cells_s // 2, self.s_progression)
        return np.r_[-half[:0:-1], half]

    def depth_nodes(self) -> np.ndarray:
        """Depths (mm) of the node rows below the surface, 0 .. depth_mm."""
        return graded_nodes(self.depth_mm, self.cells_depth, self.depth_progression)

    def x_nodes(self) -> np.ndarray:
        """x (mm) of the layer planes, 0 .. length_mm."""
        return graded_nodes(self.length_mm, self.layers, self.x_progression)

    @property
    def h_mm(self) -> float:
        """The rest's smallest element size (mm): the smallest of the core's outermost cells."""
        return float(min(np.diff(self.s_nodes())[-1], np.diff(self.depth_nodes())[-1], np.diff(self.x_nodes())[-1]))


def core_for_contact(a_mm: float, b_mm: float, n: float, width_factor: float = 1.2, depth_factor: float = 1.0,
                     length_factor: float = 1.2) -> StructuredCore:
    """The core for a Hertz patch of semi-axes a (along x) and b (along the surface, mm) with about n cells per
    semi-axis: |s| <= width_factor b, depth depth_factor b, 0 <= x <= length_factor a; equal cells of at most
    b / n along s and in depth, layers of at most a / n along x."""
    n = float(n)
    require(math.isfinite(n) and n > 0, "n", f"must be a positive number, got {n!r}")
    half, depth, length = width_factor * b_mm, depth_factor * b_mm, length_factor * a_mm
    return StructuredCore(half, depth, length, cells_s=2 * max(1, math.ceil(half * n / b_mm - 1e-9)),
                          cells_depth=max(1, math.ceil(depth * n / b_mm - 1e-9)),
                          layers=max(1, math.ceil(length * n / a_mm - 1e-9)))


def _trim(seg, start, end):
    """The part of a surface segment between two of its points (start, end: (y, z) on it, in its direction)."""
    start, end = (float(start[0]), float(start[1])), (float(end[0]), float(end[1]))
    if isinstance(seg, Arc):
        return Arc(start, end, seg.centre, seg.tag)
    if isinstance(seg, Line):
        return Line(start, end, seg.tag)
    pts = segment_points(seg)
    d = np.sign(pts[-1, 0] - pts[0, 0])
    lo, hi = sorted((start[0] * d, end[0] * d))
    inner = pts[1:-1][(pts[1:-1, 0] * d > lo + 1e-6) & (pts[1:-1, 0] * d < hi - 1e-6)]
    return PointCurve(np.vstack([start, inner, end]), seg.tag)


def split_outline(profile, outline, y0: float, half_width_mm: float):
    """Cut the window |s - s(y0)| <= half_width_mm out of the outline's surface segments.

    Returns (segments before the window, y at the window's entry, y at its exit, segments after), in the
    outline's order (the window lies between the two lists; the rest of the section runs around it)."""
    check_outline(outline)
    s0 = float(profile.arc_length(y0))
    surf = [i for i, seg in enumerate(outline) if seg.tag == "surface"]
    first = segment_points(outline[surf[0]])
    direction = 1.0 if first[-1, 0] > first[0, 0] else -1.0  # traversal along increasing (1) or decreasing y
    s_lo, s_hi = s0 - half_width_mm, s0 + half_width_mm
    require(s_lo >= 0.0 and s_hi <= profile.length, "core.half_width_mm",
            f"the core |s| <= {half_width_mm:.3g} mm around y0 = {y0:g} mm runs past the end of the profile "
            f"{profile.name}")
    y_lo, y_hi = (float(v) for v in profile.y_at_arc_length([s_lo, s_hi]))
    y_in, y_out = (y_lo, y_hi) if direction > 0 else (y_hi, y_lo)
    p_in, p_out = (y_in, float(profile.z(y_in))), (y_out, float(profile.z(y_out)))
    key = (lambda y: direction * y)
    before, after, found = [], [], False
    for i, seg in enumerate(outline):
        if seg.tag != "surface":
            (after if found else before).append(seg)
            continue
        pts = segment_points(seg)
        a, b = key(pts[0, 0]), key(pts[-1, 0])
        k_in, k_out = key(y_in), key(y_out)
        if b <= k_in + SNAP_MM:          # entirely before the window
            (after if found else before).append(seg)
            continue
        if a >= k_out - SNAP_MM:         # entirely after it
            found = True
            after.append(seg)
            continue
        if a < k_in - SNAP_MM:           # starts before: keep up to the entry
            before.append(_trim(seg, pts[0], p_in))
        if b > k_out + SNAP_MM:          # ends after: keep from the exit
            after.append(_trim(seg, p_out, pts[-1]))
        found = True
    require(found, "y0", f"{y0:g} mm: no surface segment of the outline contains the load point")
    return before, y_in, y_out, after


def _spline_points(profile, s_mm: np.ndarray, offset_mm: float = 0.0) -> np.ndarray:
    """Points (y, z) on the profile (offset_mm along the inward normal) at the arc lengths s_mm and
    SPLINE_POINTS_PER_CELL - 1 equally spaced ones inside each interval: row i * SPLINE_POINTS_PER_CELL is s_mm[i]."""
    per = SPLINE_POINTS_PER_CELL
    s = np.r_[np.concatenate([np.linspace(s_mm[i], s_mm[i + 1], per + 1)[:-1] for i in range(len(s_mm) - 1)]),
              s_mm[-1]]
    y = profile.y_at_arc_length(s)
    pts = np.column_stack([y, profile.z(y)])
    if offset_mm:
        pts = pts - offset_mm * profile.normal(y)  # normal() points out of the material
    return pts


def _size_fields(gmsh, h: float, h_max: float, grading: float, core_entities: tuple[str, list[int]],
                 curved: list[tuple[float, list[int]]]) -> None:
    """Background size: min(h_max, h + grading * distance from the core's boundary entities), limited on curved
    boundary surfaces to 2 pi R / ELEMENTS_PER_2PI."""
    field = gmsh.model.mesh.field
    dist = field.add("Distance")
    field.setNumbers(dist, core_entities[0], core_entities[1])
    field.setNumber(dist, "Sampling", 60)
    graded = field.add("MathEval")
    field.setString(graded, "F", f"Min({float(h_max)!r}, {float(h)!r} + {float(grading)!r} * F{dist})")
    set_background_size([graded], [(curvature_size(radius, h, h_max), "SurfacesList", tags) for radius, tags in curved],
                        h, h_max)


@dataclass(frozen=True)
class _Window:
    """The core's window in the section outline: the outline before and after it, and the spline points of its
    top (on the surface) and bottom (core.depth_mm along the inward normal) curves, (y, z) in mm."""

    before: list
    after: list
    top: np.ndarray
    bottom: np.ndarray


def _window(profile, y0: float, core: StructuredCore, depth_mm: float) -> _Window:
    """The section outline split around the core (InputError when the offset curve would fold)."""
    outline = profile.section_outline(float(depth_mm))
    before, y_in, y_out, after = split_outline(profile, outline, float(y0), core.half_width_mm)
    s_in, s_out = (float(v) for v in profile.arc_length([y_in, y_out]))
    s_nodes = float(profile.arc_length(y0)) + np.sign(s_out - s_in) * core.s_nodes()
    s_nodes[0], s_nodes[-1] = s_in, s_out
    top = _spline_points(profile, s_nodes)
    bottom = _spline_points(profile, s_nodes, offset_mm=core.depth_mm)
    top[0], top[-1] = (y_in, profile.z(y_in)), (y_out, profile.z(y_out))
    # the offset curve must stay inside the section and must not fold (offset beyond the radius of curvature)
    kappa = np.abs(profile.curvature(top[:, 0]))
    require(np.all(core.depth_mm * kappa < 0.8), "core.depth_mm",
            f"{core.depth_mm:.3g} mm is close to the surface's radius of curvature {1 / np.max(kappa):.3g} mm")
    return _Window(before, after, top, bottom)


def _point(geo, p) -> int:
    return geo.addPoint(float(p[0]), float(p[1]), 0.0)


def _curve(geo, seg, start: int, end: int) -> int:
    if isinstance(seg, Arc):
        return geo.addCircleArc(start, _point(geo, seg.centre), end)
    if isinstance(seg, PointCurve):
        return geo.addSpline([start, *[_point(geo, q) for q in segment_points(seg)[1:-1]], end])
    return geo.addLine(start, end)


@dataclass(frozen=True)
class _Section:
    """The section's two plane surfaces (Gmsh tags): the structured core and the rest, with the boundary names and
    smallest radii (mm) of the rest's curves in loop order."""

    core_surface: int
    rest: int
    rest_names: list[str]
    rest_radii: list[float]


def _section(geo, profile, y0: float, core: StructuredCore, win: _Window) -> _Section:
    """The core (transfinite) and the rest of the section as plane surfaces in Gmsh's built-in kernel."""
    before, after, top, bottom = win.before, win.after, win.top, win.bottom
    # the rest's loop: before ... -> P_in, down the entry normal to Q_in, along the offset curve to Q_out, up
    # the exit normal to P_out -> after ...; the outline is closed, so after[-1] ends where before[0] starts
    require(before and after, "y0", f"{y0:g} mm: the core must not contain the outline's first point")
    require(np.allclose(segment_points(after[0])[0], top[-1], atol=1e-6)
            and np.allclose(segment_points(before[-1])[-1], top[0], atol=1e-6), "outline",
            "the outline around the core does not meet its entry and exit points")
    # one spline per structured cell along s: the nodes sit exactly at s_i on the surface and at the same s_i
    # on the offset curve, so that every column of the core lies on the normal at s_i
    per = SPLINE_POINTS_PER_CELL
    top_nodes = [_point(geo, top[i * per]) for i in range(core.cells_s + 1)]
    bottom_nodes = [_point(geo, bottom[i * per]) for i in range(core.cells_s + 1)]
    top_curves = [geo.addSpline([top_nodes[i], *[_point(geo, q) for q in top[i * per + 1:(i + 1) * per]],
                                 top_nodes[i + 1]]) for i in range(core.cells_s)]
    bottom_curves = [geo.addSpline([bottom_nodes[i], *[_point(geo, q) for q in bottom[i * per + 1:(i + 1) * per]],
                                    bottom_nodes[i + 1]]) for i in range(core.cells_s)]
    p_in, p_out, q_in, q_out = top_nodes[0], top_nodes[-1], bottom_nodes[0], bottom_nodes[-1]
    starts_b = [_point(geo, segment_points(s)[0]) for s in before]
    starts_a = [p_out] + [_point(geo, segment_points(s)[0]) for s in after[1:]]
    depths = core.depth_nodes()

    def side(k):  # the normal at the window's entry (k = 0) or exit (-1), split at the depth nodes
        y = float(top[k][0])
        pts = [top_nodes[k]] + [_point(geo, top[k] - d * profile.normal(y)) for d in depths[1:-1]]
        pts.append(bottom_nodes[k])
        return [geo.addLine(pts[j], pts[j + 1]) for j in range(len(pts) - 1)]

    side_in = side(0)                                   # P_in -> Q_in
    side_out = [-c for c in side(-1)[::-1]]             # Q_out -> P_out (signed tags)
    rest_curves = [_curve(geo, seg, starts_b[i], starts_b[i + 1] if i + 1 < len(before) else p_in)
                   for i, seg in enumerate(before)]
    rest_curves += [*side_in, *bottom_curves, *side_out]
    rest_curves += [_curve(geo, seg, starts_a[i], starts_a[i + 1] if i + 1 < len(after) else starts_b[0])
                    for i, seg in enumerate(after)]
    n_window = core.cells_s + 2 * core.cells_depth
    rest_names = [s.tag for s in before] + ["core"] * n_window + [s.tag for s in after]
    rest_radii = [min_radius(s) for s in before] + [math.inf] * n_window + [min_radius(s) for s in after]
    rest = geo.addPlaneSurface([geo.addCurveLoop(rest_curves)])
    core_loop = geo.addCurveLoop([*top_curves, *[-c for c in side_out[::-1]], *[-c for c in bottom_curves[::-1]],
                                  *[-c for c in side_in[::-1]]])
    core_surface = geo.addPlaneSurface([core_loop])
    for c in top_curves + bottom_curves + side_in + side_out:
        geo.mesh.setTransfiniteCurve(abs(c), 2)
    geo.mesh.setTransfiniteSurface(core_surface, "Alternate", [p_in, p_out, q_out, q_in])
    return _Section(core_surface, rest, rest_names, rest_radii)


def _extrude(gmsh, core: StructuredCore, sec: _Section, length: float):
    """The section extruded over 0 <= x <= length (the core in structured layers up to core.length_mm); returns
    the physical groups {name: surface tags}, the curved surfaces [(radius in mm, tags)] and the faces the size
    grows away from (the core block's inner lateral faces and its end face)."""
    geo = gmsh.model.geo
    # extrude: per input surface [far end, volume, one lateral surface per boundary curve in loop order]
    # the core in structured layers; the rest unstructured over the same length (Gmsh reuses the core's
    # lateral faces on the common boundary, so the two conform)
    first = geo.extrude([(2, sec.core_surface)], 0.0, 0.0, core.length_mm, numElements=[1] * core.layers,
                        heights=(core.x_nodes()[1:] / core.length_mm).tolist())
    first += geo.extrude([(2, sec.rest)], 0.0, 0.0, core.length_mm)
    n_core = 2 + 2 * core.cells_s + 2 * core.cells_depth
    core_top, core_lat = first[0], [t for _, t in first[2:n_core]]
    rest_top, rest_lat = first[n_core], [t for _, t in first[n_core + 2:]]
    second = geo.extrude([core_top, rest_top], 0.0, 0.0, length - core.length_mm)
    core_top2, core_lat2 = second[0], [t for _, t in second[2:n_core]]
    rest_top2, rest_lat2 = second[n_core], [t for _, t in second[n_core + 2:]]
    geo.synchronize()
    m = core.cells_s
    groups = {"surface": core_lat[:m] + core_lat2[:m], "side": [], "fixed": []}
    curved = []
    for lat in (rest_lat, rest_lat2):
        for tag, name, radius in zip(lat, sec.rest_names, sec.rest_radii):
            if name in groups:
                groups[name].append(tag)
                if math.isfinite(radius):
                    curved.append((radius, [tag]))
    groups.update(symmetry=[sec.core_surface, sec.rest], end=[core_top2[1], rest_top2[1]])
    return groups, curved, core_lat[m:] + [core_top[1]]


def structured_core_local_mesh(profile, y0: float, core: StructuredCore, h_max: float, length_mm: float,
                               depth_mm: float | None = None, order: int = 1,
                               grading: float = DEFAULT_GRADING) -> skfem.Mesh:
    """Tetrahedral mesh (mm) of the section over 0 <= x <= length_mm with a core structured along the surface,
    the normal and x around the load point (y0, z(y0)) (module docstring). h_max: largest element size (mm);
    depth_mm: section depth (default by body). Returns ``MeshTet1`` (order 1) or ``MeshTet2`` (order 2)."""
    require(isinstance(core, StructuredCore), "core", f"must be a StructuredCore, got {type(core).__name__}")
    depth_mm = default_depth_mm(profile) if depth_mm is None else depth_mm
    h = core.h_mm
    z0 = check_mesh_inputs(profile, y0, h, max(float(h_max), h), depth_mm, order, grading)
    h_max = max(float(h_max), h)
    length = float(length_mm)
    require(math.isfinite(length) and length > core.length_mm + h, "length_mm",
            f"must exceed the core length + h = {core.length_mm + h:.3g} mm, got {length_mm!r}")
    room = depth_mm + z0 if profile.body == "rail" else depth_mm - z0
    require(core.depth_mm <= 0.5 * room, "core.depth_mm",
            f"{core.depth_mm:.3g} mm is more than half the {room:.3g} mm of material below the load point")
    win = _window(profile, y0, core, depth_mm)
    with gmsh_session("structured") as gmsh:
        sec = _section(gmsh.model.geo, profile, y0, core, win)
        groups, curved, grow_from = _extrude(gmsh, core, sec, length)
        _size_fields(gmsh, h, h_max, grading, ("SurfacesList", grow_from), curved)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.Algorithm3D", 1)
        gmsh.option.setNumber("Mesh.Optimize", 1)
        gmsh.option.setNumber("Mesh.OptimizeNetgen", 1)
        generate(3, order)
        mesh = gmsh_to_skfem(3, groups, axes=[2, 0, 1])
    return check_quality(mesh)
