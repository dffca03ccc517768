"""Recalibration of the layer tables on the worn profiles during a wear run (units mm, N, MPa).

The layer characteristics depend on the local geometry (the paper: they vary along the profile and must come from
FEM on the actual sections), so after wear has changed a profile its tables can be recomputed. With
``[wear.recalibrate] config = "template.toml", every_steps = N`` the loop, after every N-th step and for every
simulated side, writes the current profiles as SIMPACK files, substitutes them into a calibration configuration
template (the placeholders ``@wheel_profile@`` and ``@rail_profile@``, e.g. ``profile = "@wheel_profile@"``,
``mate = "@rail_profile@"``) and runs ``python -m calibration run`` on it (a separate process: the contact package
does not import the calibration package). The calibration runs on local processes (its ``[run] workers``) or on
the Dask cluster of ``wear.scheduler`` (``--scheduler``, the calibration's own option). The tables it writes
(``<body>_layer_table.json``) replace the scene's tables of that side from the next step on; the layer state
(largest load per position) is kept. A failed calibration stops the loop naming the step; positions that failed
inside a table are listed by it and the solver refuses to interpolate across them.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from contact.layer.layer_table import LayerTable
from meshes.profiles.io import write_simpack
from wrlayer.errors import InputError

PLACEHOLDERS = {"wheel": "@wheel_profile@", "rail": "@rail_profile@"}


def template_bodies(text: str) -> list[str]:
    """The bodies whose worn profile the template uses (by placeholder)."""
    return [b for b, ph in PLACEHOLDERS.items() if ph in text]


def recalibrate_side(template_text: str, profiles: dict, work: Path, scheduler: str = "",
                     what: str = "wear.recalibrate") -> dict[str, LayerTable]:
    """Calibrate the bodies of the template on ``profiles[body]`` (current profiles of one side) in ``work``;
    returns {body: LayerTable} for the bodies the template calibrates (those with a ``[[bodies]]`` entry)."""
    work = Path(work)
    work.mkdir(parents=True, exist_ok=True)
    text = template_text
    for body, ph in PLACEHOLDERS.items():
        path = work / f"{body}.{'prw' if body == 'wheel' else 'prr'}"
        write_simpack(path, profiles[body], body=body, comment=f"worn {body} profile for recalibration")
        text = text.replace(ph, str(path.resolve()))
    cfg = work / "calibration.toml"
    cfg.write_text(text, encoding="utf-8")
    out = work / "tables"
    cmd = [sys.executable, "-m", "calibration", "run", str(cfg), "--out", str(out), "--quiet", "--no-plots"]
    if scheduler:
        cmd += ["--scheduler", scheduler]
    env = dict(os.environ)
    root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    if proc.returncode not in (0, 4):  # 4: some positions failed, the tables list them
        last = (proc.stderr.strip().splitlines() or ["no message"])[-1]
        raise InputError(what, f"calibration of the worn profiles failed (exit {proc.returncode}): {last}")
    tables = {}
    for path in sorted(out.glob("*_layer_table.json")):
        table = LayerTable.read(path)
        tables[table.body] = table
    if not tables:
        raise InputError(what, f"the calibration wrote no layer table into {out}")
    return tables


__all__ = ["PLACEHOLDERS", "recalibrate_side", "template_bodies"]
