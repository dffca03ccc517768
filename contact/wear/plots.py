"""Pictures of a wear run (units mm, km): profile evolution (overlay, zoomed on the changed part), wear and
inelastic depth along the profile per step (zoomed on the same part: :func:`changed_range`), rolling-radius
difference against distance."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from contact.wear.records import WearRun
from wrlayer.plotting import MICRO_M, save_figure


#: The pictures show the part of a profile where some step changed it by more than this fraction of that step's
#: largest change (wear + inelastic depth), widened by CHANGED_MARGIN_MM on each side.
CHANGED_FRACTION = 0.02
CHANGED_MARGIN_MM = 3.0


def _keys(run: WearRun) -> list[tuple[str, str]]:
    return [(s, b) for s in run.initial_profiles for b in ("wheel", "rail")]


def changed_range(run: WearRun, side: str, body: str) -> tuple[float, float] | None:
    """(lo, hi) in mm of the profile coordinate y where some step's wear + inelastic depth exceeds
    :data:`CHANGED_FRACTION` of that step's largest, widened by :data:`CHANGED_MARGIN_MM`; None if nothing changed."""
    changed = []
    for rec in run.steps:
        bs = rec.bodies[side, body]
        tot = bs.wear_mm + bs.inelastic_mm
        if np.any(tot > 0):
            changed.append(bs.grid.y_mm[tot > CHANGED_FRACTION * tot.max()])
    if not changed:
        return None
    y = np.concatenate(changed)
    return float(y.min()) - CHANGED_MARGIN_MM, float(y.max()) + CHANGED_MARGIN_MM


def plot_profiles(run: WearRun, path: Path) -> Path:
    """Top: the profiles after every step over the initial one (zoomed on the changed part). Bottom: the total
    change (normal distance from the initial profile, material removed positive) after every step."""
    keys = _keys(run)
    fig, axes = plt.subplots(2, len(keys), figsize=(4.2 * len(keys), 6.5), squeeze=False, sharex="col")
    cmap = plt.get_cmap("viridis")
    for col, (s, b) in enumerate(keys):
        ax, ax2 = axes[0][col], axes[1][col]
        first = run.initial_profiles[s][b]
        lo, hi = changed_range(run, s, b) or (first.y_min, first.y_max)
        y = np.linspace(max(lo, first.y_min), min(hi, first.y_max), 400)
        ax.plot(y, first.z(y), "k-", lw=1.2, label="initial")
        for k, rec in enumerate(run.steps):
            prof = rec.profiles[s][b]
            c = cmap((k + 1) / max(1, len(run.steps)))
            yy = y[(y >= prof.y_min) & (y <= prof.y_max)]
            ax.plot(yy, prof.z(yy), color=c, lw=0.9, label=f"{rec.end_km:.0f} km")
            pts = prof.points if hasattr(prof, "points") else np.column_stack(prof.sample(0.2))
            pts = pts[(pts[:, 0] >= y[0]) & (pts[:, 0] <= y[-1])]
            if pts.size:
                d, _ = first.signed_distance(pts)
                ax2.plot(pts[:, 0], np.abs(d) * 1e3, color=c, lw=0.9)
        ax.set_title(f"{s} {b}")
        ax.set_ylabel("z (mm)")
        ax.grid(alpha=0.3)
        ax2.set_xlabel("y (mm)")
        ax2.set_ylabel(f"total change ({MICRO_M})")
        ax2.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.suptitle("profile evolution: profiles (top) and total change from the initial profile (bottom)")
    fig.tight_layout()
    save_figure(fig, path)
    return path


def depths_figure(run: WearRun):
    """The figure of :func:`plot_depths` (returned open, for tests): one panel per side and body, the abscissa
    limited to :func:`changed_range` (the whole grid if nothing changed), one legend right of the panels."""
    keys = _keys(run)
    fig, axes = plt.subplots(1, len(keys), figsize=(4.2 * len(keys) + 1.8, 3.8), squeeze=False,
                             constrained_layout=True)
    cmap = plt.get_cmap("viridis")
    for ax, (s, b) in zip(axes[0], keys):
        for k, rec in enumerate(run.steps):
            bs = rec.bodies[s, b]
            c = cmap((k + 1) / max(1, len(run.steps)))
            ax.plot(bs.grid.y_mm, bs.wear_mm * 1e3, color=c, lw=1.0, label=f"wear, step {rec.index}")
            if np.any(bs.inelastic_mm > 0):
                ax.plot(bs.grid.y_mm, bs.inelastic_mm * 1e3, color=c, lw=1.0, ls="--",
                        label=f"inelastic, step {rec.index}")
        span = changed_range(run, s, b)
        if span is not None:
            y = run.steps[0].bodies[s, b].grid.y_mm
            ax.set_xlim(max(span[0], float(y.min())), min(span[1], float(y.max())))
        ax.set_title(f"{s} {b}")
        ax.set_xlabel("y (mm)")
        ax.set_ylabel(f"depth per step ({MICRO_M})")
        ax.grid(alpha=0.3)
    fig.legend(*axes[0][0].get_legend_handles_labels(), loc="outside right upper", fontsize=7)
    fig.suptitle("wear (solid) and inelastic (dashed) depth along the profile, per step; y limited to where a "
                 f"step changed the profile by > {CHANGED_FRACTION:.0%} of its largest change, ± "
                 f"{CHANGED_MARGIN_MM:g} mm", fontsize=10)
    return fig


def plot_depths(run: WearRun, path: Path) -> Path:
    """depth_per_step.png: wear and inelastic depth (µm) along the profile y (mm) per step (:func:`depths_figure`)."""
    save_figure(depths_figure(run), path)
    return path


def draw_equivalent_conicity(ax, right_axis, run: WearRun, amp: float) -> None:
    """The EN 15302 equivalent conicity against distance, drawn in the units of the right (conicity) axis of the
    rolling-radius-difference picture (a conicity gamma sits at 2 A gamma on the left axis)."""
    km = [0.0] + [r.end_km for r in run.steps]
    gamma = [run.initial_conicity.equivalent_conicity] + [r.conicity.equivalent_conicity for r in run.steps]
    ax.lines[0].set_label(f"rolling-radius difference at {amp:g} mm (left axis)")
    ax.plot(km, 2.0 * amp * np.asarray(gamma), "s--", color="C3",
            label=f"equivalent conicity, EN 15302, amplitude {amp:g} mm (right axis)")
    right_axis.set_ylabel("conicity (-): quasi dr/(2y), equivalent")
    ax.legend(fontsize=7, loc="best")


def plot_conicity(run: WearRun, path: Path) -> Path:
    km = [0.0] + [r.end_km for r in run.steps]
    dr = [run.initial_conicity.delta_r_mm] + [r.conicity.delta_r_mm for r in run.steps]
    amp = run.scene.settings.conicity_amplitude_mm
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    ax.plot(km, dr, "o-")
    ax.set_xlabel("running distance (km)")
    ax.set_ylabel(f"rolling-radius difference at {amp:g} mm (mm)")
    ax2 = ax.secondary_yaxis("right", functions=(lambda d: d / (2 * amp), lambda q: q * 2 * amp))
    ax2.set_ylabel("quasi-conicity dr/(2y)")
    ax.grid(alpha=0.3)
    draw_equivalent_conicity(ax, ax2, run, amp)
    fig.tight_layout()
    save_figure(fig, path)
    return path


def write_wear_plots(run: WearRun, out_dir: Path) -> list[Path]:
    out_dir = Path(out_dir)
    if not run.steps:
        return []
    return [plot_profiles(run, out_dir / "profile_evolution.png"), plot_depths(run, out_dir / "depth_per_step.png"),
            plot_conicity(run, out_dir / "rolling_radius_difference.png")]


__all__ = ["CHANGED_FRACTION", "CHANGED_MARGIN_MM", "changed_range", "depths_figure", "draw_equivalent_conicity",
           "plot_conicity", "plot_depths", "plot_profiles", "write_wear_plots"]
