"""Pictures of a wear run (units mm, km): profile evolution (overlay, zoomed on the changed part), wear and
inelastic depth along the profile per step, rolling-radius difference against distance."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from contact.wear.loop import WearRun
from wrlayer.plotting import DPI, MICRO_M


def _keys(run: WearRun) -> list[tuple[str, str]]:
    return [(s, b) for s in run.initial_profiles for b in ("wheel", "rail")]


def plot_profiles(run: WearRun, path: Path) -> Path:
    keys = _keys(run)
    fig, axes = plt.subplots(1, len(keys), figsize=(4.2 * len(keys), 4.0), squeeze=False)
    cmap = plt.get_cmap("viridis")
    for ax, (s, b) in zip(axes[0], keys):
        first = run.initial_profiles[s][b]
        changed = np.zeros(0)
        for rec in run.steps:
            bs = rec.bodies[s, b]
            tot = bs.wear_mm + bs.inelastic_mm
            if np.any(tot > 0):
                changed = np.concatenate([changed, bs.grid.y_mm[tot > 0.02 * tot.max()]])
        lo, hi = (changed.min() - 3, changed.max() + 3) if changed.size else (first.y_min, first.y_max)
        y = np.linspace(max(lo, first.y_min), min(hi, first.y_max), 400)
        ax.plot(y, first.z(y), "k-", lw=1.2, label="initial")
        for k, rec in enumerate(run.steps):
            prof = rec.profiles[s][b]
            yy = y[(y >= prof.y_min) & (y <= prof.y_max)]
            ax.plot(yy, prof.z(yy), color=cmap((k + 1) / max(1, len(run.steps))), lw=0.9,
                    label=f"{rec.end_km:.0f} km")
        ax.set_title(f"{s} {b}")
        ax.set_xlabel("y (mm)")
        ax.set_ylabel("z (mm)")
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.suptitle("profile evolution (zoomed on the changed part)")
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def plot_depths(run: WearRun, path: Path) -> Path:
    keys = _keys(run)
    fig, axes = plt.subplots(1, len(keys), figsize=(4.2 * len(keys), 3.8), squeeze=False)
    cmap = plt.get_cmap("viridis")
    for ax, (s, b) in zip(axes[0], keys):
        for k, rec in enumerate(run.steps):
            bs = rec.bodies[s, b]
            c = cmap((k + 1) / max(1, len(run.steps)))
            ax.plot(bs.grid.y_mm, bs.wear_mm * 1e3, color=c, lw=1.0, label=f"wear, step {rec.index}")
            if np.any(bs.inelastic_mm > 0):
                ax.plot(bs.grid.y_mm, bs.inelastic_mm * 1e3, color=c, lw=1.0, ls="--",
                        label=f"inelastic, step {rec.index}")
        ax.set_title(f"{s} {b}")
        ax.set_xlabel("y (mm)")
        ax.set_ylabel(f"depth per step ({MICRO_M})")
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=6)
    fig.suptitle("wear (solid) and inelastic (dashed) depth along the profile, per step")
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def plot_conicity(run: WearRun, path: Path) -> Path:
    km = [0.0] + [r.end_km for r in run.steps]
    dr = [run.initial_conicity["delta_r_mm"]] + [r.conicity["delta_r_mm"] for r in run.steps]
    amp = run.scene.settings.conicity_amplitude_mm
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    ax.plot(km, dr, "o-")
    ax.set_xlabel("running distance (km)")
    ax.set_ylabel(f"rolling-radius difference at {amp:g} mm (mm)")
    ax2 = ax.secondary_yaxis("right", functions=(lambda d: d / (2 * amp), lambda q: q * 2 * amp))
    ax2.set_ylabel("quasi-conicity dr/(2y)")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def write_wear_plots(run: WearRun, out_dir: Path) -> list[Path]:
    out_dir = Path(out_dir)
    if not run.steps:
        return []
    return [plot_profiles(run, out_dir / "profile_evolution.png"), plot_depths(run, out_dir / "depth_per_step.png"),
            plot_conicity(run, out_dir / "rolling_radius_difference.png")]


__all__ = ["plot_conicity", "plot_depths", "plot_profiles", "write_wear_plots"]
