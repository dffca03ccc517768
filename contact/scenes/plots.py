"""Pictures of a contact scene run (matplotlib, Agg): patches, separation and residuals, shakedown history.

- ``patch_pass<N>.png``: the patch(es) of pass N on the square grid (x rolling direction, y lateral), pressure
  contours (MPa; labelled on the reference strip's leading side where they do not overlap,
  :func:`label_positions`; every level in the colour bar), slip cells grey and adhesion cells white (like the paper's Figs. 6–8), a 1 x 1 mm box for scale
  and the rolling-direction arrow; with a Hertz ``[reference]`` (``source`` starting with "Hertz", ``length_mm``
  and ``width_mm`` given) the Hertz ellipse's outline centred on the reference point. Written for the first and
  the last pass.
- ``separation.png``: the separation f(y) before the first and after the last pass, the residual displacements of
  each layer (cumulative), and the peak pressure p(0, y) of the first and last pass against the elastic limit p_2;
  the legends right of the panels, never over the curves.
- ``shakedown.png``: area, p_max and approach delta against the pass number (scenes with more than one pass).
- ``exact_pressure_pass<N>.png``: with ``method.normal = "exact"``, the pressure on the exact solver's grid (with
  the Hertz ellipse as above) and p(x) (and the layer displacement) on the line of the largest pressure.
Units: mm, MPa.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Ellipse, Rectangle
from matplotlib.ticker import MaxNLocator

from contact.tangential.grid_sample import sample_on_grid
from wrlayer.plotting import outside_legend, save_figure

_SLIP = ListedColormap(["#ffffff", "#9a9a9a"])  # adhesion white, slip grey


def _elastic_limit(run) -> float | None:
    layers = run.scene.layers
    if layers is None:
        return None
    chars = layers.sources.at_contact()
    limits = [c.elastic_limit_MPa for c in chars if np.isfinite(c.elastic_limit_MPa)]
    return min(limits) if limits else None


def _p2_label(p2: float) -> str:
    return f"elastic limit p$_2$ = {p2:.0f} MPa\n(at the contact point)"


def hertz_semi_axes(scene) -> tuple[float, float] | None:
    """Semi-axes (a along x, b along y; mm) of the Hertz ellipse the scene compares with: its ``[reference]`` when
    ``source`` names Hertz ("Hertz ..." in any case) and gives ``length_mm`` = 2a and ``width_mm`` = 2b; else None
    (a published Kik–Piotrowski patch, like the paper's Table 1, is not an ellipse)."""
    ref = scene.reference
    if not str(ref.get("source", "")).strip().lower().startswith("hertz"):
        return None
    if ref.get("length_mm") is None or ref.get("width_mm") is None:
        return None
    return 0.5 * float(ref["length_mm"]), 0.5 * float(ref["width_mm"])


def draw_hertz_ellipse(ax, semi_axes: tuple[float, float] | None, centre_mm: tuple[float, float]) -> None:
    """The Hertz ellipse's outline (red dashed, labelled with its size) centred on ``centre_mm`` (x, y; mm)."""
    if semi_axes is None:
        return
    a, b = semi_axes
    ax.add_patch(Ellipse(centre_mm, 2.0 * a, 2.0 * b, fill=False, ls="--", lw=1.3, color="tab:red",
                         label=f"Hertz ellipse (reference): 2a = {2 * a:.2f} mm, 2b = {2 * b:.2f} mm"))


#: Least distance between two contour labels along the reference strip, as a fraction of the plotted x span (-).
LABEL_GAP = 0.045


def label_positions(x_mm: np.ndarray, p_row_MPa: np.ndarray, levels, y_mm: float, gap_mm: float
                    ) -> tuple[list[float], list[tuple[float, float]]]:
    """Where to label the pressure contours of a patch without overlaps: on the reference strip ``y_mm`` (the
    largest p0), on the leading side (x > 0, adhesion: white behind the labels), where the pressure ``p_row_MPa``
    (MPa, at ``x_mm``) crosses each level, from the highest level outwards, a level being left out when its
    crossing is within ``gap_mm`` (mm) of the last labelled one or within half of it of the patch's leading edge
    (the outline; the colour bar still names every level).
    Returns (the labelled levels, their (x, y) positions)."""
    lead = (x_mm > 0.0) & (p_row_MPa > 0.0)
    xs, ps = x_mm[lead], p_row_MPa[lead]
    edge = float(xs.max()) if xs.size else 0.0
    order = np.argsort(ps)  # increasing pressure for np.interp (the leading half falls monotonically)
    labelled, where, last = [], [], None
    for level in sorted(levels, reverse=True):
        if xs.size < 2 or not ps.min() < level < ps.max():
            continue
        x = float(np.interp(level, ps[order], xs[order]))
        if (last is None or abs(x - last) >= gap_mm) and x <= edge - 0.5 * gap_mm:
            labelled.append(float(level))
            where.append((x, float(y_mm)))
            last = x
    return labelled, where


def plot_patch(snapshot, path: Path, title: str, hertz: tuple[float, float] | None = None) -> Path:
    """The patches of one pass on their grid: pressure contours, slip cells grey, scale box, rolling arrow, and
    the Hertz ellipse of semi-axes ``hertz`` (a, b; mm) centred on the reference point when given."""
    sol = snapshot.solution
    h = sol.patches[0].grid_mm
    x_max = max(p.x_lead_mm.max() for p in sol.patches)
    y_lo = min(yr + p.y_mm[0] for yr, p in zip(snapshot.y_ref_mm, snapshot.local_patches)) - 0.5 * h
    y_hi = max(yr + p.y_mm[-1] for yr, p in zip(snapshot.y_ref_mm, snapshot.local_patches)) + 0.5 * h
    span_x, span_y = 2.0 * x_max + 4.0, (y_hi - y_lo) + 3.0
    width = 11.0
    height = float(np.clip(width * span_y / span_x + 1.6, 3.0, 9.0))
    fig, ax = plt.subplots(figsize=(width, height), constrained_layout=True)
    p_levels = None
    contour = None
    any_slip = False
    for yr, patch, tr in zip(snapshot.y_ref_mm, snapshot.local_patches, snapshot.tangential):
        x, mask = patch.grid()
        y = yr + patch.y_mm
        xe = np.append(x - 0.5 * h, x[-1] + 0.5 * h)
        ye = np.append(y - 0.5 * h, y[-1] + 0.5 * h)
        pressure = patch.pressure_MPa(x[:, None]).T  # (ny, nx)
        slip = np.zeros_like(mask) if tr is None else sample_on_grid(patch, tr).slip
        any_slip |= bool(slip.any())
        edge = "#d0d0d0" if x.size <= 80 else "face"
        ax.pcolormesh(xe, ye, np.ma.masked_where(~mask, slip.astype(float)), cmap=_SLIP, vmin=0, vmax=1,
                      edgecolors=edge, linewidth=0.2, shading="flat")
        if p_levels is None:
            nice = MaxNLocator(nbins=8, steps=[1, 2, 2.5, 5, 10]).tick_values(0.0, sol.p_max_MPa)
            p_levels = nice[(nice > 0.0) & (nice < sol.p_max_MPa)]
        if y.size > 1:
            contour = ax.contour(x, y, np.where(mask, pressure, 0.0), levels=p_levels, cmap="viridis",
                                 linewidths=1.0)
            labelled, where = label_positions(x, pressure[int(np.argmin(np.abs(y - yr)))], p_levels, yr,
                                              LABEL_GAP * (2.0 * x_max))
            for level, (lx, ly) in zip(labelled, where):  # upright text on white: no overlap, no rotation
                ax.text(lx, ly, f"{level:.0f}", ha="center", va="center", fontsize=7,
                        color=contour.cmap(contour.norm(level)),
                        bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none"})
        # outline: leading and trailing edges of the strips
        ax.step(patch.x_lead_mm, y, where="mid", color="k", lw=0.8)
        ax.step(-patch.x_lead_mm, y, where="mid", color="k", lw=0.8)
        ax.plot([0.0], [yr], "k+", ms=8, label="reference point (x = 0, strip of the largest p$_0$)"
                if yr == snapshot.y_ref_mm[0] else None)
    # 1 x 1 mm scale box and rolling direction
    bx, by = -x_max - 1.5, y_lo - 1.8
    ax.add_patch(Rectangle((bx, by), 1.0, 1.0, fill=False, lw=1.2, color="k"))
    ax.text(bx + 1.3, by + 0.5, "1 x 1 mm", va="center", fontsize=8)
    ax.annotate("", xy=(x_max, by + 0.5), xytext=(x_max - 6.0, by + 0.5),
                arrowprops={"arrowstyle": "->", "lw": 1.5})
    ax.text(x_max - 3.0, by + 0.8, "rolling direction x", ha="center", va="bottom", fontsize=8)
    ax.set_xlim(-x_max - 2.0, x_max + 2.0)
    ax.set_ylim(y_lo - 2.2, y_hi + 0.8)
    ax.set_aspect("equal")
    ax.set_xlabel("x (rolling direction) [mm]")
    ax.set_ylabel("y (lateral) [mm]")
    d = snapshot
    first = d.tangential[0]
    info = (f"N = {sol.normal_force_N / 1e3:.1f} kN, area {sol.area_mm2:.1f} mm$^2$, "
            f"p$_{{max}}$ = {sol.p_max_MPa:.0f} MPa, delta = {sol.delta_mm:.5f} mm")
    if first is not None:
        fx = sum(t.Fx_N for t in d.tangential) / 1e3
        fy = sum(t.Fy_N for t in d.tangential) / 1e3
        info += f", F$_x$ = {fx:.2f} kN, F$_y$ = {fy:.2f} kN"
    legend = "pressure contours [MPa]" + ("; grey: slip, white: adhesion" if first is not None else "")
    ax.set_title(f"{title}\n{info}\n{legend}", fontsize=9)
    if contour is not None:
        fig.colorbar(contour, ax=ax, label="pressure contour p [MPa]", shrink=0.7, pad=0.01, format="%.0f")
    draw_hertz_ellipse(ax, hertz, (0.0, snapshot.y_ref_mm[0]))
    ax.legend(loc="upper right", fontsize=8, frameon=False)
    save_figure(fig, path)
    return path


def separation_figure(run):
    """The figure of :func:`plot_separation` (returned open, for tests): three panels over y, legends outside."""
    y = run.strip_y_mm
    on = (run.first.solution.p_peak_MPa > 0) | (run.last.solution.p_peak_MPa > 0)
    lo, hi = y[on].min(), y[on].max()
    pad = max(1.0, 0.5 * (hi - lo))
    view = (y >= lo - pad) & (y <= hi + pad)
    rows = 3 if run.residual_mm else 2
    fig, axes = plt.subplots(rows, 1, figsize=(11.0, 2.9 * rows), sharex=True, constrained_layout=True)
    ax = axes[0]
    ax.plot(y[view], run.separation_before_mm[view] * 1e3, label="before the first pass")
    if run.residual_mm:
        ax.plot(y[view], run.separation_after_mm[view] * 1e3, "--", label=f"after pass {len(run.history)}")
    ax.axhline(run.first.solution.delta0_mm * 1e3, color="C0", lw=0.7, ls=":",
               label=f"virtual penetration delta$_0$\npass 1 = {run.first.solution.delta0_mm * 1e3:.1f} µm")
    ax.set_ylabel("separation f [µm]")
    ax.set_ylim(0, max(3.0 * run.first.solution.delta0_mm * 1e3, 1e-3))
    if run.residual_mm:
        ax = axes[1]
        for name, up in run.residual_mm.items():
            ax.plot(y[view], np.asarray(up)[view] * 1e3, label=f"{name} layer")
        ax.set_ylabel(f"residual u$_p$\nafter pass {len(run.history)} [µm]")
    ax = axes[-1]
    ax.plot(y[view], run.first.solution.p_peak_MPa[view], label="pass 1")
    if len(run.history) > 1:
        ax.plot(y[view], run.last.solution.p_peak_MPa[view], "--", label=f"pass {len(run.history)}")
    p2 = _elastic_limit(run)
    if p2 is not None:
        ax.axhline(p2, color="r", lw=0.8, ls=":", label=_p2_label(p2))
    ax.set_ylabel("peak pressure p(0, y) [MPa]")
    ax.set_xlabel("y (lateral) [mm]")
    for a in axes:
        outside_legend(a)
        a.grid(alpha=0.3)
    shown = "separation, residual displacements, peak pressure" if run.residual_mm else "separation, peak pressure"
    fig.suptitle(f"{run.scene.title}: {shown}", fontsize=10)
    return fig


def plot_separation(run, path: Path) -> Path:
    """Separation before/after the passes, cumulative residual displacement per layer, peak pressure p(0, y)."""
    save_figure(separation_figure(run), path)
    return path


def plot_shakedown(run, path: Path) -> Path:
    """Area, p_max and delta against the pass number."""
    hist = run.history
    n = np.array([h.index for h in hist])
    fig, axes = plt.subplots(3, 1, figsize=(7.5, 7.5), sharex=True, constrained_layout=True)
    for ax, key, label in zip(axes, ("area_mm2", "p_max_MPa", "delta_mm"),
                              ("area [mm$^2$]", "p$_{max}$ [MPa]", "approach delta [mm]")):
        ax.plot(n, [getattr(h, key) for h in hist], "o-", ms=3)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    p2 = _elastic_limit(run)
    if p2 is not None:
        axes[1].axhline(p2, color="r", lw=0.8, ls=":", label=_p2_label(p2))
        axes[1].legend(fontsize=8)
    sd = run.result.shakedown_pass
    if sd is not None:
        for ax in axes:
            ax.axvline(sd, color="k", lw=0.7, ls="--")
        axes[0].text(sd, axes[0].get_ylim()[0], f"shakedown: pass {sd} ", fontsize=8, va="bottom", ha="right")
    axes[-1].set_xlabel("pass")
    axes[-1].xaxis.set_major_locator(MaxNLocator(integer=True))
    mode = {"state_kept": "state kept (hardening)", "relaxed": "sliders relaxed before each pass",
            "rolling": "the layers' rolling law (relaxed where a layer has none)"}[run.scene.passes.options.rule]
    fig.suptitle(f"{run.scene.title}\nshakedown history ({mode})", fontsize=10)
    save_figure(fig, path)
    return path


def plot_exact_field(snapshot, path: Path, title: str, hertz: tuple[float, float] | None = None) -> Path:
    """The exact normal solver's pressure on its own grid (method.normal = "exact"): the cell pressures (colour),
    the refined contact ends of every line, the Hertz ellipse of semi-axes ``hertz`` (a, b; mm) when given, and p
    along x on the line of the largest pressure (its asymmetry shows the rolling mode's unloading behind the
    peak)."""
    sol = snapshot.solution
    fld = sol.field
    xe = np.append(fld.x_mm - 0.5 * fld.dx_mm, fld.x_mm[-1] + 0.5 * fld.dx_mm)
    ye = np.append(fld.y_mm - 0.5 * fld.dy_mm, fld.y_mm[-1] + 0.5 * fld.dy_mm)
    span_x, span_y = xe[-1] - xe[0], ye[-1] - ye[0]
    width = 11.0
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(width, float(np.clip(width * span_y / span_x, 1.5, 6.0)) + 4.2),
                                  constrained_layout=True, height_ratios=[max(span_y / span_x * 3.0, 0.6), 1.0])
    mesh = ax.pcolormesh(xe, ye, np.ma.masked_where(fld.p_MPa <= 0, fld.p_MPa), cmap="viridis", shading="flat")
    ok = np.isfinite(fld.x_extent_mm[:, 0])
    ax.plot(fld.x_extent_mm[ok, 0], fld.y_mm[ok], "k.", ms=2, label="refined contact ends (trailing / leading)")
    ax.plot(fld.x_extent_mm[ok, 1], fld.y_mm[ok], "k.", ms=2)
    draw_hertz_ellipse(ax, hertz, (0.0, snapshot.y_ref_mm[0]))
    ax.set_xlim(xe[0], xe[-1])
    ax.set_ylim(ye[0], ye[-1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (rolling direction; material moves from +x to -x) [mm]")
    ax.set_ylabel("y (lateral) [mm]")
    ax.legend(loc="upper right", fontsize=8, frameon=False)
    fig.colorbar(mesh, ax=ax, label="p [MPa]", shrink=0.8, pad=0.01, format="%.0f")
    j = int(np.argmax(fld.p_MPa.max(axis=1)))
    ax2.step(fld.x_mm, fld.p_MPa[j], where="mid", color="C0", label=f"p(x) on the line y = {fld.y_mm[j]:.2f} mm")
    if np.any(fld.u_layer_mm != 0):
        ax3 = ax2.twinx()
        ax3.plot(fld.x_mm, 1e3 * fld.u_layer_mm[j], color="C3", lw=1.0, label="layer displacement u$_L$")
        ax3.set_ylabel("u$_L$ [µm]", color="C3")
    ax2.axvline(0.0, color="0.6", lw=0.6)
    ax2.set_xlim(xe[0], xe[-1])
    ax2.set_xlabel("x [mm]")
    ax2.set_ylabel("p [MPa]")
    ax2.legend(loc="upper left", fontsize=8, frameon=False)
    it = sol.iterations
    ax.set_title(f"{title}\nexact solver: {it['grid_cells'][0]} x {it['grid_cells'][1]} cells of "
                 f"{it['cell_mm'][0]:.3f} x {it['cell_mm'][1]:.3f} mm, p$_{{max}}$ = {sol.p_max_MPa:.0f} MPa, "
                 f"area {sol.area_mm2:.1f} mm$^2$, delta = {sol.delta_mm:.5f} mm", fontsize=9)
    save_figure(fig, path)
    return path


def write_scene_plots(run, out_dir: str | Path) -> list[Path]:
    """All pictures of a run into ``out_dir``; returns their paths."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    title = run.scene.title
    hertz = hertz_semi_axes(run.scene)
    snaps = [run.first] if run.last.number == run.first.number else [run.first, run.last]
    paths = [plot_patch(snap, out / f"patch_pass{snap.number}.png", f"{title}: pass {snap.number}", hertz)
             for snap in snaps]
    for snap in snaps:
        if getattr(snap.solution, "field", None) is not None:
            paths.append(plot_exact_field(snap, out / f"exact_pressure_pass{snap.number}.png",
                                          f"{title}: pass {snap.number}", hertz))
    paths.append(plot_separation(run, out / "separation.png"))
    if len(run.history) > 1:
        paths.append(plot_shakedown(run, out / "shakedown.png"))
    return paths
