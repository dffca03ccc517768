"""The packages' public API: every exported name resolves, importing a package stays cheap, docs/api.md lists it."""

import subprocess
import sys
from pathlib import Path

import pytest

import calibration
import contact
import meshes
import wrlayer

REPO = Path(__file__).resolve().parents[1]
PACKAGES = (wrlayer, meshes, calibration, contact)


@pytest.mark.parametrize("package", PACKAGES, ids=lambda p: p.__name__)
def test_every_exported_name_resolves_to_its_module(package):
    for name in package.__all__:
        value = getattr(package, name)
        if name in package.API:
            assert getattr(sys.modules[package.API[name]], name) is value
    assert set(package.__all__) <= set(dir(package))
    with pytest.raises(AttributeError, match="no attribute 'not_a_name'"):
        package.not_a_name


def test_importing_the_packages_loads_no_heavy_module():
    code = ("import sys, contact, calibration, meshes, wrlayer; "
            "print(sorted(m for m in ('scipy', 'numba', 'gmsh', 'skfem', 'matplotlib') if m in sys.modules))")
    run = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"


@pytest.mark.parametrize("package", PACKAGES, ids=lambda p: p.__name__)
def test_api_page_names_every_exported_name(package):
    page = (REPO / "docs" / "api.md").read_text(encoding="utf-8")
    missing = [n for n in package.API if f"`{n}" not in page]
    assert missing == []


def test_profiles_load_by_name_and_alias():
    assert meshes.load_profile("uic60").name == meshes.get_profile("60E1").name
    assert meshes.load_profile("S1002", r0=450.0).body == "wheel"
