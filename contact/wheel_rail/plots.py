"""Pictures of a wheel_rail scene (matplotlib, Agg): the profiles in contact with contact points and patches, the
sweep (contact position, p_max, forces against the lateral displacement; the title names the scene file and its
solvers) and the residual displacements (one curve per case coloured by its lateral displacement, colour bar).
Units mm, N, MPa."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.lines import Line2D

from contact.normal.exact import DEFAULT_CELLS
from contact.normal.problem import ALPHA, GRID_MM
from contact.wheel_rail.deformed import residual_on_profiles
from contact.wheel_rail.results import CaseResult, SweepResult
from contact.wheel_rail.solution import WheelRailSolution
from contact.wheel_rail.track_geometry import wheel_locus, wheel_sample_y
from wrlayer.plotting import save_figure

SIDE_COLOURS = {"right": "tab:blue", "left": "tab:orange"}


def _profiles_panel(ax, sol: WheelRailSolution, title: str) -> None:
    """One wheel on its rail in the side frame, zoomed on the rail head; contact points and patch extents."""
    rail, inputs = sol.rail, sol.inputs
    pose = inputs.pose.for_side(inputs.side)
    ax.plot(rail.Y_mm, rail.Z_mm, color="0.3", lw=1.2, label=f"rail {rail.profile.name}")
    y = wheel_sample_y(sol.wheel, 0.1)
    loc = wheel_locus(sol.wheel, inputs.layout, pose, y)
    Zw = loc.Z_mm + sol.search.wheel_height_mm
    keep = (loc.Y_mm > rail.Y_mm[0] - 25) & (loc.Y_mm < rail.Y_mm[-1] + 10)
    ax.plot(loc.Y_mm[keep], Zw[keep], color="tab:green", lw=1.2, label="wheel (rigid contact position)")
    for p in sol.patches:
        c = p.candidate
        ax.plot(c.Y_mm, c.Z_mm, "o", color="tab:red", ms=5)
        on = p.normal.p_peak_MPa > 0
        if np.any(on):
            eta = p.strip_sign * p.problem.strip_y_mm[on]
            q = c.rail_coordinate(eta)
            pts = rail.point(q)
            ax.plot(pts[:, 0], pts[:, 1], "-", color="tab:red", lw=4, alpha=0.6)
    for i, p in enumerate(sorted(sol.patches, key=lambda p: p.candidate.Y_mm)):
        c = p.candidate  # labels alternate above/below the profile so that two close patches do not overlap
        ax.annotate(f"{np.degrees(c.contact_angle_rad):.1f}°, {p.normal_force_N / 1e3:.1f} kN", (c.Y_mm, c.Z_mm),
                    textcoords="offset points", xytext=(-4, 10) if i % 2 == 0 else (4, -16), fontsize=7,
                    color="tab:red", ha="right" if i % 2 == 0 else "left")
    for c in sol.unloaded:
        ax.plot(c.Y_mm, c.Z_mm, "x", color="0.5", ms=5)
    ax.set_xlim(rail.Y_mm[0] - 20, rail.Y_mm[-1] + 5)
    ax.set_ylim(-30, 15)
    ax.set_aspect("equal")
    ax.set_xlabel("Y (mm, side frame: field side +)")
    ax.set_ylabel("Z (mm)")
    ax.set_title(title, fontsize=8)
    ax.grid(alpha=0.3)


def write_wheel_rail_plots(result: SweepResult, solutions: list[dict[str, WheelRailSolution] | None],
                           out_dir: Path) -> list[Path]:
    """profiles_in_contact.png (first, middle and last computed case), sweep.png (if more than one case) and
    residual_displacements.png (if any case left a residual displacement)."""
    out_dir = Path(out_dir)
    paths = []
    ok = [k for k, s in enumerate(solutions) if s is not None]
    picks = sorted({ok[0], ok[len(ok) // 2], ok[-1]}) if ok else []
    if picks:
        sides = list(solutions[picks[0]])
        fig, axes = plt.subplots(len(sides), len(picks), figsize=(4.4 * len(picks), 2.6 * len(sides)), squeeze=False)
        for j, k in enumerate(picks):
            case = result.cases[k]
            for i, side in enumerate(sides):
                _profiles_panel(axes[i, j], solutions[k][side],
                                f"{side} wheel: lateral {case.lateral_mm:g} mm, yaw {case.yaw_rad * 1e3:.1f} "
                                f"mrad, roll {case.roll_rad * 1e3:.2f} mrad")
        axes[0, 0].legend(fontsize=7, loc="lower left")
        fig.suptitle("profiles in contact (red: loaded patches with contact angle and normal force; grey x: "
                     "unloaded candidates)", fontsize=8)
        fig.tight_layout()
        path = out_dir / "profiles_in_contact.png"
        save_figure(fig, path)
        paths.append(path)
    if len(result.cases) > 1 and ok:
        paths.append(_sweep_plot(result, out_dir / "sweep.png"))
    residual = _residual_plot(result, solutions, out_dir / "residual_displacements.png")
    if residual is not None:
        paths.append(residual)
    return paths


#: residual_displacements.png shows y where some curve of a panel exceeds this fraction of the panel's largest
#: residual displacement, widened by RESIDUAL_MARGIN_MM on each side.
RESIDUAL_FRACTION = 0.01
RESIDUAL_MARGIN_MM = 3.0
#: Line style of each wheel in residual_displacements.png (the colour is the case's sweep value).
SIDE_STYLES = {"right": "-", "left": "--"}


@dataclass(frozen=True)
class ResidualCurve:
    """One curve of residual_displacements.png: a body's residual displacement after the passes of one case.

    Attributes
    ----------
    body : str
        "rail" or "wheel".
    side : str
        "right" or "left" wheel.
    value : float
        The case's sweep abscissa (lateral displacement in mm, or the case number; :func:`_sweep_axis`).
    y_mm : numpy.ndarray
        Profile coordinate, ascending (mm, field side +).
    up_um : numpy.ndarray
        Residual displacement into the body (µm).
    """

    body: str
    side: str
    value: float
    y_mm: np.ndarray
    up_um: np.ndarray


def residual_curves(result: SweepResult, solutions: list) -> list[ResidualCurve]:
    """The non-zero residual displacements of every computed case, wheel and body."""
    key, _ = _sweep_axis(result)
    curves = []
    for k, sols in enumerate(solutions):
        for side, sol in (sols or {}).items():
            for body, res in residual_on_profiles(sol.patches).items():
                if res is None or not np.any(res[1] > 1e-9):
                    continue
                order = np.argsort(res[0])
                value = result.cases[k].lateral_mm if key == "lateral_mm" else k + 1
                curves.append(ResidualCurve(body, side, float(value), res[0][order], res[1][order] * 1e3))
    return curves


def residual_span(curves: list[ResidualCurve]) -> tuple[float, float]:
    """(lo, hi) in mm: where some curve exceeds :data:`RESIDUAL_FRACTION` of the largest, ± RESIDUAL_MARGIN_MM."""
    peak = max(float(c.up_um.max()) for c in curves)
    y = np.concatenate([c.y_mm[c.up_um > RESIDUAL_FRACTION * peak] for c in curves])
    return float(y.min()) - RESIDUAL_MARGIN_MM, float(y.max()) + RESIDUAL_MARGIN_MM


def residual_figure(curves: list[ResidualCurve], value_label: str):
    """rail and wheel panels: one curve per case and wheel, coloured by the case's sweep value (colour bar), line
    style by wheel (legend of the styles only), y limited to :func:`residual_span`. Returned open (for tests)."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.0), constrained_layout=True)
    values = [c.value for c in curves]
    norm = Normalize(min(values), max(values) if max(values) > min(values) else min(values) + 1.0)
    cmap = plt.get_cmap("viridis")
    for ax, body in zip(axes, ("rail", "wheel")):
        mine = [c for c in curves if c.body == body]
        for c in mine:
            ax.plot(c.y_mm, c.up_um, SIDE_STYLES.get(c.side, ":"), color=cmap(norm(c.value)), lw=1)
        if mine:
            ax.set_xlim(*residual_span(mine))
        sides = sorted({c.side for c in mine}, key=lambda side: list(SIDE_STYLES).index(side)
                       if side in SIDE_STYLES else len(SIDE_STYLES))
        if sides:
            ax.legend([Line2D([], [], color="0.3", ls=SIDE_STYLES.get(side, ":")) for side in sides],
                      [f"{side} wheel" for side in sides], fontsize=8, loc="upper right")
        ax.set_xlabel(f"{body} profile coordinate y (mm, field side +)")
        ax.set_ylabel("residual displacement u_p (µm, into the body)")
        ax.set_title(f"{body}: residual displacement after the passes", fontsize=9)
        ax.grid(alpha=0.3)
    fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=axes, label=value_label, pad=0.01)
    return fig


def _residual_plot(result: SweepResult, solutions: list, path: Path) -> Path | None:
    """residual_displacements.png (:func:`residual_figure`); None when no case left a residual displacement."""
    curves = residual_curves(result, solutions)
    if not curves:
        return None
    save_figure(residual_figure(curves, _sweep_axis(result)[1]), path)
    return path


def method_label(method: dict[str, Any], layered: bool = True) -> str:
    """The solvers of a result's ``inputs.method`` in words: normal method (with its options; the exact solver's
    layer mode only when ``layered``), tangential method when recorded, reported contact point."""
    if method.get("normal") == "exact":
        cells = DEFAULT_CELLS if method.get("exact_cells") is None else method["exact_cells"]
        mode = f", {method.get('layer_mode', 'indentation')} layer" if layered else ""
        normal = f"exact half-space solver ({cells} cells along x{mode})"
    else:
        normal = f"Kik–Piotrowski (α = {method.get('alpha', ALPHA):g}, strips {method.get('grid_mm', GRID_MM):g} mm)"
    words = [f"normal: {normal}"]
    if method.get("tangential"):
        words.append(f"tangential: {method['tangential']}")
    if method.get("contact_point"):
        words.append(f"contact point: {method['contact_point'].replace('_', ' ')}")
    return "; ".join(words)


def sweep_title(inputs: dict[str, Any], failed: bool = False) -> str:
    """Title of sweep.png from the result's inputs echo: the scene's title, its file name and its solvers
    (:func:`method_label`), what is drawn."""
    name = Path(inputs["scene_file"]).name if inputs.get("scene_file") else "scene"
    note = "one marker per loaded patch" + ("; red dotted lines: failed cases" if failed else "")
    label = method_label(inputs.get("method", {}), layered=bool(inputs.get("layers")))
    return f"{inputs.get('title', '')}\n{name} — {label}\n{note}"


def _sweep_axis(result: SweepResult) -> tuple[str, str]:
    """The sweep's abscissa: the lateral displacement if it varies over the cases, else the case number."""
    lateral = {c.lateral_mm for c in result.cases}
    if len(lateral) > 1:
        return "lateral_mm", "wheelset lateral displacement (mm)"
    return "case", "case"


#: The panels of sweep.png, row by row: (title naming what and in which frame, y label). Rows 1-3 per loaded patch
#: (its location, its normal solution, its creep forces in the contact frame), row 4 per wheel in the track frame.
SWEEP_PANELS = (
    ("per patch: contact position, rail profile coordinate", "y_rail (mm, field side +)"),
    ("per patch: contact angle, normal vs. track vertical", "contact angle γ (°)"),
    ("per patch: normal force, along the contact normal", "normal force N (kN)"),
    ("per patch: largest pressure", "p_max (MPa)"),
    ("per patch, contact frame: longitudinal creep force", "F_x on the wheel (kN)"),
    ("per patch, contact frame: lateral creep force\n(in the contact plane)", "F_y on the wheel (kN)"),
    ("per wheel, track frame: lateral force Y\n(solid: total; dashed: of the normal forces alone)",
     "Y on the wheel (kN)"),
    ("per wheel, track frame: Y/Q", "Y/Q (-)"),
)


def _sweep_plot(result: SweepResult, path: Path) -> Path:
    """Eight panels over the cases, one quantity each and titled with its frame (:data:`SWEEP_PANELS`), one colour
    per wheel, one marker per patch of a case: per patch the contact position on the rail (mm), the contact angle
    (°), the normal force (kN), p_max (MPa), the creep forces F_x and F_y of the rail on the wheel in the contact
    frame (kN); per wheel in the track frame the lateral force Y (kN; also its part from the normal forces alone)
    and Y/Q (-): F_y (contact plane) stands
    above Y (track) so that the two frames are not mixed in a panel. One legend below the panels (wheel colours),
    none over the points."""
    fig, axes = plt.subplots(4, 2, figsize=(10, 12.5), sharex=True, constrained_layout=True)
    key, xlabel = _sweep_axis(result)
    x_of = (lambda k, c: c.lateral_mm) if key == "lateral_mm" else (lambda k, c: k + 1)
    cases: list[tuple[int, CaseResult]] = list(enumerate(result.cases))
    sides = sorted({s for _, c in cases for s in c.wheels or {}})
    per_patch = (lambda p: p.y_rail_mm, lambda p: np.degrees(p.contact_angle_rad),
                 lambda p: p.normal_force_N / 1e3, lambda p: p.p_max_MPa, lambda p: p.Fx_N / 1e3,
                 lambda p: p.Fy_N / 1e3)
    per_wheel = (lambda w: w.force_on_wheel_track_N[1] / 1e3, lambda w: w.Y_over_Q)
    for side in sides:
        col = SIDE_COLOURS.get(side, "k")
        rows = [(x_of(k, c), p) for k, c in cases if side in (c.wheels or {}) for p in c.wheels[side].patches]
        if rows:
            x = np.array([r[0] for r in rows])
            for ax, value in zip(axes.ravel(), per_patch):
                ax.plot(x, [value(r[1]) for r in rows], "o", color=col, ms=4, ls="none")
        wheels = [(x_of(k, c), c.wheels[side]) for k, c in cases if side in (c.wheels or {})]
        for ax, value in zip(axes[-1], per_wheel):
            ax.plot([w[0] for w in wheels], [value(w[1]) for w in wheels], "o-", color=col, ms=4, lw=1)
        axes[-1, 0].plot([w[0] for w in wheels],  # Y = sum N n_Y + creep forces: the flange's share shows here
                         [sum(p.normal_force_N * p.normal_track[1] for p in w[1].patches) / 1e3 for w in wheels],
                         "x--", color=col, ms=4, lw=0.8)
    failed = [x_of(k, c) for k, c in cases if c.error is not None]
    for ax, (title, ylabel) in zip(axes.ravel(), SWEEP_PANELS):
        for xf in failed:
            ax.axvline(xf, color="r", lw=0.8, ls=":")
        ax.grid(alpha=0.3)
        ax.set_title(title, fontsize=8)
        ax.set_ylabel(ylabel)
    handles = [Line2D([], [], color=SIDE_COLOURS.get(side, "k"), marker="o", ms=4, ls="none") for side in sides]
    fig.legend(handles, [f"{side} wheel" for side in sides], loc="outside lower center", ncol=max(len(handles), 1),
               fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel(xlabel)
    fig.suptitle(sweep_title(result.inputs, bool(failed)), fontsize=9)
    save_figure(fig, path)
    return path


__all__ = ["SWEEP_PANELS", "ResidualCurve", "method_label", "residual_curves", "residual_figure", "residual_span",
           "sweep_title", "write_wheel_rail_plots"]
