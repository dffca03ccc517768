"""Reading ``python -X importtime`` output: the import records, their cost by package and who pulls them in.

``-X importtime`` prints one line per module when its import finishes: ``import time: <self µs> | <cumulative µs> |
<name indented two spaces per nesting level>``; a module is printed after the modules its import pulled in. Our
modules that import a package at module level are also found from the sources (:func:`module_level_importers`).
"""

from __future__ import annotations

import ast
import dataclasses
import pathlib
import sys

#: our packages: grouped one level deeper, and the ones whose module-level imports are listed
PROJECT_PACKAGES = ("wrlayer", "meshes", "calibration", "contact")


@dataclasses.dataclass(frozen=True)
class ImportRecord:
    """One line of ``python -X importtime`` output.

    Attributes
    ----------
    name : str
        Module name.
    self_us : int
        Time spent in the module's own body, µs.
    cumulative_us : int
        Time including the modules it imported first, µs.
    depth : int
        Nesting level (0: imported by the running code, not by another module's import).
    parent : int
        Index of the module whose import pulled this one in, -1 at depth 0.
    """

    name: str
    self_us: int
    cumulative_us: int
    depth: int
    parent: int


@dataclasses.dataclass(frozen=True)
class ImportGroup:
    """The import cost of one package (or, for our packages, one sub-package).

    Attributes
    ----------
    group : str
        Package name (``numba``) or our sub-package (``contact.normal``).
    self_s : float
        Summed self time of its modules, s.
    modules : int
        Number of its modules imported.
    importer : str
        Module whose import pulled in the group's most expensive entry (a module of the group imported from outside
        it); ``(run time)`` when that entry was imported by running code.
    project_importer : str
        Nearest module of our packages on that import chain (the one that imports it at module level), or "".
    """

    group: str
    self_s: float
    modules: int
    importer: str
    project_importer: str


def parse_importtime(text: str) -> list[ImportRecord]:
    """The records of ``-X importtime`` stderr, in output order (a module is printed after those it imported).

    Lines that are not ``import time: <self> | <cumulative> | <indent><name>`` (the header, other output) are
    skipped; the nesting depth is the indentation of the name in steps of two spaces."""
    rows: list[tuple[str, int, int, int]] = []
    for line in text.splitlines():
        if not line.startswith("import time:"):
            continue
        parts = line[len("import time:"):].split("|")
        if len(parts) != 3 or not parts[0].strip().isdigit():
            continue
        label = parts[2][1:] if parts[2].startswith(" ") else parts[2]
        depth = (len(label) - len(label.lstrip(" "))) // 2
        rows.append((label.strip(), int(parts[0]), int(parts[1]), depth))
    parents = [-1] * len(rows)
    waiting: dict[int, list[int]] = {}  # depth -> records still looking for their importer
    for i, (_, _, _, depth) in enumerate(rows):
        for child in waiting.pop(depth + 1, []):
            parents[child] = i
        waiting.setdefault(depth, []).append(i)
    return [ImportRecord(n, s, c, d, p) for (n, s, c, d), p in zip(rows, parents)]


def import_seconds(records: list[ImportRecord], exclude: frozenset[str] = frozenset()) -> float:
    """Summed cumulative time (s) of the top-level imports, leaving out the modules in ``exclude`` (e.g. those the
    bare interpreter imports)."""
    return sum(r.cumulative_us for r in records if r.depth == 0 and r.name not in exclude) / 1e6


def lazy_library_seconds(records: list[ImportRecord]) -> float:
    """Summed cumulative time (s) of the top-level imports of third-party modules: imported by a library while it
    runs (not by an import statement of ours, which would nest them under our module)."""
    return sum(r.cumulative_us for r in records if r.depth == 0 and third_party(r.name)) / 1e6


def third_party(name: str) -> bool:
    """Whether module ``name`` belongs to neither our packages nor the standard library."""
    top = name.split(".")[0]
    return top not in PROJECT_PACKAGES and top not in sys.stdlib_module_names


def group_of(name: str) -> str:
    """The group a module's cost is counted in: its top-level package, or for our packages the sub-package."""
    parts = name.split(".")
    return ".".join(parts[:2]) if parts[0] in PROJECT_PACKAGES else parts[0]


def import_groups(records: list[ImportRecord]) -> list[ImportGroup]:
    """Import cost per group, heaviest first, with the module through which the group's most expensive entry was
    imported (an entry: a module of the group whose importer is outside the group)."""
    self_us: dict[str, int] = {}
    count: dict[str, int] = {}
    entry: dict[str, int] = {}  # group -> its entry record of the largest cumulative time
    for i, r in enumerate(records):
        g = group_of(r.name)
        self_us[g] = self_us.get(g, 0) + r.self_us
        count[g] = count.get(g, 0) + 1
        is_entry = r.parent < 0 or group_of(records[r.parent].name) != g
        if is_entry and (g not in entry or r.cumulative_us > records[entry[g]].cumulative_us):
            entry[g] = i
    out = []
    for g in sorted(self_us, key=self_us.get, reverse=True):
        first = records[entry[g]] if g in entry else None
        importer = records[first.parent].name if first is not None and first.parent >= 0 else "(run time)"
        out.append(ImportGroup(g, self_us[g] / 1e6, count[g], importer, _project_ancestor(records, entry.get(g))))
    return out


def _project_ancestor(records: list[ImportRecord], index: int | None) -> str:
    while index is not None and index >= 0:
        index = records[index].parent
        if index >= 0 and records[index].name.split(".")[0] in PROJECT_PACKAGES:
            return records[index].name
    return ""


def module_level_importers(root: pathlib.Path, packages: set[str],
                           modules: set[str] | None = None) -> dict[str, list[str]]:
    """Our modules (of ``modules`` when given) that import one of ``packages`` at module level (statements in the
    module body, also inside a top-level ``if``/``try``), by package. Read from the sources: every such module is
    found, not only the first one an import chain meets."""
    found: dict[str, list[str]] = {p: [] for p in sorted(packages)}
    for pkg in PROJECT_PACKAGES:
        for path in sorted((root / pkg).rglob("*.py")):
            module = ".".join(path.relative_to(root).with_suffix("").parts).removesuffix(".__init__")
            if modules is not None and module not in modules:
                continue
            for p in sorted(_top_imports(ast.parse(path.read_text(encoding="utf-8"))) & packages):
                found[p].append(module)
    return found


def _top_imports(tree: ast.Module) -> set[str]:
    names: set[str] = set()
    stack = list(tree.body)
    while stack:
        node = stack.pop()
        if isinstance(node, ast.Import):
            names.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
        elif isinstance(node, (ast.If, ast.Try)):
            stack += node.body + node.orelse + getattr(node, "finalbody", [])
            stack += [s for h in getattr(node, "handlers", []) for s in h.body]
    return names
