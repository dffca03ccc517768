"""The README's worked example: run its command and check the numbers the README states."""

import json
import re
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def _example_command(readme: str) -> list[str]:
    block = re.search(r"## Worked example\s+```sh\n(.*?)```", readme, re.S).group(1)
    line = next(ln for ln in block.splitlines() if ln.startswith("wrlayer simulate"))
    return line.split()


def test_readme_worked_example_runs_and_its_numbers_hold(tmp_path):
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    argv = _example_command(readme)
    out = tmp_path / "example"
    argv[argv.index("--out") + 1] = str(out)
    run = subprocess.run([sys.executable, "-m", "wrlayer.cli", *argv[1:]], cwd=REPO, capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert (out / "patch_pass1.png").is_file() and (out / "separation.png").is_file()
    first = json.loads((out / "result.json").read_text())["passes"][0]
    row = re.search(r"\| patch length \|.*?\n\|[-| ]+\|\n(\|.*\|)\n", readme, re.S).group(1)
    stated = re.findall(r"\|\s*([0-9.]+) (?:mm²|mm|MPa)", row)
    keys = ["length_mm", "width_mm", "area_mm2", "delta_mm", "p_max_MPa", "u0_mm", "up0_mm"]
    assert len(stated) == len(keys)
    for key, text in zip(keys, stated):
        decimals = len(text.split(".")[1]) if "." in text else 0     # the README rounds to what it prints
        assert abs(first[key] - float(text)) <= 0.5 * 10.0 ** -decimals, (key, first[key], text)
