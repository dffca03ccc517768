"""Command-line conventions shared by every entry point, and the ``wrlayer`` console command.

    wrlayer simulate SCENE --out DIR [--plots]        = python -m contact simulate ...
    wrlayer simulate-all SCENES_DIR --out DIR          = python -m contact simulate-all ...
    wrlayer wear SCENE --out DIR                       = python -m contact wear ...
    wrlayer calibrate CONFIG --out DIR                 = python -m calibration run ...
    wrlayer rolling CONFIG --out DIR                   = python -m calibration rolling ...
    wrlayer mesh PROFILE --y0 Y --h-min H --h-max H --out FILE   = python -m meshes mesh ...
    wrlayer mesh-plots --out DIR                       = python -m meshes plots ...
    wrlayer example NAME DIR | --list                  (copies a shipped scene or configuration, wrlayer.shipped)
    wrlayer --version

Every sub-command's help is in the ``wrlayer`` form (also when run as ``python -m contact`` etc.) and names the
reference page of its keys. Every entry point prints ``error: <input>: <what is wrong>`` (one line, no traceback)
for bad input and exits with the codes of :data:`EXIT_CODES`. ``--version`` asks git or the package metadata only
when given (a run does not pay for it).
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from wrlayer.errors import ArgumentParser
from wrlayer.shipped import reference_page
from wrlayer.version import source_tree, version_text

#: Exit codes of every entry point.
EXIT_CODES = {
    0: "success",
    1: "some scenes of a batch (simulate-all) failed; the others were written",
    2: "bad input (file, key, value or argument; a run refused by its cost estimate without --force; an --out in "
       "use by another run or not writable): nothing written",
    3: "numerical failure (an iteration did not converge; out of memory): nothing written (a rolling run: its "
       "record with the passes completed before the failed step)",
    4: "some positions of a calibration or cases of a wheel-rail sweep failed (printed on stderr; the tables "
       "and results hold the others and list the failed ones)",
    5: "wear: the loop stopped at a step (named); the completed steps' profiles and table were written",
    130: "interrupted (Ctrl-C)",
    143: "terminated (SIGTERM); the run's staging folders are removed and its workers ended (a wear run keeps its "
         "completed steps, a rolling run its completed passes, in <out>.partial)",
}


def exit_codes_text() -> str:
    """The exit-code table as help text."""
    return "exit codes:\n" + "\n".join(f"  {code:>3}  {text}" for code, text in EXIT_CODES.items())


#: wrlayer sub-command -> (module whose ``main(argv)`` runs it, arguments put before the user's, help).
COMMANDS = {
    "simulate": ("contact.__main__", ["simulate"], "run one contact scene (Kik-Piotrowski or wheel-rail)"),
    "simulate-all": ("contact.__main__", ["simulate-all"], "run every scene of a folder and print a summary"),
    "wear": ("contact.__main__", ["wear"], "wear simulation: profiles evolving by wear and inelastic displacement"),
    "calibrate": ("calibration.__main__", ["run"], "FEM calibration of layer tables from a TOML configuration"),
    "rolling": ("calibration.__main__", ["rolling"], "moving-load elastoplastic FEM, pass after pass (rolling)"),
    "mesh": ("meshes.__main__", ["mesh"], "mesh a profile section (2D) or local block (3D)"),
    "mesh-plots": ("meshes.__main__", ["plots"], "pictures of the default meshes"),
    "geometry": ("contact.__main__", ["geometry"], "contact geometry of a wheel/rail pair (Δr, conicity)"),
    "example": ("wrlayer.shipped", [], "copy a shipped scene or configuration (with its tables) into a folder"),
}

#: wrlayer sub-command -> the reference pages of its input keys and outputs (docs/).
REFERENCE_PAGES = {
    "simulate": ("scene-keys.md", "result-keys.md"),
    "simulate-all": ("scene-keys.md", "result-keys.md"),
    "wear": ("scene-keys.md", "wear.md"),
    "calibrate": ("calibration-config.md", "calibration.md"),
    "rolling": ("rolling.md",),
    "mesh": ("profiles-and-meshes.md",),
    "mesh-plots": ("profiles-and-meshes.md",),
    "geometry": ("geometry.md",),
    "example": ("scene-keys.md",),
}


def wrlayer_name(subcommand: str) -> str:
    """The ``wrlayer`` command of a package entry point's sub-command (``run`` -> ``calibrate``)."""
    for name, (_, prefix, _) in COMMANDS.items():
        if prefix[:1] == [subcommand]:
            return name
    return subcommand


def reference_text(command: str | None) -> str:
    """The help's pointer to the reference pages of ``command`` (None: the index of all pages)."""
    pages = REFERENCE_PAGES.get(command, ()) if command else ("README.md",)
    return "reference: " + ", ".join(reference_page(p) for p in pages) if pages else ""


def epilog(examples: Sequence[str], command: str | None) -> str:
    """The help's closing text: the examples, the reference pages of ``command`` and the exit codes."""
    parts = ["examples:\n" + "\n".join(f"  {e}" for e in examples), reference_text(command), exit_codes_text()]
    return "\n\n".join(p for p in parts if p)


class VersionAction(argparse.Action):
    """``--version``: the version line is made (package metadata, ``git describe``) only when asked for."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS,
                 help="print the version (and the code revision in a source tree) and exit"):
        super().__init__(option_strings=option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        print(version_text(parser.prog))
        parser.exit()


def parser(prog: str, description: str, examples: Sequence[str]) -> argparse.ArgumentParser:
    """An ArgumentParser with ``--version``, the examples, the reference pages and the exit codes in its help."""
    ap = ArgumentParser(prog=prog, description=description, epilog=epilog(examples, None),
                        formatter_class=argparse.RawDescriptionHelpFormatter)  # one-line argument errors, exit 2
    ap.add_argument("--version", action=VersionAction)
    return ap


def subparser(sub, name: str, help: str, examples: Sequence[str]) -> argparse.ArgumentParser:
    """A sub-command parser in the project's style: usage in the ``wrlayer`` form, its examples, the reference
    pages of its keys and the exit codes in its help."""
    command = wrlayer_name(name)
    return sub.add_parser(name, prog=f"wrlayer {command}", help=help, description=help,
                          epilog=epilog(examples, command), formatter_class=argparse.RawDescriptionHelpFormatter)


def add_run_options(command: argparse.ArgumentParser, out_help: str, quiet: bool = True) -> None:
    """The options every run command shares: ``--out DIR`` (required), ``--force`` (past the cost guard) and,
    for a command that reports progress, ``--quiet``."""
    command.add_argument("--out", required=True, help=out_help)
    command.add_argument("--force", action="store_true", help="run even when the estimated cost exceeds the limit")
    if quiet:
        command.add_argument("--quiet", action="store_true", help="no progress lines")


def add_worker_options(command: argparse.ArgumentParser, workers_help: str, scheduler_help: str) -> None:
    """``--workers N`` and ``--scheduler ADDRESS`` (None: the scene's); both checked by one rule when the run
    starts (:func:`contact.run_files.run_overrides`)."""
    command.add_argument("--workers", type=int, default=None, help=workers_help)
    command.add_argument("--scheduler", default=None, metavar="ADDRESS", help=scheduler_help)


def add_profile_check_option(command: argparse.ArgumentParser) -> None:
    """``--accept-unusual-profile``: every profile file the command reads is read without the plausibility checks
    (units, orientation, steps, spikes; :mod:`meshes.profiles.plausibility`), as the input key
    ``accept_unusual_profile = true`` (a profile unusual on purpose)."""
    command.add_argument("--accept-unusual-profile", action="store_true",
                         help="read profile files without the plausibility checks (units, orientation, steps, "
                              "spikes; as the input key accept_unusual_profile = true)")


def _top_parser() -> argparse.ArgumentParser:
    ap = parser("wrlayer", "FEM-calibrated Prandtl surface layers for wheel/rail contact (units mm, N, MPa, s).",
                ["wrlayer example --list",
                 "wrlayer example hertz_check work && wrlayer simulate work/hertz_check.toml --out out/one --plots",
                 "wrlayer calibrate calibration/configs/test_coarse.toml --out out/cal",
                 "wrlayer simulate --help"])
    ap.add_argument("command", choices=sorted(COMMANDS), metavar="COMMAND",
                    help="; ".join(f"{k}: {v[2]}" for k, v in COMMANDS.items()))
    ap.add_argument("args", nargs=argparse.REMAINDER, help="arguments of the command (see wrlayer COMMAND --help)")
    return ap


def use_user_numba_cache() -> None:
    """An installed package keeps numba's compiled code in the user's cache (``$XDG_CACHE_HOME/wrlayer/numba``),
    not beside the installed sources; a source tree keeps numba's default (``__pycache__`` beside the sources).
    ``$NUMBA_CACHE_DIR`` set by the user wins. Must run before numba is imported."""
    if source_tree() is None and "NUMBA_CACHE_DIR" not in os.environ:
        cache = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
        os.environ["NUMBA_CACHE_DIR"] = str(cache / "wrlayer" / "numba")


def main(argv: Sequence[str] | None = None) -> int:
    """The ``wrlayer`` console command: dispatch to the package entry points."""
    argv = list(sys.argv[1:] if argv is None else argv)
    args = _top_parser().parse_args(argv[:1] if argv and not argv[0].startswith("-") else argv)
    module, prefix, _ = COMMANDS[args.command]
    use_user_numba_cache()
    return int(importlib.import_module(module).main(prefix + argv[1:]) or 0)


if __name__ == "__main__":
    sys.exit(main())
