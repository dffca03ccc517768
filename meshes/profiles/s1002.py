"""The S1002 wheel profile (EN 13715), piecewise analytic definition, sections A..H.

Frame: y = S (mm), 0 at the taping line, positive towards the field side, flange at negative y;
z = -F(S) (mm, z up, the flange hangs down); material above the curve; rolling radius
r(y) = r0 - z(y). Coefficients from ``../shared/reference/profiles.md`` (beside the repository).

Valid range: y in [-70, +60] mm by default. At the flange back y = -70 the section-H arc is
vertical, so ``dz``/``d2z`` return -inf/-inf exactly there (normal, curvature and arc length are
evaluated from the circle and stay finite). Pass ``y_min > -70`` if finite slopes are needed
everywhere (e.g. ``y_min=-69.9``: slope -12.8).
"""

from __future__ import annotations

import dataclasses

from wrlayer.errors import InputError
from meshes.profiles.base import Profile
from meshes.profiles.pieces import ArcPiece, line_piece, poly_piece

# EN 13715 S1002 coefficients (profiles.md).
AA, BA = 1.364323640, 0.066666667
AB, BB, CB, DB, EB = 0.0, 3.358537058e-02, 1.565681624e-03, 2.810427944e-05, 5.844240864e-08
FB, GB, HB, IB = 1.562379023e-08, 5.309217349e-15, 5.957839843e-12, 2.646656573e-13
AC, BC, CC, DC = 4.320221063e03, 1.038384026e03, 1.065501873e02, 6.051367875
EC, FC, GC, HC = 2.054332446e-01, 4.169739389e-03, 4.687195829e-05, 2.252755540e-07
AD, BD, CD = 16.446, 13.0, 26.210665
AE, BE = 93.576667419, 2.747477419
AF, BF, CF = 8.834924130, 20.0, 58.558326413
AG, BG, CG = 16.0, 12.0, 55.0
AH, BH, CH = 9.519259302, 20.5, 49.5

#: Section bounds in S (mm), by increasing S: H | G | F | E | D | C | B | A.
BOUNDS = (-70.0, -62.764705882, -49.662510381, -39.764473993, -38.426669071, -35.0, -26.0,
          32.15796, 60.0)
SECTION_NAMES = ("H", "G", "F", "E", "D", "C", "B", "A")


def _section_pieces(bounds):
    """The eight exact pieces of z(y) = -F(y), ordered by increasing y (sections H .. A)."""
    b = bounds
    # z = -F: arcs with F = A + sqrt(..) hang below their centre (lower), F = A - sqrt(..) above.
    return [
        ArcPiece(b[0], b[1], (-CH, -AH), BH, upper=False),                                   # H
        ArcPiece(b[1], b[2], (-CG, -AG), BG, upper=False),                                   # G
        ArcPiece(b[2], b[3], (-CF, -AF), BF, upper=False),                                   # F
        line_piece(b[3], b[4], AE + BE * b[3], BE),                                          # E
        ArcPiece(b[4], b[5], (-CD, -AD), BD, upper=True),                                    # D
        poly_piece(b[5], b[6], [AC, BC, CC, DC, EC, FC, GC, HC]),                            # C
        poly_piece(b[6], b[7], [-AB, BB, -CB, DB, -EB, FB, -GB, HB, -IB], max_sub=2.0),      # B
        line_piece(b[7], b[8], -AA + BA * b[7], BA),                                         # A
    ]


def section_pieces_raw():
    """The eight pieces over their full published bounds (for checking the joins)."""
    return dict(zip(SECTION_NAMES, _section_pieces(BOUNDS)))


class S1002(Profile):
    """EN 13715 S1002 wheel profile with nominal rolling radius ``r0`` (mm) at the taping line."""

    def __init__(self, r0: float = 460.0, y_min: float = -70.0, y_max: float = 60.0):
        if not r0 > 0:
            raise InputError("r0", f"nominal rolling radius must be positive, got {r0} mm")
        if not (BOUNDS[0] <= y_min < y_max <= BOUNDS[-1]):
            raise InputError("y_min/y_max", f"[{y_min}, {y_max}] mm must lie within [-70, 60] mm")
        self.r0 = float(r0)
        pieces = []
        for p in _section_pieces(BOUNDS):
            ya, yb = max(p.ya, y_min), min(p.yb, y_max)
            if yb > ya:
                pieces.append(_trimmed(p, ya, yb))
        super().__init__("S1002", "wheel", pieces)

    def F(self, y):
        """EN 13715 F(S) (mm, positive downwards towards the flange tip) at S = y."""
        return -self.z(y)

    def radius(self, y):
        """Rolling radius r(y) = r0 - z(y) (mm)."""
        return self.r0 - self.z(y)

    # section_outline(depth_mm): the base class's block section is the rim section: surface from
    # the flange back to the field face, vertical side faces up to z = depth_mm, horizontal cut.


def _trimmed(piece, ya, yb):
    """The piece restricted to [ya, yb]."""
    return piece if (ya, yb) == (piece.ya, piece.yb) else dataclasses.replace(piece, ya=ya, yb=yb)


__all__ = ["BOUNDS", "S1002", "SECTION_NAMES", "section_pieces_raw"]
