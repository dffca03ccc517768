"""Rail heads 60E1 (UIC60) and 54E1 (UIC54) (EN 13674-1) built from arcs and lines.

Frame: y lateral from the head centre line, positive towards the FIELD side, z up, crown at
(0, 0), material below; the head is symmetric in y. Construction (one side, from the crown out):
R300 about (0, -300) to y = ``y_crown_end``; tangent R80 to y = ``y_r80_end``; tangent R13 down
to its tangency with the side flank of slope 1:20 (lateral:vertical, widening downwards); R3
fillet; head underside rising outwards at 1:2.75 (vertical:lateral) from the web; web side at
|y| = 8.25 mm. Every arc centre follows from tangency (:func:`head_geometry`).

Running surface (``z(y)``) and its valid range: the R300, R80 and R13 arcs of both sides, up to
the R13/flank tangent points |y| = half head width (60E1: 36.00 mm, slope there -+20). Beyond, the
1:20 flank still is a graph z(y) but has no contact-relevant curvature; it is part of the section
outline only.

The depth of the underside/web junction (``z_web_top``) is not in profiles.md: the default values
(60E1: -51.0 mm, 54E1: -49.4 mm) are ASSUMED nominal values; they only shape the section outline
below the flank, far from contact (> 25 mm below the running surface).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wrlayer.errors import InputError
from meshes.profiles.base import Profile
from meshes.profiles.pieces import ArcPiece
from meshes.profiles.segments import Arc, Line, Segment, reversed_segment


@dataclass(frozen=True)
class RailHeadDimensions:
    """Nominal head dimensions (mm; slopes as ratios)."""

    name: str
    y_crown_end: float           # end of the R300 crown arc
    y_r80_end: float             # end of the R80 arc
    z_web_top: float             # z where the head underside meets the web side (assumed)
    r_crown: float = 300.0
    r_mid: float = 80.0
    r_corner: float = 13.0
    flank_slope: float = 1.0 / 20.0      # lateral per vertical (flank widens downwards)
    r_fillet: float = 3.0
    underside_slope: float = 1.0 / 2.75  # vertical per lateral (underside rises outwards)
    web_half_width: float = 8.25
    rail_height: float = float("nan")    # for information only
    foot_width: float = float("nan")     # for information only


DIMENSIONS_60E1 = RailHeadDimensions("60E1", 10.228, 26.0265, -51.0, rail_height=172.0, foot_width=150.0)
DIMENSIONS_54E1 = RailHeadDimensions("54E1", 10.012, 24.8635, -49.4, rail_height=159.0, foot_width=140.0)


@dataclass(frozen=True)
class HeadGeometry:
    """Key points (y, z) of the field-side (y > 0) half of a head; all arcs tangent to neighbours."""

    c_crown: np.ndarray
    p_crown_end: np.ndarray
    c_mid: np.ndarray
    p_mid_end: np.ndarray
    c_corner: np.ndarray
    p_flank_top: np.ndarray      # R13 / flank tangent point (half head width)
    p_flank_bottom: np.ndarray   # flank / R3 tangent point
    c_fillet: np.ndarray
    p_underside_out: np.ndarray  # R3 / underside tangent point
    p_web_top: np.ndarray        # underside / web corner


def head_geometry(d: RailHeadDimensions) -> HeadGeometry:
    """Arc centres and tangent points from the radii, slopes and the two listed arc ends."""
    c1 = np.array([0.0, -d.r_crown])
    p1 = np.array([d.y_crown_end, c1[1] + np.sqrt(d.r_crown**2 - d.y_crown_end**2)])
    c2 = c1 + (d.r_crown - d.r_mid) * (p1 - c1) / d.r_crown
    p2 = np.array([d.y_r80_end, c2[1] + np.sqrt(d.r_mid**2 - (d.y_r80_end - c2[0]) ** 2)])
    c3 = c2 + (d.r_mid - d.r_corner) * (p2 - c2) / d.r_mid
    n_flank = np.array([1.0, d.flank_slope]) / np.hypot(1.0, d.flank_slope)      # outward normal
    p3 = c3 + d.r_corner * n_flank
    n_under = np.array([d.underside_slope, -1.0]) / np.hypot(1.0, d.underside_slope)  # outward (down)
    w = np.array([d.web_half_width, d.z_web_top])
    # Fillet centre: r_fillet inside both the flank line (through p3) and the underside (through w).
    a = np.array([n_flank, n_under])
    rhs = np.array([n_flank @ p3 - d.r_fillet, n_under @ w - d.r_fillet])
    c4 = np.linalg.solve(a, rhs)
    p4, p5 = c4 + d.r_fillet * n_flank, c4 + d.r_fillet * n_under
    if not (p4[1] < p3[1] and p5[0] > w[0]):
        raise InputError(d.name, "head dimensions give no flank/underside between the R13 arc and the web")
    return HeadGeometry(c1, p1, c2, p2, c3, p3, p4, c4, p5, w)


def _mirror(p) -> tuple[float, float]:
    return (-float(p[0]), float(p[1]))


def _pt(p) -> tuple[float, float]:
    return (float(p[0]), float(p[1]))


class RailHead(Profile):
    """Rail head profile built from :class:`RailHeadDimensions` (see the module docstring)."""

    def __init__(self, dims: RailHeadDimensions):
        self.dims = dims
        g = self.geometry = head_geometry(dims)
        r = dims
        y3, y2, y1 = g.p_flank_top[0], g.p_mid_end[0], g.p_crown_end[0]
        pieces = [
            ArcPiece(-y3, -y2, (-g.c_corner[0], g.c_corner[1]), r.r_corner, upper=True),
            ArcPiece(-y2, -y1, (-g.c_mid[0], g.c_mid[1]), r.r_mid, upper=True),
            ArcPiece(-y1, y1, _pt(g.c_crown), r.r_crown, upper=True),
            ArcPiece(y1, y2, _pt(g.c_mid), r.r_mid, upper=True),
            ArcPiece(y2, y3, _pt(g.c_corner), r.r_corner, upper=True),
        ]
        super().__init__(dims.name, "rail", pieces)

    @property
    def head_width(self) -> float:
        """Head width (mm) between the R13/flank tangent points."""
        return 2.0 * float(self.geometry.p_flank_top[0])

    def _field_side_flank(self) -> list[Segment]:
        """Field side below the running surface, from the web top up to the R13/flank point."""
        g = self.geometry
        return [
            Line(_pt(g.p_web_top), _pt(g.p_underside_out), "side"),
            Arc(_pt(g.p_underside_out), _pt(g.p_flank_bottom), _pt(g.c_fillet), "side"),
            Line(_pt(g.p_flank_bottom), _pt(g.p_flank_top), "side"),
        ]

    def section_outline(self, depth_mm: float) -> list[Segment]:
        """Closed CCW head section cut horizontally through the web at z = -depth_mm.

        Order: web cut (left to right, "fixed"), field-side web, underside, R3, flank ("side"),
        running surface from the field side to the gauge side ("surface"), then the mirrored
        gauge-side flank, R3, underside and web ("side").
        """
        g = self.geometry
        if not depth_mm > -g.p_web_top[1]:
            raise InputError("depth_mm", f"{depth_mm} mm must exceed the depth of the head/web junction "
                                         f"{-g.p_web_top[1]:.4g} mm ({self.name})")
        w = self.dims.web_half_width
        bl, br = (-w, -float(depth_mm)), (w, -float(depth_mm))
        right = [Line(br, _pt(g.p_web_top), "side")] + self._field_side_flank()
        top = [reversed_segment(s) for s in reversed(self.surface_segments())]
        left = [_mirror_segment(s) for s in reversed(right)]
        return [Line(bl, br, "fixed")] + right + top + left


def _mirror_segment(seg: Segment) -> Segment:
    """Mirror y -> -y and reverse the direction (keeps a CCW loop CCW)."""
    if isinstance(seg, Arc):
        return Arc(_mirror(seg.end), _mirror(seg.start), _mirror(seg.centre), seg.tag)
    return Line(_mirror(seg.end), _mirror(seg.start), seg.tag)


class Rail60E1(RailHead):
    """60E1 (UIC60) rail head, EN 13674-1 nominal profile (head width 72.0 mm)."""

    def __init__(self):
        super().__init__(DIMENSIONS_60E1)


class Rail54E1(RailHead):
    """54E1 (UIC54) rail head, EN 13674-1 nominal profile (head width 70.0 mm)."""

    def __init__(self):
        super().__init__(DIMENSIONS_54E1)
