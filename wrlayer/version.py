"""The package version and the code revision that every result, table and ``--version`` records."""

from __future__ import annotations

import functools
import platform
import subprocess
from importlib import metadata
from pathlib import Path

_ROOT = Path(__file__).resolve().parents[1]


def package_version() -> str:
    """The installed ``wrlayer`` version (pyproject.toml), or "unknown" when it is not installed."""
    try:
        return metadata.version("wrlayer")
    except metadata.PackageNotFoundError:
        return "unknown"


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """``git describe --always --dirty`` of the source tree, else the installed package version."""
    try:
        out = subprocess.run(["git", "describe", "--always", "--dirty", "--tags"], cwd=_ROOT, capture_output=True,
                             text=True, timeout=10, check=True)
        desc = out.stdout.strip()
        if desc:
            return f"git {desc}"
    except (OSError, subprocess.SubprocessError):
        pass
    return f"wrlayer {package_version()}"


def version_text(prog: str) -> str:
    """One line for ``--version``: program, package version and, from a source tree, the code revision (an
    installed package has no revision of its own: its version is printed once)."""
    revision = code_version()
    return f"{prog} {package_version()}" + (f" ({revision})" if revision.startswith("git ") else "")


#: Packages whose versions every calibration table records.
RECORDED_PACKAGES = ("numpy", "scipy", "scikit-fem", "gmsh", "wrlayer")


def software_versions(packages: tuple[str, ...] = RECORDED_PACKAGES) -> dict[str, str]:
    """{"python": version, package: installed version or "not installed"} for the result files."""
    out = {"python": platform.python_version()}
    for pkg in packages:
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out
