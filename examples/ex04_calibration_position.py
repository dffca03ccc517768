"""Example 4: FEM calibration of the Prandtl layer at one rail position (the coarsest configuration).

Problem (``calibration/configs/test_coarse.toml``, restricted to one body and one position): the 60E1 rail at its
crown (y = 0 mm) under the elliptic Hertz pressure of an S1002 wheel, reference load 100 kN; steel E = 210 GPa,
Poisson 0.3, initial yield Y = 500 MPa, linear isotropic and kinematic hardening 10 GPa each; 3D quadratic
elements, 2 per semi-axis; loads up to 2 x the first-yield pressure in 3 levels, unloading from 1.5 and 2 x.
The FEM indentation's inelastic displacement u_pl(p) is fitted by a Prandtl element of 3 segments
(paper eqs. 4-8) and written as a layer table (``rail_layer_table.json``/``.csv``) into the output folder.

Read with ``calibration.load_config``, changed with :func:`dataclasses.replace` (one position), run with
``calibration.run_calibration`` (about 15 s on one core) and read back with ``contact.LayerTable``.

Expected result: the elastic limit p_2 = the FEM first yield, 808 MPa = 1.616 Y (Johnson, axisymmetric Hertz
contact: 1.61 Y; the crown's patch is nearly round, a/b = 1.3); the fit's largest error 0.0011 mm.
``main(out_dir)`` returns p_2 (MPa).

Run: ``python examples/ex04_calibration_position.py [OUT_DIR]`` (default: a temporary folder).
"""

from __future__ import annotations

import dataclasses
import sys
import tempfile
from pathlib import Path

import calibration
import contact
from wrlayer.shipped import configs_dir



def main(out_dir: str | Path | None = None) -> float:
    """Calibrate the rail crown with the coarse configuration into ``out_dir``; returns p_2 (MPa)."""
    out = Path(out_dir) if out_dir is not None else Path(tempfile.mkdtemp(prefix="ex04_"))
    cfg = calibration.load_config(configs_dir() / "test_coarse.toml")
    rail = dataclasses.replace(cfg.bodies[0], positions_mm=(0.0,))
    cfg = dataclasses.replace(cfg, bodies=(rail,))
    summary = calibration.run_calibration(cfg, out / "calibration", plots=False, show_progress=False,
                                          log=lambda *args: None)
    body = summary["bodies"]["rail"]
    table = contact.LayerTable.read(body["table"])
    characteristic = table.characteristics[0]
    p2 = characteristic.elastic_limit_MPa
    yield_MPa = rail.material.yield_MPa
    print(f"rail crown y = {table.y_mm[0]:g} mm: p_2 = {p2:.1f} MPa = {p2 / yield_MPa:.3f} Y; "
          f"fit error {body['max_fit_error_mm']:.2g} mm; FEM {summary['fem_seconds']['total']:.1f} s; "
          f"table in {out / 'calibration'}")
    print("characteristic:", characteristic.to_dict())
    return float(p2)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
