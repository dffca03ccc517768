"""Packaging beyond pyproject.toml: the repository's shipped scenes (with their layer tables) and reference pages
installed as package data under ``wrlayer/data/`` (``wrlayer example`` copies them out; :mod:`wrlayer.shipped`).

pyproject.toml cannot map a folder outside the packages into one, so the package list is made here: every package
of the four source packages (namespace folders such as ``calibration/configs`` included) plus one data package per
folder of ``scenes/`` and ``docs/``.
"""

from pathlib import Path

from setuptools import find_namespace_packages, setup

HERE = Path(__file__).resolve().parent
#: installed data package -> repository folder
DATA_FOLDERS = {"wrlayer.data.scenes": "scenes", "wrlayer.data.docs": "docs"}


def data_packages(package: str, folder: str) -> list[str]:
    """``package`` and one sub-package per sub-folder of ``folder`` (caches and images left out)."""
    subs = sorted(d.relative_to(HERE / folder) for d in (HERE / folder).rglob("*")
                  if d.is_dir() and not {"__pycache__", "img"} & set(d.parts))
    return [package] + [".".join([package, *d.parts]) for d in subs]


PACKAGES = find_namespace_packages(where=str(HERE), include=["wrlayer*", "meshes*", "calibration*", "contact*"],
                                   exclude=["*.__pycache__"])
PACKAGES += [p for package, folder in DATA_FOLDERS.items() for p in data_packages(package, folder)]

setup(packages=PACKAGES, package_dir={"": ".", **DATA_FOLDERS})
