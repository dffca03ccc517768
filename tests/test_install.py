"""Installed use: the wheel carries the scenes with their tables, the calibration configurations and the reference
pages, and the installed ``wrlayer`` command runs a shipped scene outside the repository with the same numbers.

Building the wheel needs pip's build isolation (setuptools from the package index, about 10 s); the install is
``pip install --no-deps --target`` into a temporary folder (the dependencies come from the running environment).
"""

import json
import os
import posixpath
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from wrlayer import cli

REPO = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel built from a copy of the repository's files (tracked and new, not ignored ones)."""
    tmp = tmp_path_factory.mktemp("wheel")
    files = subprocess.run(["git", "ls-files", "-co", "--exclude-standard"], cwd=REPO, capture_output=True,
                           text=True, check=True).stdout.splitlines()
    for name in files:
        if (REPO / name).is_file():
            (tmp / "src" / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(REPO / name, tmp / "src" / name)
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", str(tmp / "src"), "-w", str(tmp)],
                   check=True, capture_output=True, timeout=600)
    return next(tmp.glob("wrlayer-*.whl"))


def test_wheel_ships_scenes_tables_configurations_and_pages(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    scenes = [p.relative_to(REPO / "scenes").as_posix() for p in (REPO / "scenes").rglob("*")
              if p.suffix in (".toml", ".json", ".csv")]
    assert len(scenes) >= 20
    missing = [s for s in scenes if f"wrlayer/data/scenes/{s}" not in names]
    missing += [p.name for p in (REPO / "calibration" / "configs").glob("*.toml")
                if f"calibration/configs/{p.name}" not in names]
    missing += [p.name for p in (REPO / "docs").glob("*.md") if f"wrlayer/data/docs/{p.name}" not in names]
    missing += [p.name for p in (REPO / "examples").glob("ex*.py") if f"wrlayer/data/examples/{p.name}" not in names]
    missing += [f"{package}/py.typed" for package in ("wrlayer", "contact", "calibration", "meshes")
                if f"{package}/py.typed" not in names]
    missing += [name for name in ("README.md", "CITATION.cff") if f"wrlayer/data/{name}" not in names]
    assert not missing, missing


def test_installed_pages_links_resolve_inside_the_package(wheel):
    """Every relative link of an installed reference page names a file the wheel carries."""
    names = set(zipfile.ZipFile(wheel).namelist())
    pages = [n for n in names if n.startswith("wrlayer/data/docs/") and n.endswith(".md")]
    assert len(pages) >= 20
    broken = []
    for page in pages:
        text = zipfile.ZipFile(wheel).read(page).decode("utf-8")
        for target in re.findall(r"\]\(([^)#\s]+)", text):
            if "://" in target or target.startswith("mailto:"):
                continue
            resolved = posixpath.normpath(posixpath.join(posixpath.dirname(page), target))
            if resolved not in names and not any(n.startswith(resolved + "/") for n in names):
                broken.append(f"{page} -> {target}")
    assert not broken, broken
    sources = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "wrlayer", "meshes", "calibration",
                              "contact"], cwd=REPO, capture_output=True, text=True, check=True).stdout.split()
    assert not [s for s in sources if s.endswith(".py") and s not in names]


def _run(args, cwd, env, ok=True):
    run = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=600)
    assert (run.returncode == 0) == ok, run.stderr
    return run


def test_installed_command_runs_a_shipped_scene_outside_the_repository(wheel, tmp_path):
    site = tmp_path / "site"
    subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "-q", "--target", str(site), str(wheel)],
                   check=True, capture_output=True, timeout=300)
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "WRLAYER_REFERENCE")}
    env.update(PYTHONPATH=str(site), XDG_CACHE_HOME=str(tmp_path / "cache"), WRLAYER_PROGRESS="0")
    work = tmp_path / "run"
    work.mkdir()
    wrlayer = [sys.executable, str(site / "bin" / "wrlayer")]
    where = _run([sys.executable, "-c", "import wrlayer, contact; print(wrlayer.__file__, contact.__file__)"],
                 work, env).stdout.split()
    assert all(Path(w).is_relative_to(site) for w in where), where       # the installed copy, not the sources
    version = REPO.joinpath("pyproject.toml").read_text(encoding="utf-8").split('\nversion = "')[1].split('"')[0]
    assert _run([*wrlayer, "--version"], work, env).stdout == f"wrlayer {version}\n"   # once, no git revision
    help_text = _run([*wrlayer, "simulate", "--help"], work, env).stdout
    page = next(ln for ln in help_text.splitlines() if ln.startswith("reference: "))[11:].split(", ")[0]
    assert Path(page).is_file() and Path(page).is_relative_to(site)
    _run([*wrlayer, "example", "hertz_check", "work"], work, env)
    _run([*wrlayer, "simulate", "work/hertz_check.toml", "--out", "out", "--no-vtk"], work, env)
    installed = json.loads((work / "out" / "result.json").read_text(encoding="utf-8"))["passes"][0]
    assert cli.main(["simulate", str(REPO / "scenes" / "hertz_check.toml"), "--out", str(tmp_path / "src"),
                     "--no-vtk"]) == 0
    source = json.loads((tmp_path / "src" / "result.json").read_text(encoding="utf-8"))["passes"][0]
    for key in ("length_mm", "width_mm", "area_mm2", "delta_mm", "p_max_MPa"):
        assert installed[key] == source[key], key
    # numba's compiled code in the user's cache, never beside the installed sources (a run that compiles: the small
    # scene above runs its kernels as plain Python)
    _run([*wrlayer, "simulate", "work/hertz_check.toml", "--out", "out_compiled", "--no-vtk"], work,
         {**env, "WRLAYER_JIT": "always"})
    assert list((tmp_path / "cache" / "wrlayer" / "numba").rglob("*.nbi"))
    assert not list(site.rglob("*.nbi"))
    # no folder beside a repository: the reference folder comes from $WRLAYER_REFERENCE only, and says so
    err = _run([sys.executable, "-c", "from wrlayer.input_files import resolve_reference as r; "
                "r('reference:profiles/a.prr', 's.toml: profiles.rail')"], work, env, ok=False).stderr
    assert "$WRLAYER_REFERENCE (not set); no folder beside the repository (an installed package)" in err
