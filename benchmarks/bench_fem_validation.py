"""FEM validation: 3D elastic-plastic half-space under a prescribed circular Hertz pressure.

Problem (units mm, N, MPa): quarter block 20 mm (unstructured gmsh P2 tetrahedra, element size h within 1.5 mm of
the load centre), circular Hertz pressure p0 sqrt(1 - (r/a)^2) with a = 1 mm, far faces clamped, symmetry planes
x = 0 and y = 0; steel E = 210 GPa, nu = 0.3, Y = 500 MPa, either elastic-perfectly plastic or with the
calibration's linear hardening (H_iso = H_kin = 10 GPa, `calibration/configs/default.toml`), or isotropic
hardening only (H_iso = 10 GPa or 20 GPa, H_kin = 0, for the comparison with Tamaas). The pressure is
prescribed (no indenter): p0 rises to the levels below in steps of at most 0.1 Y, and the body is
unloaded to zero from some of them (one step, restarted from the loaded state).

Independent references: (1) the closed-form Hertz stresses on the load axis (K. L. Johnson, Contact Mechanics,
Cambridge University Press 1985, eq. 3.45, p. 62; evaluated by
`calibration.fem.verification_meshes.hertz_axis_first_yield`) give the pressure and depth of first yield; (2) the
elastic-plastic response (residual dent, plastic-zone top and bottom) is compared with the same load path solved
by Tamaas, the Fourier-accelerated volume-integral method of Frérot, Bonnet, Molinari & Anciaux (CMAME 351, 951,
2019; `benchmarks/tamaas_reference.py`), for elastic-perfectly plastic and isotropic hardening (H_iso = 10 GPa,
H_kin = 0). Tamaas has no kinematic hardening; the calibration's mixed law (H_iso = H_kin = 10 GPa) is compared
with Tamaas' isotropic hardening of the summed modulus, H = 20 GPa, which it equals wherever the stress path of a
point is proportional (the back stress and the yield radius then grow along one direction: the uniaxial slope is
H_iso + H_kin either way); how far the Hertz load path is from that is measured on our FEM (mixed against isotropic
20 GPa on the same mesh). No published table or figure of this response could be read (docs/fem-engine.md, "Validated accuracy").
If Tamaas is not installed, the report says so and gives the FEM values alone.
"""

from __future__ import annotations

import json
import pathlib
import time

from benchmarks.fem_validation_cases import (BLOCK_MM, FINE_MM, LEVELS_Y, MATERIALS, STEP_Y, UNLOAD_Y, ValidationRun,
                                             elastic_reference, load_path, tamaas_reference)
from benchmarks.fem_validation_report import markdown, plot
from benchmarks.harness import machine_info
from calibration.fem.assembly import discretise
from calibration.fem.verification_meshes import hertz_axis_first_yield, hertz_block_gmsh


def run(mode: str, out: pathlib.Path) -> dict:
    """Benchmark entry point (``python -m benchmarks --only fem_validation``). One BLAS/MKL thread, as in the
    calibration's workers (docs/calibration.md: more threads than free cores cost 2.5x on this machine)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):
        return _run(mode, out)


def _solve_meshes(hs, levels, unload, step_y: float) -> tuple[dict, dict, dict]:
    """Elastic reference and every material's load path on each mesh h: (elastic, cases, meshes)."""
    elastic, cases, meshes = {}, {}, {}
    for h in hs:
        t0 = time.perf_counter()
        mesh = hertz_block_gmsh(h, FINE_MM, BLOCK_MM, order=2, dim=3)
        disc = discretise(mesh)
        elastic[h] = elastic_reference(disc, mesh)
        meshes[h] = {"n_dofs": int(disc.n_dofs), "n_elements": int(mesh.t.shape[1]),
                     "setup_s": time.perf_counter() - t0}
        for name, mat in MATERIALS.items():
            t1 = time.perf_counter()
            cases[(name, h)] = load_path(disc, mesh, mat, levels, unload, step_y,
                                         elastic[h]["compliance_mm_per_MPa"])
            meshes[h][f"{name} s"] = time.perf_counter() - t1
    return elastic, cases, meshes


def _step_check(h: float, levels, unload, step_y: float, c_el: float) -> dict:
    """Load-step check: every material on mesh ``h`` with half the step."""
    mesh = hertz_block_gmsh(h, FINE_MM, BLOCK_MM, order=2, dim=3)
    disc = discretise(mesh)
    return {name: load_path(disc, mesh, mat, levels, unload, step_y / 2, c_el) for name, mat in MATERIALS.items()}


def _data(res: ValidationRun) -> dict:
    """The JSON data of the report."""
    hs, tam = res.hs, res.tam
    tam_data = {k: v for k, v in tam.items() if k != "runs"}
    tam_data["runs"] = {f"{name} | grid {i}": v for (name, i), v in tam.get("runs", {}).items()}
    tam_data["time_s"] = res.t_tam
    return {"reference": {"first_yield_over_Y": res.ref_fy, "depth_over_a": res.ref_depth,
                          "source": "Johnson 1985 eq. 3.45 (axis stresses), evaluated numerically"},
            "meshes": {str(h): res.meshes[h] for h in hs}, "step_Y": res.step_y,
            "elastic": {str(h): {k: v for k, v in res.elastic[h].items() if not k.startswith("axis_")} for h in hs},
            "cases": {f"{name} | h={h}": rows for (name, h), rows in res.cases.items()},
            "step_check": res.step_check, "tamaas": tam_data, "machine": machine_info()}


def _run(mode: str, out: pathlib.Path) -> dict:
    out = pathlib.Path(out)
    quick = mode == "quick"
    # quick: the two coarser meshes (under a minute on 2 busy cores); full: the numbers of the docs and a step check
    hs = (0.35, 0.25) if quick else (0.25, 0.18, 0.13)
    step_y = STEP_Y
    levels = LEVELS_Y if quick else LEVELS_Y + (3.2, 3.4)
    unload = UNLOAD_Y if quick else UNLOAD_Y + (3.4,)
    ref_fy, ref_depth = hertz_axis_first_yield(0.3)
    elastic, cases, meshes = _solve_meshes(hs, levels, unload, step_y)
    step_check = ({} if quick else
                  _step_check(hs[-2], levels, unload, step_y, elastic[hs[-2]]["compliance_mm_per_MPa"]))
    t_tam = time.perf_counter()
    tam = tamaas_reference(quick)
    t_tam = time.perf_counter() - t_tam
    res = ValidationRun(hs=hs, step_y=step_y, ref_fy=ref_fy, ref_depth=ref_depth, elastic=elastic, meshes=meshes,
                        cases=cases, step_check=step_check, tam=tam, t_tam=t_tam)
    fig = plot(res, out)
    data = _data(res)
    json.dumps(data)  # must be serialisable
    return {"title": "FEM validation: elastic-plastic half-space under a Hertz pressure",
            "markdown": markdown(res, __doc__.split("\n\n", 1)[1].strip()), "figures": [fig], "data": data}
