"""Packaging beyond pyproject.toml: the repository's shipped scenes (with their layer tables), Python examples,
reference pages, README and citation installed as package data under ``wrlayer/data/`` in the repository's layout,
so that the pages' relative links (``../README.md``, ``../examples/...``) hold when installed (``wrlayer example``
copies them out; :mod:`wrlayer.shipped`).

pyproject.toml cannot map a folder outside the packages into one, so the package list is made here: every package
of the four source packages (namespace folders such as ``calibration/configs`` included) plus one data package per
folder of ``scenes/``, ``examples/`` and ``docs/``; the top-level files are copied by :class:`BuildPy`.
"""

import shutil
from pathlib import Path

from setuptools import find_namespace_packages, setup
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent
#: installed data package -> repository folder
DATA_FOLDERS = {"wrlayer.data.scenes": "scenes", "wrlayer.data.docs": "docs", "wrlayer.data.examples": "examples"}
#: repository files installed as wrlayer/data/<name> (the reference pages link to them)
TOP_FILES = ("README.md", "CITATION.cff")


class BuildPy(build_py):
    """build_py that also copies :data:`TOP_FILES` into ``wrlayer/data/``."""

    def run(self):
        super().run()
        target = Path(self.build_lib) / "wrlayer" / "data"
        target.mkdir(parents=True, exist_ok=True)
        for name in TOP_FILES:
            shutil.copyfile(HERE / name, target / name)


def data_packages(package: str, folder: str) -> list[str]:
    """``package`` and one sub-package per sub-folder of ``folder`` (caches and images left out)."""
    subs = sorted(d.relative_to(HERE / folder) for d in (HERE / folder).rglob("*")
                  if d.is_dir() and not {"__pycache__", "img"} & set(d.parts))
    return [package] + [".".join([package, *d.parts]) for d in subs]


PACKAGES = find_namespace_packages(where=str(HERE), include=["wrlayer*", "meshes*", "calibration*", "contact*"],
                                   exclude=["*.__pycache__"])
PACKAGES += [p for package, folder in DATA_FOLDERS.items() for p in data_packages(package, folder)]

setup(packages=PACKAGES, package_dir={"": ".", **DATA_FOLDERS}, cmdclass={"build_py": BuildPy})
