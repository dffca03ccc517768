"""Memory of one process that runs block after block: rolling blocks and a long wear run (units MiB, s).

A process that runs many rolling blocks (the gap study: positions x meshes) or a long wear run must not keep what
an earlier block built. :func:`memory_scenario` runs ``blocks`` small rolling blocks (a coarse 3D pass, one level,
PARDISO where installed) and then a ``wear_steps``-step small wear run in ONE fresh process and records the peak
resident memory (Linux VmHWM, reset at the start of each phase) after every block and every wear step.

Cause of the growth this guards against (found with ``gc.get_referrers`` on the blocks' discretisations): the
discretisation kept its solver problem (assembled stiffness, factorisation, PARDISO handle) in its cache and the
problem referred back to the discretisation, a cycle freed only by Python's rare full collections; eight fine
blocks reached 20 GB. The problem now refers to its discretisation weakly, and a finished block runs a collection
for scikit-fem's own mesh cycles (:func:`calibration.fem.assembly.frees_its_meshes`).

``python -m benchmarks --only fem_memory`` (quick: 10 blocks and 100 wear steps; full: 20 and 200).
"""

from __future__ import annotations

import multiprocessing
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent

#: the peak memory after the first block / step may grow by at most this fraction over the run (-)
GROWTH_LIMIT = 0.10


def peak_rss_mb() -> float:
    """Peak resident memory of this process since the last :func:`reset_peak` (MiB; Linux VmHWM)."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024.0
    raise OSError("no VmHWM in /proc/self/status (not Linux?)")


def reset_peak() -> None:
    """Reset the peak resident memory (VmHWM) to the current one (Linux: ``5`` into /proc/self/clear_refs)."""
    Path("/proc/self/clear_refs").write_text("5")


def small_rolling_config():
    """A coarse 3D block (h = a/1.5), one level 1.7 p_y, one pass of 5 positions: about 1-3 s."""
    from calibration.rolling.config import (ContactSettings, RollingConfig, RollingRunSettings, TrackMeshSettings,
                                            TrackSettings)

    return RollingConfig(contact=ContactSettings(a_mm=1.0, levels=(1.7,), model="3d", level_unit="p_y"),
                         track=TrackSettings(length_factor=1.0, step_factor=0.5, n_passes=1, ramp_steps=2),
                         mesh=TrackMeshSettings(elements_per_semi_axis=1.5, size_factor=3.0),
                         run=RollingRunSettings(plots=False, linear_solver="auto"))


def small_wear_scene(steps: int, folder: Path):
    """A one-side wear scene without layers, two passes, coarse grids, ``steps`` steps over 1 km."""
    from contact.wear.scene import parse_wear_scene

    data = {"type": "wear", "profiles": {"rail": "60E1", "wheel": "S1002"},
            "wheel": {"nominal_radius_mm": 460.0, "side": "right"}, "wheelset": {"roll_rad": 0.0},
            "load": {"vertical_load_N": 40000.0, "speed_mm_s": 2000.0},
            "material": {"G_MPa": 82000.0, "poisson": 0.28}, "tangential": {"friction": 0.3},
            "passes": {"max": 2}, "method": {"grid_mm": 0.5, "fastsim_cells": 8},
            "wear": {"law": "archard", "distance_km": 1.0, "steps": steps, "max_depth_per_step_mm": 10.0,
                     "smoothing_mm": 0.0, "grid_mm": 0.5, "inelastic": False},
            "collective": {"lateral_mm": [2.0], "yaw_rad": 0.002, "weights": [1.0]}}
    return parse_wear_scene(data, folder / "wear.toml")


def memory_scenario(blocks: int = 10, wear_steps: int = 100) -> dict:
    """Run the blocks and the wear run in this process; peak memory (MiB) after each block and each wear step,
    and the wall time of each phase (s)."""
    from calibration.rolling.run import run_rolling
    from contact.wear.loop import run_wear

    out: dict = {"blocks": blocks, "wear_steps": wear_steps, "rolling_peak_MiB": [], "wear_peak_MiB": []}
    with tempfile.TemporaryDirectory() as tmp:
        cfg = small_rolling_config()
        reset_peak()
        t0 = time.perf_counter()
        for k in range(blocks):
            run_rolling(replace(cfg), Path(tmp) / f"block_{k}")
            out["rolling_peak_MiB"].append(peak_rss_mb())
        out["rolling_s"] = time.perf_counter() - t0
        scene = small_wear_scene(wear_steps, Path(tmp))
        reset_peak()
        t0 = time.perf_counter()
        result = run_wear(scene, on_step=lambda record, run: out["wear_peak_MiB"].append(peak_rss_mb()),
                          show_progress=False)
        out["wear_s"] = time.perf_counter() - t0
        out["wear_steps_done"] = len(result.steps)
    return out


def _child(blocks: int, wear_steps: int, queue) -> None:
    try:
        queue.put(("ok", memory_scenario(blocks, wear_steps)))
    except BaseException as err:  # noqa: BLE001 - reported to the parent
        queue.put(("error", f"{type(err).__name__}: {err}"))


def in_fresh_process(blocks: int = 10, wear_steps: int = 100, timeout_s: float = 1800.0) -> dict:
    """:func:`memory_scenario` in a new interpreter (spawned: no memory of the caller's earlier work)."""
    ctx = multiprocessing.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_child, args=(blocks, wear_steps, queue))
    proc.start()
    try:
        status, value = queue.get(timeout=timeout_s)
    finally:
        proc.join(timeout=60)
        if proc.is_alive():
            proc.kill()
    if status != "ok":
        raise RuntimeError(f"memory scenario failed: {value}")
    return value


def growth(peaks: list[float]) -> float:
    """Relative growth of the peak memory from the first entry to the last (-)."""
    return peaks[-1] / peaks[0] - 1.0


def run(mode: str, out: Path) -> dict:
    blocks, steps = (10, 100) if mode == "quick" else (20, 200)
    res = in_fresh_process(blocks, steps)
    rows = [("rolling blocks", blocks, res["rolling_peak_MiB"], res["rolling_s"]),
            ("wear steps", steps, res["wear_peak_MiB"], res["wear_s"])]
    md = ("Peak resident memory (VmHWM, reset at the start of each phase) of one fresh process after the first and "
          f"the last block / step; limit: growth below {100 * GROWTH_LIMIT:.0f} %.\n\n"
          "| phase | count | peak after first (MiB) | peak after last (MiB) | growth | wall (s) |\n"
          "|---|---|---|---|---|---|\n"
          + "".join(f"| {name} | {n} | {p[0]:.0f} | {p[-1]:.0f} | {100 * growth(p):+.1f} % | {s:.1f} |\n"
                    for name, n, p, s in rows))
    return {"title": "FEM memory: rolling blocks and a wear run in one process", "markdown": md, "figures": [],
            "data": res}


if __name__ == "__main__":
    print(in_fresh_process(*(int(a) for a in sys.argv[1:3])))
