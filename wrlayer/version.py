"""The package version and the code revision that every result, table and ``--version`` records.

A source tree (a git checkout with its ``pyproject.toml``) records ``git describe`` of that tree; an installed
package records its version (the wheel carries no git revision: the version's tag names it). ``importlib.metadata``
and ``subprocess`` are imported inside the functions: the command line imports this module for ``--version``,
and a run that never asks pays nothing for them (about 60 ms).
"""

from __future__ import annotations

import functools
from pathlib import Path

_ROOT = Path(__file__).resolve().parents[1]


def source_tree() -> Path | None:
    """The repository this code runs from (the folder holding ``pyproject.toml`` beside the packages), or None for
    an installed package (whose parent folder is ``site-packages``)."""
    return _ROOT if (_ROOT / "pyproject.toml").is_file() and (_ROOT / "wrlayer").is_dir() else None


def package_version() -> str:
    """The ``wrlayer`` version: a source tree's pyproject.toml (an editable install's metadata keeps the version of
    its last installation), else the installed package's metadata, else "unknown"."""
    root = source_tree()
    if root is not None:
        import tomllib  # here: only a source tree reads its pyproject.toml

        try:
            return str(tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8"))["project"]["version"])
        except (OSError, ValueError, KeyError):
            pass
    from importlib import metadata  # here: 50 ms of imports that only a version query needs

    try:
        return metadata.version("wrlayer")
    except metadata.PackageNotFoundError:
        return "unknown"


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """``git describe --always --dirty --tags`` of the source tree, else ``wrlayer <installed version>``.

    An installed package never asks git: a virtual environment inside some other checkout would otherwise report
    that checkout's revision."""
    root = source_tree()
    if root is not None:
        import subprocess  # here: only a source tree runs git

        try:
            out = subprocess.run(["git", "describe", "--always", "--dirty", "--tags"], cwd=root,
                                 capture_output=True, text=True, timeout=10, check=True)
            if out.stdout.strip():
                return f"git {out.stdout.strip()}"
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
    """{"python": version, package: installed version or "not installed"} for the result files (wrlayer's own
    as :func:`package_version` gives it)."""
    import platform  # here, with importlib.metadata: only calibration tables record these
    from importlib import metadata

    out = {"python": platform.python_version()}
    for pkg in packages:
        if pkg == "wrlayer":
            out[pkg] = package_version()
            continue
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out
