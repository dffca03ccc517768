"""Shipped files refer to other files by their path in the repository (or ``../shared/reference/``), never by a
machine-specific absolute path."""

import re
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
ABSOLUTE = re.compile(r"(?<![\w.])/(work|home|Users|root|mnt|opt)/[\w.-]+")


def test_no_machine_specific_paths_in_shipped_files():
    files = subprocess.run(["git", "ls-files"], cwd=REPO, capture_output=True, text=True, check=True).stdout.split()
    shipped = [f for f in files if not f.startswith("tests/") and f.endswith((".py", ".toml", ".md", ".json",
                                                                                ".csv", ".cfg", ".txt"))]
    assert len(shipped) > 50
    hits = []
    for name in shipped:
        text = (REPO / name).read_text(encoding="utf-8", errors="replace")
        hits += [f"{name}: {m.group(0)}" for m in ABSOLUTE.finditer(text)]
    assert not hits, hits
