"""Pictures of a calibrated layer table (PNG, matplotlib Agg): characteristic curves with their fits per position,
k_i and T_0i along the profile, and the profile with the calibrated positions marked. Units mm, MPa, N/mm^3."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from calibration.config import profile_of
from wrlayer.plotting import outside_legend, save_figure


def plot_characteristics(table, path: Path) -> Path:
    """One panel per position: FEM points u(p) (layer definition) and the fitted N-segment characteristic."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(table.positions)
    cols = min(4, n)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.4 * cols, 2.8 * rows), squeeze=False)
    for ax, pos, ch in zip(axes.ravel(), table.positions, table.characteristics):
        pts = pos.get("fem_points", {})
        if pts:
            ax.plot(1e3 * np.asarray(pts["u_mm"]), pts["p_MPa"], "o", ms=3, label="FEM")
        u = np.linspace(0.0, ch.u_mm[-1], 200)
        ax.plot(1e3 * u, ch.pressure(u), "-", lw=1.2, label=f"fit N={ch.n_segments}")
        ax.plot(1e3 * ch.u_mm, ch.p_MPa, "k+", ms=6)
        ax.set_title(f"y = {pos['y_mm']:g} mm", fontsize=9)
        ax.set_xlabel("u [µm]", fontsize=8)
        ax.set_ylabel("p [MPa]", fontsize=8)
        ax.tick_params(labelsize=7)
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    axes.ravel()[0].legend(fontsize=7)
    fig.suptitle(f"{table.body} ({table.profile_name}): layer characteristics", fontsize=10)
    fig.tight_layout()
    return save_figure(fig, path)


#: Line style and marker of segment i (one per segment a table can hold; the colours repeat after ten):
#: neighbouring k_i or T_0i that nearly coincide stay distinguishable.
SEGMENT_STYLES = (("-", "o"), ("--", "s"), ("-.", "^"), (":", "D"), ((0, (5, 1, 1, 1)), "v"), ((0, (1, 1)), "P"),
                  ((0, (3, 1, 1, 1, 1, 1)), "X"), ((0, (8, 2)), "h"), ((0, (2, 3)), "*"), ((0, (6, 2, 2, 2)), "p"),
                  ((0, (10, 3)), "d"), ((0, (1, 3)), "<"), ((0, (4, 1, 1, 1, 1, 1, 1, 1)), ">"), ((0, (3, 3)), "8"),
                  ((0, (7, 1, 1, 1)), "H"), ((0, (2, 1)), "+"))


def segment_style(i: int) -> dict:
    """Matplotlib line keywords of segment i (0-based): its own line style and marker (open markers)."""
    ls, marker = SEGMENT_STYLES[i % len(SEGMENT_STYLES)]
    return {"ls": ls, "marker": marker, "ms": 5, "mfc": "none", "lw": 1.2}


def parameters_figure(table):
    """The figure of :func:`plot_parameters` (returned open, for tests): k_i (log scale) and T_0i along y, each
    segment with its own colour, line style and marker; the legends right of the panels."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    y = table.y_mm
    pars = [ch.to_parameters() for ch in table.characteristics]
    n = max(p.n_segments for p in pars)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 3.8), constrained_layout=True)
    for i in range(n):
        a1.semilogy(y, [p.k_N_per_mm3[i] if i < p.n_segments else np.nan for p in pars], color=f"C{i}",
                    label=f"k_{i + 1}", **segment_style(i))
        if i < n - 1:
            a2.plot(y, [p.T0_MPa[i] if i < p.n_segments - 1 else np.nan for p in pars], color=f"C{i}",
                    label=f"T_0{i + 1}", **segment_style(i))
    a1.set_xlabel("y [mm]")
    a1.set_ylabel("k_i [N/mm³]")
    a2.set_xlabel("y [mm]")
    a2.set_ylabel("T_0i [MPa]")
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
        outside_legend(ax, fontsize=7)
    fig.suptitle(f"{table.body} ({table.profile_name}): Prandtl element parameters along the profile", fontsize=10)
    return fig


def plot_parameters(table, path: Path) -> Path:
    """k_i (N/mm^3) and T_0i (MPa) along the profile coordinate (:func:`parameters_figure`)."""
    return save_figure(parameters_figure(table), path)


def plot_profile_positions(profile, table, path: Path, failed_y=()) -> Path:
    """The profile z(y) with calibrated (and failed) positions marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ys = np.linspace(profile.y_min, profile.y_max, 800)
    fig, ax = plt.subplots(figsize=(8, 3.2))
    ax.plot(ys, profile.z(ys), "k-", lw=1)
    y = table.y_mm
    ax.plot(y, profile.z(y), "o", color="tab:blue", label="calibrated")
    if len(failed_y):
        fy = np.asarray(failed_y, dtype=float)
        ax.plot(fy, profile.z(fy), "x", color="tab:red", label="failed")
    ax.set_aspect("equal")
    ax.set_xlabel("y [mm]")
    ax.set_ylabel("z [mm]")
    ax.legend(fontsize=8)
    ax.set_title(f"{profile.name} ({profile.body}): calibrated positions", fontsize=10)
    fig.tight_layout()
    return save_figure(fig, path)


def write_body_plots(table, body_settings, out_dir: Path) -> list[Path]:
    """All pictures of one body's table into ``out_dir``."""
    out_dir = Path(out_dir)
    b = table.body
    return [plot_characteristics(table, out_dir / f"{b}_characteristics.png"),
            plot_parameters(table, out_dir / f"{b}_parameters.png"),
            plot_profile_positions(profile_of(body_settings.profile), table, out_dir / f"{b}_positions.png",
                                   [f["y_mm"] for f in table.failed])]
