"""The benchmark set of normal contact patches on which the fast methods are measured against the exact solver.

Units: mm, N, MPa. 30 patches in seven classes (each a :class:`NormalProblem` on a 0.1 mm strip grid, E = 210 GPa,
nu = 0.28 unless taken from the wheel-rail scene):

- ``hertz``: x^2/(2 R_x) + y^2/(2 R_y), R_x = 460 mm, 10 kN, R_y chosen for Hertzian a/b = 0.1, 0.2, 0.5, 1, 2, 5,
  10 (a along x), and the two plain checks R_y 300 mm at 100 kN and R_y 40 mm at 80 kN;
- ``s1002 tread`` / ``s1002 gauge corner`` / ``s1002 flange``: the patches of the shipped Manchester A-2.2 scene
  (S1002 on 60E1 1:40, right wheel, Kik-Piotrowski balance) at contact angles below 0.1 rad, 0.1-0.6 rad and above
  0.6 rad, four of each spread over the sweep (their separation functions and balanced forces);
- ``two close patches``: two parabolic valleys 6-8 mm apart, the second raised by 0-5 um;
- ``quartic``: y^4 / (4 c^3) (flat bottom, no curvature at the minimum), three loads;
- ``flat-topped``: a flat middle of half-width w with parabolic flanks, three shapes.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from contact.normal.problem import NormalProblem

E_MPA, POISSON, R_X_MM, GRID_MM = 210000.0, 0.28, 460.0, 0.1
#: (a/b, R_y mm) of the Hertzian cases at 10 kN with R_x = 460 mm (a/b from Hertz's elliptic integrals).
HERTZ_RY_MM = ((0.1, 16806.6), (0.2, 5440.23), (0.5, 1307.67), (1.0, 460.0), (2.0, 161.81), (5.0, 38.9),
               (10.0, 12.59))
#: The plain Hertz checks (R_y mm, N).
HERTZ_CHECKS = ((300.0, 1.0e5), (40.0, 8.0e4))
#: Contact-angle limits (rad) between tread, gauge corner and flange.
ANGLE_LIMITS_RAD = (0.1, 0.6)
CLASSES = ("hertz", "s1002 tread", "s1002 gauge corner", "s1002 flange", "two close patches", "quartic",
           "flat-topped")


@dataclass(frozen=True)
class BenchPatch:
    """One patch of the set: its class, a name and the problem."""

    kind: str
    name: str
    problem: NormalProblem


def _table(half_mm: float, f) -> tuple[np.ndarray, np.ndarray]:
    y = np.linspace(-half_mm, half_mm, int(round(2 * half_mm / 0.025)) + 1)
    return y, f(y)


def _problem(y, f, N) -> NormalProblem:
    return NormalProblem(y, f, N, R_X_MM, E_MPA, POISSON, grid_mm=GRID_MM)


def hertz_patches() -> list[BenchPatch]:
    out = []
    for ratio, r_y in HERTZ_RY_MM:
        half = 2.5 * np.sqrt(2 * r_y * 0.05) + 1.0
        out.append(BenchPatch("hertz", f"a/b {ratio:g}", _problem(*_table(half, lambda y: y * y / (2 * r_y)), 1e4)))
    for r_y, n in HERTZ_CHECKS:
        out.append(BenchPatch("hertz", f"R_y {r_y:g} mm, {n / 1e3:g} kN",
                              _problem(*_table(12.0, lambda y: y * y / (2 * r_y)), n)))
    return out


def synthetic_patches() -> list[BenchPatch]:
    out = []
    for d, lift in ((3.0, 0.0), (3.5, 0.002), (4.0, 0.005)):
        f = (lambda y, d=d, lift=lift: np.minimum((y + d) ** 2 / 60.0, (y - d) ** 2 / 80.0 + lift))
        out.append(BenchPatch("two close patches", f"{2 * d:g} mm apart, +{lift * 1e3:g} um",
                              _problem(*_table(14.0, f), 2.0e4)))
    for n in (5e3, 2e4, 8e4):
        quartic = _table(12.0, lambda y: y ** 4 / (4 * 6.0 ** 3))
        out.append(BenchPatch("quartic", f"{n / 1e3:g} kN", _problem(*quartic, n)))
    for w, r in ((1.5, 40.0), (3.0, 80.0), (2.0, 15.0)):
        f = (lambda y, w=w, r=r: np.maximum(np.abs(y) - w, 0.0) ** 2 / (2 * r))
        out.append(BenchPatch("flat-topped", f"w {w:g} mm, R {r:g} mm", _problem(*_table(12.0, f), 2.0e4)))
    return out


@functools.cache
def wheel_rail_patches(per_class: int = 4) -> tuple[BenchPatch, ...]:
    """``per_class`` patches of each S1002 class from the A-2.2 sweep (right wheel), spread over the sweep."""
    # imported here: the wheel-rail scene is needed only for these patches
    from benchmarks.bench_manchester import SCENE, _scene_data
    from contact.wheel_rail.parse import parse_wheel_rail_scene
    from contact.wheel_rail.run import solve_case
    from contact.wheel_rail.track_geometry import place_rail

    data = _scene_data()
    data["wheel"]["side"] = "right"
    scene = parse_wheel_rail_scene(data, SCENE)
    placed = place_rail(scene.rail_profile, scene.layout)
    found: dict[str, list[BenchPatch]] = {k: [] for k in CLASSES[1:4]}
    for k, case in enumerate(scene.cases):
        _, sols = solve_case(scene, case, placed)
        for patch in sols["right"].patches:
            angle = abs(patch.candidate.contact_angle_rad)
            kind = CLASSES[1 + int(np.searchsorted(ANGLE_LIMITS_RAD, angle))]
            found[kind].append(BenchPatch(kind, f"case {k + 1}, angle {angle:.2f} rad", patch.problem))
    out = []
    for kind, items in found.items():
        pick = np.unique(np.linspace(0, len(items) - 1, min(per_class, len(items))).round().astype(int))
        out.extend(items[i] for i in pick)
    return tuple(out)


def patch_set() -> list[BenchPatch]:
    """The whole set, by class."""
    return hertz_patches() + list(wheel_rail_patches()) + synthetic_patches()
