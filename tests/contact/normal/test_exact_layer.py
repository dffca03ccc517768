"""The exact solver with the Prandtl layer: an independent axisymmetric 1-D check of the indentation mode, the
rolling mode's asymmetry and trailing-edge residual (eq. 8), passes to shakedown, and every shipped scene with
method.normal = "exact". Units: mm, N, MPa."""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import ellipk

from wrlayer.characteristic import Characteristic
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.normal.exact import ExactOptions, solve_exact
from contact.normal.halfspace import compliance_factor
from contact.normal.kik_piotrowski import NormalProblem
from contact.normal.method import NormalMethod
from contact.passes.passes import PassesOptions, run_passes
from contact.scenes.paper_example import paper_characteristic, paper_layers, paper_problem
from contact.scenes.scene import load_scene
from contact.scenes.simulation import simulate

E, NU = 210000.0, 0.3
ROOT = Path(__file__).resolve().parents[3]


# ------------------------------------------------------------------ independent axisymmetric check (indentation)
def _ring_matrix(n: int, dr: float) -> np.ndarray:
    """U[i, j]: displacement (mm) at radius (i + 1/2) dr under a unit pressure on the ring [j dr, (j + 1) dr]:
    C II p / r dA with the angular integral in closed form, int_0^2pi dtheta / |r - s| = 4 K(m) / (r + s),
    m = 4 r s / (r + s)^2 (K: complete elliptic integral of the first kind, parameter m)."""
    rho = (np.arange(n) + 0.5) * dr
    out = np.empty((n, n))

    def integrand(s, r):
        return 4.0 * s * ellipk(4.0 * r * s / (r + s) ** 2) / (r + s)

    for i, r in enumerate(rho):
        for j in range(n):
            a, b = j * dr, (j + 1) * dr
            cuts = [a, r, b] if a < r < b else [a, b]          # the log singularity at s = r as an end point
            out[i, j] = sum(quad(integrand, lo, hi, args=(r,), limit=200)[0] for lo, hi in zip(cuts[:-1], cuts[1:]))
    return compliance_factor(E, NU) * out


def _axisymmetric(R: float, delta: float, ch: Characteristic, n: int, dr: float):
    """Sphere (f = r^2 / 2R) pressed by ``delta`` onto the half-space with the layer ``ch`` in series, on rings:
    grow the contact disk ring by ring; on each disk Newton on f + U p + u_layer(p) = delta (u_layer piecewise
    linear); the disk is the largest one whose pressures are all positive. Returns (p per ring, force)."""
    rho = (np.arange(n) + 0.5) * dr
    U = _ring_matrix(n, dr)
    f = rho ** 2 / (2.0 * R)
    best = None
    for k in range(1, n):
        p = np.full(k, 100.0)
        for _ in range(100):
            res = f[:k] + U[:k, :k] @ p + ch.displacement(p) - delta
            c = (ch.displacement(p + 1e-3) - ch.displacement(p)) / 1e-3        # the segment's compliance
            step = np.linalg.solve(U[:k, :k] + np.diag(c), res)
            p = p - step
            if np.max(np.abs(step)) < 1e-10:
                break
        if not np.all(p > 0):
            break
        best = p
    area = np.pi * ((np.arange(1, n + 1) * dr) ** 2 - (np.arange(n) * dr) ** 2)
    return best, float(np.sum(best * area[: best.size]))


def test_indentation_mode_agrees_with_an_axisymmetric_ring_solution():
    ch = paper_characteristic()
    R, delta = 20.0, 0.05
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                     # quad's roundoff notes near the log singularity
        p1d, force = _axisymmetric(R, delta, ch, n=64, dr=0.04)
    assert p1d.size < 60                                    # the disk ends inside the rings
    y = np.linspace(-5.0, 5.0, 401)
    prob = NormalProblem(y, y * y / (2 * R), force, R, E, NU, grid_mm=0.04)
    layer = LayerPair(combined=PrandtlLayer.uniform(ch, prob.strip_y_mm))
    sol = solve_exact(prob, layer, ExactOptions(cells=64, approach_mm=delta))
    assert sol.normal_force_N == pytest.approx(force, rel=0.01)
    assert sol.p_max_MPa == pytest.approx(p1d[0], rel=0.01)
    a1d = p1d.size * 0.04                                 # outer edge of the last loaded ring (+- one ring)
    assert sol.width_mm / 2 == pytest.approx(a1d, abs=0.04)
    assert p1d[0] > ch.elastic_limit_MPa                # the layer yields: the nonlinear branch is tested


# ------------------------------------------------------------------ rolling mode
def _eq8(ch: Characteristic, p0: np.ndarray) -> np.ndarray:
    """Paper eq. (8): u_p = u_i + (p_0 - p_i)/S_i - p_0/S_1 on the segment i holding p_0 (0 on the first)."""
    u, p = np.asarray(ch.u_mm), np.asarray(ch.p_MPa)
    s = np.diff(p) / np.diff(u)
    i = np.clip(np.searchsorted(p, p0, side="right") - 1, 0, s.size - 1)
    return np.where(i == 0, 0.0, u[i] + (p0 - p[i]) / s[i] - p0 / s[0])


@pytest.fixture(scope="module")
def rolling_and_indentation():
    prob = paper_problem()
    layer = paper_layers(prob)
    return (prob, solve_exact(prob, layer, ExactOptions(cells=32, layer_mode="rolling")),
            solve_exact(prob, layer, ExactOptions(cells=32, layer_mode="indentation")))


def test_rolling_pressure_leans_to_the_leading_edge(rolling_and_indentation):
    """Behind its peak an element unloads on its stiff first branch and keeps a residual dent, so the trailing
    half carries less pressure: the centre of pressure moves to +x (the leading edge); indentation is symmetric."""
    _, roll, ind = rolling_and_indentation
    for sol, sign in ((roll, 1), (ind, 0)):
        x = sol.field.x_mm
        p = sol.field.p_MPa
        xc = float(np.sum(p * x[None, :]) / p.sum())
        if sign:
            assert xc > 0.01 * sol.field.dx_mm
        else:
            assert abs(xc) < 1e-6 * sol.field.dx_mm
    assert roll.delta_mm != ind.delta_mm


def test_rolling_mode_strip_centres_reach_fastsim(rolling_and_indentation):
    """The most loaded line's extent shifts to the leading edge in rolling mode (its trailing part is lifted by the
    residual dent), every line stays centred in indentation mode, and FASTSIM gets each strip's centre (its spin
    slip and Mz use the true x, consistent with the pressure mapped onto the line's extent)."""
    from contact.normal.exact import strip_centres
    from contact.tangential.fastsim import Creepage, solve_tangential

    _, roll, ind = rolling_and_indentation
    c_roll, c_ind = strip_centres(roll, 0), strip_centres(ind, 0)
    assert np.all(np.abs(c_ind) < 1e-9 + 0.5 * ind.field.dx_mm)
    main = int(np.argmax(roll.patches[0].p_peak_MPa))
    assert c_roll[main] > 0.1 * roll.field.dx_mm
    patch = roll.patches[0]
    t = solve_tangential(patch, Creepage(0.0, 0.0, 1e-3), 80769.0, NU, 0.3, nx=30, strip_centre_mm=c_roll)
    np.testing.assert_allclose(t.x_mm.mean(axis=1), c_roll, atol=1e-12)


def test_rolling_trailing_edge_residual_is_eq8_at_the_line_peak(rolling_and_indentation):
    _, roll, _ = rolling_and_indentation
    fld = roll.field
    p0 = fld.p_MPa.max(axis=1)
    residual = fld.u_layer_mm[:, 0]                         # behind the patch (smallest x)
    assert np.all(fld.p_MPa[:, 0] == 0)
    expected = _eq8(paper_characteristic(), p0)
    assert np.max(expected) > 0.005                          # lines yield
    np.testing.assert_allclose(residual, expected, atol=1e-12)


def test_passes_with_the_exact_solver_reach_shakedown():
    prob = paper_problem()
    records, _ = run_passes(prob, paper_layers(prob), PassesOptions(max_passes=60, tolerance_mm=1e-4),
                            method=NormalMethod("exact", exact_cells=24, layer_mode="rolling"))
    assert records[-1].shakedown and 3 < len(records) < 60
    assert records[0].up0_mm > 0.005
    assert records[-1].p_max_MPa < records[0].p_max_MPa
    assert records[-1].p_max_MPa == pytest.approx(1190.0, rel=0.03)     # the elastic limit p_2


# ------------------------------------------------------------------ scenes
def _shipped_kp_scenes():
    out = []
    for path in sorted((ROOT / "scenes").glob("*.toml")):
        text = path.read_text()
        if 'type = "wheel_rail"' in text:
            continue
        out.append(path)
    return out


@pytest.mark.parametrize("path", _shipped_kp_scenes(), ids=lambda p: p.stem)
def test_every_shipped_scene_runs_with_the_exact_solver(path):
    scene = load_scene(path)
    method = dataclasses.replace(scene.method, normal="exact", exact_cells=24)
    scene = dataclasses.replace(scene, method=method, passes=dataclasses.replace(scene.passes,
                                                                                 max=min(scene.passes.max, 3)))
    run = simulate(scene)
    result = run.result.to_dict()
    last = result["passes"][-1]
    assert "exact half-space" in result["method"]["normal"]
    assert last["iterations"]["cg_iterations"] > 0
    assert np.isfinite(last["p_max_MPa"]) and last["p_max_MPa"] > 0
    assert last["normal_force_N"] == pytest.approx(scene.load.normal_force_N, rel=1e-9)


def test_exact_scene_writes_its_pressure_picture(tmp_path):
    from contact.scenes.plots import write_scene_plots

    run = simulate(load_scene(ROOT / "scenes" / "paper_with_layer_rolling.toml"))
    paths = write_scene_plots(run, tmp_path)
    pic = tmp_path / "exact_pressure_pass1.png"
    assert pic in paths and pic.stat().st_size > 10_000
