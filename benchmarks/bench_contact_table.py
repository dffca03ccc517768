"""Contact table for multibody codes: wall time of a wheel–rail sweep written as contact_table.csv, in this process
(``run.workers = 1``) against 2 local worker processes (``run.workers = 2``, one BLAS thread each), and the
speed-up (units s, cases).

Two sweeps of S1002 on 60E1 1:40, both wheels, rigid-wheelset roll:

- "elastic": scenes/wheel_rail_sweep_elastic.toml with its cases replaced by a product of lateral displacement,
  yaw and vertical load (``mode = "product"``; about 0.02-0.06 s per case);
- "layers": scenes/wheel_rail_sweep_layers.toml as shipped (21 cases with the calibrated layers, about 0.5-1.5 s
  per case).

Both with ``output.contact_table = true``, no frictional CSVs (``output.frictional_csv = false``: written by this
process, they take about as long as solving an elastic case), no VTK, no deformed profiles, no pictures. Each
repetition runs a sweep on 1 worker then on 2 workers (interleaved, so that a change of the machine's load hits
both); the 2-worker time includes starting the worker processes. The 1-minute load average before every run is
recorded: this machine's 2 cores are shared, and the kernel shares the CPU between sessions (autogroup), so while
other sessions keep both cores busy the 2 workers get no more CPU than one process.
``python -m benchmarks --only contact_table`` runs it.
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import statistics
import time
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from contact.wheel_rail.contact_table import TABLE_FILE
from contact.wheel_rail.parse import parse_wheel_rail_scene
from contact.run_files import run_wheel_rail_scene
from contact.wheel_rail.scene import RunSpec
from wrlayer.plotting import save_figure

SCENES = pathlib.Path(__file__).resolve().parents[1] / "scenes"
#: The elastic product sweep per mode: lateral displacement {start, stop, step} (mm), yaw angles (rad), vertical
#: loads (N).
ELASTIC = {"quick": ({"start": 0.0, "stop": 8.0, "step": 0.25}, [0.0, 0.002], [10000.0, 20000.0]),
           "full": ({"start": 0.0, "stop": 8.0, "step": 0.25}, [0.0, 0.002, 0.004], [5000.0, 10000.0, 20000.0])}
#: Repetitions of the 1-worker / 2-worker pair per sweep.
REPEAT = {"quick": 2, "full": 4}
#: The table's outputs: the table alone.
OUTPUT = {"contact_table": True, "vtk": False, "deformed_profiles": False, "frictional_csv": False}


def sweep_scene(kind: str, mode: str = "quick"):
    """The benchmark's scene "elastic" or "layers" (see the module docstring)."""
    path = SCENES / ("wheel_rail_sweep_elastic.toml" if kind == "elastic" else "wheel_rail_sweep_layers.toml")
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    if kind == "elastic":
        lateral, yaw, load = ELASTIC[mode]
        data["sweep"] = {"lateral_mm": lateral, "yaw_rad": yaw, "vertical_load_N": load, "mode": "product"}
    data["output"] = dict(OUTPUT)
    return parse_wheel_rail_scene(data, path)


def timed_run(scene, workers: int, out: pathlib.Path) -> dict:
    """One sweep into ``out`` with ``workers``: wall time (s), the load average before it, the table text."""
    scene = dataclasses.replace(scene, run=RunSpec(workers=workers))
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    result = run_wheel_rail_scene(scene, out, plots=False, vtk=False)
    wall = time.perf_counter() - t0
    return {"workers": workers, "wall_s": wall, "load_1min": load, "n_failed": result.n_failed,
            "table": (out / TABLE_FILE).read_text(encoding="utf-8")}


def repetition(scene, out: pathlib.Path) -> dict:
    """One repetition: the sweep on 1 then on 2 workers."""
    one, two = (timed_run(scene, w, out / f"contact_table_{w}") for w in (1, 2))
    return {"serial_s": one["wall_s"], "parallel_s": two["wall_s"], "speedup": one["wall_s"] / two["wall_s"],
            "load_1min": max(one["load_1min"], two["load_1min"]), "identical": one["table"] == two["table"],
            "n_rows": one["table"].count("\n") - 1}


def plot(results: dict[str, dict], out: pathlib.Path) -> pathlib.Path:
    """Each repetition's 2-worker time against its 1-worker time, and its speed-up against the load."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.4))
    for j, (kind, res) in enumerate(results.items()):
        style = {"marker": "os"[j % 2], "color": f"C{j + 2}", "ls": "none", "label": f"{kind} ({res['n_cases']} cases)"}
        ax1.plot([r["serial_s"] for r in res["runs"]], [r["parallel_s"] for r in res["runs"]], **style)
        ax2.plot([r["load_1min"] for r in res["runs"]], [r["speedup"] for r in res["runs"]], **style)
    top = max(max(r["serial_s"], r["parallel_s"]) for res in results.values() for r in res["runs"]) * 1.1
    ax1.plot([0, top], [0, top], color="0.5", ls=":", label="no gain")
    ax1.plot([0, top], [0, top / 2], color="0.5", ls="--", label="ideal (2 cores)")
    ax1.set_xlim(0, top)
    ax1.set_ylim(0, top)
    ax1.set_xlabel("1 worker, in-process (s)")
    ax1.set_ylabel("2 worker processes (s)")
    ax1.set_title("wall time of each sweep (the table written)")
    ax1.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=8)
    loads = [r["load_1min"] for res in results.values() for r in res["runs"]]
    ax2.axhline(2.0, color="0.5", ls="--", label="ideal (2 cores)")
    ax2.axhline(1.0, color="0.5", ls=":", label="no gain")
    ax2.set_xlabel("1-minute load average before the runs (2 cores; this run included)")
    ax2.set_ylabel("speed-up (1 worker / 2 workers)")
    ax2.set_ylim(0.0, 2.3)
    ax2.set_xlim(0.0, max(2.0, *loads) * 1.1)
    ax2.set_title("speed-up against the machine's load")
    ax2.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=8)
    fig.suptitle("Contact table for multibody codes: sweeps on 1 and 2 workers")
    fig.tight_layout()
    return save_figure(fig, out / "contact_table_speedup.png")


def _markdown(results: dict[str, dict]) -> str:
    rows = "\n".join(f"| {kind} | {res['n_cases']} | {i + 1} | {r['load_1min']:.2f} | {r['serial_s']:.2f} | "
                     f"{r['parallel_s']:.2f} | {r['speedup']:.2f} |"
                     for kind, res in results.items() for i, r in enumerate(res["runs"]))
    identical = all(r["identical"] for res in results.values() for r in res["runs"])
    return ("Sweeps written as `contact_table.csv` (no frictional CSVs); wall times, the 2 workers' start "
            "included.\n\n| sweep | cases | rep. | load (1 min) | 1 worker (s) | 2 workers (s) | speed-up |\n"
            f"|---|---|---|---|---|---|---|\n{rows}\n\nTables of 1 and 2 workers "
            f"{'bit-identical' if identical else 'DIFFERENT'} in every repetition.\n")


def run(mode: str, out: pathlib.Path) -> dict:
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    results = {}
    for kind in ("elastic", "layers"):
        scene = sweep_scene(kind, mode)
        timed_run(scene, 1, out / "contact_table_warmup")  # numba caches, imports, layer tables
        runs = [repetition(scene, out) for _ in range(REPEAT[mode])]
        results[kind] = {"n_cases": len(scene.cases), "n_rows": runs[0]["n_rows"], "runs": runs,
                         "median_speedup": statistics.median(r["speedup"] for r in runs)}
    fig = plot(results, out)
    return {"title": "Contact table: sweep speed-up on 2 workers", "markdown": _markdown(results),
            "figures": [str(fig)], "data": results}


__all__ = ["ELASTIC", "OUTPUT", "REPEAT", "SCENES", "plot", "repetition", "run", "sweep_scene", "timed_run"]
