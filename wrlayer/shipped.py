"""The files shipped with wrlayer (scenes with their layer tables, calibration configurations, Python examples,
reference pages) and ``wrlayer example``, which copies one of them out.

In a source tree they are the repository's ``scenes/``, ``calibration/configs/``, ``examples/`` and ``docs/``; an
installed package carries ``scenes/``, ``examples/``, ``docs/``, ``README.md`` and ``CITATION.cff`` as
``wrlayer/data/`` (setup.py: the repository's layout, so the pages' relative links hold) and the configurations
inside the ``calibration`` package, so the same names work after ``pip install``::

    wrlayer example --list
    wrlayer example hertz_check work/          # work/hertz_check.toml
    wrlayer example wear/s1002_60e1 work/      # work/wear/s1002_60e1.toml and the two tables it names
    wrlayer example config/test_coarse work/   # work/test_coarse.toml
    wrlayer example examples/ex02_hertz_check work/   # work/ex02_hertz_check.py (finds its scene through
                                                      # wrlayer.shipped.scenes_dir)

A scene that another shipped scene names as its template (the wear scene's recalibration configuration) is listed
with the scene it belongs to: it is not run by itself.

A copied scene keeps its place relative to the files it names (layer tables), so it runs unchanged from the new
folder; ``reference:`` files stay in the shared reference folder (``$WRLAYER_REFERENCE``). Nothing is overwritten.
"""

from __future__ import annotations

import shutil
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from wrlayer.errors import InputError, cli_guard
from wrlayer.input_files import REFERENCE_ENV, REFERENCE_PREFIX, read_toml
from wrlayer.version import source_tree

_PACKAGE = Path(__file__).resolve().parent
#: Name prefix of the calibration and rolling configurations.
CONFIG_PREFIX = "config/"
#: Width of ``wrlayer example --list`` (characters; longer titles are cut).
LIST_COLUMNS = 100
#: Name prefix of the Python examples.
EXAMPLES_PREFIX = "examples/"


def scenes_dir() -> Path:
    """The shipped scenes: ``scenes/`` of the source tree, or ``wrlayer/data/scenes`` when installed."""
    root = source_tree()
    return root / "scenes" if root is not None else _PACKAGE / "data" / "scenes"


def configs_dir() -> Path:
    """The shipped calibration and rolling configurations (inside the ``calibration`` package either way)."""
    return _PACKAGE.parent / "calibration" / "configs"


def examples_dir() -> Path:
    """The Python examples: ``examples/`` of the source tree, or ``wrlayer/data/examples`` when installed."""
    root = source_tree()
    return root / "examples" if root is not None else _PACKAGE / "data" / "examples"


def docs_dir() -> Path:
    """The reference pages: ``docs/`` of the source tree, or ``wrlayer/data/docs`` when installed."""
    root = source_tree()
    return root / "docs" if root is not None else _PACKAGE / "data" / "docs"


def reference_page(name: str) -> str:
    """Where reference page ``name`` (e.g. ``scene-keys.md``) is: ``docs/NAME`` in a source tree (the README's
    links), the full path of the installed copy otherwise."""
    return f"docs/{name}" if source_tree() is not None else str(docs_dir() / name)


@dataclass(frozen=True)
class Example:
    """One shipped scene or configuration.

    Attributes
    ----------
    name : str
        Its name for ``wrlayer example``: the scene's path in the scenes folder without ``.toml``
        (``wear/s1002_60e1``), or ``config/`` and the configuration's stem.
    path : Path
        The shipped file.
    command : str
        What runs it: ``wrlayer simulate``, ``wrlayer wear``, ``wrlayer calibrate``, ``wrlayer rolling``,
        ``python`` (an example script), or ``template of <scene>`` (read by that scene, not run by itself).
    title : str
        The file's ``title`` key, else its first comment line.
    """

    name: str
    path: Path
    command: str
    title: str


def _title(data: dict[str, Any], path: Path) -> str:
    if isinstance(data.get("title"), str):
        return data["title"]
    first = path.read_text(encoding="utf-8").splitlines()[:1]
    return first[0].lstrip("# ").strip() if first and first[0].startswith("#") else ""


def _example(name: str, path: Path, config: bool, templates: dict[Path, str]) -> Example:
    data = read_toml(path)
    if config:
        command = "wrlayer rolling" if "track" in data and "contact" in data else "wrlayer calibrate"
    elif path.resolve() in templates:
        command = f"template of {templates[path.resolve()]}"
    else:
        command = "wrlayer wear" if data.get("type") == "wear" else "wrlayer simulate"
    return Example(name, path, command, _title(data, path))


def _script(path: Path) -> Example:
    doc = path.read_text(encoding="utf-8").split('"""')
    title = doc[1].strip().splitlines()[0] if len(doc) > 2 else ""
    return Example(EXAMPLES_PREFIX + path.stem, path, "python", title)


def _templates(scenes: Path, paths: list[Path]) -> dict[Path, str]:
    """The scene files another scene names (path -> the naming scene's example name)."""
    named = {}
    for path in paths:
        for text in _strings(read_toml(path)):
            candidate = (path.parent / text).resolve() if text.endswith(".toml") else None
            if candidate is not None and candidate.is_file() and candidate != path.resolve():
                named[candidate] = path.relative_to(scenes).with_suffix("").as_posix()
    return named


def examples() -> list[Example]:
    """Every shipped scene (``scenes/**.toml``), configuration and Python example, scenes first, by name."""
    scenes = scenes_dir()
    paths = sorted(scenes.rglob("*.toml"))
    templates = _templates(scenes, paths)
    found = [_example(p.relative_to(scenes).with_suffix("").as_posix(), p, False, templates) for p in paths]
    found += [_example(CONFIG_PREFIX + p.stem, p, True, templates) for p in sorted(configs_dir().glob("*.toml"))]
    found += [_script(p) for p in sorted(examples_dir().glob("ex*.py"))]
    return found


def find_example(name: str) -> Example:
    """The shipped example ``name`` (InputError listing the names when there is none)."""
    by_name = {e.name: e for e in examples()}
    if name.removesuffix(".toml") not in by_name:
        raise InputError(f"example {name!r}", "no such shipped scene, configuration or example script "
                                              "(wrlayer example --list names them)")
    return by_name[name.removesuffix(".toml")]


def _strings(value: Any) -> list[str]:
    """Every string in a TOML value (tables and arrays walked)."""
    if isinstance(value, str):
        return [value]
    if isinstance(value, dict):
        return [s for v in value.values() for s in _strings(v)]
    if isinstance(value, list):
        return [s for v in value for s in _strings(v)]
    return []


def needed_files(example: Example) -> tuple[list[Path], list[str]]:
    """The shipped files a scene names relative to itself (layer tables, profile or CSV files inside the shipped
    folder), and the ``reference:`` names it needs from the shared reference folder."""
    base = example.path.parent
    root = scenes_dir().resolve()
    files, references = [], []
    for text in _strings(read_toml(example.path)):
        if text.startswith(REFERENCE_PREFIX):
            references.append(text)
            continue
        if "/" not in text and "." not in text:
            continue                                   # a name or keyword, not a file
        candidate = (base / text).resolve()
        if candidate.is_file() and candidate.is_relative_to(root) and candidate not in files:
            files.append(candidate)
    return files, references


def copy_example(name: str, folder: str | Path) -> list[Path]:
    """Copy the shipped example ``name`` and the files it names into ``folder`` (their layout kept); the copied
    paths, the scene or configuration first.

    Raises
    ------
    InputError
        No such example, or a file to write exists already with other contents (nothing is overwritten; nothing
        is written then). A file that exists with the same contents (a table two examples share) is kept.
    """
    example = find_example(name)
    folder = Path(folder)
    if example.name.startswith((CONFIG_PREFIX, EXAMPLES_PREFIX)):
        pairs = [(example.path, folder / example.path.name)]
    else:
        root = scenes_dir().resolve()
        sources = [example.path.resolve(), *needed_files(example)[0]]
        pairs = [(src, folder / src.relative_to(root)) for src in sources]
    same = [(src, dst) for src, dst in pairs if dst.is_file() and dst.read_bytes() == src.read_bytes()]
    clash = [str(dst) for src, dst in pairs if (dst.exists() or dst.is_symlink()) and (src, dst) not in same]
    if clash:
        raise InputError(str(folder), f"{', '.join(clash)} exists already and differs (wrlayer example never "
                                      "overwrites)")
    for src, dst in pairs:
        if (src, dst) not in same:                     # a table shared with an example copied before is kept
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(src, dst)
    return [dst for _, dst in pairs]


def list_text() -> str:
    """The table printed by ``wrlayer example --list``: name, what runs it, title (cut to :data:`LIST_COLUMNS`)."""
    rows = examples()
    width = max(len(e.name) for e in rows)
    run_width = max(len(e.command) for e in rows)
    lines = [f"{'NAME':<{width}}  {'RUN WITH':<{run_width}}  TITLE"]
    for e in rows:
        line = f"{e.name:<{width}}  {e.command:<{run_width}}  {e.title}"
        lines.append(line if len(line) <= LIST_COLUMNS else line[:LIST_COLUMNS - 3] + "...")
    return "\n".join(lines)


def copied_text(name: str, copied: list[Path]) -> str:
    """What ``wrlayer example NAME DIR`` prints: the files written and the command that runs the copy."""
    example = find_example(name)
    scene = not example.name.startswith((CONFIG_PREFIX, EXAMPLES_PREFIX))
    _, references = needed_files(example) if scene else ([], [])
    lines = [f"wrote {p}" for p in copied]
    if example.command == "python":
        lines.append(f"run it: python {copied[0]}")
    elif example.command.startswith("wrlayer"):
        lines.append(f"run it: {example.command} {copied[0]} --out out/{Path(example.name).name}")
    else:
        lines.append(f"it is the {example.command}: copy and run that scene")
    if references:
        lines.append(f"it reads {', '.join(references)} from the shared reference folder (${REFERENCE_ENV})")
    return "\n".join(lines)


@cli_guard
def main(argv: Sequence[str] | None = None) -> int:
    """``wrlayer example NAME DIR`` / ``wrlayer example --list``."""
    from wrlayer import cli  # here: cli imports this module for the reference pages of its help texts

    usage_examples = ["wrlayer example --list", "wrlayer example hertz_check work",
                 "wrlayer example wear/s1002_60e1 work", "wrlayer example config/test_coarse work"]
    ap = cli.parser("wrlayer example", "copy a shipped scene or configuration (with the layer tables it names) into "
                    "a folder, to run or edit it", usage_examples)
    ap.epilog = cli.epilog(usage_examples, "example")
    ap.add_argument("name", nargs="?", help="shipped scene (e.g. hertz_check) or config/NAME (see --list)")
    ap.add_argument("folder", nargs="?", help="folder to copy into (created; nothing in it is overwritten)")
    ap.add_argument("--list", action="store_true", help="list the shipped scenes and configurations")
    args = ap.parse_args(argv)
    if args.list:
        print(list_text())
        return 0
    if not (args.name and args.folder):
        ap.error("give NAME and DIR, or --list")
    print(copied_text(args.name, copy_example(args.name, args.folder)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
