"""Files of a wear run (units mm, N, MPa, s; distances in km), written step by step so that a stop keeps every
completed step. Each file is written atomically.

    profiles/step_000_<side>_<body>.{prr|prw,csv}   initial profiles; step_NNN_...: after step NNN (SIMPACK and CSV,
                                                    read back with meshes.profiles.io, the largest |z| error recorded)
    depth/step_NNN_<side>_<body>.csv                per profile node: y, arc length s, z before the step, wear depth,
                                                    inelastic depth of the step (mm)
    layer_state/step_NNN_<side>_<body>.csv          hardening mode: largest peak pressure carried so far (MPa) at the
                                                    profile coordinates y (mm) of the initial profile
    steps.csv                                       one row per step, side and body: distance, wear and inelastic
                                                    max/location/area, mass loss, rolling-radius difference
    result.json                                     inputs, units, every step's numbers, warnings (the
                                                    method's approximate p_max), status: "complete",
                                                    "stopped: <reason naming the step>", "running: N steps
                                                    completed" (the run was killed after step N, or still runs),
                                                    "terminated (SIGTERM) after step N", "interrupted after step N";
                                                    always the steps of the folder's files
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from contact.result_warnings import method_warnings
from contact.scenes.result_io import code_version, read_result, write_result
from contact.wear.records import StepRecord, WearRun
from meshes.profiles.io import write_profile_files
from wrlayer.atomic_write import atomic_write_text
from wrlayer.json_io import jsonable

UNITS = {"length": "mm", "distance": "km", "force": "N", "stress": "MPa", "speed": "mm/s", "area": "mm^2",
         "mass_loss_g_per_km": "g of wheel material per km of running (the whole wheel circumference)",
         "mass_loss_g_per_m_rail_per_km": "g of rail material per metre of rail per km of wheel running"}
TABLE_COLUMNS = ("step", "start_km", "length_km", "end_km", "side", "body", "wear_max_mm", "wear_max_y_mm",
                 "worn_area_mm2", "inelastic_max_mm", "inelastic_max_y_mm", "inelastic_area_mm2", "mass_loss",
                 "mass_loss_unit", "delta_r_mm", "quasi_conicity", "equivalent_conicity", "conicity_amplitude_mm")
#: Columns of steps.csv taken from a body's statistics (:class:`contact.wear.statistics.BodyStats`).
STATS_COLUMNS = ("wear_max_mm", "wear_max_y_mm", "worn_area_mm2", "inelastic_max_mm", "inelastic_max_y_mm",
                 "inelastic_area_mm2")


def write_profile_pair(out_dir: Path, stem: str, profile, body: str) -> dict[str, Any]:
    """Write one profile as SIMPACK and CSV, read both back; returns file names and the read-back error (mm)."""
    pts = profile.points if hasattr(profile, "points") else np.column_stack(profile.sample(0.2))
    paths, err = write_profile_files(out_dir / "profiles" / stem, pts, body,
                                     f"{profile.name} ({body}), wrlayer wear loop")
    files = [str(p.relative_to(out_dir)) for p in paths]
    return {"files": files, "read_back_max_error_mm": err}


def write_initial(out_dir: Path, run: WearRun) -> list[dict]:
    return [{"side": s, "body": b, **write_profile_pair(out_dir, f"step_000_{s}_{b}", p[b], b)}
            for s, p in run.initial_profiles.items() for b in ("wheel", "rail")]


def write_step(out_dir: Path, rec: StepRecord) -> list[dict]:
    """Profiles and depth distributions of one completed step."""
    written = []
    for (s, b), bs in rec.bodies.items():
        stem = f"step_{rec.index:03d}_{s}_{b}"
        info = write_profile_pair(out_dir, stem, rec.profiles[s][b], b)
        g = bs.grid
        rows = "\n".join(f"{y:.9e},{sv:.9e},{z:.9e},{w:.9e},{i:.9e}" for y, sv, z, w, i in
                         zip(g.y_mm, g.s_mm, g.z_mm, bs.wear_mm, bs.inelastic_mm))
        path = out_dir / "depth" / f"{stem}.csv"
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(path, f"y_mm,s_mm,z_before_mm,wear_mm,inelastic_mm\n{rows}\n")  # step: see result.json
        info["depth_file"] = str(path.relative_to(out_dir))
        if (s, b) in rec.layer_state:
            y, p = rec.layer_state[s, b]
            state_path = out_dir / "layer_state" / f"{stem}.csv"
            state_path.parent.mkdir(parents=True, exist_ok=True)
            atomic_write_text(state_path, "y_mm,p_hist_MPa\n" + "".join(f"{a:.9e},{c:.9e}\n" for a, c in zip(y, p)))
            info["layer_state_file"] = str(state_path.relative_to(out_dir))
        written.append({"side": s, "body": b, **info})
    return written


def table_rows(run: WearRun) -> list[dict]:
    rows = []
    for rec in run.steps:
        for (s, b), bs in rec.bodies.items():
            unit = "g/km" if b == "wheel" else "g/(m rail km)"
            rows.append({"step": rec.index, "start_km": rec.start_km, "length_km": rec.length_km,
                         "end_km": rec.end_km, "side": s, "body": b,
                         **{k: getattr(bs.stats, k) for k in STATS_COLUMNS}, "mass_loss": bs.stats.mass_loss,
                         "mass_loss_unit": unit, "delta_r_mm": rec.conicity.delta_r_mm,
                         "quasi_conicity": rec.conicity.quasi_conicity,
                         "equivalent_conicity": rec.conicity.equivalent_conicity,
                         "conicity_amplitude_mm": rec.conicity.amplitude_mm})
    return rows


def write_table(out_dir: Path, run: WearRun) -> Path:
    rows = table_rows(run)
    lines = [",".join(TABLE_COLUMNS)]
    for r in rows:
        lines.append(",".join(f"{r[c]:.9g}" if isinstance(r[c], float) else str(r[c]) for c in TABLE_COLUMNS))
    return atomic_write_text(out_dir / "steps.csv", "\n".join(lines) + "\n")


@dataclass
class WrittenFiles:
    """The files written so far (names relative to the output folder), as result.json lists them.

    Attributes
    ----------
    initial : list
        The initial profiles: per side and body, the profile files and their read-back error (mm).
    steps : dict
        ``steps[index]``: per side and body, the step's profile, depth and layer-state files.
    pictures : list
        The PNG pictures.
    """

    initial: list = field(default_factory=list)
    steps: dict[int, list] = field(default_factory=dict)
    pictures: list[str] = field(default_factory=list)


def result_dict(run: WearRun, files: WrittenFiles, status: str) -> dict[str, Any]:
    sc = run.scene
    warnings = method_warnings(Path(sc.path).name, sc.normal.name)
    return jsonable({
        "type": "wear", "status": status, "code_version": code_version(), "units": UNITS,
        "inputs": sc.to_dict(),
        "initial": {"conicity": run.initial_conicity.to_dict(), "profiles": files.initial},
        "steps": [{"step": r.index, "start_km": r.start_km, "length_km": r.length_km, "end_km": r.end_km,
                   "notes": r.notes, "conicity": r.conicity.to_dict(), "timings_s": r.timings,
                   "bodies": [{"side": s, "body": b, **bs.stats.to_dict()} for (s, b), bs in r.bodies.items()],
                   "files": files.steps.get(r.index, []), "conditions": [c.to_dict() for c in r.conditions],
                   **({"balance": [b.to_dict() for b in r.balances]} if r.balances else {})}
                  for r in run.steps],
        "distance_done_km": run.steps[-1].end_km if run.steps else 0.0,
        "pictures": files.pictures,
        **({"warnings": warnings} if warnings else {}),
    })


def write_run_result(out_dir: Path, run: WearRun, files: WrittenFiles, status: str) -> Path:
    return write_result(out_dir, result_dict(run, files, status))


class RunFiles:
    """The files of one run in ``out_dir``, written as the run goes: the initial profiles with the first step (or
    at the end of a run without steps), each step's files, the table and result.json after every step."""

    def __init__(self, out_dir: Path, run: WearRun):
        self.out_dir, self.run = Path(out_dir), run
        self.files = WrittenFiles()
        self._initial_written = False

    def _initial(self) -> None:
        if not self._initial_written:
            self.files.initial = write_initial(self.out_dir, self.run)
            self._initial_written = True

    def step(self, rec: StepRecord) -> None:
        """Write a completed step's profiles and depths, the table and result.json ("running: N steps
        completed", written last: the folder is then consistent and may be published)."""
        self._initial()
        self.files.steps[rec.index] = write_step(self.out_dir, rec)
        write_table(self.out_dir, self.run)
        write_run_result(self.out_dir, self.run, self.files, f"running: {len(self.run.steps)} steps completed")

    def finish(self, status: str, pictures: list[Path] = ()) -> dict[str, Any]:
        """Write the table and the final result.json with ``status`` and the ``pictures``; returns the result."""
        self._initial()
        write_table(self.out_dir, self.run)
        self.files.pictures = [p.name for p in pictures]
        write_run_result(self.out_dir, self.run, self.files, status)
        return result_dict(self.run, self.files, status)


def mark_published(out_dir: Path, status: str) -> None:
    """Set the ``status`` of the result.json published in ``out_dir`` (its steps and files unchanged)."""
    write_result(out_dir, {**read_result(out_dir), "status": status})


__all__ = ["TABLE_COLUMNS", "UNITS", "RunFiles", "WrittenFiles", "mark_published", "result_dict", "table_rows",
           "write_initial", "write_profile_pair", "write_run_result", "write_step", "write_table"]
