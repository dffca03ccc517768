"""Example 5: one short wear step of an S1002 wheelset on 60E1 rails with the calibrated layers.

Problem (``scenes/wear/s1002_60e1.toml`` with a distance of 100 km in 1 step instead of 3000 km in 3): both wheels
of a wheelset on straight track (rails 1:40, gauge 1435 mm, nominal radius 460 mm), 60 kN per wheel,
2000 mm/s, G = 82 GPa, Poisson 0.28, friction 0.3; a load collective of lateral displacements -3..3 mm (weights
0.15/0.2/0.3/0.2/0.15); the calibrated Prandtl layers of both bodies (``scenes/tables``, scaled to each patch);
Archard wear with Jendel's coefficient map, hardness 2550 MPa; profile grid 0.2 mm, Gaussian smoothing 2 mm.
Each condition is solved (normal with the layer over the passes, FASTSIM), the worn depth (abrasive wear) and
the layer's inelastic displacement are deposited on the profiles, and the profiles are updated.

Written with a copy of the scene (distance and steps changed, table paths made absolute) and run with
``contact.run_wear_file`` into the output folder: ``steps.csv``, ``result.json``, the profiles before and after
the step (``profiles/``) and the depths (``depth/``).

Expected result: one step of 100 km; right wheel: worn area 0.168 mm^2 (largest wear depth 17 um at
y = -12.3 mm), inelastic displacement 0.069 mm^2 (largest 9 um), mass loss 0.038 g/km; the rail: 0.168 mm^2 and
0.059 mm^2. ``main(out_dir)`` returns the right wheel's abrasive worn area (mm^2).

Run: ``python examples/ex05_wear_step.py [OUT_DIR]`` (default: a temporary folder).
"""

from __future__ import annotations

import re
import sys
import tempfile
from pathlib import Path

import contact
from wrlayer.shipped import scenes_dir

SCENE = scenes_dir() / "wear" / "s1002_60e1.toml"
DISTANCE_KM, STEPS = 100.0, 1


def short_scene(folder: Path) -> Path:
    """A copy of the wear scene with DISTANCE_KM in STEPS step(s); the layer tables named by absolute path."""
    text = SCENE.read_text(encoding="utf-8")
    text = re.sub(r"(?m)^distance_km = .*$", f"distance_km = {DISTANCE_KM}", text)
    text = re.sub(r"(?m)^steps = .*$", f"steps = {STEPS}", text)
    text = re.sub(r'"(\.\./tables/[^"]+)"', lambda m: '"' + (SCENE.parent / m.group(1)).resolve().as_posix() + '"',
                  text)
    path = folder / "wear_short.toml"
    path.write_text(text, encoding="utf-8")
    return path


def main(out_dir: str | Path | None = None) -> float:
    """Run one wear step into ``out_dir``; returns the right wheel's abrasive worn area (mm^2)."""
    out = Path(out_dir) if out_dir is not None else Path(tempfile.mkdtemp(prefix="ex05_"))
    out.mkdir(parents=True, exist_ok=True)
    result = contact.run_wear_file(short_scene(out), out / "wear", plots=False, show_progress=False)
    step = result["steps"][-1]
    for b in step["bodies"]:
        mass = f", mass loss {b['mass_loss_g_per_km']:.3g} g/km" if "mass_loss_g_per_km" in b else ""
        print(f"step {step['step']} ({step['length_km']:g} km), {b['side']} {b['body']}: worn area "
              f"{b['worn_area_mm2']:.4g} mm^2, inelastic {b['inelastic_area_mm2']:.4g} mm^2, "
              f"max wear depth {b['wear_max_mm'] * 1e3:.3g} um{mass}")
    print(f"files in {out / 'wear'}")
    right_wheel = next(b for b in step["bodies"] if b["side"] == "right" and b["body"] == "wheel")
    return float(right_wheel["worn_area_mm2"])


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
