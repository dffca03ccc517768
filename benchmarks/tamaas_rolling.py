"""Rolling reference with Tamaas: a circular Hertz pressure moved pass after pass across a periodic elastic-plastic
half-space (Fourier-accelerated volume-integral method, Frérot et al. 2019; see ``benchmarks/tamaas_reference.py``
for the library, its conventions and the checks of how it is driven).

Problem (units mm, MPa): the prescribed pressure p0 sqrt(1 - (r/a)^2) of a frictionless circular contact, no
indenter. The periodic cell (period L in x and y, plastic layer 0 <= z <= Lz) is the grid of ``TamaasSettings``.

* Rolling: the load is raised at x = 0 (the cell edge) in the static load path's steps (one elastic step to
  1.5 Y, then 0.1 Y), then moved in steps of ``step_a`` a along x; a pass is one period L (the load comes back to
  x = 0, where the next pass starts). Each step is one Tamaas increment whose traction is the pressure at the new
  centre minus the one at the old centre (the pressure is evaluated analytically at any centre, so steps shorter
  than the grid spacing are possible); the plastic state is committed after each step and kept between passes.
* Groove after a pass: the inelastic surface displacement (Mindlin operator of C : eps_p, the load's elastic
  part excluded), mean over the centreline points with |x - L/2| <= a/2 (half a period from where the load
  stands between passes) minus the mean over the same x on the line y = 0, L/2 to the side (the far field of
  a periodic cell).
* Static dent at the same p0: a fresh cell loaded at the centre in the same steps and unloaded in one step; the
  dent is u_pl(centre) - u_pl(corner) as in ``tamaas_reference``, the centreline window mean is also recorded.

Method differences to the FEM of ``calibration.rolling``: periodic cell (every pass also sees the load's images
in the neighbouring cells, and the track has no start or end) against a finite clamped block with the load
ramped at the track's start; far field at L/2 to the side against the block's far field; isotropic hardening only;
a regular grid and one return mapping per increment (the plain-step error of a step of ``step_a``).

``python benchmarks/tamaas_rolling.py --out out/tamaas_rolling [--tiny]`` runs the cases; each is cached as
``OUT/<case>.json`` (delete to rerun).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import pathlib
import sys
import time
from typing import Any

import numpy as np

from benchmarks.tamaas_reference import TamaasSettings, load_steps, tamaas_version

#: Johnson's first-yield pressure of a circular Hertz contact for nu = 0.3 (p_y / Y; Johnson 1985, eq. 3.46)
PY_OVER_Y = 1.61
#: p0 / p_y of the reference levels
LEVELS = (1.3, 1.7, 2.1)


@dataclasses.dataclass(frozen=True)
class RollingCase:
    """One Tamaas rolling case.

    Attributes
    ----------
    name : str
        Case name, the cache file's stem (-).
    level_py : float
        Peak pressure p0 / p_y, p_y = 1.61 Y (-).
    hardening_MPa : float
        Linear isotropic hardening modulus (MPa; 0: elastic-perfectly plastic).
    dx_a : float
        Grid spacing / a in x, y and z (-).
    period_a : float
        Period L / a of the cell (-).
    depth_a : float
        Depth Lz / a of the plastic layer (-).
    step_a : float
        Load step along the track / a (-).
    passes : int
        Number of passes, each one period (-).
    """

    name: str
    level_py: float
    hardening_MPa: float = 0.0
    dx_a: float = 0.25
    period_a: float = 8.0
    depth_a: float = 2.0
    step_a: float = 0.25
    passes: int = 3

    def settings(self) -> TamaasSettings:
        return TamaasSettings(period_a=self.period_a, dx_a=self.dx_a, depth_a=self.depth_a,
                              hardening_MPa=self.hardening_MPa)

    def p0_over_Y(self) -> float:
        return self.level_py * PY_OVER_Y


class Cell:
    """A Tamaas periodic cell with its J2 isotropic-hardening material and DF-SANE solver."""

    def __init__(self, s: TamaasSettings):
        import tamaas as tm  # optional dependency: imported only when a case is run
        from tamaas.nonlinear_solvers import DFSANECXXSolver

        tm.set_log_level(tm.LogLevel.warning)
        self.tm, self.s = tm, s
        self.n, self.nz = s.n_xy, s.n_z
        self.length = s.period_a * s.a_mm
        self.model = tm.ModelFactory.createModel(tm.model_type.volume_2d, [s.depth_a * s.a_mm, self.length,
                                                                           self.length], [self.nz, self.n, self.n])
        self.model.E, self.model.nu = s.E_MPa, s.poisson
        # material and residual are kept: the C++ solver refers to them
        self.material = tm.materials.IsotropicHardening(self.model, sigma_y=s.yield_MPa, hardening=s.hardening_MPa)
        self.residual = tm.Residual(self.model, self.material)
        self.solver = DFSANECXXSolver(self.residual)
        self.solver.tolerance = s.tolerance
        self.x = np.arange(self.n) * self.length / self.n
        self.gx, self.gy = np.meshgrid(self.x, self.x, indexing="ij")
        self.c = self.n // 2

    def shape(self, xc: float) -> np.ndarray:
        """Unit Hertz pressure centred at (xc, L/2), periodic in x."""
        dx = (self.gx - xc + 0.5 * self.length) % self.length - 0.5 * self.length
        r2 = (dx ** 2 + (self.gy - self.x[self.c]) ** 2) / self.s.a_mm ** 2
        return np.sqrt(np.clip(1.0 - r2, 0.0, None))

    def increment(self, traction: np.ndarray) -> None:
        """Solve one increment with the normal traction increment ``traction`` (MPa) and commit it."""
        self.model.traction[...] = 0.0
        self.model.traction[..., 2] = traction
        self.solver.solve()
        self.solver.updateState()

    def u_pl_surface(self) -> np.ndarray:
        """Inelastic surface displacement u_z (mm, > 0 into the body): Mindlin operator of C : eps_p."""
        eps_p = np.ascontiguousarray(np.array(self.model["plastic_strain"]))
        eig = np.zeros_like(eps_p)
        self.model.operators["hooke"](eps_p, eig)
        u = np.zeros(eps_p.shape[:-1] + (3,))
        self.model.operators["mindlin"](eig, u)
        return u[0, :, :, 2]

    def groove(self, u: np.ndarray) -> float:
        """Mean of u over the centreline window |x - L/2| <= a/2 minus the same window on y = 0 (mm)."""
        win = np.abs(self.x - self.x[self.c]) <= 0.5 * self.s.a_mm + 1e-12
        return float(u[win, self.c].mean() - u[win, 0].mean())

    def max_cum_plastic(self) -> float:
        return float(np.array(self.model["cumulated_plastic_strain"]).max())

    def zone_bottom_a(self) -> float:
        cum = np.array(self.model["cumulated_plastic_strain"])
        layers = np.flatnonzero((cum > 0).reshape(self.nz, -1).any(axis=1))
        return float(layers[-1] * self.s.depth_a / (self.nz - 1)) if layers.size else float("nan")

    def ramp(self, xc: float, f_Y: float) -> None:
        """Raise the pressure at centre xc from zero to p0 = f_Y Y in the static load path's steps."""
        prev, shape = 0.0, self.shape(xc)
        for f in load_steps((f_Y,), 0.1, min(1.5, f_Y)):
            self.increment((f - prev) * self.s.yield_MPa * shape)
            prev = f


def static_dent(case: RollingCase) -> dict:
    """Load up at the centre and unload: the dent (centre minus corner) and the centreline-window groove (mm)."""
    cell = Cell(case.settings())
    f = case.p0_over_Y()
    xc = cell.x[cell.c]
    cell.ramp(xc, f)
    cell.increment(-f * cell.s.yield_MPa * cell.shape(xc))
    u = cell.u_pl_surface()
    c = cell.c
    return {"dent_mm": float(u[c, c] - u[0, 0]), "window_mm": cell.groove(u),
            "zone_bottom_a": cell.zone_bottom_a()}


def roll(case: RollingCase, progress=None) -> dict:
    """Passes of the load across the periodic cell: the groove (mm) after each pass and after the final unloading."""
    cell = Cell(case.settings())
    f = case.p0_over_Y()
    p0 = f * cell.s.yield_MPa
    n_steps = int(round(case.period_a / case.step_a))
    if abs(n_steps * case.step_a - case.period_a) > 1e-9:
        raise ValueError(f"period_a / step_a must be an integer, got {case.period_a / case.step_a}")
    ds = case.step_a * cell.s.a_mm
    cell.ramp(0.0, f)
    grooves, secs, cum = [], [], []
    for p in range(case.passes):
        t0 = time.perf_counter()
        old = cell.shape(0.0)
        for k in range(1, n_steps + 1):
            new = cell.shape((k * ds) % cell.length)
            cell.increment(p0 * (new - old))
            old = new
        grooves.append(cell.groove(cell.u_pl_surface()))
        secs.append(time.perf_counter() - t0)
        cum.append(cell.max_cum_plastic())
        if progress:
            progress(f"  {case.name} pass {p + 1}: groove {grooves[-1] * 1e3:.5f} um, {secs[-1]:.0f} s")
    cell.increment(-p0 * cell.shape(0.0))
    return {"groove_mm": grooves, "groove_unloaded_mm": cell.groove(cell.u_pl_surface()), "pass_seconds": secs,
            "max_cum_plastic": cum, "zone_bottom_a": cell.zone_bottom_a(), "steps_per_pass": n_steps}


def run_case(case: RollingCase, folder: pathlib.Path, progress=None) -> dict:
    """Run (or read from ``folder/<name>.json``) one case: static dent and rolling passes."""
    path = folder / f"{case.name}.json"
    if path.exists():
        return json.loads(path.read_text())
    t0 = time.perf_counter()
    static = static_dent(case)
    t1 = time.perf_counter()
    rolling = roll(case, progress)
    s = case.settings()
    out = {"case": dataclasses.asdict(case), "p0_MPa": case.p0_over_Y() * s.yield_MPa,
           "p_y_MPa": PY_OVER_Y * s.yield_MPa, "grid": {"n_xy": s.n_xy, "n_z": s.n_z},
           "static": static, "rolling": rolling, "static_seconds": t1 - t0,
           "seconds": time.perf_counter() - t0, "load_average": list(os.getloadavg()),
           "tamaas_version": tamaas_version()}
    folder.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=1))
    return out


def cases(mode: str) -> list[RollingCase]:
    """tiny: a/2 grid and step, 2 passes (pipeline check); coarse: a/4 grid, step a/8, 5 passes, the three EPP
    levels and 2.1 p_y with H_iso = 10 GPa; fine: also a plastic layer 3 a deep at 2.1 p_y, the step a/16 at 1.7 and
    2.1 p_y (2 passes), the a/8 grid at 1.7 and 2.1 p_y, 3 passes (convergence checks)."""
    if mode == "tiny":
        return [RollingCase(f"tiny_L{lv}", lv, dx_a=0.5, step_a=0.5, passes=2) for lv in (0.9, 1.7)]
    out = [RollingCase(f"coarse_L{lv}", lv, step_a=0.125, passes=5) for lv in LEVELS]
    out.append(RollingCase("coarse_L2.1_H10000", 2.1, hardening_MPa=10000.0, step_a=0.125, passes=5))
    if mode == "fine":
        out += [RollingCase("coarse_L2.1_Lz3", 2.1, depth_a=3.0, step_a=0.125),
                *(RollingCase(f"coarse_L{lv}_s16", lv, step_a=0.0625, passes=2) for lv in (1.7, 2.1)),
                RollingCase("fine_L1.7", 1.7, dx_a=0.125, step_a=0.125),
                RollingCase("fine_L2.1", 2.1, dx_a=0.125, step_a=0.125)]
    return out


def _pct(a: float, b: float) -> str:
    return f"{100.0 * (a / b - 1.0):+.1f} %" if b > 0 else "-"


def markdown(results: list[dict]) -> list[str]:
    """The table of the docs: grid, static dent, grooves after each pass, ratio and per-pass increments."""
    md = ["| p0 / p_y | H_iso (MPa) | grid dx | step | static dent (mm) | groove after each pass (mm) | "
          "groove / static | pass 2 adds | pass 3 adds | last pass adds | plastic zone bottom | s per pass |",
          "|" + "---|" * 12]
    for r in results:
        c, g = r["case"], r["rolling"]["groove_mm"]
        dent = r["static"]["dent_mm"]
        ratio = f"{g[0] / dent:.3f}" if dent > 0 else "-"
        adds = [_pct(g[k], g[k - 1]) if len(g) > k else "-" for k in (1, 2, len(g) - 1)]
        md.append(f"| {c['level_py']:g} | {c['hardening_MPa']:g} | a/{1 / c['dx_a']:g} | a/{1 / c['step_a']:g} | "
                  f"{dent:.4g} | {', '.join(f'{x:.4g}' for x in g)} | {ratio} | {adds[0]} | {adds[1]} | "
                  f"{adds[2]} | {r['rolling']['zone_bottom_a']:g} a | {np.mean(r['rolling']['pass_seconds']):.0f} |")
    return md


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python benchmarks/tamaas_rolling.py", description=__doc__.splitlines()[0])
    ap.add_argument("--mode", choices=("tiny", "coarse", "fine"), default="coarse")
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/tamaas_rolling"))
    args = ap.parse_args(argv)
    results = [run_case(c, args.out, progress=lambda s: print(s, flush=True)) for c in cases(args.mode)]
    print("\n".join(markdown(results)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
