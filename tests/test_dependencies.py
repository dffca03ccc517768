"""The packages' dependency lines are true: checked on the source with ``ast`` (nothing is imported).

Every package ``__init__`` docstring states its dependencies in one paragraph starting ``Depends on:`` (the
top-level packages in the uniform form ``Depends on: wrlayer, meshes.`` or ``Depends on: none (...).``; a
parenthesised note is allowed). A listed name allows that package and everything below it. The rules:

1. no module of a top-level package imports another project package that its line does not list;
2. ``wrlayer`` (the shared basics) imports none of the others;
3. no module of a subpackage whose ``__init__`` has a dependency line imports a sibling subpackage or another
   top-level package that the line does not list (``wrlayer``, imported by every package, is implied);
4. no private name (``_x``) is imported from another module of the project.

``ALLOWED`` lists the known violations in code owned elsewhere, each with the change that removes it; it is to
be emptied, not extended.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
ROOTS = ("wrlayer", "meshes", "calibration", "contact")

#: (importing module, imported module or "module:private name") -> the change that removes the violation.
ALLOWED: dict[tuple[str, str], str] = {}


def module_name(path: Path) -> str:
    parts = path.relative_to(REPO).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def package_dirs() -> list[Path]:
    return sorted(p.parent for root in ROOTS for p in (REPO / root).rglob("__init__.py"))


def source_files(package_dir: Path) -> list[Path]:
    return sorted(package_dir.rglob("*.py"))


def dependency_paragraph(package_dir: Path) -> str | None:
    """The first sentence after ``Depends on:`` in the package's docstring (None when it has none)."""
    doc = ast.get_docstring(ast.parse((package_dir / "__init__.py").read_text(encoding="utf-8"))) or ""
    m = re.search(r"^Depends on:(.*?)(?:\.\s|\.$)", doc, flags=re.M | re.S)
    return None if m is None else m.group(1)


def listed(paragraph: str) -> set[str]:
    """The project packages named in a dependency sentence (parenthesised notes left out)."""
    text = re.sub(r"\([^)]*\)", "", paragraph)
    return set(re.findall(r"\b(?:%s)(?:\.\w+)*\b" % "|".join(ROOTS), text))


def project_imports(path: Path) -> list[tuple[str, list[str]]]:
    """(imported project module, imported names) of every import statement in the file, at any depth."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module.split(".")[0] in ROOTS:
                out.append((node.module, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            out.extend((a.name, []) for a in node.names if a.name.split(".")[0] in ROOTS)
    return out


def covered(module: str, allowed: set[str]) -> bool:
    return any(module == a or module.startswith(a + ".") for a in allowed)


def violations(package_dir: Path, allowed: set[str], inside: str) -> list[tuple[str, str]]:
    """(importer, imported) pairs of the package's modules that import outside ``inside`` and ``allowed``."""
    found = []
    for path in source_files(package_dir):
        importer = module_name(path)
        for module, _ in project_imports(path):
            if not covered(module, {inside} | allowed):
                found.append((importer, module))
    return found


def unexpected(found: list[tuple[str, str]]) -> list[str]:
    return [f"{a} imports {b}" for a, b in found if (a, b) not in ALLOWED]


@pytest.mark.parametrize("root", ROOTS)
def test_top_level_dependency_line_is_uniform(root):
    doc = ast.get_docstring(ast.parse((REPO / root / "__init__.py").read_text(encoding="utf-8"))) or ""
    lines = [ln for ln in doc.splitlines() if ln.startswith("Depends on:")]
    assert len(lines) == 1, f"{root}: needs exactly one 'Depends on:' line"
    assert re.fullmatch(r"Depends on: (none|[\w.]+(, [\w.]+)*)( \([^)]*\))?\.", lines[0]), lines[0]
    names = listed(lines[0])
    assert all(n.split(".")[0] in ROOTS and n.split(".")[0] != root for n in names), lines[0]


@pytest.mark.parametrize("root", ROOTS)
def test_top_level_package_imports_only_what_it_lists(root):
    allowed = listed(dependency_paragraph(REPO / root))
    assert unexpected(violations(REPO / root, allowed, root)) == []


def test_wrlayer_imports_no_other_project_package():
    assert violations(REPO / "wrlayer", set(), "wrlayer") == []


@pytest.mark.parametrize("package_dir", [d for d in package_dirs() if d.parent != REPO],
                         ids=lambda d: module_name(d / "__init__.py"))
def test_subpackage_imports_only_what_it_lists(package_dir):
    paragraph = dependency_paragraph(package_dir)
    if paragraph is None:
        pytest.skip("no dependency line")
    name = module_name(package_dir / "__init__.py")
    root = name.split(".")[0]
    allowed = listed(paragraph) | {"wrlayer"}
    # the package's own root package (e.g. ``contact`` itself) is not a sibling: only its subpackages are checked
    found = [(a, b) for a, b in violations(package_dir, allowed, name) if b != root]
    assert unexpected(found) == []


def test_no_private_name_is_imported_from_another_module():
    found = []
    for root in ROOTS:
        for path in source_files(REPO / root):
            importer = module_name(path)
            for module, names in project_imports(path):
                found += [(importer, f"{module}:{n}") for n in names if n.startswith("_") and n != "__version__"]
    assert unexpected(found) == []


def test_allow_list_holds_only_current_violations():
    """An entry whose violation is gone must leave the list (so that it is emptied, never stale)."""
    current = set()
    for root in ROOTS:
        for path in source_files(REPO / root):
            importer = module_name(path)
            for module, names in project_imports(path):
                current.add((importer, module))
                current.update((importer, f"{module}:{n}") for n in names)
    assert sorted(set(ALLOWED) - current) == []
