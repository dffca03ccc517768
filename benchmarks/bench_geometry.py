"""Wheel–rail geometry benchmark: run time of a whole lateral sweep, load balance, separation-function accuracy, and
the analytic S1002/60E1 profiles against the Manchester-benchmark SIMPACK files (units mm, N, MPa, s).

The sweep is the Manchester A-2.2 set-up (S1002 on 60E1 at 1:40, gauge 1435, back-to-back 1360, r0 = 460 mm,
10 kN per wheel, friction 0.3, G = 82 GPa, nu = 0.28, V = 2000 mm/s) with lateral displacement 0..10 mm in 0.5 mm
steps together with yaw 0..24 mrad (21 cases).
"""

from __future__ import annotations

import math
import pathlib
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from benchmarks.harness import machine_info, median_time, peak_memory_mb
from contact.wheel_rail.contact_search import search_contacts
from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose, place_rail
from contact.wheel_rail.deformed import rigid_roll
from contact.scenes.sections import MaterialSpec
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.solve import solve_wheel
from meshes.profiles import S1002, Rail60E1, get_profile
from wrlayer.plotting import save_figure

E_MPA = 2.0 * 82000.0 * 1.28
LATERAL = np.arange(21) * 0.5
YAW = np.arange(21) * 0.0012
REFERENCE = pathlib.Path(__file__).resolve().parents[2] / "shared" / "reference" / "profiles"


def _inputs(d: float, psi: float, side: str = "right", roll: float = 0.0) -> WheelRailInputs:
    return WheelRailInputs(pose=WheelsetPose(float(d), float(psi), roll), side=side,
                           material=MaterialSpec(E_MPa=E_MPA, poisson=0.28))


def _sweep(rail, wheel, placed, layout, yaw=True, side="right"):
    return [solve_wheel(rail, wheel, _inputs(d, psi if yaw else 0.0, side), placed_rail=placed)
            for d, psi in zip(LATERAL, YAW)]


def _sweep_both_with_roll(rail, wheel, placed, layout):
    out = []
    for d, psi in zip(LATERAL, YAW):
        roll = rigid_roll(placed, wheel, layout, WheelsetPose(float(d), float(psi)))
        out.append([solve_wheel(rail, wheel, _inputs(d, psi, side, roll), placed_rail=placed)
                    for side in ("right", "left")])
    return out


def _search_only(wheel, placed, layout):
    for d, psi in zip(LATERAL, YAW):
        search_contacts(placed, wheel, layout, WheelsetPose(float(d), float(psi)))


def _separation_error(sols, placed) -> float:
    """Largest |distance| of the rail points found on the contact-plane normal lines from the rail profile (mm)."""
    worst = 0.0
    a = -placed.angle_rad
    cs, sn = math.cos(a), math.sin(a)
    for sol in sols:
        for c in sol.search.candidates:
            eta = c.eta_mm[:: max(1, c.eta_mm.size // 40)]
            rp = placed.point(c.rail_coordinate(eta)) - np.array([placed.dy_mm, placed.dz_mm])
            pts = np.column_stack([cs * rp[:, 0] - sn * rp[:, 1], sn * rp[:, 0] + cs * rp[:, 1]])
            d, _ = placed.profile.signed_distance(pts)
            worst = max(worst, float(np.max(np.abs(d))))
    return worst


def _main_patch(sol):
    return max(sol.patches, key=lambda p: p.normal_force_N)


def _timings(rail, wheel, placed, layout, repeat: int) -> dict:
    """Wall and CPU times (s) of the sweep, the search alone and both wheels with roll; heap peak (MiB) and the
    accuracy checks of one sweep."""
    t_sweep, _ = median_time(lambda: _sweep(rail, wheel, placed, layout), repeat=repeat)
    t_search, _ = median_time(lambda: _search_only(wheel, placed, layout), repeat=repeat)
    t_both, _ = median_time(lambda: _sweep_both_with_roll(rail, wheel, placed, layout), repeat=max(1, repeat // 2))
    sols, peak_mb = peak_memory_mb(lambda: _sweep(rail, wheel, placed, layout))
    cpu = []
    for _ in range(repeat):  # CPU time of this process: insensitive to the other jobs on a shared machine
        c0 = time.process_time()
        _sweep(rail, wheel, placed, layout)
        cpu.append(time.process_time() - c0)
    return {"sweep_s": t_sweep, "search_s": t_search, "both_wheels_roll_s": t_both,
            "sweep_cpu_s": float(np.median(cpu)), "peak_heap_MiB": peak_mb,
            "balance_rel_max": max(s.vertical_balance_rel for s in sols),
            "separation_rail_distance_max_mm": _separation_error(sols, placed),
            "two_patch_cases": sum(1 for s in sols if len(s.patches) > 1)}


def _profile_comparison(rail, wheel, placed, layout) -> list[dict]:
    """The analytic profiles against the Manchester SIMPACK files (no yaw, right wheel); empty without the files."""
    comparison = []
    if not (REFERENCE / "MBench_UIC60_v3.prr").is_file():
        return comparison
    rail_f = get_profile(str(REFERENCE / "MBench_UIC60_v3.prr"))
    wheel_f = get_profile(str(REFERENCE / "MBench_S1002_v3.prw"))
    layout_f = TrackLayout(inclination_rad=0.0)  # the file's head is canted already
    placed_f = place_rail(rail_f, layout_f)
    a_sols = _sweep(rail, wheel, placed, layout, yaw=False)
    f_sols = _sweep(rail_f, wheel_f, placed_f, layout_f, yaw=False)
    for d, sa, sf in zip(LATERAL, a_sols, f_sols):
        pa, pf = _main_patch(sa), _main_patch(sf)
        comparison.append({
            "lateral_mm": float(d),
            "Y_analytic_mm": float(pa.point_track[1]), "Y_file_mm": float(pf.point_track[1]),
            "y_wheel_analytic_mm": pa.candidate.y_wheel_mm, "y_wheel_file_mm": pf.candidate.y_wheel_mm,
            "angle_analytic_deg": math.degrees(pa.candidate.contact_angle_rad),
            "angle_file_deg": math.degrees(pf.candidate.contact_angle_rad),
            "p_max_analytic_MPa": pa.normal.p_max_MPa, "p_max_file_MPa": pf.normal.p_max_MPa,
            "n_patches_analytic": len(sa.patches), "n_patches_file": len(sf.patches)})
    return comparison


def _plot_comparison(comparison: list[dict], out: pathlib.Path) -> str:
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    d = [c["lateral_mm"] for c in comparison]
    for ax, key, label in ((axes[0], "Y", "contact point Y on the rail (track, mm)"),
                           (axes[1], "angle", "contact angle (deg)"), (axes[2], "p_max", "p_max (MPa)")):
        suffix = "_mm" if key == "Y" else ("_deg" if key == "angle" else "_MPa")
        ax.plot(d, [c[f"{key}_analytic{suffix}"] for c in comparison], "o-", ms=4, label="analytic S1002 / 60E1")
        ax.plot(d, [c[f"{key}_file{suffix}"] for c in comparison], "x--", ms=5,
                label="Manchester SIMPACK files")
        ax.set_xlabel("lateral displacement (mm), yaw 0")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    path = out / "geometry_profiles_vs_files.png"
    save_figure(fig, path)
    return str(path)


def _timings_markdown(t: dict, repeat: int) -> list[str]:
    t_sweep = t["sweep_s"]
    return [
        "## Wheel–rail geometry (S1002 on 60E1 at 1:40, Manchester A-2.2 conditions)",
        "",
        ("Whole lateral sweep: 21 cases (lateral 0..10 mm with yaw 0..24 mrad), right wheel, elastic: contact search, "
         "vertical load balance, Kik–Piotrowski normal problem and FASTSIM per patch."),
        "",
        "| quantity | value |",
        "|---|---|",
        (f"| sweep of 21 cases (geometry + normal + tangential), median of {repeat} | {t_sweep * 1e3:.0f} ms "
         f"({t_sweep / 21 * 1e3:.1f} ms per case) |"),
        f"| the same sweep, CPU time of this process (median of {repeat}) | {t['sweep_cpu_s'] * 1e3:.0f} ms |",
        f"| contact search only (21 cases) | {t['search_s'] * 1e3:.0f} ms |",
        f"| both wheels with the rigid-wheelset roll (21 cases) | {t['both_wheels_roll_s'] * 1e3:.0f} ms |",
        f"| peak Python heap during one sweep | {t['peak_heap_MiB']:.1f} MiB |",
        f"| largest vertical load balance residual sum N cos(gamma) vs Q (relative) | {t['balance_rel_max']:.1e} |",
        ("| largest distance of the separation's rail points from the exact rail profile "
         f"(reference: `Profile.signed_distance`) | {t['separation_rail_distance_max_mm']:.1e} mm |"),
        f"| cases with two loaded patches | {t['two_patch_cases']} of 21 |",
        "",
        ("Wall-clock timings are taken on a shared 2-core machine (other jobs running): treat them as upper bounds; "
         "the CPU time is the cost of the sweep itself."),
    ]


def _comparison_markdown(comparison: list[dict]) -> list[str]:
    dY = max(abs(c["Y_analytic_mm"] - c["Y_file_mm"]) for c in comparison)
    dA = max(abs(c["angle_analytic_deg"] - c["angle_file_deg"]) for c in comparison)
    lines = [
        "",
        ("Analytic profiles (EN 13715 S1002, EN 13674-1 60E1 canted 1:40) against the Manchester benchmark "
         "SIMPACK files (`MBench_S1002_v3.prw`, `MBench_UIC60_v3.prr`, canted in the file), yaw 0: the reference "
         "is the same sweep on the files."),
        "",
        ("| lateral (mm) | Y analytic / file (mm) | wheel y analytic / file (mm) | angle analytic / file (deg) | "
         "p_max analytic / file (MPa) | patches |"),
        "|---|---|---|---|---|---|",
    ]
    lines += [f"| {c['lateral_mm']:.1f} | {c['Y_analytic_mm']:.2f} / {c['Y_file_mm']:.2f} | "
              f"{c['y_wheel_analytic_mm']:.2f} / {c['y_wheel_file_mm']:.2f} | {c['angle_analytic_deg']:.2f} / "
              f"{c['angle_file_deg']:.2f} | {c['p_max_analytic_MPa']:.0f} / {c['p_max_file_MPa']:.0f} | "
              f"{c['n_patches_analytic']} / {c['n_patches_file']} |" for c in comparison]
    lines += ["", (f"Largest differences: contact point Y {dY:.2f} mm, contact angle {dA:.2f} deg (near a contact "
                   "jump the two nearly equal gap minima can swap, which moves the point by several mm).")]
    return lines


def run(mode: str, out: pathlib.Path) -> dict:
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    repeat = 3 if mode == "quick" else 7
    layout = TrackLayout()
    rail, wheel = Rail60E1(), S1002()
    placed = place_rail(rail, layout)
    timings = _timings(rail, wheel, placed, layout, repeat)
    comparison = _profile_comparison(rail, wheel, placed, layout)
    figures = [_plot_comparison(comparison, out)] if comparison else []
    lines = _timings_markdown(timings, repeat) + (_comparison_markdown(comparison) if comparison else [])
    return {
        "title": "Wheel-rail geometry: sweep run time, load balance, profiles vs Manchester files",
        "markdown": "\n".join(lines) + "\n",
        "figures": figures,
        "data": {**timings, "comparison": comparison, "machine": machine_info()},
    }


if __name__ == "__main__":  # pragma: no cover
    res = run("quick", pathlib.Path("out/bench"))
    print(res["markdown"])
