"""Contact table for multibody codes: wall time of a wheel–rail sweep written as contact_table.csv, in this process
(``run.workers = 1``) against 2 local worker processes (``run.workers = 2``, one BLAS thread each), and the
speed-up (units s, cases).

The sweep: scenes/wheel_rail_sweep_elastic.toml (S1002 on 60E1 1:40, both wheels, rigid-wheelset roll, elastic)
with its cases replaced by a product of lateral displacement, yaw and vertical load (``mode = "product"``),
``output.contact_table = true``, no frictional CSVs (``output.frictional_csv = false``: written by this process,
they take about as long as solving an elastic case), no VTK, no pictures. Each repetition runs the sweep on 1
worker then on 2 workers (interleaved, so that a change of the machine's load hits both); the 2-worker time
includes starting the worker processes. The 1-minute load average before every run is recorded: this machine's 2
cores are shared, and the kernel shares the CPU between sessions (autogroup), so while other sessions keep both
cores busy the 2 workers get no more CPU than one process. ``python -m benchmarks --only contact_table`` runs it.
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
from contact.wheel_rail.run import run_wheel_rail_scene
from contact.wheel_rail.scene import RunSpec
from wrlayer.plotting import save_figure

SCENE = pathlib.Path(__file__).resolve().parents[1] / "scenes" / "wheel_rail_sweep_elastic.toml"
#: The sweep per mode: lateral displacement {start, stop, step} (mm), yaw angles (rad), vertical loads (N);
#: repetitions of the 1-worker / 2-worker pair.
SWEEPS = {"quick": ({"start": 0.0, "stop": 8.0, "step": 0.25}, [0.0, 0.002], [10000.0, 20000.0], 3),
          "full": ({"start": 0.0, "stop": 8.0, "step": 0.25}, [0.0, 0.002, 0.004], [5000.0, 10000.0, 20000.0], 5)}


def sweep_scene(mode: str):
    """The benchmark's scene (see the module docstring)."""
    lateral, yaw, load, _ = SWEEPS[mode]
    data = tomllib.loads(SCENE.read_text(encoding="utf-8"))
    data["sweep"] = {"lateral_mm": lateral, "yaw_rad": yaw, "vertical_load_N": load, "mode": "product"}
    data["output"] = {"contact_table": True, "vtk": False, "deformed_profiles": False, "frictional_csv": False}
    return parse_wheel_rail_scene(data, SCENE)


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


def _plot(reps: list[dict], n_cases: int, out: pathlib.Path) -> pathlib.Path:
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    k = np.arange(len(reps))
    ax1.bar(k - 0.2, [r["serial_s"] for r in reps], 0.4, label="1 worker (in-process)")
    ax1.bar(k + 0.2, [r["parallel_s"] for r in reps], 0.4, label="2 worker processes")
    for i, r in enumerate(reps):
        ax1.annotate(f"load {r['load_1min']:.1f}", (i, max(r["serial_s"], r["parallel_s"])), ha="center",
                     va="bottom", fontsize=8)
    ax1.set_xticks(k, [f"rep. {i + 1}" for i in k])
    ax1.set_ylabel("wall time of the sweep (s)")
    ax1.set_title(f"{n_cases} cases, both wheels")
    ax1.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2, fontsize=8)
    ax1.margins(y=0.15)
    ax2.plot([r["load_1min"] for r in reps], [r["speedup"] for r in reps], "o", label="measured")
    ax2.axhline(2.0, color="0.5", ls="--", label="ideal (2 cores)")
    ax2.axhline(1.0, color="0.5", ls=":", label="no gain")
    ax2.set_xlabel("1-minute load average before the runs (2 cores)")
    ax2.set_ylabel("speed-up (1 worker / 2 workers)")
    ax2.set_ylim(0.0, 2.3)
    ax2.set_xlim(0.0, max(2.0, *(r["load_1min"] for r in reps)) * 1.1)
    ax2.set_title("speed-up against the machine's load")
    ax2.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=3, fontsize=8)
    fig.suptitle("Contact table for multibody codes: a sweep on 1 and 2 workers")
    fig.tight_layout()
    return save_figure(fig, out / "contact_table_speedup.png")


def _markdown(data: dict) -> str:
    rows = "\n".join(f"| {i + 1} | {r['load_1min']:.2f} | {r['serial_s']:.2f} | {r['parallel_s']:.2f} | "
                     f"{r['speedup']:.2f} |" for i, r in enumerate(data["runs"]))
    best = data["lowest_load_run"]
    return (f"Sweep of {data['n_cases']} cases (both wheels, {data['n_rows']} table rows) written as "
            f"`{TABLE_FILE}` (without the frictional CSVs); wall times, the 2 workers' start included.\n\n"
            "| rep. | load (1 min) | 1 worker (s) | 2 workers (s) | speed-up |\n|---|---|---|---|---|\n"
            f"{rows}\n\nAt the lowest load ({best['load_1min']:.2f}): speed-up {best['speedup']:.2f}; median "
            f"{data['median_speedup']:.2f}. Tables of 1 and 2 workers "
            f"{'bit-identical' if data['identical'] else 'DIFFERENT'} in every repetition. The same sweep with the "
            f"frictional CSVs (1 worker): {data['with_frictional_s']:.2f} s.\n")


def run(mode: str, out: pathlib.Path) -> dict:
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    scene = sweep_scene(mode)
    timed_run(scene, 1, out / "contact_table_warmup")  # numba caches, imports
    reps = [repetition(scene, out) for _ in range(SWEEPS[mode][3])]
    frictional = dataclasses.replace(scene, output=dataclasses.replace(scene.output, frictional_csv=True))
    data = {"n_cases": len(scene.cases), "n_rows": reps[0]["n_rows"], "runs": reps,
            "identical": all(r["identical"] for r in reps),
            "lowest_load_run": min(reps, key=lambda r: r["load_1min"]),
            "median_speedup": statistics.median(r["speedup"] for r in reps),
            "with_frictional_s": timed_run(frictional, 1, out / "contact_table_frictional")["wall_s"]}
    fig = _plot(reps, len(scene.cases), out)
    return {"title": "Contact table: sweep speed-up on 2 workers", "markdown": _markdown(data), "figures": [str(fig)],
            "data": data}


__all__ = ["SCENE", "SWEEPS", "repetition", "run", "sweep_scene", "timed_run"]
