"""Example 6: reading result files into tables: a scene's result.json and a wheel-rail sweep's cases.csv.

Problem: run two shipped scenes into the output folder with ``contact.run_scene_file``: the paper's example with
the layer (``scenes/paper_with_layer.toml``: result.json with one entry per pass, lengths mm, pressures MPa,
forces N) and the elastic wheel-rail sweep (``scenes/wheel_rail_sweep_elastic.toml``: S1002 on 60E1 1:40,
lateral 0-10 mm with yaw 0-24 mrad, 21 cases, both wheels, 10 kN per wheel; cases.csv with one row per contact
patch). Then read them as tables: with pandas when it is installed (``pandas.json_normalize``, ``read_csv``,
``groupby``), else with the standard library (``json``, ``csv``), with the same numbers.

Expected result: pass 1 of the paper's example p_max = 1517 MPa, delta = 0.127109 mm (the README's worked example);
the sweep: 21 cases (43 patches), the largest p_max 2008 MPa on the right wheel (flange contact, 46 degrees, at
10 mm lateral), 682 MPa on the left wheel, and the vertical force of each wheel 10 kN. ``main(out_dir)`` returns
the first pass's p_max (MPa) read from result.json.

Run: ``python examples/ex06_results_pandas.py [OUT_DIR]`` (default: a temporary folder).
"""

from __future__ import annotations

import csv
import json
import sys
import tempfile
from pathlib import Path

import contact
from wrlayer.shipped import scenes_dir

try:
    import pandas as pd
except ImportError:                                       # the example runs without pandas, with the csv module
    pd = None



def passes_table(result_json: Path) -> list[dict]:
    """The per-pass entries of a scene's result.json (a DataFrame with pandas, else a list of dicts)."""
    result = json.loads(result_json.read_text(encoding="utf-8"))
    if pd is not None:
        return pd.json_normalize(result["passes"])
    return result["passes"]


def largest_p_max_per_side(cases_csv: Path) -> dict[str, float]:
    """The largest p_max (MPa) over all cases and patches, per wheel side, from a wheel-rail sweep's cases.csv."""
    if pd is not None:
        cases = pd.read_csv(cases_csv)
        return cases.groupby("side")["p_max_MPa"].max().to_dict()
    out: dict[str, float] = {}
    with cases_csv.open(newline="", encoding="utf-8") as fh:
        for row in csv.DictReader(fh):
            if row["p_max_MPa"]:
                out[row["side"]] = max(out.get(row["side"], 0.0), float(row["p_max_MPa"]))
    return out


def main(out_dir: str | Path | None = None) -> float:
    """Run the two scenes into ``out_dir`` and read their results as tables; returns pass 1's p_max (MPa)."""
    out = Path(out_dir) if out_dir is not None else Path(tempfile.mkdtemp(prefix="ex06_"))
    contact.run_scene_file(scenes_dir() / "paper_with_layer.toml", out / "paper")
    contact.run_scene_file(scenes_dir() / "wheel_rail_sweep_elastic.toml", out / "sweep")
    passes = passes_table(out / "paper" / "result.json")
    if pd is not None:
        print(passes[["pass", "delta_mm", "p_max_MPa", "length_mm", "width_mm", "area_mm2"]].to_string(index=False))
        first = float(passes["p_max_MPa"].iloc[0])
    else:
        print(passes[0]["pass"], passes[0]["delta_mm"], passes[0]["p_max_MPa"])
        first = float(passes[0]["p_max_MPa"])
    print("largest p_max over the sweep (MPa):", largest_p_max_per_side(out / "sweep" / "cases.csv"))
    return first


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
