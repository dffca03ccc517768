"""CSV tables and pictures of a contact-geometry analysis (units in every column name: mm, rad, - for none).

``geometry.csv``: one row per lateral displacement; ``conicity.csv``: one row per amplitude; pictures
``delta_r.png`` (Delta r, Delta tan gamma, roll), ``contact_points.png`` (contact positions on the rail and the
wheel against the lateral displacement, jumps marked, and where they lie on the profiles) and ``conicity.png``
(equivalent conicity against the amplitude, both methods). Every file is written atomically.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from contact.geometry.analysis import GeometryResult
from contact.geometry.jumps import jump_steps
from wrlayer.atomic_write import atomic_write_text

SIDES = ("right", "left")


def _side_columns(result: GeometryResult) -> list[tuple[str, np.ndarray]]:
    cols = []
    for side in SIDES:
        s = getattr(result.sweep, side)
        cols += [(f"y_rail_{side}_mm", s.y_rail_mm), (f"y_wheel_{side}_mm", s.y_wheel_mm),
                 (f"Y_{side}_mm", s.Y_mm), (f"Z_{side}_mm", s.Z_mm),
                 (f"contact_angle_{side}_rad", s.contact_angle_rad), (f"rolling_radius_{side}_mm", s.rolling_radius_mm),
                 (f"next_gap_{side}_mm", s.next_gap_mm),
                 (f"jump_{side}_-", jump_steps(s.y_rail_mm, s.y_wheel_mm, result.jump_mm).astype(int))]
    return cols


def geometry_columns(result: GeometryResult) -> list[tuple[str, np.ndarray]]:
    """(name, values) of ``geometry.csv``'s columns."""
    s = result.sweep
    return [("lateral_mm", s.lateral_mm), ("delta_r_mm", s.delta_r_mm), ("delta_tan_gamma_-", s.delta_tan_gamma),
            ("roll_rad", s.roll_rad), ("roll_parameter_-", s.roll_parameter)] + _side_columns(result)


def conicity_columns(result: GeometryResult) -> list[tuple[str, np.ndarray]]:
    """(name, values) of ``conicity.csv``'s columns."""
    c = result.conicity
    return [("amplitude_mm", c.amplitude_mm), ("equivalent_conicity_-", c.equivalent_conicity),
            ("harmonic_conicity_-", c.harmonic_conicity), ("wavelength_mm", c.wavelength_mm)]


def _csv_text(columns: list[tuple[str, np.ndarray]], comment: str) -> str:
    buf = io.StringIO()
    buf.write(f"# {comment}\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([name for name, _ in columns])
    for row in zip(*(v for _, v in columns)):
        w.writerow(["" if isinstance(v, float | np.floating) and not np.isfinite(v) else
                    (f"{v:.10g}" if isinstance(v, float | np.floating) else str(v)) for v in row])
    return buf.getvalue()


def _header(result: GeometryResult) -> str:
    p, lay = result.profiles, result.layout
    left = "" if p.left_wheel is None and p.left_rail is None else " (left side: its own profiles)"
    return (f"wheel {p.wheel.name} on rail {p.rail.name}{left}; gauge {lay.gauge_mm:g} mm, inclination "
            f"{lay.inclination_rad:.6g} rad, back-to-back {lay.back_to_back_mm:g} mm, nominal radius "
            f"{lay.nominal_radius_mm:g} mm; e0 = {result.sweep.e0_mm:.4f} mm, r0 = {result.sweep.r0_mm:.4f} mm")


def write_tables(result: GeometryResult, out: Path) -> list[Path]:
    """``geometry.csv`` and ``conicity.csv`` in ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    head = _header(result)
    return [atomic_write_text(out / "geometry.csv", _csv_text(geometry_columns(result), head)),
            atomic_write_text(out / "conicity.csv", _csv_text(
                conicity_columns(result), head + "; equivalent_conicity: EN 15302 kinematic wavelength, "
                "harmonic_conicity: harmonic linearisation"))]


def write_pictures(result: GeometryResult, out: Path) -> list[Path]:
    """The three PNG pictures in ``out`` (matplotlib, Agg)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from wrlayer.plotting import save_figure

    s, c = result.sweep, result.conicity
    y = s.lateral_mm
    paths = []
    fig, ax = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    ax[0].plot(y, s.delta_r_mm)
    ax[0].set_ylabel("Δr = r_right − r_left [mm]")
    ax[1].plot(y, s.delta_tan_gamma)
    ax[1].set_ylabel("tan γ_right − tan γ_left [-]")
    ax[2].plot(y, s.roll_rad * 1e3)
    ax[2].set_ylabel("roll angle φ [mrad]")
    ax[2].set_xlabel("lateral displacement y of the wheelset [mm] (+ towards the right rail)")
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle(_title(result))
    fig.tight_layout()
    paths.append(save_figure(fig, out / "delta_r.png"))

    fig, ax = plt.subplots(2, 2, figsize=(10, 7))
    for k, side in enumerate(SIDES):
        sd = getattr(s, side)
        jumps = jump_steps(sd.y_rail_mm, sd.y_wheel_mm, result.jump_mm)
        for body, q in (("rail", sd.y_rail_mm), ("wheel", sd.y_wheel_mm)):
            ax[0, k].plot(y, q, ".", ms=2, label=body)
            ax[0, k].plot(y[jumps], q[jumps], "rx", ms=6)
        ax[0, k].set_title(f"{side} wheel (x: after a jump > {result.jump_mm:g} mm)")
        ax[0, k].set_xlabel("lateral displacement y [mm]")
        ax[0, k].set_ylabel("contact position on the profile [mm]")
        ax[0, k].legend(fontsize=8)
        ax[0, k].grid(alpha=0.3)
        rail, wheel = result.profiles.side(side)
        _profile_with_points(ax[1, k], rail, sd.y_rail_mm, y, "rail")
        _profile_with_points(ax[1, k], wheel, sd.y_wheel_mm, y, "wheel", offset=-25.0, colorbar=True)
        ax[1, k].set_xlabel("profile coordinate [mm] (+ field side)")
        ax[1, k].set_ylabel("z [mm] (wheel shifted −25 mm)")
    fig.suptitle(_title(result))
    fig.tight_layout()
    paths.append(save_figure(fig, out / "contact_points.png"))

    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(c.amplitude_mm, c.equivalent_conicity, "o-", label="kinematic wavelength (EN 15302 definition)")
    ax.plot(c.amplitude_mm, c.harmonic_conicity, "s--", ms=4, label="harmonic linearisation")
    ax.set_xlabel("amplitude ŷ [mm]")
    ax.set_ylabel("equivalent conicity tan γe [-]")
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(_title(result), fontsize=9)
    fig.tight_layout()
    paths.append(save_figure(fig, out / "conicity.png"))
    return paths


def _title(result: GeometryResult) -> str:
    lay = result.layout
    return (f"{result.profiles.wheel.name} on {result.profiles.rail.name}, gauge {lay.gauge_mm:g} mm, "
            f"inclination {lay.inclination_rad:.4g} rad")


def _profile_with_points(ax, profile, q, lateral, label, offset=0.0, colorbar=False):
    yy = np.linspace(profile.y_min, profile.y_max, 600)
    ax.plot(yy, profile.z(yy) + offset, "k-", lw=0.8)
    sc = ax.scatter(q, profile.z(q) + offset, c=lateral, s=8, cmap="coolwarm", zorder=3)
    ax.text(yy[0], float(profile.z(yy[0])) + offset, f" {label}", fontsize=8, va="bottom")
    if colorbar:
        ax.figure.colorbar(sc, ax=ax, label="lateral y [mm]")


def write_geometry(result: GeometryResult, out: str | Path, pictures: bool = True) -> list[Path]:
    """Tables and (with ``pictures``) pictures of ``result`` in the folder ``out``; returns the paths."""
    out = Path(out)
    paths = write_tables(result, out)
    return paths + (write_pictures(result, out) if pictures else [])


__all__ = ["conicity_columns", "geometry_columns", "write_geometry", "write_pictures", "write_tables"]
